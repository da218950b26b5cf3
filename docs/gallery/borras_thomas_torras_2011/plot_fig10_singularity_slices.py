"""
Fig. 10: the singularity locus over the platform positions, as the orientation turns
====================================================================================

Borràs, Thomas & Torras 2011, Section IV and Fig. 10: for a fixed
orientation i = (u, v, w), the singularity locus (17) in the space of
positions (pₓ, p_y, p_z) is a surface; at each height p_z it is a line in
(pₓ, p_y). Going from the pole (0, 0, 1) towards the equator (u, v, 0), the
spiral-like surface of a quartic design flattens (top row); a cubic design
gives another topology (centre row); for the quadratic family each slice is
a plane (bottom row), with normal (δw, 0, 1 − δu) from eq. (33) in the
frame of eq. (26).

Designs: a quartic one (that of :doc:`/line_plane`), a cubic one built as in
Section IV-B, and the catalogue's ``5-spu`` (quadratic, δ = 1/2).
:func:`classify.figures.line_plane.locus_slice` gives the line at each
height; the surfaces are drawn here with :mod:`matplotlib`.
"""

# %%
import numpy as np
from matplotlib.figure import Figure

from classify.figures.line_plane import locus_slice
from classify.line_plane import design_from_mechanism, family, line_plane_design, singularity_polynomial
from mechanisms import catalogue

quartic = line_plane_design([(0.1, 0.2), (1.3, -0.4), (-0.7, 1.1), (0.9, 1.6), (-1.2, -0.8)],
                            [0.3, -1.1, 0.6, 1.4, -0.2])
rng = np.random.default_rng(0)
heights = rng.normal(size=5)
c1, c2, c4, c6 = rng.normal(size=4)
across = -(c1 * heights + c6) / (c4 * heights + c2)
turn = np.array([[np.cos(0.7), -np.sin(0.7)], [np.sin(0.7), np.cos(0.7)]])
cubic = line_plane_design(np.column_stack([across, rng.normal(size=5)]) @ turn.T, heights)
quadratic, _, _ = design_from_mechanism(catalogue.entry("5-spu").mechanism())

figure = Figure(figsize=(12, 12), layout="constrained")
for row, (label, design) in enumerate((("quartic", quartic), ("cubic", cubic), ("quadratic", quadratic))):
    print(f"{label} design: family found {family(design).name}")
    for column, tilt in enumerate((0.0, 0.6, 1.2)):
        direction = np.array([np.sin(tilt), 0.0, np.cos(tilt)])
        axes = figure.add_subplot(3, 3, 3 * row + column + 1, projection="3d")
        for height in np.linspace(0.2, 4.0, 20):
            a, b, c = locus_slice(design, direction, height)  # a² + b² = 1
            # the line's points in the box |p_x|, |p_y| ≤ 4 (3-D axes do not clip)
            along = np.linspace(-12.0, 12.0, 400)
            xs, ys = -c * a - along * b, -c * b + along * a
            kept = (np.abs(xs) <= 4.0) & (np.abs(ys) <= 4.0)
            if kept.any():
                axes.plot(xs[kept], ys[kept], np.full(kept.sum(), height), color="tab:red", linewidth=0.8)
        axes.set_xlim(-4, 4)
        axes.set_ylim(-4, 4)
        axes.set_zlim(0, 4)
        axes.set_xlabel("p_x")
        axes.set_ylabel("p_y")
        axes.set_zlabel("p_z")
        axes.set_title(f"{label}, i tilted {np.degrees(tilt):.0f}° from the pole", fontsize=9)

# %%
# The quadratic family: the slice is a plane; its normal against eq. (33) (δ = 1/2).
delta = 0.5
for direction in rng.normal(size=(3, 3)):
    direction = direction / np.linalg.norm(direction) * np.sign(direction[2])
    u, _, w = direction
    # three points of the locus: (17) is linear in p_x at fixed (p_y, p_z)
    points = []
    for p_y, p_z in ((0.0, 1.0), (1.0, 1.0), (0.0, 2.0)):
        constant = singularity_polynomial(quadratic, np.array([0.0, p_y, p_z]), direction)
        slope = singularity_polynomial(quadratic, np.array([1.0, p_y, p_z]), direction) - constant
        points.append([-constant / slope, p_y, p_z])
    points = np.array(points)
    normal = np.cross(points[1] - points[0], points[2] - points[0])
    normal /= np.linalg.norm(normal)
    stated = np.array([delta * w, 0.0, 1.0 - delta * u])
    stated /= np.linalg.norm(stated)
    print(f"i = {direction.round(3).tolist()}: locus plane normal {(normal * np.sign(normal[0])).round(6).tolist()}, "
          f"eq. (33): {(stated * np.sign(stated[0])).round(6).tolist()}")
