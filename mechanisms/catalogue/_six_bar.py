"""What the planar and spherical six-bars (Park & Kim Figs. 7, 8, 12) share: a single 6R loop."""

from __future__ import annotations

from ..errors import MechanismError

__all__ = ["LINKS", "actuated_joints"]

#: the links of the loop J1 (ground-link1), ..., J6 (link5-ground)
LINKS = ("ground", "link1", "link2", "link3", "link4", "link5", "ground")


def actuated_joints(actuated, entry_name):
    """The set of joint numbers in a string such as ``"135"``; MechanismError naming `actuated` otherwise."""
    numbers = set(actuated)
    if not actuated or not numbers <= set("123456") or len(numbers) != len(actuated):
        raise MechanismError(f"{entry_name}: actuated must list distinct joint numbers 1-6 "
                             f"(e.g. '135'), got {actuated!r}")
    return {int(number) for number in numbers}
