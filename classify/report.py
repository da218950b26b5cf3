"""The frozen classification report: contract JSON and readable text."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from manifold import RankDecision

from .metrics import Manipulability
from .second_order import SecondOrderResult
from .text import printable  # re-exported: part of this module's API

__all__ = ["KindResult", "Report", "KINDS", "printable", "format_values", "source_lines"]

KINDS = ("actuator", "cspace", "end_effector")


def _number(value):
    """A joint value or parameter for text: 4 significant digits, no negative zero."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        return printable(value)
    text = f"{float(value):.4g}"
    return "0" if text == "-0" else text


def _finite_or_none(value):
    """A float for JSON, or None where it is not finite (JSON has no NaN)."""
    value = float(value)
    return value if np.isfinite(value) else None


def format_values(values, width=100, indent="      "):
    """``name = value`` pairs as wrapped text lines (names escaped with :func:`printable`).

    Parameters
    ----------
    values : dict
        Name -> number (or any value, printed as text).
    width : int
        Line width of the wrapped text.
    indent : str
        Indent of the continuation lines.

    Returns
    -------
    str
        The pairs, comma-separated; continuation lines start with `indent`.

    Examples
    --------
    >>> format_values({"crank": 0.5235987755982989, "slide": -0.0})
    'crank = 0.5236, slide = 0'
    """
    pairs = [f"{printable(name)} = {_number(value)}" for name, value in values.items()]
    if not pairs:
        return "(none)"
    lines = [pairs[0]]
    for pair in pairs[1:]:
        used = len(lines[-1]) + (len(indent) if len(lines) == 1 else 0)  # the caller indents the first line
        if used + len(pair) + 2 > width:
            lines[-1] += ","
            lines.append(indent + pair)
        else:
            lines[-1] += ", " + pair
    return "\n".join(lines)


def source_lines(source, indent="  "):
    """The text lines that say where a result comes from.

    Parameters
    ----------
    source : dict
        ``{"catalogue": NAME, "parameters": {...}, "configuration": C}`` or
        ``{"file": PATH, "configuration": C}``, optionally with ``"at"``
        (the displacements given with ``--at``); C is a name or None.
    indent : str

    Returns
    -------
    list of str
    """
    configuration = source.get("configuration")
    where = f", configuration {printable(configuration)}" if configuration is not None else ""
    if "catalogue" in source:
        if not where:
            where = (" at its default parameters" if source.get("parameters") == _defaults(source["catalogue"])
                     else " with the parameters below")
        lines = [f"{indent}source: catalogue entry {printable(source['catalogue'])}{where}",
                 f"{indent}parameters: " + format_values(source.get("parameters", {}), indent=indent + "    ")]
    else:
        lines = [f"{indent}source: file {printable(source.get('file'))}{where}"]
    if source.get("at"):
        lines.append(f"{indent}--at: " + format_values(_flat(source["at"]), indent=indent + "    "))
    return lines


def _defaults(name):
    """The default parameters of catalogue entry `name` (None for a name the catalogue does not have)."""
    from mechanisms import MechanismError, catalogue

    try:
        return catalogue.entry(name).values()
    except MechanismError:
        return None


def _flat(displacements):
    """Displacements by joint (numbers or lists) as one number per coordinate: ``S1[0]``, ``S1[1]``, …."""
    result = {}
    for name, value in displacements.items():
        if isinstance(value, (list, tuple, np.ndarray)):
            result.update({f"{name}[{index}]": item for index, item in enumerate(value)})
        else:
            result[name] = value
    return result


#: entries within this fraction of the largest magnitude tie for the sign of a reported vector (the first of
#: them is made positive): a rounding difference cannot then decide the sign, as a bare argmax did
SIGN_TIE = 1e-6


