"""
Fig. 12: the planar six-bar — an end-effector singularity removed by relocating the end-effector
================================================================================================

Park & Kim 1999, Fig. 12 (Section 3, Case 3): a planar 6R loop of six equal
links. (a) The end-effector frame on a link that, in this configuration,
cannot translate along itself, whichever joints are actuated: an end-effector
singularity (position only). (b) The same configuration with the end-effector
on the adjacent link: regular.

The catalogue's ``planar-six-bar`` at ``fig12a_end_effector`` and
``fig12b_relocated`` (end-effector on link 2, then link 3).
"""

# %%
from matplotlib.figure import Figure

from classify import classify
from classify.figures.drawing import draw_mechanism
from mechanisms import catalogue, configuration

entry = catalogue.entry("planar-six-bar")
stated = {"fig12a_end_effector": ("12a", "end-effector"), "fig12b_relocated": ("12b", "regular")}
figure = Figure(figsize=(10, 5), layout="constrained")
for index, (name, (number, paper)) in enumerate(stated.items()):
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    report = classify(mechanism, point)
    found = report.label
    draw_mechanism(mechanism, point, report=report, axes=figure.add_subplot(1, 2, index + 1),
                   title=f"Fig. {number}: {found}")
    print(f"Fig. {number} ({name}): paper: {paper};  found: {found}; "
          f"rank J {report.end_effector.rank}/{report.end_effector.expected_rank}")
