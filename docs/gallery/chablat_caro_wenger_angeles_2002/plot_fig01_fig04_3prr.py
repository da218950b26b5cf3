"""
Figs. 1-4: the 3-PRR, its parallel and serial singularities, an isotropic configuration
=======================================================================================

Chablat, Caro, Wenger & Angeles 2002: the planar 3-PRR (Fig. 1; three
actuated prismatic joints on the sides of the base triangle, r = 100 mm,
R = 200 mm, l = 200 mm), the velocity relation A t = B ρ̇ (eqs. 3-4).

* Fig. 2, parallel singularity (A singular, §2.2): the three legs' lines
  concurrent, or all parallel.
* Fig. 3, serial singularity (B singular, §2.3): a leg orthogonal to its rail.
* Fig. 4a, isotropy (§3.4): κ(J̄) = 1 with L = √2 r (γ = π/2), at
  x = y = 0, φ = π/3 (the catalogue's default).

The catalogue's ``3-prr`` at ``fig4a_isotropic`` (Figs. 1, 4a),
``fig2_concurrent_at_centre``, ``fig2_parallel_legs`` and
``fig3_serial_leg1``, classified by :func:`classify.classify`; κ of the
normalised Jacobian from :func:`classify.conditioning.mechanism_condition_numbers`.
"""

# %%
import math

from matplotlib.figure import Figure

from classify import classify
from classify.conditioning import mechanism_condition_numbers
from classify.figures.drawing import draw_mechanism
from mechanisms import catalogue, configuration

entry = catalogue.entry("3-prr")
stated = {"fig4a_isotropic": ("Figs. 1, 4a", "regular, isotropic: κ(J̄) = 1"),
          "fig2_concurrent_at_centre": ("Fig. 2, concurrent", "parallel (A singular)"),
          "fig2_parallel_legs": ("Fig. 2, parallel", "parallel (A singular)"),
          "fig3_serial_leg1": ("Fig. 3", "serial (B singular)")}
figure = Figure(figsize=(10, 9), layout="constrained")
for index, (name, (where, paper)) in enumerate(stated.items()):
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    report = classify(mechanism, point)
    found = report.label
    draw_mechanism(mechanism, point, report=report, axes=figure.add_subplot(2, 2, index + 1),
                   title=f"{where}: {found}")
    print(f"{where} ({name}): paper: {paper};  found: {found} (Park & Kim: actuator = parallel, "
          f"end-effector = serial)")

# %%
isotropic = entry.mechanism("fig4a_isotropic")
numbers = mechanism_condition_numbers(isotropic, configuration(isotropic).point[None],
                                      length=math.sqrt(2.0) * 100.0)
print(f"Fig. 4a with L = √2 r = {math.sqrt(2.0) * 100.0:.3f} mm: 1/κ(J̄) = {numbers.inverse('A-1B')[0]:.12f} "
      f"(paper: κ = 1)")
