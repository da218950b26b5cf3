"""Park–Kim and Gosselin–Angeles side by side, with every disagreement explained.

The correspondence (docs/design.rst, "Gosselin–Angeles"): G–A kind I (det B = 0)
↔ an end-effector singularity, kind II (det A = 0) ↔ an actuator
singularity, kind III (both) ↔ both, or a C-space singularity. Where the two
differ, or G–A is not defined, the row carries one reason of :data:`REASONS`,
a closed list; ``"unexplained"`` is reserved for anything else and the test
suite requires that it never occurs on the catalogue.

Gosselin & Angeles call a configuration "third kind" when, for special
architectures, the chain has a finite motion with the actuators locked
(Gosselin & Angeles 1990, Section II, item 3; eq. 87); with their own
matrices det B need not vanish there (eq. 83), so such a configuration is
kind II here and Park–Kim's *degenerate* actuator singularity, which the row's
note points out.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from typing import Optional

import numpy as np

from manifold import DEFAULT_RTOL, local_rank, numerical_rank, sample_manifold, tangent_basis
from mechanisms import Mechanism

from .classification import classify
from .gosselin_angeles import GA_KINDS, derived_gosselin_angeles, gosselin_angeles, variable_scales
from .model import model_of
from .report import format_values, printable, source_lines
from .survey import decision_blocks, survey as survey_model

__all__ = ["REASONS", "expected_kinds", "correspondence", "ComparisonRow", "Comparison", "comparison_row", "compare",
           "sample_configurations", "relation_variables_mismatch"]

#: the closed list of reasons for a disagreement (or an undefined G–A classification)
REASONS = {
    "redundant_actuation": "more actuated coordinates than degrees of freedom: G–A's B is not square, so "
                           "kinds I–III are not defined; Park–Kim's semidefinite E handles it",
    "unequal_dimensions": "inputs and outputs differ in number (or there are none): G–A needs n ≥ 1 of each "
                          "(choose them, e.g. `closedchain compare --inputs … --outputs …`)",
    "idle_freedom": "a freedom the inputs do not control moves the outputs everywhere on M (an architecture "
                    "singularity, e.g. G–A eq. 87's similar hexagons): Park–Kim flags an architecture singularity, "
                    "G–A sees det A = 0 everywhere, or no n×n A and B at all",
    "stationary_motion": "a motion of M moves neither inputs nor outputs here: {(Dπ T u, J u)} has "
                         "dimension below n and does not determine A and B",
    "cspace_singularity": "C-space singularity: ker DΦ(p) is larger than the tangent spaces of M nearby, "
                          "so the derived A and B are not defined (or a given F does not show kind III)",
    "not_differentiable": "the given F is not differentiable here: A or B is not finite (a branch point of "
                          "its ± roots), or [B A] jumps across the configuration (a kink of F, e.g. ‖w‖ at "
                          "w = 0)",
    "degenerate_relation": "the given F has a degenerate differential ([B A] of rank below n) where the "
                           "C-space is smooth: det A = det B = 0 comes from how F is written (squared or "
                           "factored terms), not from a singularity of the C-space",
    "inconsistent_relation": "the given F does not describe this configuration: [B A] does not annihilate "
                             "the mechanism's velocities (another branch, or another mechanism)",
    "numerical_margin": "the two rank decisions differ only within a factor 100 of the cut",
}

#: the relative defect ‖[B A] v‖ / ‖v‖ above which a given F does not describe the mechanism
CONSISTENCY_TOLERANCE = 1e-4
#: a relation's variable θ stands still where ‖Dθ T‖ ≤ STILL · max(1, ‖θ‖): central differences of step 1e-6
#: round to about 1e-10 ‖θ‖ (:func:`relation_variables_mismatch`)
STILL = 1e-8


def expected_kinds(report):
    """The G–A kinds that correspond to a Park–Kim report.

    Parameters
    ----------
    report : Report

    Returns
    -------
    tuple of str
        I if end-effector singular, II if actuator singular, III if both;
        all three at a C-space singularity.
    """
    kinds = set(report.kinds)
    if "cspace" in kinds:
        return GA_KINDS
    first, second = "end_effector" in kinds, "actuator" in kinds
    return tuple(kind for kind, holds in zip(GA_KINDS, (first, second, first and second)) if holds)


def _near_cut(decision, factor=100.0):
    """Whether a rank decision has a singular value within `factor` of its cut (either side)."""
    if decision is None:
        return False
    values = np.asarray(decision.singular_values)
    cut = decision.tolerance
    return bool(np.any((values > cut / factor) & (values < cut * factor)))


def _lost_to_cspace(report, inputs):
    """Whether `inputs` exceed the freedoms at a C-space singularity only because it took them.

    A four-bar fully stretched is a point of M (dof 0) where DΦ loses a rank: its one crank is not
    redundant, its freedom is lost to the singularity. The freedoms of the mechanism wherever DΦ has its
    expected rank are k − (expected rank of DΦ).
    """
    return "cspace" in report.kinds and inputs <= report.ambient_dimension - report.cspace.expected_rank


def correspondence(report, result, consistent=True):
    """Whether a Park–Kim report and a G–A classification correspond, and why not.

    Parameters
    ----------
    report : Report
    result : GosselinAngeles
    consistent : bool
        False when a given F was found not to annihilate the mechanism's
        velocities at this configuration.

    Returns
    -------
    agree : bool
    reason : str or None
        A key of :data:`REASONS`, ``"unexplained"``, or None when they agree.
    note : str
    """
    expected = expected_kinds(report)
    pk = report.label
    if not result.defined:
        if result.undefined in ("not_finite", "not_differentiable"):
            reason = "not_differentiable"
        elif result.n > report.dof and not _lost_to_cspace(report, result.n):
            reason = "redundant_actuation"
        elif result.undefined == "not_square":
            reason = "unequal_dimensions"
        elif "cspace" in report.kinds:
            reason = "cspace_singularity"
        elif result.velocity_dimension is not None and result.velocity_dimension > result.n:
            reason = "idle_freedom"
        else:
            reason = "stationary_motion"
        return False, reason, f"G–A undefined ({result.detail}); Park–Kim: {pk}"
    ga = result.label  # defined here
    if not consistent:
        return False, "inconsistent_relation", f"F does not describe this configuration; G–A: {ga}; Park–Kim: {pk}"
    if result.kinds == expected:
        pieces = []
        if "I" in result.kinds:
            pieces.append("I ↔ end-effector")
        if "II" in result.kinds:
            pieces.append("II ↔ actuator" + (f" ({report.degeneracy})" if report.degeneracy else ""))
        if "cspace" in report.kinds:
            pieces = ["III ↔ C-space"]
        if report.degeneracy == "degenerate" and "I" not in result.kinds:
            pieces.append("a finite motion with the actuators locked: Gosselin–Angeles's 'third kind' in words, "
                          "kind II by det A, det B")
        return True, None, "; ".join(pieces) or "both regular"
    note = f"G–A: {ga}; Park–Kim: {pk}"
    if "cspace" in report.kinds:
        return False, "cspace_singularity", note
    if report.moving_idle_freedoms and "II" in result.kinds and "actuator" not in report.kinds:
        return False, "idle_freedom", note
    if result.relation_decision is not None and result.relation_decision.rank < result.n:
        return False, "degenerate_relation", note
    decisions = [report.actuator.decision, None if report.end_effector is None else report.end_effector.decision,
                 result.input_decision, result.output_decision]
    if any(_near_cut(decision) for decision in decisions):
        return False, "numerical_margin", note
    return False, "unexplained", note


@dataclass(frozen=True, eq=False)
class ComparisonRow:
    """Both classifications of one configuration."""

    label: str
    park_kim: object
    gosselin_angeles: object
    agree: bool
    reason: Optional[str]
    note: str

    def to_dict(self, park_kim=True):
        """The row as JSON; ``park_kim=False`` leaves out the Park–Kim report (given elsewhere)."""
        result = {"configuration": self.label}
        if park_kim:
            result["park_kim"] = self.park_kim.to_dict()
        return {**result, "gosselin_angeles": self.gosselin_angeles.to_dict(), "agree": bool(self.agree),
                "reason": self.reason, "note": self.note}


@dataclass(frozen=True, eq=False)
class Comparison:
    """A comparison over configurations of one mechanism.

    Attributes
    ----------
    mechanism : str
    inputs, outputs : tuple of str
        Names of the input and output coordinates.
    source : str
        ``"derived"`` or the name of the given relation F.
    rows : tuple of ComparisonRow
    """

    mechanism: str
    inputs: tuple
    outputs: tuple
    source: str
    rows: tuple

    @property
    def summary(self):
        """Counts: configurations, agreements, disagreements by reason, kinds of each side."""
        reasons = Counter(row.reason for row in self.rows if not row.agree)
        park_kim = Counter(kind for row in self.rows for kind in row.park_kim.kinds)
        ga = Counter(kind for row in self.rows for kind in row.gosselin_angeles.kinds)
        return {
            "configurations": len(self.rows),
            "agree": sum(row.agree for row in self.rows),
            "disagree": sum(not row.agree for row in self.rows),
            "reasons": dict(sorted(reasons.items())),
            "park_kim": {"regular": sum(not row.park_kim.kinds for row in self.rows), **dict(sorted(park_kim.items()))},
            "gosselin_angeles": {
                "regular": sum(row.gosselin_angeles.defined and not row.gosselin_angeles.kinds for row in self.rows),
                "undefined": sum(not row.gosselin_angeles.defined for row in self.rows),
                **{kind: ga[kind] for kind in GA_KINDS}},
        }

    def to_dict(self):
        return {"mechanism": self.mechanism, "inputs": list(self.inputs), "outputs": list(self.outputs),
                "gosselin_angeles_source": self.source,
                "configurations": [row.to_dict() for row in self.rows], "summary": self.summary}

    def to_text(self, source=None):
        """A table, one row per configuration, then the summary, the reasons used and the joint values.

        Parameters
        ----------
        source : dict, optional
            Where the configurations come from (:func:`classify.report.source_lines`), printed under the title.

        Returns
        -------
        str
            Every name escaped with :func:`classify.report.printable`.
        """
        header = ("configuration", "Park–Kim", "G–A", "rank A", "rank B", "agree", "reason")
        table = []
        for row in self.rows:
            report, ga = row.park_kim, row.gosselin_angeles
            pk = report.label
            if report.degeneracy:
                pk += f" ({report.degeneracy})"
            rank = (lambda value: "-" if value is None else f"{value}/{ga.n}")
            table.append((printable(row.label), pk, ga.label, rank(ga.rank_A), rank(ga.rank_B),
                          "yes" if row.agree else "NO", row.reason or ""))
        widths = [max(len(line[i]) for line in table + [header]) for i in range(len(header))]
        lines = [f"{printable(self.mechanism)}: Park–Kim and Gosselin–Angeles ({printable(self.source)}); "
                 f"inputs {', '.join(map(printable, self.inputs))}; outputs {', '.join(map(printable, self.outputs))}"]
        if source is not None:
            lines += source_lines(source)
        lines.append("")
        top = len(lines)
        lines += ["  ".join(cell.ljust(width) for cell, width in zip(line, widths)).rstrip()
                  for line in [header] + table]
        lines.insert(top + 1, "  ".join("-" * width for width in widths))
        summary = self.summary
        lines += ["", f"{summary['agree']} of {summary['configurations']} configurations correspond; "
                  f"{summary['disagree']} differ"]
        for reason, count in summary["reasons"].items():
            lines.append(f"  {count} × {reason}: {REASONS.get(reason, 'no reason from the closed list')}")
        notes = {}
        for row in self.rows:
            if row.note and not row.agree:
                notes.setdefault(row.note, []).append(row.label)
        for note, where in notes.items():
            lines.append(f"  [{', '.join(map(printable, where))}] {printable(note)}")
        lines += ["", "joint values (displacements from home):"]
        lines += [f"  {printable(row.label)}: " + format_values(row.park_kim.joint_values, indent="      ")
                  for row in self.rows]
        return "\n".join(lines)


def _relation_velocities(model, point, basis, coordinates, step=1e-6):
    """``[dθ; dx] T`` by central differences of the user's coordinate map, shape=[2n, m]."""
    ambient = model.manifold.ambient
    columns = []
    for column in basis.T:
        plus = np.concatenate([np.ravel(value) for value in coordinates(ambient.retract(point, step * column))])
        minus = np.concatenate([np.ravel(value) for value in coordinates(ambient.retract(point, -step * column))])
        columns.append((plus - minus) / (2 * step))
    return np.array(columns).T


