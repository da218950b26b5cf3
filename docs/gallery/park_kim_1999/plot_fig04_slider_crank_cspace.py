"""
Fig. 4: the slider-crank's joint-space curve, two branches crossing
===================================================================

Park & Kim 1999, Fig. 4 (and Fig. 3a): the joint configuration manifold of a
slider-crank with crank and coupler of equal length, projected onto the
(θ, ϕ) plane — θ the crank, ϕ the revolute joint at the slider (``wrist``).
M is a curve; its C-space singularities are the points where the curve
crosses itself: the two assembly branches meet where crank and coupler fold
onto each other, θ = ±π/2 (Fig. 3a). Gosselin & Angeles 1990, eq. (17), name
the two branches: x = 0 (the constant branch, Fig. 4 of their paper) and
x = 2R cos θ.

:func:`classify.loci.trace_loci` follows M's branches from sampled points and
keeps the sign changes of the actuator and end-effector functions that
:func:`classify.classify` confirms C-space singular;
:func:`classify.figures.loci.draw_cspace_map` draws them. Coordinates are
displacements from the catalogue configuration ``fig3a_self_intersection``
(θ = π/2, ϕ = 0): displacement 0 is θ = π/2, displacement π is θ = −π/2.

The second figure is the default design (crank R = 2, coupler l = 1, Figs.
3b-c): a single closed curve, on which the actuator singularities
(sin θ = ±l/R, Fig. 3b) and the end-effector dead centres (θ = 0, π, Fig. 3c)
are found: four of each, two per branch.
"""

# %%
import numpy as np
from matplotlib.figure import Figure

from classify.figures.loci import draw_cspace_map
from classify.loci import locus_coordinates, trace_loci
from mechanisms import catalogue, configuration

entry = catalogue.entry("slider-crank")
figure = Figure(figsize=(5.5, 5), layout="constrained")

equal = entry.mechanism("fig3a_self_intersection")
columns = [equal.coordinate_names.index("crank"), equal.coordinate_names.index("wrist")]
loci = trace_loci(equal, configuration(equal).point, kinds=("cspace",), rng=np.random.default_rng(0))
draw_cspace_map(equal, loci, columns, axes=figure.add_subplot(),
                title="R = l: M and its branch points (Fig. 4)")
home_theta = entry.configurations["fig3a_self_intersection"]["theta"]
print(f"R = l: {loci.coverage['branches']} branches, closed: {loci.coverage['branches_closed']}")
for piece in loci.pieces:
    values, _ = locus_coordinates(equal, piece.points, columns)
    theta = np.angle(np.exp(1j * (values[0, 0] + home_theta)))
    print(f"    branch point (C-space singular): θ = {theta:+.6f} rad (paper: ±π/2 = ±{np.pi / 2:.6f})")

# %%
# traced from a regular configuration (θ = 0.3, the catalogue's default)
default = entry.mechanism()
home_theta = entry.parameters["theta"]
loci = trace_loci(default, configuration(default).point, kinds=("actuator", "end_effector"),
                  rng=np.random.default_rng(0))
second = draw_cspace_map(default, loci, columns, title="R = 2, l = 1: actuator and end-effector points")
print(f"R = 2, l = 1: {loci.coverage['branches']} branch(es), closed: {loci.coverage['branches_closed']}")
for piece in loci.pieces:
    values, _ = locus_coordinates(default, piece.points, columns)
    theta = np.angle(np.exp(1j * (values[0, 0] + home_theta)))
    print(f"    {piece.kind}: θ = {theta:+.6f} rad, sin θ = {np.sin(theta):+.6f}")
print("paper: actuator at sin θ = ±l/R = ±0.5 (Fig. 3b; Gosselin & Angeles eq. 14), "
      "end-effector at θ = 0, π (Fig. 3c)")
