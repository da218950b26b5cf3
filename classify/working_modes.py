"""Working modes: the inverse-kinematics branches of a pose (Chablat & Wenger, via both papers' §3.3/§3.5).

Where B is diagonal (the 3-PRR, Chablat, Caro, Wenger & Angeles 2002 eq. 4b;
the five-bar, Chablat, Wenger & Angeles 1998 eq. 3c), a serial singularity is
the vanishing of a diagonal entry and a working mode is a sign pattern of B's
diagonal: 2³ = 8 for the 3-PRR (§3.5, Fig. 5), 2² = 4 for the five-bar
(§3.3, Fig. 2). For a given pose each pattern is one inverse-kinematics
solution; this module lists them, with B's diagonal and whether the pose is
reachable in that mode. Where B is not diagonal, the modes are the
inverse-kinematics branches (:mod:`classify.inverse_kinematics_branches`).

Symmetry (2002 §3.5): flipping every sign maps a mode to its partner (1-5,
2-6, 3-7, 4-8 in the catalogue's numbering): the mirror of the base triangle
about one of its axes maps the rails onto themselves with reversed directions,
so a posture of mode s goes to a posture of mode −s with the same
conditioning. The modes with one reversed leg (2, 3, 4) are images of each
other by turns of 120° (and so are 6, 7, 8).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["WorkingMode", "sign_pattern", "three_prr_working_modes", "three_prr_mode_pairs",
           "three_prr_rotation_classes", "five_bar_working_modes"]

@dataclass(frozen=True)
class WorkingMode:
    """One working mode at one pose.

    Attributes
    ----------
    label : str
        The mode's name (the 3-PRR: 1-8 as the catalogue; the five-bar: ``"++"`` …).
    signs : tuple of int
        Signs of B's diagonal.
    reachable : bool
    diagonal : tuple of float
        B's diagonal at the pose in this mode (NaN out of reach).
    angles : tuple of float or None
        The joint angles of the solution, where the mechanism has them (the five-bar: θ1..θ4; a general
        mechanism: its actuated coordinates, as displacements from home).
    point : ndarray or None
        A general mechanism's configuration on M in this mode
        (:func:`classify.inverse_kinematics_branches.mechanism_working_modes`).
    margin : float or None
        A general mechanism's 1/κ(Dπ T) (the actuator block's inverse condition) at the solution.
    """

    label: str
    signs: tuple
    reachable: bool
    diagonal: tuple
    angles: tuple | None = None
    point: np.ndarray | None = None
    margin: float | None = None

    def to_dict(self):
        result = {"label": self.label, "signs": list(self.signs), "reachable": self.reachable,
                  "diagonal": [float(value) for value in self.diagonal],
                  "angles": None if self.angles is None else [float(value) for value in self.angles]}
        if self.margin is not None:
            result["actuator_inverse_condition"] = float(self.margin)
        return result


def sign_pattern(inverse, rtol=1e-9):
    """Signs of B's diagonal, and the margin of the decision, for stacks of diagonal B.

    Parameters
    ----------
    inverse : array_like, shape=[..., n, n]
    rtol : float
        An entry with ``|Bᵢᵢ| ≤ rtol · max|Bⱼⱼ|`` is a serial singularity (sign 0).

    Returns
    -------
    signs : ndarray of int, shape=[..., n]
    margins : ndarray, shape=[...]
        ``min |Bᵢᵢ| / max |Bⱼⱼ|`` (the distance of the smallest entry to the cut, relative).

    Raises
    ------
    ValueError
        If B is not diagonal (relative off-diagonal size above `rtol`): its working modes are then the
        inverse-kinematics branches, not sign patterns.
    """
    inverse = np.asarray(inverse, dtype=float)
    diagonal = np.diagonal(inverse, axis1=-2, axis2=-1)
    scale = np.max(np.abs(diagonal), axis=-1)
    off = np.max(np.abs(inverse - diagonal[..., :, None] * np.eye(inverse.shape[-1])), axis=(-2, -1))
    if np.any(off > rtol * scale):
        raise ValueError("B is not diagonal: its working modes are inverse-kinematics branches, not sign patterns")
    with np.errstate(invalid="ignore", divide="ignore"):
        relative = np.abs(diagonal) / scale[..., None]
    signs = np.where(relative <= rtol, 0, np.sign(diagonal)).astype(int)
    return signs, np.min(relative, axis=-1)


def three_prr_working_modes(pose, platform_radius=100.0, base_radius=200.0, leg_length=200.0):
    """The eight working modes of the 3-PRR at a pose (Chablat, Caro, Wenger & Angeles 2002 §3.5, Fig. 5).

    Parameters
    ----------
    pose : array_like, shape=[3]
        (x, y, φ).

    Returns
    -------
    list of WorkingMode
        Labels ``"1"``-``"8"`` with the signs of :data:`mechanisms.catalogue.three_prr.WORKING_MODES`.
    """
    from mechanisms.catalogue.three_prr import WORKING_MODES

    from .conditioning_matrices import three_prr_matrices

    labels = sorted(WORKING_MODES)
    signs = np.array([WORKING_MODES[label] for label in labels], dtype=float)
    poses = np.broadcast_to(np.asarray(pose, dtype=float), (len(labels), 3))
    _, inverse, reachable = three_prr_matrices(poses, signs, platform_radius, base_radius, leg_length)
    diagonals = np.diagonal(inverse, axis1=-2, axis2=-1)
    return [WorkingMode(str(label), WORKING_MODES[label], bool(ok), tuple(diagonal))
            for label, ok, diagonal in zip(labels, reachable, diagonals)]


def three_prr_mode_pairs():
    """Pairs of modes with opposite signs (2002 §3.5: 1-5, 2-6, 3-7, 4-8), from the catalogue's numbering."""
    from mechanisms.catalogue.three_prr import WORKING_MODES

    by_signs = {signs: label for label, signs in WORKING_MODES.items()}
    pairs = {tuple(sorted((label, by_signs[tuple(-sign for sign in signs)]))) for label, signs in WORKING_MODES.items()}
    return sorted(pairs)


def three_prr_rotation_classes():
    """Modes that are images of each other by turns of 120° (2002 §3.5): same count of negative signs."""
    from mechanisms.catalogue.three_prr import WORKING_MODES

    classes = {}
    for label, signs in sorted(WORKING_MODES.items()):
        classes.setdefault(sum(sign < 0 for sign in signs), []).append(label)
    return [classes[key] for key in sorted(classes)]


def five_bar_working_modes(point, base=6.0, proximal=8.0, distal=5.0):
    """The four working modes of the five-bar at P = (x, y) (Chablat, Wenger & Angeles 1998 §3.3, Fig. 2).

    Returns
    -------
    list of WorkingMode
        Labels ``"++"``, ``"+-"``, ``"-+"``, ``"--"`` (signs of sin(θ3 − θ1), sin(θ4 − θ2)), with θ1..θ4.
    """
    from .conditioning_matrices import five_bar_inverse_kinematics, five_bar_matrices

    modes = []
    for label in ("++", "+-", "-+", "--"):
        signs = tuple(1 if sign == "+" else -1 for sign in label)
        angles, reachable = five_bar_inverse_kinematics(np.asarray(point, dtype=float), signs, base, proximal, distal)
        _, inverse = five_bar_matrices(angles, proximal, distal)
        modes.append(WorkingMode(label, signs, bool(reachable), tuple(np.diagonal(inverse)), tuple(angles)))
    return modes


# ------------------------------------------------------------------------------------------------ any mechanism