def _consistent(result, velocities):
    """Whether the rows of [B A] annihilate the velocities (relative to their size).

    Rows and velocities are taken in the variables' scales σ (columns of [B A] times σ, velocities over σ:
    :func:`classify.gosselin_angeles.variable_scales`), so that the test depends on no unit; ``[B A] v`` itself is
    unchanged.
    """
    if not result.defined or result.relation_decision is None or result.relation_decision.rank < result.n:
        return True
    rows = np.hstack([result.input_jacobian, result.output_jacobian])
    if result.variable_scales is not None:
        rows = rows * result.variable_scales
        velocities = velocities / result.variable_scales[:, None]
    rows = rows / np.linalg.norm(rows, axis=1, keepdims=True)
    size = max(float(np.linalg.norm(velocities, 2)), 1e-300)
    return float(np.linalg.norm(rows @ velocities, 2)) <= CONSISTENCY_TOLERANCE * size


def relation_variables_mismatch(model, point, coordinates, rtol=DEFAULT_RTOL, count=3, radius=1e-2):
    """Which of a given relation's variables are not the model's near `point`: ``"inputs"``, ``"outputs"`` or None.

    G–A's θ must be the model's inputs (its actuated coordinates π) and x its
    outputs (its end-effector f), up to a change of coordinates: then
    ``dθ = K dπ`` on M, so the rows of ``Dθ T`` lie in the row space of
    ``Dπ T`` at every point, singular or not (and likewise ``Dx T`` in that
    of ``Df T``). A relation written for other inputs (the slider-crank's
    crank angle, with the slide driven) fails this wherever θ moves while π
    stands still. The test is made at `point` (unless it is a C-space
    singularity, where ker DΦ is larger than the tangent spaces) and at
    `count` points of M about `radius` away (:func:`manifold.local_rank`):
    ``Dθ T`` by central differences of `coordinates`, the row space of the
    model's decision rows (:func:`classify.survey.decision_blocks`, rank
    decided with `rtol`); a mismatch is a part of ``Dθ T`` outside that row
    space above :data:`CONSISTENCY_TOLERANCE` times the largest ``‖Dθ T‖``
    over the points. θ stands still at a point where ``‖Dθ T‖`` is below
    that, or below :data:`STILL` · max(1, ‖θ‖) (the rounding of the
    differences, about 1e-10 ‖θ‖): nothing is tested there.
    The test is one-way: on a mechanism of one degree of freedom any two
    outputs move together wherever both move, so a wrong output is caught
    only where the model's stands still and the relation's does not.

    Parameters
    ----------
    model : Model
    point : ndarray, shape=[point_size]
    coordinates : callable
        ``coordinates(point) -> (theta, x)``.
    rtol : float
    count : int
    radius : float

    Returns
    -------
    str or None
    """
    near = local_rank(model.manifold, point, np.random.default_rng(0), count=count, radius=radius, rtol=rtol)
    points = list(near.neighbours)
    if tangent_basis(model.manifold, point, rtol=rtol)[0].shape[1] == near.dimension:
        points.append(point)
    theta = np.ravel(coordinates(point)[0]).size
    checks = []
    for at in points:
        basis = tangent_basis(model.manifold, at, rtol=rtol)[0]
        velocities = _relation_velocities(model, at, basis, coordinates)
        values = [np.ravel(value) for value in coordinates(at)]
        floors = [STILL * max(1.0, float(np.linalg.norm(value))) for value in values]
        actuator, actuator_scale, end_effector, end_effector_scale = decision_blocks(model, at, basis)
        checks.append(((velocities[:theta], floors[0], actuator, actuator_scale),
                       (velocities[theta:], floors[1], end_effector, end_effector_scale)))
    for which, name in enumerate(("inputs", "outputs")):
        largest = max((float(np.linalg.norm(check[which][0], 2)) for check in checks if check[which][0].size),
                      default=0.0)
        for rows, floor, block, scale in (check[which] for check in checks):
            if not rows.size or float(np.linalg.norm(rows, 2)) <= max(CONSISTENCY_TOLERANCE * largest, floor):
                continue
            if block is None:
                return name
            span = np.linalg.svd(block, full_matrices=False)[2][:numerical_rank(block, rtol=rtol, scale=scale).rank]
            if float(np.linalg.norm(rows - rows @ span.T @ span, 2)) > CONSISTENCY_TOLERANCE * largest:
                return name
    return None