def _named(vector, names):
    """A joint-rate vector as {coordinate name: value}, largest entries only, sign-normalised: the first
    entry of largest magnitude (within :data:`SIGN_TIE`) positive."""
    vector = np.asarray(vector, dtype=float)
    if not len(vector) or np.max(np.abs(vector)) == 0:
        return {}
    vector = vector / np.linalg.norm(vector)
    magnitudes = np.abs(vector)
    if vector[np.flatnonzero(magnitudes >= (1 - SIGN_TIE) * magnitudes.max())[0]] < 0:
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
        i: the directions of T_pM that, generically on M, move neither an
        actuator nor the end-effector (ker G ∩ ker J); m minus the largest
        rank on M of the stacked map (E^½Dπ T; H^½Df T). They are not
        counted as actuator singularity: G is expected to have rank m − i.
    survey : dict
    notes : tuple of str
    moving_idle_freedoms : int
        How many locked-actuator freedoms move the end-effector at every
        configuration of M (:attr:`classify.survey.Survey.moving_idle_freedoms`):
        the largest rank of the stacked map minus the largest rank of G, i.e.
        the directions of ker G outside ker J, generically on M. They are not
        idle (docs/design.rst, "The three kinds"): where there is one, the
        design is architecturally singular (:attr:`architecture_singular`;
        ``architecture_singular`` and ``actuator.moving_idle_freedoms`` in
        :meth:`to_dict`).
    source : dict or None
        Where the configuration comes from, for the reader (set by the
        command line): ``{"catalogue": NAME, "parameters": {...},
        "configuration": C}`` or ``{"file": PATH, "configuration": C}``
        (:func:`source_lines`).
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
    source: Optional[dict] = None

    @property
    def kinds(self):
        """Sorted names of the kinds that hold."""
        results = {"actuator": self.actuator, "cspace": self.cspace, "end_effector": self.end_effector}
        return tuple(kind for kind in KINDS if results[kind] is not None and results[kind].singular)

    @property
    def label(self):
        """The kinds that hold, comma-separated, or ``"regular"``: for tables and captions."""
        return ", ".join(self.kinds) or "regular"

    @property
    def singular(self):
        return bool(self.kinds)

    @property
    def architecture_singular(self):
        """Whether the design is singular at every configuration: with the actuators locked, the
        end-effector still moves (Gosselin & Angeles 1990, eq. 87)."""
        return self.moving_idle_freedoms > 0

    @property
    def joint_values(self):
        """The configuration as {joint coordinate name: displacement from home}.

        One number per coordinate of :attr:`coordinate_names`, in their order;
        a ball joint's displacement is its rotation vector. Empty when the
        report has no joint displacements (a model without joints).
        """
        values = [float(value) for value in np.ravel(np.concatenate(
            [np.ravel(np.asarray(value, dtype=float)) for value in self.displacements.values()]))] \
            if self.displacements else []
        if len(values) != len(self.coordinate_names):
            return _flat(self.displacements)
        return dict(zip(self.coordinate_names, values))

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
        actuator["architecture_singular"] = self.architecture_singular
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
                    "cut": _finite_or_none(second.self_motion.cut),
                    "length": _finite_or_none(second.self_motion.length),
                    "offset": float(second.self_motion.offset),
                },
                "higher_order": None if second.higher_order is None else {
                    "verdict": second.higher_order.verdict, "order": int(second.higher_order.order),
                    "obstruction": _finite_or_none(second.higher_order.obstruction),
                    "tolerance": _finite_or_none(second.higher_order.tolerance),
                    "noise": _finite_or_none(second.higher_order.noise),
                },
            }
        result = {
            "mechanism": self.mechanism,
            "dof": int(self.dof),
            "singular": self.singular,
            "kinds": list(self.kinds),
            "architecture_singular": self.architecture_singular,
            "moving_idle_freedoms": int(self.moving_idle_freedoms),
            "cspace": self.cspace.to_dict(names),
            "actuator": actuator,
            "end_effector": None if self.end_effector is None else self.end_effector.to_dict(names),
            "manipulability": None if self.manipulability is None else self.manipulability.to_dict(),
            "ambient_dimension": int(self.ambient_dimension),
            "configuration": self.displacements,
            "joint_values": self.joint_values,
            "survey": self.survey,
            "notes": list(self.notes),
        }
        if self.source is not None:
            result = {"mechanism": result.pop("mechanism"), "source": self.source, **result}
        return result

    def to_text(self):
        """A readable account: ranks, margins, kernel directions, self-motion."""
        names = self.coordinate_names
        lines = [f"{printable(self.mechanism)}: "
                 + (f"SINGULAR ({', '.join(self.kinds)})" if self.singular else "regular")]
        if self.source is not None:
            lines += source_lines(self.source)
        if self.displacements:
            catalogued = self.source is not None and "catalogue" in self.source
            lines.append("  joint values (from home; the parameters build the home at this configuration):"
                         if catalogued else "  joint values (displacements from home):")
            lines.append("      " + format_values(self.joint_values))
        lines.append(f"  dof m = {self.dof} (k = {self.ambient_dimension} joint coordinates)")

        def describe(label, result, extra=""):
            if result is None:
                lines.append(f"  {label:<13} none")
                return
            kept, dropped = result.decision.margin
            shown = _apart(result.decision.tolerance, kept, dropped)
            margin = ", ".join(filter(None, [
                None if kept is None else f"smallest kept σ = {shown[1]}",
                None if dropped is None else f"largest dropped σ = {shown[2]}"])) or "no singular values"
            state = "SINGULAR" if result.singular else "regular"
            where = " on ker DΦ(p)" if result.extra.get("on_kernel_of_constraint") else ""
            lines.append(f"  {label:<13} {state:<9} rank {result.rank}{where} / expected {result.expected_rank}"
                         f"{extra}  [{margin}; cut {shown[0]}]")
            if result.singular:
                for column in result.kernel.T:
                    lines.append("      lost direction: " + _format_direction(_named(column, names)))

        describe("C-space", self.cspace)
        degeneracy = f", {self.degeneracy}" if self.actuator.singular else ""
        describe("actuator", self.actuator, degeneracy)
        if self.idle_freedoms:
            lines.append(f"      idle freedoms: {self.idle_freedoms} (move neither an actuator nor the "
                         f"end-effector; not counted as singular)")
        if self.architecture_singular:
            lines.append(f"      ARCHITECTURE SINGULARITY: {self.moving_idle_freedoms} locked-actuator "
                         f"freedom(s) move the end-effector at every configuration of M: the design has an "
                         f"architecture singularity (every configuration is an actuator singularity)")
            dropped = ((self.survey or {}).get("margins") or {}).get("actuator", {}).get("dropped")
            if dropped is not None:
                lines.append(f"      (margin: over the survey's samples of M the actuator rows' next singular "
                             f"value reached at most {dropped:.2g} of its cut)")
        if self.second_order is not None:
            second = self.second_order
            vanish = second.smallest <= second.tolerance   # a common root: the smallest value is "dropped"
            cut, above, below = _apart(second.tolerance, None if vanish else second.smallest,
                                       second.smallest if vanish else None)
            lines.append(f"      second order: min |Q(v)| = {below if vanish else above} (cut {cut}): "
                         f"{second.reason}")
            if second.self_motion is not None:
                motion = second.self_motion
                start = "" if motion.offset == 0.0 else f" from the singularity at distance {motion.offset:.2g}"
                lines.append(f"      self-motion: {_format_direction(_named(motion.direction, names))}; "
                             f"followed{start} to distance {motion.distance:.3g}, "
                             f"residual ≤ {motion.largest_residual:.1e} (cut {motion.cut:.1e})")
        describe("end-effector", self.end_effector)
        if self.manipulability is not None:
            values = ", ".join(f"{value:.4g}" for value in self.manipulability.eigenvalues)
            condition = self.manipulability.condition_number
            lines.append(f"  manipulability λ = [{values}], condition "
                         f"{'∞' if condition is None else f'{condition:.4g}'}, "
                         f"volume {self.manipulability.volume:.4g}")
        for note in self.notes:
            lines.append(f"  note: {printable(note)}")
        return "\n".join(lines)


def _format_direction(named):
    """``name ±value, …``: three decimals, or three significant digits for an entry below 5e-4 (which three
    decimals would show as ±0.000 beside the entries left out as zero)."""
    return ", ".join(f"{printable(name)} {value:+.3f}" if abs(value) >= 5e-4 else f"{printable(name)} {value:+.2e}"
                     for name, value in named.items()) or "(zero)"


def _apart(cut, kept=None, dropped=None):
    """`cut`, `kept` and `dropped` as text with as many significant digits as it takes (3 at least for the
    values, 2 for the cut) for the printed kept value to stay above the printed cut and the dropped one not above
    it: rounding never shows a verdict's margin the wrong way round. A missing value is None."""
    for digits in range(3, 18):
        texts = (f"{cut:.{digits - 2}e}", None if kept is None else f"{kept:.{digits}g}",
                 None if dropped is None else f"{dropped:.{digits}g}")
        if ((kept is None or float(texts[1]) > float(texts[0]))
                and (dropped is None or float(texts[2]) <= float(texts[0]))):
            return texts
    return texts
