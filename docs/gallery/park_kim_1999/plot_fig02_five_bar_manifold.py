"""
Fig. 2: the 5R linkage's configuration space over (x₁, x₂, x₅), front and rear views
====================================================================================

Park & Kim 1999, Fig. 2 (Section 3, Cases 1-2, Figs. 1 and 6): the
two-dimensional configuration space M of the planar 5R linkage of Fig. 1
(base 2, four links of length 1), projected onto the x₁–x₂–x₅ subspace. The
paper marks its C-space singularities — C and D (Fig. 1a: the same physical
configuration, where the manifold wraps around), E (Fig. 1c), F and G
(Fig. 1d), H (Fig. 1b, on the half not drawn) — the ridges of nondegenerate
actuator singularities A→D and B→C (B is Fig. 6a), and the line through F, E
and H of degenerate actuator singularities (a self-motion: x₁ and x₅ fixed).

Here the catalogue's ``five-bar`` at Park & Kim's Fig. 1 design, started at
``fig6a_distal_aligned``, is sampled by
:func:`classify.loci.trace_loci` on two assembly branches (grey points: the
assembled grid), which also traces the actuator locus (red: nondegenerate,
orange: degenerate, by :func:`classify.classify_many`'s second-order test)
and searches for C-space singularities (purple, labelled with the Fig. 1
configuration each one is). x_i is the angle at joint i between the link
entering it and the link leaving it, going round the loop A, C, P, D, B
(joints numbered 1-5 as in the paper, from the left base joint), computed
from the joint places; angles are taken in [−π/2, 3π/2), so that the collinear values 0
and π lie inside the box and the torus-like surface is cut open at −π/2.
"""

# %%
import numpy as np
from matplotlib.figure import Figure

from classify import classify, classify_many
from classify.figures.drawing import joint_places
from classify.loci import trace_loci
from mechanisms import catalogue, configuration

entry = catalogue.entry("five-bar")
mechanism = entry.mechanism("fig6a_distal_aligned")
LOOP = ("A", "C", "P", "D", "B")  # x1 ... x5, the paper's numbering


def loop_angles(mechanism, points):
    """x₁ … x₅: the turning angle at each joint of the loop A, C, P, D, B (and back to A), in [−π/2, 3π/2), [n, 5]."""
    places = joint_places(mechanism, np.atleast_2d(points))
    corners = [places[name] for name in LOOP]
    edges = [corners[(index + 1) % 5] - corners[index] for index in range(5)]  # A→C, C→P, P→D, D→B, B→A
    headings = np.stack([np.arctan2(edge[:, 1], edge[:, 0]) for edge in edges], axis=1)
    turns = headings - np.roll(headings, 1, axis=1)  # at joint i: from the edge entering to the edge leaving
    return np.mod(turns + np.pi / 2, 2 * np.pi) - np.pi / 2  # in [−π/2, 3π/2): 0 and π inside


loci = trace_loci(mechanism, configuration(mechanism).point, kinds=("actuator", "cspace"),
                  assembly_branches=2, counts=(20, 20))
samples = loop_angles(mechanism, loci.samples)[:, [0, 1, 4]]
actuator = [piece for piece in loci.pieces if piece.kind == "actuator"]
cspace = [piece.points[0] for piece in loci.pieces if piece.kind == "cspace"]
degenerate = [bool((classify_many(mechanism, piece.points).degenerate == 1).all()) for piece in actuator]

# which Fig. 1 configuration each C-space point is: the same joint places, to 1e-6
paper_letters = {"a": "C, D", "b": "H", "c": "E", "d": "F, G"}
references = {}
for panel in "abcd":
    other = entry.mechanism(f"fig1{panel}_collinear")
    references[panel] = joint_places(other, configuration(other).point[None])
names = []
for point in cspace:
    places = joint_places(mechanism, point[None])
    match = [panel for panel, reference in references.items()
             if max(np.abs(places[name] - reference[name]).max() for name in LOOP) < 1e-6]
    names.append(match[0] if match else None)

