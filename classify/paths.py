"""Configurations along a path of M, and the singular configurations the path crosses or touches.

A comparison "along a path through singularities" needs the singular
configurations themselves, not only points near them. Along a path, with T
an orthonormal tangent basis carried continuously, :func:`singular_crossings`
looks, per kind (actuator, end-effector, C-space), at two things at the
samples and at the midpoint of every segment:

- the sign of ``det(E^½ Dπ T)`` (or ``det(H^½ Df T)``, or the bordered
  ``det[DΦ·diag(s); (T/s)ᵀ]``): a change brackets a crossing, located by
  bisection on M;
- the smallest singular value of the kind's dimensionless block (the block
  whose rank :func:`classify.classify` decides), over its rank cut: where it
  dips (a sample or midpoint no larger than its neighbours half a step away
  and below :data:`DIP_FACTOR` times the larger of them), a bounded
  minimisation along the segments' chords re-projected onto M finds where it
  is least; below the cut, that is a touching point of the singular set, or a
  crossing the sign does not show (two singular curves crossed at once, where
  the determinant is a product of two factors that both change sign), or a
  pair of crossings within one step (then located by bisection).

What can still be missed: a dip narrower than the sampling, which shows at no
sample and no midpoint (two crossings, or a touching point, within a quarter
of a step of one another and of no midpoint, where the values at the samples
and midpoints all keep their sign and decrease monotonically towards one end).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from manifold import (
    DEFAULT_RTOL, ProjectionError, continue_curve, numerical_rank, project, scaled_jacobian, tangent_basis,
)

from .metrics import metric_root
from .survey import decision_blocks, survey_of

__all__ = ["Crossing", "DIP_FACTOR", "NoPathError", "Path", "follow_path", "path_configurations",
           "singular_crossings"]

#: A sample or midpoint of a path is a dip of a kind's σ_min (over its rank cut) when it is no larger than its two
#: neighbours (half a step away) and below DIP_FACTOR times the larger of them: then σ_min is minimised around it.
#: Below 1 so that rounding along a flat stretch is no dip; any dip to a touching point (σ_min ∝ distance²) or a
#: crossing of two singular curves (∝ distance) passes it, the larger neighbour being 3 to 9 times the smaller.
DIP_FACTOR = 0.9

KINDS = ("actuator", "end_effector", "cspace")


class NoPathError(ValueError):
    """No curve of M leaves the start (0 degrees of freedom there)."""


class Crossing(tuple):
    """``(index, point, kind)`` of a singular configuration between ``points[index]`` and ``points[index + 1]``
    of a path, with ``touching``: True where the path only touches the singular set of the kind there (the sign
    of the kind's determinant is the same on both sides, and one singular value vanishes)."""

    def __new__(cls, index, point, kind, touching=False):
        crossing = super().__new__(cls, (index, point, kind))
        crossing.touching = bool(touching)
        return crossing

    @property
    def index(self):
        """int: the segment of the path."""
        return self[0]

    @property
    def point(self):
        """ndarray: the singular configuration."""
        return self[1]

    @property
    def kind(self):
        """str: ``"actuator"``, ``"end_effector"`` or ``"cspace"``."""
        return self[2]


@dataclass(frozen=True)
class Path:
    """A path of M through a start (:func:`follow_path`).

    Attributes
    ----------
    points : ndarray, shape=[count, point_size]
        In order along the path.
    steps : ndarray of int, shape=[count]
        Signed index of each point along the path (0 at the start).
    closed : bool
        The path went round a closed curve of M: its last point is within a step of its first, and the segment
        from the last point to the first closes it (the two sides of the path met there, and stopped).
    reason : str or None
        Why the path is the start alone: ``"cspace"`` (the start is a C-space singularity, where more than one
        curve of M may meet: none is chosen) or ``"stuck"`` (M could not be continued either way); else None.
    """

    points: np.ndarray
    steps: np.ndarray
    closed: bool = False
    reason: Optional[str] = None


def follow_path(model, point, count, step=0.05, direction=None, rtol=DEFAULT_RTOL):
    """Configurations along a curve of M through `point`, both ways (``count`` on each side at most).

    Continues M along `direction` with :func:`manifold.continue_curve`; for a
    one-degree-of-freedom mechanism this is the path of the mechanism itself,
    through every fold of its inputs or outputs. The two sides grow in turn;
    where a new sample comes within `step` of the last sample of the other
    side (in the chart, angles modulo 2π) the curve is closed: both sides stop
    there (the new sample dropped if it went past the other's) and the path is
    ``closed``, each configuration of the loop on it once.

    Parameters
    ----------
    model : Model
    point : ndarray, shape=[point_size]
    count : int
    step : float
        Distance between successive configurations (coordinate scales).
    direction : ndarray, shape=[k], optional
        Default the first tangent direction at `point`; then a start at a
        C-space singularity (the rank of DΦ below its rank on M, as
        :func:`classify.classify` decides) is not continued: more than one
        curve of M may leave it, and which to follow is not defined
        (``reason`` ``"cspace"``). A given direction is followed from any start.
    rtol : float

    Returns
    -------
    Path

    Raises
    ------
    NoPathError
        No curve of M passes through `point` (no tangent direction: 0 degrees of freedom there).
    """
    manifold, ambient = model.manifold, model.manifold.ambient
    point = np.asarray(point, dtype=float)
    alone = point[None], np.zeros(1, dtype=int)
    if direction is None:
        basis, decision = tangent_basis(manifold, point, rtol=rtol)
        if basis.shape[1] == 0:
            raise NoPathError("no curve of M through the start: 0 degrees of freedom there (M is isolated points)")
        if decision.rank < survey_of(model, rtol).constraint_rank:
            return Path(*alone, reason="cspace")
        direction = basis[:, 0]
    sides = [_side(manifold, point, sign * direction, count, step) for sign in (-1.0, 1.0)]
    kept, closed = _closing(ambient, point, sides, step)
    sides = [side[:length] for side, length in zip(sides, kept)]
    points = np.concatenate([sides[0][::-1], point[None], sides[1]])
    steps = np.arange(-len(sides[0]), len(sides[1]) + 1)
    return Path(points, steps, closed, "stuck" if len(points) == 1 else None)


def _side(manifold, point, direction, count, step):
    """Up to `count` samples of M from `point` along `direction`, `step` apart (:func:`manifold.continue_curve`).

    :func:`manifold.continue_curve` stops where the distance from its start no longer grows (half-way round a
    closed curve, in the chart): the side is continued from its last sample along its last chord until `count`
    samples, or until M cannot be continued there (the other side and :func:`_closing` stop it where the
    curve closes)."""
    ambient = manifold.ambient
    pieces, total, current, heading = [], 0, point, direction
    while total < count:
        piece = continue_curve(manifold, current, heading, length=(count - total) * step, step=step).points[1:]
        piece = piece[:count - total]
        if not len(piece):
            break
        pieces.append(piece)
        total += len(piece)
        previous = pieces[-1][-2] if len(piece) > 1 else current
        current = piece[-1]
        heading = ambient.inverse_retract(previous, current)
    return np.concatenate(pieces) if pieces else np.zeros((0, len(point)))


def _closing(ambient, point, sides, step):
    """How many samples of each side (backward, forward) to keep, and whether the two met (a closed curve).

    The sides grow in turn; a new sample within `step` of the last kept sample of the other side (the start if
    none) closes the curve: it is kept unless it went past that sample (which then projects inside the new
    chord), and both sides stop."""
    scales = ambient.tangent_scales
    kept = [0, 0]
    for index in range(max(len(side) for side in sides)):
        for side in (0, 1):
            if index >= len(sides[side]):
                continue
            new = sides[side][index]
            other = sides[1 - side][kept[1 - side] - 1] if kept[1 - side] else point
            if index and np.linalg.norm(ambient.inverse_retract(new, other) / scales) <= step:
                previous = sides[side][index - 1]
                chord = ambient.inverse_retract(previous, new) / scales
                to_other = ambient.inverse_retract(previous, other) / scales
                if to_other @ chord >= chord @ chord:  # the other side's sample is beyond the new one
                    kept[side] = index + 1
                return kept, True
            kept[side] = index + 1
    return kept, False


def path_configurations(model, point, count, step=0.05, direction=None, rtol=DEFAULT_RTOL):
    """The points and steps of :func:`follow_path` (whether the path closed is in its :class:`Path`).

    Parameters
    ----------
    model : Model
    point : ndarray, shape=[point_size]
    count : int
    step : float
        Distance between successive configurations (coordinate scales).
    direction : ndarray, shape=[k], optional
    rtol : float

    Returns
    -------
    points : ndarray, shape=[≤ 2 count + 1, point_size]
        In order along the path.
    steps : ndarray of int, shape=[≤ 2 count + 1]
        Signed index of each point along the path (0 at `point`).
    """
    path = follow_path(model, point, count, step=step, direction=direction, rtol=rtol)
    return path.points, path.steps


def _aligned_basis(model, point, previous, rtol):
    """A tangent basis at `point` turned to be closest to `previous` (orthogonal Procrustes in the inner product
    ``⟨v, w⟩_s = Σ vᵢ wᵢ / sᵢ²`` in which the bases are orthonormal: in the plain product of joint
    coordinates, a slide's scale s = 200 outweighs the angles, and the turn could mirror the basis between two
    close points)."""
    basis = tangent_basis(model.manifold, point, rtol=rtol)[0]
    if previous is None or basis.shape != previous.shape:
        return basis
    scales = model.manifold.ambient.tangent_scales[:, None]
    left, _, right = np.linalg.svd((basis / scales).T @ (previous / scales))
    return basis @ left @ right


def _raw_determinants(model, point, basis, jacobian=None):
    """``(det(E^½ Dπ T), det(H^½ Df T), det[DΦ·diag(s); (T/s)ᵀ])``, each None where the matrix is not square.

    The third is the classical test function of branch points in continuation (the Jacobian bordered by the
    carried tangent basis): it changes sign where the path crosses a simple bifurcation of M, a C-space
    singularity (a parallelogram flattening into an antiparallelogram). `jacobian`: DΦ·diag(s) at `point`,
    if the caller has it.
    """
    actuator = model.actuators @ basis
    values = [np.linalg.det(actuator) if actuator.shape[0] == actuator.shape[1] else None, None, None]
    if model.end_effector_dimension:
        output = metric_root(model.end_effector_metric) @ model.end_effector_jacobian(point) @ basis
        values[1] = np.linalg.det(output) if output.shape[0] == output.shape[1] else None
    scales = model.manifold.ambient.tangent_scales
    jacobian = scaled_jacobian(model.manifold, point) if jacobian is None else jacobian
    bordered = np.vstack([jacobian, (basis / scales[:, None]).T])
    values[2] = np.linalg.det(bordered) if bordered.shape[0] == bordered.shape[1] else None
    return values


@dataclass(frozen=True)
class _Sample:
    """A point of M with its tangent basis (aligned), the raw determinants of :func:`_raw_determinants`, and per
    kind ``(σ_min / cut, rank deficiency)`` of the kind's block (None where the map is not square)."""

    point: np.ndarray
    basis: np.ndarray
    raw: list
    measures: list

    def regular(self, which):
        """Whether the map of kind `which` has full rank here (the rank decision of :func:`classify.classify`)."""
        return self.measures[which] is not None and self.measures[which][1] == 0

    def sign(self, which):
        """The sign of the determinant of kind `which`."""
        return np.sign(self.raw[which])


def _measure(decision, rows):
    """``(σ_min / cut, rows − rank)`` of a rank decision of a matrix with `rows` rows."""
    values = decision.singular_values
    smallest = values[rows - 1] if len(values) >= rows else 0.0
    return float(smallest / decision.tolerance) if decision.tolerance > 0 else np.inf, rows - decision.rank


def _evaluate(model, point, reference, rtol):
    """The :class:`_Sample` at `point`, its basis turned to `reference` (None: as it comes). The blocks and cuts
    are those of :func:`classify.survey.decision_blocks` and :func:`manifold.numerical_rank`, as
    :func:`classify.classify` decides."""
    basis = _aligned_basis(model, point, reference, rtol)
    jacobian = scaled_jacobian(model.manifold, point)
    raw = _raw_determinants(model, point, basis, jacobian)
    measures = [None, None, None]
    blocks = decision_blocks(model, point, basis)
    for which, (block, scale) in enumerate((blocks[:2], blocks[2:])):
        if raw[which] is not None:
            measures[which] = _measure(numerical_rank(block, rtol=rtol, scale=scale), len(block))
    if raw[2] is not None:
        measures[2] = _measure(numerical_rank(jacobian, rtol=rtol), len(jacobian))
    return _Sample(point, basis, raw, measures)


def _between(ambient, low, high, fraction):
    """``low ⊕ fraction (high ⊖ low)`` (not yet projected onto M)."""
    return ambient.retract(low, fraction * ambient.inverse_retract(low, high))


def _bisect(model, low, high, which, rtol, tolerance, max_bisections):
    """The crossing of kind `which` between two :class:`_Sample` whose determinants differ in sign: bisection
    on M (the midpoint ``p ⊕ ½ (q ⊖ p)`` projected back onto M). Returns ``(point, kind)``: the kind is
    ``"cspace"`` where ker DΦ grew at a midpoint (a C-space singularity, to the rank cut)."""
    manifold, ambient = model.manifold, model.manifold.ambient
    scales = ambient.tangent_scales
    low_point, high_point, low_basis = low.point, high.point, low.basis
    low_value, high_value = low.raw[which], high.raw[which]
    for _ in range(max_bisections):
        if np.linalg.norm(ambient.inverse_retract(low_point, high_point) / scales) < tolerance:
            break
        try:
            middle = project(manifold, _between(ambient, low_point, high_point, 0.5))
        except ProjectionError:
            break
        middle_basis = _aligned_basis(model, middle, low_basis, rtol)
        middle_value = _raw_determinants(model, middle, middle_basis)[which]
        if middle_value is None:  # ker DΦ grew: the midpoint is a C-space singularity (to the rank cut)
            return middle, "cspace"
        if middle_value * low_value > 0:
            low_point, low_basis, low_value = middle, middle_basis, middle_value
        else:
            high_point, high_value = middle, middle_value
    return (low_point if abs(low_value) < abs(high_value) else high_point), KINDS[which]


class _Chords:
    """The path as a function of a position x ∈ [0, count − 1]: ``points[i]`` at x = i, and between two points
    the chord ``points[i] ⊕ τ (points[i + 1] ⊖ points[i])`` (τ = x − i) projected onto M, evaluated once per
    position (:class:`_Sample`, its basis turned to that of ``points[i]``)."""

    def __init__(self, model, samples, rtol):
        self.model, self.samples, self.rtol, self.cache = model, samples, rtol, {}

    def __call__(self, position):
        segment = min(int(np.floor(position)), len(self.samples) - 2)
        fraction = position - segment
        if fraction in (0.0, 1.0):
            return self.samples[segment + int(fraction)]
        key = round(position, 15)
        if key not in self.cache:
            manifold = self.model.manifold
            low, high = self.samples[segment], self.samples[segment + 1]
            try:
                point = project(manifold, _between(manifold.ambient, low.point, high.point, fraction))
            except ProjectionError:
                self.cache[key] = None
            else:
                self.cache[key] = _evaluate(self.model, point, low.basis, self.rtol)
        return self.cache[key]


#: golden-section ratio (1/φ)
_GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


def _minimise(chords, which, left, centre, right, centre_value, max_steps=60, resolution=1e-10):
    """Golden-section search of the least ``σ_min / cut`` of kind `which` on positions [left, right], from a
    centre no larger than the ends. Returns the :class:`_Sample` of the least value found and every sample
    evaluated on the way."""
    best, seen = chords(centre), []
    low, high = left, right
    middle, middle_value = centre, centre_value
    for _ in range(max_steps):
        if high - low < resolution:
            break
        wider_right = high - middle > middle - low
        probe = middle + (1 - _GOLDEN) * (high - middle) if wider_right else middle - (1 - _GOLDEN) * (middle - low)
        sample = chords(probe)
        if sample is None or sample.measures[which] is None:
            break
        seen.append(sample)
        value = sample.measures[which][0]
        if value < middle_value:
            if wider_right:
                low = middle
            else:
                high = middle
            middle, middle_value, best = probe, value, sample
        elif wider_right:
            high = probe
        else:
            low = probe
    return best, middle, seen


def _dip_crossings(model, chords, which, left, centre, right, rtol, tolerance, max_bisections):
    """The crossings (or touching point) of kind `which` inside a dip of its σ_min at position `centre`
    (neighbours `left`, `right`, all regular or the centre alone singular, of one sign): σ_min is minimised;
    below the cut, a sample of the other sign found on the way or half a step either side splits the dip into
    two sign changes, each bisected; else the least point is reported, touching where one singular value
    vanishes (an even number vanishing at once, as where two singular curves cross, change the sign of none of
    the products: a crossing). Returns a list of ``(point, kind, touching)``."""
    ends = chords(left), chords(right)
    best, position, seen = _minimise(chords, which, left, centre, right, chords(centre).measures[which][0])
    deficiency = best.measures[which][1]
    if deficiency == 0:
        return []
    sign = ends[0].sign(which)
    width = right - left
    for offset in (1e-6, 1e-4, 1e-2, 1e-1, None):
        opposite = [sample for sample in seen if sample.regular(which) and sample.sign(which) != sign]
        if opposite or offset is None:
            break
        for probe in (position - offset * width, position + offset * width):
            if left < probe < right:
                sample = chords(probe)
                if sample is not None and sample.measures[which] is not None:
                    seen.append(sample)
    if opposite:
        other = opposite[0]
        return [(*_bisect(model, ends[0], other, which, rtol, tolerance, max_bisections), False),
                (*_bisect(model, other, ends[1], which, rtol, tolerance, max_bisections), False)]
    return [(best.point, KINDS[which], deficiency % 2 == 1)]


def _segment_of(chords, point, left, right):
    """The segment (index of its first point) of positions [left, right] that `point` lies on: the least excess
    ``‖p − pᵢ‖ + ‖p − pᵢ₊₁‖ − ‖pᵢ₊₁ − pᵢ‖`` (0 on the chord; dimensionless), symmetric in the two ends (the
    distance to the segments' second ends alone filed a point just after sample j under the segment before j)."""
    segments = sorted({int(np.floor(left)), min(int(np.floor(right)), len(chords.samples) - 2)})
    if len(segments) == 1:
        return segments[0]
    ambient = chords.model.manifold.ambient
    scales = ambient.tangent_scales

    def distance(first, second):
        return np.linalg.norm(ambient.inverse_retract(first, second) / scales)

    excess = [distance(chords.samples[index].point, point) + distance(point, chords.samples[index + 1].point)
              - distance(chords.samples[index].point, chords.samples[index + 1].point) for index in segments]
    return segments[int(np.argmin(excess))]


def singular_crossings(model, points, rtol=DEFAULT_RTOL, tolerance=1e-12, max_bisections=80, closed=False):
    """The actuator, end-effector and C-space singularities crossed (or touched) between consecutive points of
    a path.

    With T carried continuously along the path (each basis turned to the
    previous one), ``det(E^½ Dπ T)`` and ``det(H^½ Df T)`` are continuous; a
    sign change between two consecutive points, both regular for the kind
    (the rank decision of :func:`classify.classify`), brackets a crossing,
    found by bisection: the midpoint ``p ⊕ ½ (q ⊖ p)`` projected back onto M.
    So is a sign change between the two points and the midpoint of their
    segment (a pair of crossings within one step). Where the kind's smallest
    singular value over its rank cut dips (:data:`DIP_FACTOR`) at a point or
    at the midpoint of a segment, it is minimised (golden section along the
    chords, projected onto M); a least value below the cut is a singular
    configuration the sign does not show: a touching point (``touching``), a
    crossing of an even number of singular curves at once (two legs of a
    five-bar stretched), or a pair of crossings (found by bisection). The
    cost: one more configuration per segment (its midpoint), and about 50
    per dip. What can still be missed is in the module's docstring. A
    singular point of the path (its start, say) is no crossing: it is on the
    path already. Only square maps (as many inputs, or outputs, as degrees of
    freedom) are followed. A C-space singularity the path crosses (a simple
    bifurcation of M) is found the same way from the sign of
    ``det[DΦ·diag(s); (T/s)ᵀ]`` where DΦ has full row rank on M (not for an
    overconstrained chain), and from the smallest singular value of DΦ·diag(s).

    Parameters
    ----------
    model : Model
    points : array_like, shape=[count, point_size]
        Consecutive points of a curve of M, closely spaced (as from
        :func:`follow_path`).
    rtol : float
    tolerance : float
        Bisect until the bracket is shorter than this (coordinate scales).
    max_bisections : int
    closed : bool
        The path is a closed loop (:attr:`Path.closed`): the segment from the
        last point to the first is searched too (its crossings have index
        ``count − 1``).

    Returns
    -------
    list of Crossing
        ``(index, point, "actuator" | "end_effector" | "cspace")`` in order along the
        path, with ``touching``: the singular point lies between ``points[index]`` and
        ``points[index + 1]`` (``points[0]`` for the last index of a closed path).
    """
    points = np.asarray(points, dtype=float)
    if closed and len(points) > 2:
        points = np.concatenate([points, points[:1]])
    samples = []
    for point in points:
        samples.append(_evaluate(model, point, samples[-1].basis if samples else None, rtol))
    if len(samples) < 2:
        return []
    chords = _Chords(model, samples, rtol)
    middles = [chords(index + 0.5) for index in range(len(samples) - 1)]
    found = []
    for which, kind in enumerate(KINDS):
        crossed = set()
        for index, middle in enumerate(middles):
            low, high = samples[index], samples[index + 1]
            if not (low.regular(which) and high.regular(which)):
                continue
            if low.sign(which) != high.sign(which):
                pieces = [(low, high)]
            elif middle is not None and middle.regular(which) and middle.sign(which) != low.sign(which):
                pieces = [(low, middle), (middle, high)]
            else:
                continue
            crossed.add(index)
            for first, second in pieces:
                point, found_kind = _bisect(model, first, second, which, rtol, tolerance, max_bisections)
                if found_kind == kind or (index, found_kind) not in [(item[0], item[2]) for item in found]:
                    found.append((index, point, found_kind, False))
        sequence = [chords(0.5 * position) for position in range(2 * len(samples) - 1)]
        for position in range(1, len(sequence) - 1):
            left, centre, right = sequence[position - 1:position + 2]
            if not _is_dip(left, centre, right, which, position % 2 == 0) \
                    or {(position - 1) // 2, position // 2} & crossed:
                continue
            for point, found_kind, touching in _dip_crossings(model, chords, which, 0.5 * (position - 1),
                                                              0.5 * position, 0.5 * (position + 1), rtol,
                                                              tolerance, max_bisections):
                index = _segment_of(chords, point, 0.5 * (position - 1), 0.5 * (position + 1))
                if found_kind == kind or (index, found_kind) not in [(item[0], item[2]) for item in found]:
                    found.append((index, point, found_kind, touching))
    found.sort(key=lambda item: (item[0], _along(model, points[item[0]], item[1])))
    return [Crossing(*item) for item in found]


def _is_dip(left, centre, right, which, at_sample):
    """Whether the centre of three consecutive samples or midpoints is a dip of the σ_min of kind `which`: all
    three regular and of one sign (a midpoint may be singular), the centre no larger than the right and smaller
    than the left neighbour (a tie counted once), and below :data:`DIP_FACTOR` times the larger neighbour."""
    if any(item is None or item.measures[which] is None for item in (left, centre, right)):
        return False
    if not (left.regular(which) and right.regular(which)) or left.sign(which) != right.sign(which):
        return False
    if centre.regular(which) and centre.sign(which) != left.sign(which):
        return False
    if at_sample and not centre.regular(which):  # a singular point of the path is a row already
        return False
    value, neighbours = centre.measures[which][0], (left.measures[which][0], right.measures[which][0])
    return value < neighbours[0] and value <= neighbours[1] and value < DIP_FACTOR * max(neighbours)


def _along(model, start, point):
    """The distance from `start` to `point` (coordinate scales): the order of crossings within a segment."""
    ambient = model.manifold.ambient
    return float(np.linalg.norm(ambient.inverse_retract(start, point) / ambient.tangent_scales))
