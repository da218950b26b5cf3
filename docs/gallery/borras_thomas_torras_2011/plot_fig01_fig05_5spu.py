"""
Figs. 1, 2 and 5: the 5-SPU, a regular and a singular pose
==========================================================

Borràs, Thomas & Torras 2011, Figs. 1-2: a 5-SPU parallel robot whose five
universal joints are aligned on the platform line Λ, the base attachments on
the plane Π; a tool on Λ spins freely. Fig. 5 and Section III-C: a pose is
singular iff the point A (19) where Λ meets Π lies on the B-line of its own
coordinate μ = −p_z/w along Λ.

The catalogue's ``5-spu`` (its design: base (0, 0), (2, 1), (−1, 2),
(1.5, −1.5), (−2, −1), platform z = 0, 1, −0.5, 0.75, −1 — quadratic,
zᵢ = xᵢ/2, eq. 26) at ``regular`` and
at ``eq33_second_factor``, classified by :func:`classify.classify` and read
by :func:`classify.line_plane_singularities.singularity_reading`. The paper's Fig. 5 poses
(p = (5, 8, 13), i = (1/3, −2/3, −2/3) and p = (7√6 − 7, 4, 14),
i = (√6/6, −√6/6, −√6/3)) belong to a design the text does not give; they
depend on it only through δ: for every quadratic design in normal form (26)
with δ = 1, (17) is −δ²wF[δwpₓ − (δu − 1)p_z] (33), whose second factor is
16/3 at the first pose and 0 at the second. They are reproduced below on such
a design (zᵢ = xᵢ, same base as the catalogue's), and in
``tests/classify/test_line_plane_frames.py``.

The catalogue's end-effector is the paper's axisymmetric tool (``output:
tool``: the point p and the direction i of Λ), which the free spin of the
platform about Λ does not move: the classifier counts that spin as an idle
freedom, so G has rank 5 on the 6-dimensional C-space at a regular pose and
drops below it exactly on the zero set of (17) (:doc:`/line_plane`, "The
tool and its spin").
"""

# %%
from matplotlib.figure import Figure

from classify import classify
from classify.figures.drawing import draw_mechanism
import numpy as np

from classify.line_plane import design_from_mechanism, line_plane_design, singularity_reading
from mechanisms import catalogue, configuration

entry = catalogue.entry("5-spu")
figure = Figure(figsize=(11, 5.5), layout="constrained")
for index, (name, where) in enumerate((("regular", "Figs. 1-2: a regular pose"),
                                       ("eq33_second_factor", "Fig. 5 (bottom): a singular pose"))):
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    report = classify(mechanism, point)
    design, position, direction = design_from_mechanism(mechanism)
    reading = singularity_reading(design, position, direction)
    draw_mechanism(mechanism, point, axes=figure.add_subplot(1, 2, index + 1, projection="3d"), title=where)
    print(f"{where} ({name}): p = {position.round(4).tolist()}, i = {direction.round(4).tolist()}")
    print(f"    Λ meets Π at A = {reading.intersection.round(4).tolist()}, μ = {reading.z:.4f}; "
          f"distance from A to B_μ = {reading.distance:.2e}; polynomial (17) margin {reading.margin:.2e} "
          f"-> {'singular' if reading.singular else 'regular'}")
    print(f"    classify: {', '.join(report.kinds) or 'regular'}; rank G {report.actuator.rank}/"
          f"{report.actuator.expected_rank}, idle freedoms {report.idle_freedoms} (the spin about Λ)")

# %%
# Fig. 5 on a quadratic design in normal form (26) with δ = 1: the factor δwpₓ − (δu − 1)p_z of (33) and the
# reading of (17).
x, y = np.array([0.0, 2.0, -1.0, 1.5, -2.0]), np.array([0.0, 1.0, 2.0, -1.5, -1.0])
delta_one = line_plane_design(np.column_stack([x, y]), x)
root6 = np.sqrt(6.0)
for where, position, direction in (("Fig. 5 (top)", (5.0, 8.0, 13.0), (1 / 3, -2 / 3, -2 / 3)),
                                   ("Fig. 5 (bottom)", (7 * root6 - 7, 4.0, 14.0),
                                    (root6 / 6, -root6 / 6, -root6 / 3))):
    reading = singularity_reading(delta_one, position, direction)
    factor = direction[2] * position[0] - (direction[0] - 1.0) * position[2]
    print(f"{where}: p = {np.round(position, 4).tolist()}, i = {np.round(direction, 4).tolist()}: (33) factor "
          f"{factor:.3g}; margin {reading.margin:.2e} -> {'singular' if reading.singular else 'regular'}")