def comparison_row(model, point, report, label="", relation=None, coordinates=None, rtol=DEFAULT_RTOL):
    """The G–A side of one configuration already classified by Park–Kim, and how the two correspond.

    Parameters
    ----------
    model : Model
    point : ndarray, shape=[point_size]
    report : Report
        Park–Kim's classification of `point` (:func:`classify.classify`).
    label : str
    relation : InputOutputRelation, optional
        A given F (default: the matrices derived from the mechanism).
    coordinates : callable, optional
        ``coordinates(point) -> (theta, x)``; required with `relation`.
    rtol : float

    Returns
    -------
    ComparisonRow
    """
    basis = tangent_basis(model.manifold, point, rtol=rtol)[0]
    consistent = True
    if relation is None:
        result = derived_gosselin_angeles(model, point, basis, rtol=rtol)
    else:
        theta, x = coordinates(point)
        length = 1.0 if model.mechanism is None else model.mechanism.characteristic_length
        result = gosselin_angeles(relation, theta, x, rtol=rtol, variable_scales=variable_scales(relation, length))
        if "cspace" not in report.kinds:
            consistent = _consistent(result, _relation_velocities(model, point, basis, coordinates))
    agree, reason, note = correspondence(report, result, consistent)
    return ComparisonRow(label, report, result, agree, reason, note)


