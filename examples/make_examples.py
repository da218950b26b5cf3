"""Write the example mechanism files of this folder (run: ``python examples/make_examples.py``).

Each file holds one design of a Park & Kim (1999)
example at a regular home configuration and, under ``configurations``, the
joint displacements from home of the singular configurations of the paper's
figures. Displacements are computed from the target joint positions, so the
files close to rounding error.
"""

from pathlib import Path

import numpy as np

from mechanisms import EndEffector, Joint, Mechanism
from mechanisms.io import save

HERE = Path(__file__).resolve().parent


def _angle(vector):
    return float(np.arctan2(vector[1], vector[0]))


def _wrap(angle):
    return float((angle + np.pi) % (2 * np.pi) - np.pi)


def planar_displacements(mechanism, home_angles, target_angles, home_slides=None, target_slides=None):
    """Joint displacements from link orientation angles (R joints) and slides (P joints)."""
    values = {}
    for joint in mechanism.joints:
        first, second = joint.links
        if joint.type == "R":
            home = home_angles[second] - home_angles[first]
            target = target_angles[second] - target_angles[first]
            values[joint.name] = _wrap(target - home)
        else:
            values[joint.name] = float(target_slides[joint.name] - home_slides[joint.name])
    return {name: value for name, value in values.items() if abs(value) > 0.0}


# ----------------------------------------------------------------------------- five-bar

def five_bar_positions(theta1, theta5, base=2.0, proximal=1.0, distal=1.0, elbow=1):
    """Joint positions of the five-bar for crank angles (from +x), elbow up (+1) or down (-1)."""
    j1, j5 = np.zeros(2), np.array([base, 0.0])
    j2 = j1 + proximal * np.array([np.cos(theta1), np.sin(theta1)])
    j4 = j5 + proximal * np.array([np.cos(theta5), np.sin(theta5)])
    middle, half = (j2 + j4) / 2, np.linalg.norm(j4 - j2) / 2
    normal = np.array([-(j4 - j2)[1], (j4 - j2)[0]]) / (2 * half)
    j3 = middle + elbow * np.sqrt(distal ** 2 - half ** 2) * normal
    return j1, j2, j3, j4, j5


def five_bar_angles(j1, j2, j3, j4, j5):
    return {"ground": 0.0, "proximal1": _angle(j2 - j1), "distal1": _angle(j3 - j2),
            "distal2": _angle(j4 - j3), "proximal2": _angle(j4 - j5)}


def five_bar():
    positions = five_bar_positions(np.radians(75.0), np.radians(115.0))
    j1, j2, j3, j4, j5 = positions
    mechanism = Mechanism("park-kim five-bar", "planar", [
        Joint("J1", "R", ("ground", "proximal1"), point=tuple(j1), actuated=True),
        Joint("J2", "R", ("proximal1", "distal1"), point=tuple(j2)),
        Joint("J3", "R", ("distal1", "distal2"), point=tuple(j3)),
        Joint("J4", "R", ("distal2", "proximal2"), point=tuple(j4)),
        Joint("J5", "R", ("proximal2", "ground"), point=tuple(j5), actuated=True),
    ], end_effector=EndEffector("distal1", tuple(j3), "position"))
    home = five_bar_angles(*positions)
    p = lambda x, y: np.array([x, y], dtype=float)  # noqa: E731
    targets = {
        # Fig. 1: all five joints collinear (C-space singularities)
        "fig1a_collinear": (p(0, 0), p(1, 0), p(2, 0), p(3, 0), p(2, 0)),
        "fig1b_collinear": (p(0, 0), p(-1, 0), p(0, 0), p(1, 0), p(2, 0)),
        "fig1c_collinear": (p(0, 0), p(1, 0), p(0, 0), p(1, 0), p(2, 0)),
        "fig1d_collinear": (p(0, 0), p(1, 0), p(2, 0), p(1, 0), p(2, 0)),
        # Fig. 6a: distal links aligned (nondegenerate actuator singularity)
        "fig6a_distal_aligned": (p(0, 0), p(0, 1), p(1, 1), p(2, 1), p(2, 0)),
        # Fig. 6b: the two elbows coincide, equal distal links (degenerate)
        "fig6b_elbows_coincide": (p(0, 0), p(1, 0), p(1, 1), p(1, 0), p(2, 0)),
    }
    configurations = {name: planar_displacements(mechanism, home, five_bar_angles(*target))
                      for name, target in targets.items()}
    save(mechanism, HERE / "five_bar.yaml", configurations=configurations,
         description="Park & Kim (1999) planar five-bar, eq. (8): base 2, "
                     "proximal and distal links 1, base joints J1 and J5 actuated, end-effector at "
                     "the middle joint J3. Configurations: Figs. 1 and 6.")


