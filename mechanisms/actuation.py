"""Choosing which joints are driven: :func:`actuate`."""

from __future__ import annotations

from dataclasses import replace

from .errors import MechanismError
from .mechanism import Mechanism

__all__ = ["actuate", "checked_joint_names"]


def actuate(mechanism, joint_names, where="inputs"):
    """The same mechanism with exactly the named joints actuated (others passive).

    Weights of joints that stay actuated are kept; a joint that changes gets weight 1.

    Parameters
    ----------
    mechanism : Mechanism
    joint_names : sequence of str
        Joints to drive, each named once.
    where : str
        Name of the field for error messages (e.g. ``"--inputs"``).

    Returns
    -------
    Mechanism

    Raises
    ------
    MechanismError
        Naming `where` and the joint, for an unknown or repeated name or an empty list.

    Examples
    --------
    >>> from mechanisms import actuate
    >>> from mechanisms.catalogue import entry
    >>> driven = actuate(entry("slider-crank").mechanism(), ["slide"])
    >>> [joint.name for joint in driven.joints if joint.actuated]
    ['slide']
    """
    names = checked_joint_names(mechanism, joint_names, where)
    joints = [joint if joint.actuated == (joint.name in names)
              else replace(joint, actuated=joint.name in names, weight=1.0)
              for joint in mechanism.joints]
    return Mechanism(mechanism.name, mechanism.space, joints, mechanism.ground, mechanism.end_effector)


def checked_joint_names(mechanism, joint_names, where):
    """The names as a list, each a joint of `mechanism` named once (at least one).

    Raises
    ------
    MechanismError
        Naming `where` and the joint, for an unknown or repeated name or an empty list.
    """
    names = list(joint_names)
    known = [joint.name for joint in mechanism.joints]
    if not names:
        raise MechanismError(f"{where}: expected at least one joint name")
    for name in names:
        if name not in known:
            raise MechanismError(f"{where}: no joint {name!r} in {mechanism.name!r} (joints: {', '.join(known)})")
        if names.count(name) > 1:
            raise MechanismError(f"{where}: joint {name!r} is named twice")
    return names