def compare(mechanism, points, labels=None, relation=None, coordinates=None, survey=None, rng=None,
            rtol=DEFAULT_RTOL, length_scale=None, input_names=None, output_names=None):
    """Classify configurations both ways and explain every difference.

    Parameters
    ----------
    mechanism : Mechanism or Model
        Its actuated coordinates are the inputs and its end-effector
        coordinates the outputs.
    points : array_like, shape=[count, point_size]
        Configurations on M.
    labels : sequence of str, optional
        Default ``"0"``, ``"1"``, ….
    relation : InputOutputRelation, optional
        A given F; default the matrices derived from the mechanism.
    coordinates : callable, optional
        ``coordinates(point) -> (theta, x)``, the relation's variables at a
        configuration; required with `relation`.
    survey : Survey, optional
        Shared by every configuration; computed from all `points` if not given.
    rng : numpy.random.Generator, optional
    rtol : float
    length_scale : float, optional
        For a Mechanism's SE(2)/SE(3) end-effector metric.
    input_names, output_names : sequence of str, optional
        Names for the report, one per input (output); default the
        relation's, or the actuated coordinates and ``y1``, ``y2``, ….

    Returns
    -------
    Comparison

    Raises
    ------
    TypeError, ValueError
        Names that are not a sequence of str (a bare string would be read
        letter by letter), or not one per input (output).
    """
    if relation is not None and coordinates is None:
        raise ValueError("a given relation F needs `coordinates(point) -> (theta, x)`")
    rng = np.random.default_rng(0) if rng is None else rng
    model = model_of(mechanism, length_scale) if isinstance(mechanism, Mechanism) else mechanism
    points = np.atleast_2d(np.asarray(points, dtype=float))
    labels = [str(index) for index in range(len(points))] if labels is None else [str(label) for label in labels]
    if len(labels) != len(points):
        raise ValueError(f"{len(labels)} labels for {len(points)} configurations")
    if survey is None:
        survey = survey_model(model, rng, starts=np.concatenate([model.starts, points]), rtol=rtol)
    rows = [comparison_row(model, point, classify(model, point, survey=survey, rng=rng, rtol=rtol), label,
                           relation, coordinates, rtol)
            for label, point in zip(labels, points)]
    names = model.coordinate_names
    input_names = _names(input_names, "input_names", relation.input_names if relation is not None else tuple(
        names[index] for index in np.flatnonzero(np.any(model.actuators != 0, axis=0))))
    output_names = _names(output_names, "output_names", relation.output_names if relation is not None else tuple(
        f"y{index + 1}" for index in range(model.end_effector_dimension)))
    return Comparison(model.name, input_names, output_names,
                      "derived" if relation is None else relation.name, tuple(rows))


