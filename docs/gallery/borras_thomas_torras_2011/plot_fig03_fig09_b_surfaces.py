"""
Figs. 3, 4, 8 and 9: B-lines, B-surfaces and the three families
===============================================================

Borràs, Thomas & Torras 2011. For each platform coordinate z, (14) is a line
B_z of the base plane; the base attachment aᵢ lies on B_{zᵢ}, and all B-lines
pass through the point B (16); B∞ (15) is the line of z = ∞ (Figs. 4, 8).
Stacked at height z, the B-lines sweep the B-surface (13) (Fig. 3). Section
IV: B finite — the quartic family; B at infinity, B∞ finite — cubic (all
B-lines parallel); both at infinity — quadratic, zᵢ = δxᵢ (eq. 26) (Fig. 9,
left to right, designs above and B-surfaces below).

Designs: a quartic one (that of :doc:`/line_plane`); a cubic one built as
in Section IV-B (zᵢ random, B-lines parallel to the y axis at
x = −(C₁z + C₆)/(C₄z + C₂), turned); the catalogue's ``5-spu``, quadratic:
zᵢ = δxᵢ with δ = 1/2 (eq. 26). :func:`classify.line_plane_pencil.family` names
each family with its margin; :func:`classify.figures.line_plane.draw_b_lines`
draws the B-lines; the B-surfaces are drawn here with :mod:`matplotlib` from
:func:`classify.line_plane_pencil.b_line`.
"""

# %%
import numpy as np
from matplotlib.figure import Figure

from classify.figures.line_plane import draw_b_lines
from classify.line_plane import b_line, b_point, design_from_mechanism, family, line_plane_design
from mechanisms import catalogue

# a quartic design (the one of the line-plane page) and the catalogue's, quadratic: zᵢ = xᵢ/2 (eq. 26)
quartic = line_plane_design([(0.1, 0.2), (1.3, -0.4), (-0.7, 1.1), (0.9, 1.6), (-1.2, -0.8)],
                            [0.3, -1.1, 0.6, 1.4, -0.2])
catalogue_design, _, _ = design_from_mechanism(catalogue.entry("5-spu").mechanism())
rng = np.random.default_rng(0)
heights = rng.normal(size=5)
c1, c2, c4, c6 = rng.normal(size=4)
across = -(c1 * heights + c6) / (c4 * heights + c2)
turn = np.array([[np.cos(0.7), -np.sin(0.7)], [np.sin(0.7), np.cos(0.7)]])
cubic = line_plane_design(np.column_stack([across, rng.normal(size=5)]) @ turn.T, heights)
quadratic = catalogue_design

figure = Figure(figsize=(14, 9.5), layout="constrained")
for index, (label, design) in enumerate((("quartic", quartic), ("cubic", cubic), ("quadratic", quadratic))):
    found = family(design)
    draw_b_lines(design, axes=figure.add_subplot(2, 3, index + 1),
                 title=f"Fig. 9: {label} design; found: {found.name}")
    point = b_point(design)
    print(f"{label}: family found {found.name} (degree {found.degree}, deciding margin {found.margin:.2e}); "
          f"B = {None if point is None else point.round(4).tolist()}")
    # the B-surface (13): the B-line B_z at height z, clipped to the design's box
    axes = figure.add_subplot(2, 3, index + 4, projection="3d")
    centre, half = design.base.mean(axis=0), 1.5 * np.max(np.abs(design.base - design.base.mean(axis=0)))
    for z in np.linspace(-2.0, 2.0, 41):
        a, b, c = b_line(design, z) / np.hypot(*b_line(design, z)[:2])
        # the line's points in the design's box (3-D axes do not clip)
        along = np.linspace(-4 * half, 4 * half, 400) + (centre @ [-b, a])
        xs, ys = -c * a - along * b, -c * b + along * a
        kept = (np.abs(xs - centre[0]) <= half) & (np.abs(ys - centre[1]) <= half)
        if kept.any():
            axes.plot(xs[kept], ys[kept], np.full(kept.sum(), z), color="tab:blue", linewidth=0.7)
    axes.scatter(design.base[:, 0], design.base[:, 1], design.platform, color="k")
    axes.set_xlim(centre[0] - half, centre[0] + half)
    axes.set_ylim(centre[1] - half, centre[1] + half)
    axes.set_xlabel("x")
    axes.set_ylabel("y")
    axes.set_zlabel("z")
    axes.set_title(f"Figs. 3, 9: the B-surface of the {label} design", fontsize=9)
