"""
Fig. 11: the sphere of orientations at eight positions, and its four components
===============================================================================

Borràs, Thomas & Torras 2011, Section V-C, eq. (36) and Fig. 11: for the
quadratic family in the frame of eq. (26), the singularity locus in
ℝ³ × S² is two hypersurfaces, w = 0 and w pₓ − (u − 1/δ) p_z = 0; p_y and v
do not enter. Fig. 11 draws, for δ = 1 and eight positions around the
origin of the (pₓ, p_z) plane, the sphere of orientations projected along v
(a disk in (u, w)), coloured by the side of each hypersurface: the four
colours are the four connected components of the non-singular C-space.

Here the colours come from the package: the sign of w and the sign of the
singularity polynomial (17) (:func:`classify.line_plane_singularities.singularity_polynomial`)
of the quadratic design zᵢ = xᵢ (δ = 1) on the catalogue's base. Printed: how
far the polynomial is from the closed form −δ²wF[δwpₓ − (δu − 1)p_z] (33) on
the disks, F the determinant (28).
"""

# %%
import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure

from classify.line_plane import cofactors, design_from_mechanism, line_plane_design, singularity_polynomial
from mechanisms import catalogue

base, _, _ = design_from_mechanism(catalogue.entry("5-spu").mechanism())
delta = 1.0
design = line_plane_design(base.base, delta * base.base[:, 0])
F = cofactors(design)[0] / delta ** 2  # C₁ = δ²F (eq. 27)

u, w = np.meshgrid(np.linspace(-1, 1, 121), np.linspace(-1, 1, 121), indexing="xy")
inside = u ** 2 + w ** 2 < 1.0
v = np.sqrt(np.where(inside, 1.0 - u ** 2 - w ** 2, 0.0))  # the front half; (17) does not depend on v here
directions = np.stack([u, v, w], axis=-1)
colours = ListedColormap(["#f2d541", "#e07b39", "#3b7dd8", "#5bb55b"])
figure = Figure(figsize=(7, 7))
largest = 0.0
for index in range(8):
    angle = index * np.pi / 4
    position = np.array([np.cos(angle), 0.0, np.sin(angle)])  # (p_x, p_y, p_z) on the unit circle
    values = singularity_polynomial(design, np.broadcast_to(position, directions.shape), directions)
    closed = -delta ** 2 * w * F * (delta * w * position[0] - (delta * u - 1.0) * position[2])
    largest = max(largest, float(np.max(np.abs(values - closed)[inside]) / np.max(np.abs(closed)[inside])))
    pattern = 2 * (w > 0) + (values > 0)  # four sign patterns of (w, second factor), up to the factor's sign
    axes = figure.add_axes([0.41 + 0.36 * np.cos(angle), 0.41 + 0.36 * np.sin(angle), 0.18, 0.18])
    axes.imshow(np.ma.masked_where(~inside, pattern), origin="lower", extent=(-1, 1, -1, 1), cmap=colours,
                vmin=0, vmax=3)
    axes.set_axis_off()
    axes.set_title(f"(p_x, p_z) at {np.degrees(angle):.0f}°", fontsize=7)
figure.text(0.5, 0.5, "Fig. 11\nδ = 1\ndisks in (u, w)\naround the origin\nof (p_x, p_z)", ha="center",
            va="center", fontsize=9)
print(f"F = {F:.6g} (eq. 28); largest relative difference between (17) and eq. (33) on the disks: {largest:.1e}")