def _names(given, field, default):
    """The names for the report: `given` (a sequence of as many strings as `default`), or `default`."""
    if given is None:
        return tuple(default)
    try:
        names = None if isinstance(given, str) else tuple(given)
    except TypeError:
        names = None
    if names is None or not all(isinstance(name, str) for name in names):
        raise TypeError(f"{field}: expected a sequence of names (str), got {given!r}")
    if len(names) != len(default):
        raise ValueError(f"{field}: {len(names)} names given, {len(default)} expected ({', '.join(default)})")
    return names


def sample_configurations(model, count, rng, starts=None):
    """Configurations spread over the assembly branches of M (:func:`manifold.sample_manifold`).

    Parameters
    ----------
    model : Model
    count : int
    rng : numpy.random.Generator
    starts : array_like, shape=[s, point_size], optional
        Default ``model.starts``.

    Returns
    -------
    points : ndarray, shape=[≤ count, point_size]
    """
    starts = model.starts if starts is None else np.atleast_2d(starts)
    if count <= 0:
        return np.zeros((0, starts.shape[1]))
    points = sample_manifold(model.manifold, rng, starts, random_count=count, walk_count=count)[len(starts):]
    chosen = rng.choice(len(points), size=min(count, len(points)), replace=False)
    return points[np.sort(chosen)]
