"""
Figs. 10-12: the Gough-Stewart platform
=======================================

Gosselin & Angeles 1990, Section VII, eqs. (71)-(87): a spatial 6-dof
parallel manipulator (Fig. 10), its leg attachments on circles of radii R_B
on the base (Fig. 11, eqs. 71-72) and R_P on the platform (Fig. 12,
eqs. 73-74), at angles ±φ_B, ±φ_P about 0, 2π/3, 4π/3. A has rows
[wᵢᵀ, ((Q pᵢ′) × wᵢ)ᵀ] (eqs. 81-82), B = diag(cᵢ) (eq. 83).

* First kind (eq. 84): a leg of zero length.
* Second kind: A singular — an open question in the paper; the platform
  rotated by ±90° about the vertical (Fichter, their ref. [28]) is one.
* Third kind (eq. 87): R_P = R_B and θ = η: all legs parallel, the platform
  translates with the legs locked.

The catalogue's ``gough-stewart`` at its default (Fig. 10),
``eq84_leg1_zero_length``, ``fichter_rotated_plus_90`` and
``eq87_parallel_legs``. A and B are the paper's
(:func:`classify.gosselin_angeles_examples.gough_stewart.eq81_relation`) for
the default design; for the design of eq. (87) (R_P = R_B, θ = η) they are
derived from the mechanism (:func:`classify.comparison.compare` without a
relation), which spares the build a second symbolic relation.
Two differences with the paper's words, both printed below. At eq. (84)
the paper names the first kind (B = diag(cᵢ) singular); its own A (eq. 82)
has the row wᵢ = cᵢeᵢ = 0 there too, so A is singular as well and the code
reports kinds I, II, III. At eq. (87) the paper calls the design's motion a
third-kind singularity, but B = diag(cᵢ) is regular there: A alone is
singular, kind II at every configuration (Park & Kim: an architecture
singularity, a locked-actuator freedom at every configuration of M).

The second figure puts the attachment points of the default design on their
circles, as Figs. 11-12 do.
"""

# %%
from matplotlib.figure import Figure

from classify.comparison import compare
from classify.figures.drawing import draw_mechanism, joint_places
from classify.gosselin_angeles_examples.gough_stewart import eq81_relation
from mechanisms import catalogue, configuration

entry = catalogue.entry("gough-stewart")
stated = {None: ("Fig. 10", "regular"),
          "eq84_leg1_zero_length": ("eq. 84", "I (B singular)"),
          "fichter_rotated_plus_90": ("Fichter ±90°", "II"),
          "eq87_parallel_legs": ("eq. 87", "III (moves with the legs locked)")}
figure = Figure(figsize=(10, 9), layout="constrained")
for index, (name, (where, paper)) in enumerate(stated.items()):
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    if name == "eq87_parallel_legs":  # another design: A and B derived from the mechanism
        row = compare(mechanism, point[None], labels=[name]).rows[0]
    else:
        relation, coordinates = eq81_relation(mechanism)
        row = compare(mechanism, point[None], labels=[name or "default"], relation=relation,
                      coordinates=coordinates).rows[0]
    found = row.gosselin_angeles.label
    draw_mechanism(mechanism, point, report=row.park_kim,
                   axes=figure.add_subplot(2, 2, index + 1, projection="3d"), title=f"{where}: G-A {found}")
    print(f"{where} ({name or 'default'}): paper: {paper};  found: G-A {found} "
          f"(rank A {row.gosselin_angeles.rank_A}, rank B {row.gosselin_angeles.rank_B}), "
          f"Park & Kim {', '.join(row.park_kim.kinds) or 'regular'}"
          + (f"; {row.park_kim.notes[0]}" if row.park_kim.notes else ""))

# %%
# Figs. 11-12: the attachment points on the base (U joints) and the platform
# (S joints), in the base frame and in the platform's frame at home.
import numpy as np

mechanism = entry.mechanism()
values = entry.values(None)
places = joint_places(mechanism, configuration(mechanism).point[None])
attachments = Figure(figsize=(9, 4.5), layout="constrained")
for index, (prefix, radius, angle, title, centre) in enumerate(
        (("U", values["base_radius"], values["base_angle"], "Fig. 11: base, R_B", np.zeros(3)),
         ("S", values["platform_radius"], values["platform_angle"], "Fig. 12: platform, R_P",
          np.array([values["x"], values["y"], values["z"]])))):
    axes = attachments.add_subplot(1, 2, index + 1)
    circle = np.linspace(0, 2 * np.pi, 200)
    axes.plot(radius * np.cos(circle), radius * np.sin(circle), color="0.6", linestyle="--")
    stated_angles = np.array([angle, 2 * np.pi / 3 - angle, 2 * np.pi / 3 + angle,
                              4 * np.pi / 3 - angle, 4 * np.pi / 3 + angle, -angle])  # eqs. 72, 74
    for leg in range(1, 7):
        position = places[f"{prefix}{leg}"][0] - centre
        axes.plot(position[0], position[1], "o", color="tab:orange", markeredgecolor="k")
        axes.annotate(str(leg), position[:2], textcoords="offset points", xytext=(6, 6))
        print(f"{title} leg {leg}: angle {np.degrees(np.arctan2(position[1], position[0])) % 360:7.2f}° "
              f"(eq. {72 if prefix == 'U' else 74}: {np.degrees(stated_angles[leg - 1]) % 360:7.2f}°), "
              f"radius {np.hypot(position[0], position[1]):.4f} (stated {radius:g})")
    axes.set_aspect("equal")
    axes.set_title(title)
