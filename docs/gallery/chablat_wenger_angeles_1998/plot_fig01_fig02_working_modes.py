"""
Figs. 1-2: the five-bar and its four working modes
==================================================

Chablat, Wenger & Angeles 1998, Fig. 1 and §3.3 (Fig. 2): a two-dof
closed-chain manipulator (a five-bar, L₀ = 6, L₁ = 8, L₂ = 5) driven at A and
B, end-effector P. Its inverse-kinematics matrix B (eq. 3c) is diagonal,
B = L₁L₂ diag(sin(θ₃ − θ₁), sin(θ₄ − θ₂)); a working mode is a set of postures
free of serial singularities, one per sign pattern of those two entries:
four working modes for one position of P (Fig. 2).

The catalogue's ``five-bar`` at ``fig2_working_mode_pp``, ``..._pm``,
``..._mp``, ``..._mm`` (one end-effector position, four postures), drawn by
:func:`classify.figures.drawing.draw_mechanism`; the signs are read from the
drawn configuration and compared with
:func:`classify.working_modes.five_bar_working_modes` at that P.
"""

# %%
import numpy as np
from matplotlib.figure import Figure

from classify import classify
from classify.figures.drawing import draw_mechanism, joint_places
from classify.working_modes import five_bar_working_modes
from mechanisms import catalogue, configuration

entry = catalogue.entry("five-bar")


def angle(vector):
    return np.arctan2(vector[..., 1], vector[..., 0])


figure = Figure(figsize=(10, 9), layout="constrained")
for index, label in enumerate(("pp", "pm", "mp", "mm")):
    name = f"fig2_working_mode_{label}"
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    report = classify(mechanism, point)
    places = {joint: place[0] for joint, place in joint_places(mechanism, point[None]).items()}
    theta1, theta2 = angle(places["C"] - places["A"]), angle(places["D"] - places["B"])
    theta3, theta4 = angle(places["P"] - places["C"]), angle(places["P"] - places["D"])
    signs = (int(np.sign(np.sin(theta3 - theta1))), int(np.sign(np.sin(theta4 - theta2))))
    stated = label.replace("p", "+").replace("m", "-")
    # the paper's frame: A at the origin, B at (L0, 0)
    position = places["P"] - places["A"]
    modes = {mode.label: mode for mode in five_bar_working_modes(position)}
    draw_mechanism(mechanism, point, report=report, axes=figure.add_subplot(2, 2, index + 1),
                   title=f"Fig. 2, mode {stated}: {', '.join(report.kinds) or 'regular'}")
    print(f"mode {stated} ({name}): P = ({position[0]:.4f}, {position[1]:.4f}); signs of "
          f"(sin(θ3 − θ1), sin(θ4 − θ2)) drawn: {signs[0]:+d}, {signs[1]:+d}; "
          f"working_modes reaches P in mode {stated}: {modes[stated].reachable}")
