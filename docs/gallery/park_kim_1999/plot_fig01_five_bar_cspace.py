"""
Fig. 1: the 5R linkage's four configuration-space singularities
===============================================================

Park & Kim 1999, Fig. 1 and eq. (8) (Section 3, Case 1): a planar five-bar
(5R) with base 2 and four links of length 1 reaches four configurations where
all its links are collinear — stretched (a), folded back (b), and the two
folded-over ones (c), (d). There the rank of ∇Φ (eq. 8) drops below 3: the
tangent space of M is no longer two-dimensional.

The catalogue's ``five-bar`` at ``fig1a_collinear`` ... ``fig1d_collinear``,
classified by :func:`classify.classify`; the purple arrows are the lost
directions (ker DΦ beyond the tangent space).
"""

# %%
from matplotlib.figure import Figure

from classify import classify
from classify.figures.drawing import draw_mechanism
from mechanisms import catalogue, configuration

entry = catalogue.entry("five-bar")
figure = Figure(figsize=(10, 7), layout="constrained")
for index, panel in enumerate("abcd"):
    name = f"fig1{panel}_collinear"
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    report = classify(mechanism, point)
    found = report.label
    draw_mechanism(mechanism, point, report=report, axes=figure.add_subplot(2, 2, index + 1),
                   title=f"Fig. 1{panel}: {found}")
    print(f"Fig. 1{panel} ({name}): paper: rank ∇Φ < 3 (C-space singular); found: rank DΦ "
          f"{report.cspace.rank}/{report.cspace.expected_rank}, singular kinds: {found}")

# %%
# The four are C-space singularities, as the paper states. The end-effector
# (the joint between the two distal links) is singular there too: with all
# links collinear it cannot move along them to first order — the paper does
# not discuss it.