figure = Figure(figsize=(11, 5.2), layout="constrained")
for index, (view, azimuth) in enumerate((("front", -60), ("rear", 120))):
    axes = figure.add_subplot(1, 2, index + 1, projection="3d")
    axes.scatter(*samples.T, s=6, color="0.45", alpha=0.6)
    for piece, self_motion in zip(actuator, degenerate):
        angles = loop_angles(mechanism, piece.points)[:, [0, 1, 4]]
        axes.scatter(*angles.T, s=6, color="tab:orange" if self_motion else "tab:red")
    for point, panel in zip(cspace, names):
        report = classify(mechanism, point)
        x1, x2, x5 = loop_angles(mechanism, point)[0, [0, 1, 4]]
        axes.scatter([x1], [x2], [x5], s=50, color="tab:purple", depthshade=False)
        label = f"Fig. 1{panel} ({paper_letters[panel]})" if panel else "?"
        axes.text(x1, x2, x5, f"  {label}: {', '.join(report.kinds)}", fontsize=7)
    axes.view_init(elev=25, azim=azimuth)
    axes.set(xlabel="x₁", ylabel="x₂", zlabel="x₅", title=f"{view} view")
figure.suptitle("Park & Kim 1999 Fig. 2: M of the 5R linkage over (x₁, x₂, x₅); red: nondegenerate, "
                "orange: degenerate actuator singularities", fontsize=9)

print(f"M sampled: {len(loci.samples)} points on {loci.coverage['assembly_branches']['found']} assembly branches")
for point, panel in zip(cspace, names):
    values = ", ".join(f"x{number}={value:+.6f}" for number, value in zip(range(1, 6), loop_angles(mechanism, point)[0]))
    stated = f"Fig. 1{panel}, points {paper_letters[panel]}" if panel else "no Fig. 1 configuration"
    print(f"C-space singular point: {values}  -> {stated} (joint places within 1e-6); "
          f"rank DΦ {classify(mechanism, point).cspace.rank}/3")
print(f"paper: four C-space singular configurations (Fig. 1a-d); found {len(cspace)}, "
      f"matching {sorted(panel for panel in names if panel)}")
print(f"actuator-locus pieces: {len(actuator)} "
      f"({sum(degenerate)} degenerate, {len(actuator) - sum(degenerate)} nondegenerate)")
for piece, self_motion in zip(actuator, degenerate):
    angles = loop_angles(mechanism, piece.points)[:, [0, 4]]
    spread = np.abs(np.angle(np.exp(1j * (angles - angles[0])))).max(axis=0)  # around the circle
    print(f"  {len(piece.points):3d} points, closed={piece.closed}, "
          f"{'degenerate' if self_motion else 'nondegenerate'}; largest change of (x₁, x₅) along it: "
          f"({spread[0]:.2g}, {spread[1]:.2g})")
for piece, self_motion in zip(actuator, degenerate):
    if self_motion:
        line = loop_angles(mechanism, piece.points[:1])[0, [0, 4]]
        on = [f"Fig. 1{panel}" for point, panel in zip(cspace, names)
              if np.abs(np.angle(np.exp(1j * (loop_angles(mechanism, point)[0, [0, 4]] - line)))).max() < 1e-4]  # the traced points hold x₁, x₅ to ~1e-5
        print(f"degenerate line at (x₁, x₅) = ({line[0]:.6f}, {line[1]:.6f}) passes (to 1e-4) through: {', '.join(on)}")
print("paper: the degenerate actuator singularities lie on one line (F, E, H: Figs. 1d, 1c, 1b) that projects to a single point "
      "of the x₁–x₅ plane (a self-motion); the nondegenerate ones form the ridges A→D and B→C")

# %%
# Found: the four C-space singularities of Fig. 1 (each matched by its joint
# places to 1e-6), nondegenerate actuator-locus pieces running into them (the
# paper's ridges), and one closed piece of degenerate actuator singularities
# along which x₁ and x₅ stay fixed — the self-motion (the elbows C and D
# coincide at the middle of the base and P turns about them). That line
# passes through Fig. 1c (E) and Fig. 1d (F, G), but not through Fig. 1b:
# with base 2 and links 1, Fig. 1b has its elbows at (−1, 0) and (1, 0),
# which do not coincide, so it has no self-motion — the paper's "line through
# F, E and H" is not what this design gives for H.
