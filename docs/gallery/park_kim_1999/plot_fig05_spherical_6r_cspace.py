"""
Fig. 5: a configuration-space singularity of a spherical 6R linkage
===================================================================

Park & Kim 1999, Fig. 5 (Section 3, Case 1): a spherical 6R closed loop —
six revolute joints whose axes all pass through one point — at a
configuration-space singularity. For a spherical loop the closure Φ has
three (angular) rows and the i-th column of DΦ is the i-th joint's axis, so
DΦ has rank 3 unless the six axes lie in one plane; there its rank is 2 and
the tangent space of M is no longer three-dimensional.

The paper gives no dimensions for Fig. 5. **The dimensions here are this
script's own**: a spherical mechanism (the file format's ``space:
spherical``, built with :func:`mechanisms.io.mechanism_from_dict`) whose home
has its six axes in the equatorial plane, at 0°, 30°, 75°, 110°, 150° and 200°
of longitude, joints 1, 3 and 5 actuated. It is classified at home by
:func:`classify.classify` and drawn on the unit sphere by
:func:`classify.figures.drawing.draw_mechanism` (the purple arrows: the lost
directions, ker DΦ beyond the tangent space); for contrast, a regular
configuration nearby (home moved by 0.6 and 0.4 rad at joints 1 and 2, then
projected onto M by :func:`manifold.project`).
"""

# %%
import numpy as np
from matplotlib.figure import Figure

from classify import classify, model_of
from classify.figures.drawing import draw_mechanism
from manifold import project
from mechanisms import configuration
from mechanisms.io import mechanism_from_dict

LONGITUDES = np.radians([0, 30, 75, 110, 150, 200])  # the script's own choice: the paper gives none
LINKS = ("ground", "link1", "link2", "link3", "link4", "link5", "ground")
joints = [{"name": f"J{index + 1}", "type": "R", "links": [LINKS[index], LINKS[index + 1]],
           "axis": [float(np.cos(longitude)), float(np.sin(longitude)), 0.0], "actuated": index in (0, 2, 4)}
          for index, longitude in enumerate(LONGITUDES)]
mechanism = mechanism_from_dict({"name": "spherical 6R, coplanar axes", "space": "spherical", "joints": joints})

home = configuration(mechanism).point
nearby = project(model_of(mechanism).manifold, home + np.array([0.6, 0.4, 0, 0, 0, 0]))
reports = {"coplanar axes (home)": (home, classify(mechanism, home)),
           "regular, nearby": (nearby, classify(mechanism, nearby))}

figure = Figure(figsize=(10, 5), layout="constrained")
for index, (name, (point, report)) in enumerate(reports.items()):
    found = report.label
    draw_mechanism(mechanism, point, report=report, axes=figure.add_subplot(1, 2, index + 1, projection="3d"),
                   title=f"{name}: {found}\nrank DΦ {report.cspace.rank}/{report.cspace.expected_rank}")
figure.suptitle("Park & Kim 1999 Fig. 5 (dimensions: this script's own)", fontsize=10)

for name, (point, report) in reports.items():
    kept, dropped = report.cspace.decision.margin
    values = ", ".join(f"{value:.3g}" for value in report.cspace.decision.singular_values)
    joint_values = ", ".join(f"{value:+.4f}" for value in point)
    print(f"{name}: joints ({joint_values}) rad from home")
    print(f"  rank DΦ {report.cspace.rank} of {report.cspace.expected_rank}; singular values {values}; "
          f"margin: smallest kept {kept:.3g}, largest dropped {dropped if dropped is None else f'{dropped:.3g}'}, "
          f"cut {report.cspace.decision.tolerance:.1e}; singular kinds: {', '.join(report.kinds) or 'none'}")
print("paper: Fig. 5 shows a configuration-space singularity of a spherical 6R linkage (no dimensions given); "
      "found: all six axes coplanar gives rank DΦ 2 of 3, the nearby configuration rank 3")