# ----------------------------------------------------------------------------- slider-crank

def slider_crank_positions(theta, crank, coupler, branch=1):
    pin = crank * np.array([np.cos(theta), np.sin(theta)])
    if branch == 0:  # the constant branch of the equal-link design: slider at the origin
        return pin, np.zeros(2)
    return pin, np.array([pin[0] + branch * np.sqrt(max(coupler ** 2 - pin[1] ** 2, 0.0)), 0.0])


def slider_crank(name, crank, coupler, actuated, home_theta, targets, description):
    pin, slider = slider_crank_positions(home_theta, crank, coupler)
    mechanism = Mechanism(name, "planar", [
        Joint("crank", "R", ("ground", "crank"), point=(0.0, 0.0), actuated=actuated == "crank"),
        Joint("pin", "R", ("crank", "coupler"), point=tuple(pin)),
        Joint("wrist", "R", ("coupler", "slider"), point=tuple(slider)),
        Joint("slide", "P", ("ground", "slider"), axis=(1.0, 0.0), actuated=actuated == "slider"),
    ], end_effector=EndEffector("slider", tuple(slider), "position"))

    def angles(theta, pin, slider):
        return {"ground": 0.0, "crank": theta, "coupler": _angle(slider - pin), "slider": 0.0}

    home = angles(home_theta, pin, slider)
    configurations = {}
    for label, (theta, branch) in targets.items():
        target_pin, target_slider = slider_crank_positions(theta, crank, coupler, branch)
        configurations[label] = planar_displacements(
            mechanism, home, angles(theta, target_pin, target_slider),
            {"slide": slider[0]}, {"slide": target_slider[0]})
    save(mechanism, HERE / f"{name}.yaml", configurations=configurations, description=description)


def main():
    five_bar()
    slider_crank(
        "slider_crank", 2.0, 1.0, "crank", 0.3,
        {"fig3b_actuator": (np.arcsin(0.5), 1), "fig3c_dead_centre": (0.0, 1)},
        "Park & Kim Fig. 3 / Gosselin & Angeles eqs. (6)-(14): crank R = 2, coupler l = 1, crank "
        "actuated, end-effector on the slider. fig3b: sin θ = l/R (actuator singularity); fig3c: "
        "θ = 0, dead centre (end-effector singularity).")
    slider_crank(
        "slider_crank_equal", 1.0, 1.0, "crank", 0.4,
        {"fig3a_self_intersection": (np.pi / 2, 1)},
        "Park & Kim Fig. 3a / Gosselin & Angeles eqs. (15)-(17): crank = coupler = 1, crank "
        "actuated; at θ = π/2 the branches x = 2 cos θ and x = 0 cross (C-space singularity).")
    slider_crank(
        "slider_crank_slider_driven", 1.0, 1.0, "slider", 0.4,
        {"constant_branch": (0.4, 0), "fig3d_dead_centre": (0.0, 1)},
        "Park & Kim Fig. 3d / Gosselin & Angeles eq. (17): crank = coupler = 1, the slider driven "
        "and carrying the end-effector. constant_branch: the slider held at x = 0 while the crank "
        "turns (degenerate actuator singularity, a self-motion); fig3d: dead centre θ = 0, where "
        "actuator and end-effector singularities combine.")


if __name__ == "__main__":
    main()
