"""The slider-crank (RRRP): Park & Kim Fig. 3; Gosselin & Angeles eqs. (6)-(17).

Crank of length R about the origin, coupler of length l, slider on the x axis
(Park & Kim 1999 Fig. 3, Gosselin & Angeles 1990 Fig. 2).
"""

from __future__ import annotations

import math

from ..errors import MechanismError
from ..joints import EndEffector, Joint
from ..mechanism import Mechanism
from ._entry import Entry

__all__ = ["slider_crank", "ENTRIES"]


def slider_crank(*, crank=2.0, coupler=1.0, theta=0.3, branch=1, actuated="crank", end_effector=True):
    """Slider-crank (RRRP) assembled at crank angle θ on the chosen branch.

    Parameters
    ----------
    crank, coupler : float
        R and l (Gosselin & Angeles Fig. 2). Neither paper gives numbers: the defaults R = 2, l = 1
        are a design of ours, a crank that cannot turn fully (R > l), whose coupler reaches the normal
        to the slide at sin θ = l/R (Park & Kim Fig. 3b's actuator singularity); the equal-link
        configurations set R = l = 1.
    theta : float
        Crank angle θ (rad) from the slide.
    branch : int
        +1 / −1: the slider at x = R cos θ ± √(l² − R² sin² θ) (G-A eq. 9);
        0: the constant branch x = 0 of the equal-link design R = l (G-A eq. 17).
    actuated : {"crank", "slider"}
        The driven joint: the crank (Park & Kim Fig. 3a-c) or the slide (Fig. 3d, our reading).
    end_effector : bool
        Whether the slider's position is the end-effector.

    Returns
    -------
    Mechanism
        Joints ``crank`` (ground-crank), ``pin`` (crank-coupler), ``wrist``
        (coupler-slider), ``slide`` (ground-slider, along x).
    """
    if not (crank > 0 and coupler > 0):
        raise MechanismError(f"slider-crank: crank and coupler must be positive, got {crank}, {coupler}")
    if actuated not in ("crank", "slider"):
        raise MechanismError(f"slider-crank: actuated must be 'crank' or 'slider', got {actuated!r}")
    if branch not in (-1, 0, 1):
        raise MechanismError(f"slider-crank: branch must be 1, -1 or 0, got {branch}")
    pin = (crank * math.cos(theta), crank * math.sin(theta))
    if branch == 0:
        if not math.isclose(crank, coupler, rel_tol=1e-12):
            raise MechanismError("slider-crank: branch 0 (x = 0) exists only when crank = coupler (G-A eq. 17)")
        slider = (0.0, 0.0)
    else:
        reach = coupler ** 2 - pin[1] ** 2
        if reach < -1e-12 * coupler ** 2:
            raise MechanismError(f"slider-crank: theta = {theta}: the coupler cannot reach the slide "
                                 f"(‖R sin θ‖ = {abs(pin[1]):.6g} > l = {coupler})")
        slider = (pin[0] + branch * math.sqrt(max(reach, 0.0)), 0.0)
    return Mechanism("slider-crank", "planar", [
        Joint("crank", "R", ("ground", "crank"), point=(0.0, 0.0), actuated=actuated == "crank"),
        Joint("pin", "R", ("crank", "coupler"), point=pin),
        Joint("wrist", "R", ("coupler", "slider"), point=slider),
        Joint("slide", "P", ("ground", "slider"), axis=(1.0, 0.0), actuated=actuated == "slider"),
    ], end_effector=EndEffector("slider", slider, "position") if end_effector else None)


ENTRIES = (
    Entry("slider-crank", slider_crank,
          "Park & Kim (1999) Fig. 3; Gosselin & Angeles (1990) "
          "eqs. (6)-(17)",
          {
              "fig3a_self_intersection": {"crank": 1.0, "coupler": 1.0, "theta": math.pi / 2},
              "fig3b_actuator": {"theta": math.asin(0.5)},
              "fig3c_dead_centre": {"theta": 0.0},
              "fig3d_dead_centre": {"theta": 0.0, "actuated": "slider"},
              "eq17_constant_branch": {"crank": 1.0, "coupler": 1.0, "theta": 0.7, "branch": 0},
              "eq17_constant_branch_slider_driven": {"crank": 1.0, "coupler": 1.0, "theta": 0.7, "branch": 0,
                                                     "actuated": "slider"},
          }),
)
