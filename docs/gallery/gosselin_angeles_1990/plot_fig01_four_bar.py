"""
Fig. 1: a four-bar linkage degenerating — a singularity of the third kind
=========================================================================

Gosselin & Angeles 1990, Section II and Fig. 1: the third kind of
singularity needs special linkage parameters; the chain then reaches
configurations where the input-output relation F(θ, φ) = 0 degenerates —
two branches of the direct kinematic problem cross, and both A = ∂F/∂φ and
B = ∂F/∂θ vanish there (at a node of the curve F = 0 both partial
derivatives vanish).

The paper gives no dimensions for its four-bar. Here: a parallelogram
linkage, crank = rocker = 1, coupler = ground = 2, written in the
mechanism file format and read by :func:`mechanisms.io.loads` (the catalogue
has no four-bar). Folded flat (all links on the ground line), its
parallelogram and anti-parallelogram branches cross. The first figure draws
the folded configuration and one of each branch; the second the C-space
(1-dof) in the joint angles (A, B) by :func:`classify.loci.trace_loci` with
its branch points, as :func:`classify.figures.loci.draw_cspace_map` draws
it.

Printed: Park & Kim find a C-space singularity at the fold; the G–A
matrices derived from the mechanism (:func:`classify.comparison.compare`)
are undefined there — the velocities the linkage allows span two
dimensions, one per branch — which is the degeneracy the paper's third kind
describes (A = B = 0 for any F).
"""

# %%
import numpy as np
from matplotlib.figure import Figure

from classify import classify
from classify.comparison import compare
from classify.figures.drawing import draw_mechanism
from classify.figures.loci import draw_cspace_map
from classify.loci import locus_coordinates, trace_loci
from mechanisms import configuration
from mechanisms.io import loads

FOUR_BAR = """
name: parallelogram four-bar
space: planar
joints:
- {name: A, type: R, links: [ground, crank], point: [0.0, 0.0], actuated: true}
- {name: C, type: R, links: [crank, coupler], point: [1.0, 0.0]}
- {name: D, type: R, links: [coupler, rocker], point: [3.0, 0.0]}
- {name: B, type: R, links: [rocker, ground], point: [2.0, 0.0]}
end_effector: {link: rocker, output: orientation}
"""
mechanism = loads(FOUR_BAR).mechanism
folded = configuration(mechanism).point  # the home: folded flat
parallelogram = configuration(mechanism, {"A": 0.8, "C": -0.8, "D": 0.8, "B": -0.8}).point
# M's branches, followed from sampled points; on each, the configuration with the crank nearest 0.8
loci = trace_loci(mechanism, parallelogram, kinds=("cspace",), rng=np.random.default_rng(0))
crank = mechanism.coordinate_names.index("A")
nearest = [branch.points[np.argmin(np.abs(np.angle(np.exp(1j * (branch.points[:, crank] - 0.8)))))]
           for branch in loci.branches]
anti = max(nearest, key=lambda point: np.linalg.norm(point - parallelogram))  # the other branch's
figure = Figure(figsize=(13, 4.5), layout="constrained")
for index, (label, point) in enumerate((("folded flat", folded), ("parallelogram branch", parallelogram),
                                        ("anti-parallelogram branch", anti))):
    report = classify(mechanism, point)
    row = compare(mechanism, point[None], labels=[label]).rows[0]
    draw_mechanism(mechanism, point, report=report, axes=figure.add_subplot(1, 3, index + 1),
                   title=f"Fig. 1, {label}: {', '.join(report.kinds) or 'regular'}")
    print(f"{label}: Park & Kim {', '.join(report.kinds) or 'regular'}; G-A (derived) "
          f"{row.gosselin_angeles.label}" + (f" — {row.gosselin_angeles.detail}" if row.gosselin_angeles.detail
                                              else ""))
print("paper: third kind at the degenerate configuration (Fig. 1)")

# %%
columns = [mechanism.coordinate_names.index("A"), mechanism.coordinate_names.index("B")]
branches = draw_cspace_map(mechanism, loci, columns, title="the four-bar's C-space: two branches crossing")
print(f"{loci.coverage['branches']} branches, closed: {loci.coverage['branches_closed']}")
for piece in loci.pieces:
    values, _ = locus_coordinates(mechanism, piece.points, columns)
    print(f"branch point: crank A = {np.angle(np.exp(1j * values[0, 0])):+.6f} rad "
          f"(folded flat: 0 and ±π)")
