"""The frozen classification report: contract JSON and readable text."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from manifold import RankDecision

from .metrics import Manipulability
from .second_order import SecondOrderResult

__all__ = ["KindResult", "Report", "KINDS"]

KINDS = ("actuator", "cspace", "end_effector")


def _named(vector, names, threshold=1e-9):
    """A joint-rate vector as {coordinate name: value}, largest entries only, sign-normalised."""
    vector = np.asarray(vector, dtype=float)
    if not len(vector) or np.max(np.abs(vector)) == 0:
        return {}
    vector = vector / np.linalg.norm(vector)
    if vector[np.argmax(np.abs(vector))] < 0:
        vector = -vector
    return {name: round(float(value), 6) for name, value in zip(names, vector) if abs(value) > 1e-6}


@dataclass(frozen=True, eq=False)
class KindResult:
    """One kind of singularity at one configuration.

    Attributes
    ----------
    singular : bool
    rank : int
    expected_rank : int
    decision : RankDecision
        Singular values, tolerance and margin of the rank decision.
    kernel : ndarray, shape=[k, d]
        Joint-rate directions lost (ker DΦ beyond the tangent space, ker G, or ker J).
    """

    singular: bool
    rank: int
    expected_rank: int
    decision: RankDecision
    kernel: np.ndarray
    extra: dict = field(default_factory=dict)

    def to_dict(self, names):
        kept, dropped = self.decision.margin
        result = {
            "singular": bool(self.singular),
            "rank": int(self.rank),
            "expected_rank": int(self.expected_rank),
            "singular_values": [float(value) for value in self.decision.singular_values],
            "tolerance": float(self.decision.tolerance),
            "margin": {"smallest_kept": kept, "largest_dropped": dropped},
            "kernel": [_named(column, names) for column in self.kernel.T],
        }
        result.update(self.extra)
        return result


@dataclass(frozen=True, eq=False)
class Report:
    """The Park-Kim classification of one configuration.

    Attributes
    ----------
    mechanism : str
    dof : int
        Local dimension m of M.
    ambient_dimension : int
        k.
    coordinate_names : tuple of str
    displacements : dict
        The configuration, joint name -> displacement from home.
    cspace, actuator : KindResult
    end_effector : KindResult or None
    manipulability : Manipulability or None
    second_order : SecondOrderResult or None
    idle_freedoms : int
    survey : dict
    notes : tuple of str
    moving_idle_freedoms : int
        How many idle freedoms move the end-effector (see
        :attr:`classify.survey.Survey.moving_idle_freedoms`): a sign of an
        architecture singularity.
    """

    mechanism: str
    dof: int
    ambient_dimension: int
    coordinate_names: tuple
    displacements: dict
    cspace: KindResult
    actuator: KindResult
    end_effector: Optional[KindResult]
    manipulability: Optional[Manipulability]
    second_order: Optional[SecondOrderResult]
    idle_freedoms: int
    survey: dict
    notes: tuple = ()
    moving_idle_freedoms: int = 0

    @property
    def kinds(self):
        """Sorted names of the kinds that hold."""
        results = {"actuator": self.actuator, "cspace": self.cspace, "end_effector": self.end_effector}
        return tuple(kind for kind in KINDS if results[kind] is not None and results[kind].singular)

    @property
    def singular(self):
        return bool(self.kinds)

    @property
    def degeneracy(self):
        """``degenerate``, ``nondegenerate``, ``undetermined`` or None (not an actuator singularity)."""
        if not self.actuator.singular:
            return None
        return "undetermined" if self.second_order is None else self.second_order.degeneracy

    def to_dict(self):
        """The contract's JSON object (docs/design.rst, "CLI"), with additive details."""
        names = self.coordinate_names
        actuator = self.actuator.to_dict(names)
        actuator["degeneracy"] = self.degeneracy
        actuator["idle_freedoms"] = int(self.idle_freedoms)
        actuator["moving_idle_freedoms"] = int(self.moving_idle_freedoms)
        if self.second_order is not None:
            second = self.second_order
            actuator["second_order"] = {
                "smallest": float(second.smallest), "tolerance": float(second.tolerance),
                "reason": second.reason,
                "root": None if second.root is None else _named(second.root, names),
                "self_motion": None if second.self_motion is None else {
                    "direction": _named(second.self_motion.direction, names),
                    "distance": float(second.self_motion.distance),
                    "largest_residual": float(second.self_motion.largest_residual),
                },
            }
        return {
            "mechanism": self.mechanism,
            "dof": int(self.dof),
            "singular": self.singular,
            "kinds": list(self.kinds),
            "cspace": self.cspace.to_dict(names),
            "actuator": actuator,
            "end_effector": None if self.end_effector is None else self.end_effector.to_dict(names),
            "manipulability": None if self.manipulability is None else self.manipulability.to_dict(),
            "ambient_dimension": int(self.ambient_dimension),
            "configuration": self.displacements,
            "survey": self.survey,
            "notes": list(self.notes),
        }

    def to_text(self):
        """A readable account: ranks, margins, kernel directions, self-motion."""
        names = self.coordinate_names
        lines = [f"{self.mechanism}: "
                 + (f"SINGULAR ({', '.join(self.kinds)})" if self.singular else "regular"),
                 f"  dof m = {self.dof} (k = {self.ambient_dimension} joint coordinates)"]

        def describe(label, result, extra=""):
            if result is None:
                lines.append(f"  {label:<13} none")
                return
            kept, dropped = result.decision.margin
            margin = ", ".join(filter(None, [
                None if kept is None else f"smallest kept σ = {kept:.3g}",
                None if dropped is None else f"largest dropped σ = {dropped:.3g}"]))
            state = "SINGULAR" if result.singular else "regular"
            lines.append(f"  {label:<13} {state:<9} rank {result.rank} / expected {result.expected_rank}"
                         f"{extra}  [{margin}; cut {result.decision.tolerance:.1e}]")
            if result.singular:
                for column in result.kernel.T:
                    lines.append("      lost direction: " + _format_direction(_named(column, names)))

        describe("C-space", self.cspace)
        degeneracy = f", {self.degeneracy}" if self.actuator.singular else ""
        describe("actuator", self.actuator, degeneracy)
        if self.idle_freedoms:
            moving = f", {self.moving_idle_freedoms} moving the end-effector" if self.moving_idle_freedoms else ""
            lines.append(f"      idle freedoms: {self.idle_freedoms} (not counted as singular{moving})")
        if self.second_order is not None:
            second = self.second_order
            lines.append(f"      second order: min |Q(v)| = {second.smallest:.3g} "
                         f"(cut {second.tolerance:.1e}): {second.reason}")
            if second.self_motion is not None:
                motion = second.self_motion
                lines.append(f"      self-motion: {_format_direction(_named(motion.direction, names))}; "
                             f"followed to distance {motion.distance:.3g}, "
                             f"residual ≤ {motion.largest_residual:.1e}")
        describe("end-effector", self.end_effector)
        if self.manipulability is not None:
            values = ", ".join(f"{value:.4g}" for value in self.manipulability.eigenvalues)
            condition = self.manipulability.condition_number
            lines.append(f"  manipulability λ = [{values}], condition "
                         f"{'∞' if condition is None else f'{condition:.4g}'}, "
                         f"volume {self.manipulability.volume:.4g}")
        for note in self.notes:
            lines.append(f"  note: {note}")
        return "\n".join(lines)


def _format_direction(named):
    return ", ".join(f"{name} {value:+.3f}" for name, value in named.items()) or "(zero)"
