"""
Figs. 2 and 4, eqs. 3 and 9: the five-bar's singularity loci and working modes in the joint space
=================================================================================================

Chablat, Wenger & Angeles 1998, eqs. (3b), (3c), (9) and §3.3 (the boundaries
of the working modes of Fig. 2, drawn in the actuated joint space as in
Fig. 4): the direct-kinematics matrix A is singular where the distal links
are aligned, sin(θ₃ − θ₄) = 0 (eq. 9, κ(A) infinite: the actuator locus of
Park & Kim); the inverse-kinematics matrix B = L₁L₂ diag(sin(θ₃ − θ₁),
sin(θ₄ − θ₂)) (eq. 3c) where a leg is stretched or folded (the end-effector
locus, the boundaries between working modes).

:func:`classify.loci.trace_loci` assembles a grid over the actuated angles
(θ₁, θ₂) on one assembly branch, seeds the loci where the sign functions
change sign, refines them by Gauss-Newton and follows them by continuation;
every traced point is confirmed singular by :func:`classify.classify`.
:func:`classify.figures.loci.draw_cspace_map` colours the grid points by the
signs of the two determinants (the assembly and working modes) and overlays
the loci. Coordinates: displacements of A and B from the catalogue's default
configuration (θ₁ = 1.8, θ₂ = 1.3). Printed: at every traced point, the
closed forms of eqs. 9 and 3c, computed from the joint positions.
"""

# %%
import numpy as np

from classify.figures.drawing import joint_places
from classify.figures.loci import draw_cspace_map
from classify.loci import trace_loci
from mechanisms import catalogue, configuration

mechanism = catalogue.entry("five-bar").mechanism()
columns = [mechanism.coordinate_names.index("A"), mechanism.coordinate_names.index("B")]
loci = trace_loci(mechanism, configuration(mechanism).point, columns=columns, counts=(24, 24),
                  kinds=("actuator", "end_effector"))
figure = draw_cspace_map(mechanism, loci, columns, title="five-bar: loci over (θ1, θ2), one assembly branch")
coverage = loci.coverage
print(f"grid {coverage['grid_points']} points, {coverage['reached']} on the branch; pieces: {coverage['pieces']}, "
      f"closed: {coverage['closed']}; unconfirmed points dropped: {coverage['unconfirmed']}")


def angle(vector):
    return np.arctan2(vector[..., 1], vector[..., 0])


for piece in loci.pieces:
    places = joint_places(mechanism, piece.points)
    theta1, theta2 = angle(places["C"] - places["A"]), angle(places["D"] - places["B"])
    theta3, theta4 = angle(places["P"] - places["C"]), angle(places["P"] - places["D"])
    if piece.kind == "actuator":
        print(f"actuator piece, {len(piece.points)} points: max |sin(θ3 − θ4)| = "
              f"{np.max(np.abs(np.sin(theta3 - theta4))):.1e} (eq. 9: 0)")
    else:
        legs = np.minimum(np.abs(np.sin(theta3 - theta1)), np.abs(np.sin(theta4 - theta2)))
        print(f"end-effector piece, {len(piece.points)} points: max min(|sin(θ3 − θ1)|, |sin(θ4 − θ2)|) = "
              f"{np.max(legs):.1e} (eq. 3c: 0)")
