"""Working modes of any mechanism: the inverse-kinematics branches of a pose, and a map's grid followed in one.

Where B is not diagonal a working mode is not a sign pattern of its diagonal
(:mod:`classify.working_modes`): it is one of the configurations with the same
end-effector value, found by Gauss–Newton on ``Φ = 0, f = f₀`` from many
starts (:func:`inverse_kinematics_branches`, :func:`mechanism_working_modes`),
and a map over a Cartesian grid stays in it by continuation that refuses to
cross a serial singularity (:func:`follow_working_mode`). Chablat & Wenger's
working modes, as used by Chablat, Caro, Wenger & Angeles 2002 §3.5 and
Chablat, Wenger & Angeles 1998 §3.3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .working_modes import WorkingMode

__all__ = ["inverse_kinematics_branches", "mechanism_working_modes", "cartesian_outputs", "output_targets",
           "follow_working_mode", "serial_margins", "BranchMode", "BRANCH_TOLERANCE", "BRANCH_SEPARATION",
           "SERIAL_TOLERANCE", "STEP_JUMP"]

#: ‖Φ‖ and end-effector residual (relative to the characteristic length) of an inverse-kinematics solution
BRANCH_TOLERANCE = 1e-10


def _separation(tolerance):
    """The distance below which two solutions to `tolerance` are one branch: 10·√tolerance (see below)."""
    return 10 * math.sqrt(tolerance)


#: two solutions closer than this (dimensionless tangent distance) are one working mode: 10·√tolerance. At a
#: serial singularity two branches meet in a double root, where Gauss–Newton converges only linearly and its
#: solutions scatter by about √‖residual‖ along the root's direction (the five-bar with a stretched leg: by up to
#: 6e-6 with residuals under 1e-10, whose count of distinct solutions then depended on rounding); a regular root
#: is found to about 1e-14
BRANCH_SEPARATION = _separation(BRANCH_TOLERANCE)
#: serial margin (1/κ of H^½ Df T, :func:`serial_margins`) at or below which a configuration is on a serial
#: singularity: its sign of det(Df T) is not decided. It is :data:`BRANCH_SEPARATION`: a solution at a double root
#: is known to about √tolerance along the root's direction, and the margin is linear in that distance (on the
#: five-bar's folds ‖PA‖, ‖PB‖ = L1 ± L2 the solved grid points have margins 1e-10 to 3e-6, of either sign; the
#: regular points of the docs' grids 0.04 and more)
SERIAL_TOLERANCE = BRANCH_SEPARATION
#: dimensionless distances tried, in order, to step off a singular start along the kernel of Df T
_SIDE_STEPS = (1e-3, 1e-2, 1e-1)
#: largest dimensionless joint move of one continuation step between neighbouring grid points (a larger one
#: is taken for a jump to another branch; the sign of det(Df T) is the finer guard, so this only has to stop
#: the wild ones: 1.5 lets a 12 × 13 grid over the five-bar's workspace cover each mode, 0.5 does not)
STEP_JUMP = 1.5


def inverse_kinematics_branches(mechanism, point, rng=None, count=64, rounds=10, tolerance=BRANCH_TOLERANCE,
                                iterations=40, max_step=0.5):
    """Every configuration found with the end-effector where it is at `point`: the inverse-kinematics branches.

    Gauss–Newton on the square system ``Φ(q) = 0``, ``f(q) = f(point)`` (n outputs = n dof: k equations
    in k unknowns where M is regular), in the dimensionless tangent coordinates,
    ``q ← q ⊕ s·([DΦ; Df]·s)⁺ [−Φ; r(q)]`` (steps of at most `max_step`). r is the output residual to
    first order in the chart of :func:`mechanisms.end_effector_jacobian` (position: f₀ − f; orientation and
    pose: the body twist ``vee(F⁻¹F₀ − 1)``, whose zeros include the exact ones; a solution is kept only if
    the exact chart, :func:`mechanisms.kinematics.end_effector_chart`, confirms it, and
    :func:`mechanisms.closes` its loops: Φ's rotation rows also vanish at a loop turned by a half-turn).
    Starts: `point`, then in each of at most `rounds` rounds `count` starts ``q ⊕ s·ε`` around the solutions
    known (ε ~ N(0, 1) per dimensionless coordinate: about a radian) and `count` combinations
    ``q_a ⊕ (q_b ⊖ point)`` of two known ones (a parallel mechanism's legs flip independently), until two
    rounds find no new one.
    Solutions whose coordinates (revolute angles modulo 2π, divided by the tangent scales) differ by less
    than ``10·√tolerance`` (:data:`BRANCH_SEPARATION` by default) are one: at a serial singularity, where two
    branches meet, the solutions found scatter by about √tolerance. A search, not a proof: a branch no start
    falls into is missed.

    Parameters
    ----------
    mechanism : Mechanism
        With an end-effector.
    point : array_like, shape=[point_size]
        On M.
    rng : numpy.random.Generator, optional
        Draws the starts (default seeded 0).
    count, rounds : int
    tolerance : float
        Largest ‖Φ‖ and output residual (relative to the characteristic length) of a solution.
    iterations : int
    max_step : float

    Returns
    -------
    ndarray, shape=[b, point_size]
        The branches by dimensionless distance from `point` (`point`'s own first).
    """
    from mechanisms.kinematics import end_effector, kinematics_of

    rng = np.random.default_rng(0) if rng is None else rng
    ambient = kinematics_of(mechanism).ambient
    scales = ambient.tangent_scales
    point = np.asarray(point, dtype=float)
    target = end_effector(mechanism, point[None])[0]
    revolute = _revolute_columns(mechanism)

    def solve(current):
        return _solved(mechanism, _output_newton(mechanism, current, target, iterations, max_step), target,
                       tolerance)

    found, coordinates = [], []
    separation = _separation(tolerance)

    def keep(candidates):
        new = 0
        for candidate in candidates:
            values = _coordinate_values(mechanism, candidate)
            if all(np.linalg.norm(_wrapped(values - known, revolute) / scales) > separation
                   for known in coordinates):
                found.append(candidate)
                coordinates.append(values)
                new += 1
        return new

    keep(solve(point[None]))
    idle = 0
    for _ in range(rounds):
        origins = np.array(found) if found else point[None]
        chosen = origins[rng.integers(len(origins), size=count)]
        starts = [ambient.retract(chosen, scales * rng.standard_normal((count, ambient.dim)))]
        if len(origins) > 1:  # one branch's change from `point` applied to another (legs flipped independently)
            first, second = rng.integers(len(origins), size=(2, count))
            starts.append(ambient.retract(origins[first], ambient.inverse_retract(
                np.broadcast_to(point, (count, point.size)), origins[second])))
        idle = 0 if keep(solve(np.concatenate(starts))) else idle + 1
        if idle == 2:
            break
    if not found:
        return np.zeros((0, point.size))
    origin = _coordinate_values(mechanism, point)
    distance = [np.linalg.norm(_wrapped(values - origin, revolute) / scales) for values in coordinates]
    order = np.argsort(distance, kind="stable")
    return np.array([_with_wrapped_angles(mechanism, found[index], revolute) for index in order])


def _with_wrapped_angles(mechanism, point, revolute):
    """The configuration with its revolute angles in [−π, π) (the same configuration: grid continuation and
    ``--grid`` bounds compare angles without wrapping)."""
    from mechanisms import from_displacements, to_displacements

    values = _wrapped(_coordinate_values(mechanism, point), revolute)
    displacements, start = {}, 0
    for joint, value in to_displacements(mechanism, point).items():
        width = len(np.atleast_1d(value))
        displacements[joint] = (values[start:start + width].tolist() if isinstance(value, list)
                                else float(values[start]))
        start += width
    return from_displacements(mechanism, displacements)


def serial_margins(mechanism, points, bases=None):
    """The serial margin of configurations: 1/κ = σ_s/σ_l of H^½ Df T (H the end-effector metric, L² on the
    rotation rows of a pose: every row a rate of length; T a tangent basis of M), in [0, 1].

    0 on a serial singularity (an output velocity no motion of M gives: two inverse-kinematics branches meet).
    It depends neither on the basis T (T → T R with R orthogonal: the singular values of T are those of the
    dimensionless kernel basis times the tangent scales), nor on the unit of length (L scales with it).

    Parameters
    ----------
    mechanism : Mechanism
    points : array_like, shape=[b, point_size]
    bases : ndarray, shape=[b, k, m], optional
        Tangent bases at `points` (:func:`classify.conditioning.tangent_bases` by default).

    Returns
    -------
    margins : ndarray, shape=[b]
    blocks : ndarray, shape=[b, n, m]
        H^½ Df T.
    """
    from mechanisms.kinematics import end_effector_jacobian

    from .conditioning import inverse_condition, tangent_bases
    from .metrics import metric_root
    from .model import model_of

    points = np.atleast_2d(np.asarray(points, dtype=float))
    bases = tangent_bases(mechanism, points) if bases is None else bases
    metric = metric_root(model_of(mechanism).end_effector_metric)
    blocks = metric @ end_effector_jacobian(mechanism, points) @ bases
    if blocks.shape[-1] != blocks.shape[-2]:
        raise ValueError(f"{mechanism.name}: {blocks.shape[-2]} outputs and {blocks.shape[-1]} degrees of freedom; "
                         f"a working mode needs as many of each")
    return np.nan_to_num(inverse_condition(blocks), nan=0.0), blocks


def _oriented_output_signs(mechanism, points, reference_bases):
    """Tangent bases T oriented as `reference_bases` (det(Tᵣᵀ S⁻² T) > 0, S the tangent scales; as computed
    where None) and the signs of det(Df T), the working mode's invariant along a path of regular points.

    Returns
    -------
    bases : ndarray, shape=[b, k, m]
    signs : ndarray, shape=[b]
        ±1; 0 where the serial margin (:func:`serial_margins`) is at most :data:`SERIAL_TOLERANCE` (a serial
        singularity: the sign there is rounding).
    margins : ndarray, shape=[b]
    """
    from mechanisms.kinematics import kinematics_of

    from .conditioning import tangent_bases

    bases = tangent_bases(mechanism, points)
    if reference_bases is not None:
        weights = 1.0 / kinematics_of(mechanism).ambient.tangent_scales ** 2
        overlap = np.linalg.det(np.einsum("bkm,k,bkn->bmn", reference_bases, weights, bases))
        bases[:, :, 0] *= np.where(overlap < 0, -1.0, 1.0)[:, None]
    margins, blocks = serial_margins(mechanism, points, bases)
    signs = np.where(margins <= SERIAL_TOLERANCE, 0.0, np.sign(np.linalg.det(blocks)))
    return bases, signs, margins


def _regular_sides(mechanism, start, tolerance):
    """Regular configurations next to a singular `start`, one on each side of the serial singularity: `start`
    moved along ±v (each sign combination of the kernel vectors v of H^½ Df T) by the first of
    :data:`_SIDE_STEPS` that gives a margin above :data:`SERIAL_TOLERANCE`, then put back on M.

    Returns
    -------
    list of ndarray, shape=[point_size]
        At most 2^corank configurations (fewer where a side stays singular or does not close).
    """
    from manifold import project_many
    from mechanisms.kinematics import configuration_space, kinematics_of

    from .conditioning import tangent_bases

    ambient = kinematics_of(mechanism).ambient
    basis = tangent_bases(mechanism, start[None])
    margins, blocks = serial_margins(mechanism, start[None], basis)
    _, values, right = np.linalg.svd(blocks[0])
    kernel = right[values <= SERIAL_TOLERANCE * max(values[0], 1e-300)]
    if not len(kernel):
        kernel = right[-1:]
    combinations = np.array(np.meshgrid(*[(1.0, -1.0)] * len(kernel), indexing="ij")).reshape(len(kernel), -1).T
    sides = []
    for combination in combinations:
        direction = basis[0] @ (combination @ kernel) / math.sqrt(len(kernel))
        for size in _SIDE_STEPS:
            guess = ambient.retract(start[None], size * direction[None])
            moved, _ = project_many(configuration_space(mechanism), guess)   # closure checked below
            if not _closes(mechanism, moved, tolerance)[0]:
                continue
            if serial_margins(mechanism, moved)[0][0] > SERIAL_TOLERANCE:
                sides.append(moved[0])
                break
    return sides


def _closes(mechanism, points, tolerance):
    """Which rows close their loops (‖Φ‖ ≤ tolerance, no half-turn), shape=[b]."""
    from mechanisms.kinematics import closes, constraint

    with np.errstate(invalid="ignore", over="ignore"):
        closure = np.linalg.norm(constraint(mechanism, points), axis=-1)
    good = np.isfinite(closure) & (closure <= tolerance)
    if np.any(good):
        good[good] = np.asarray(closes(mechanism, points[good], tolerance), dtype=bool)
    return good


def _output_newton(mechanism, current, target, iterations, max_step):
    """Gauss–Newton on ``Φ = 0, f = target`` from a stack of configurations (target one value or one per row)."""
    from mechanisms.kinematics import constraint, constraint_jacobian, end_effector, end_effector_jacobian, \
        kinematics_of

    compiled = kinematics_of(mechanism)
    ambient, scales = compiled.ambient, compiled.ambient.tangent_scales
    current = np.array(current, dtype=float)
    with np.errstate(invalid="ignore", over="ignore"):
        for _ in range(iterations):
            residual = np.concatenate([-constraint(mechanism, current), _output_residual(
                compiled.output, end_effector(mechanism, current), target)], axis=-1)
            jacobian = np.concatenate([constraint_jacobian(mechanism, current),
                                       end_effector_jacobian(mechanism, current)], axis=-2) * scales
            finite = np.all(np.isfinite(jacobian), axis=(-2, -1)) & np.all(np.isfinite(residual), axis=-1)
            step = np.zeros(current.shape[:1] + (ambient.dim,))
            step[finite] = np.einsum("bkr,br->bk", np.linalg.pinv(jacobian[finite], rcond=1e-12), residual[finite])
            size = np.linalg.norm(step, axis=-1)
            step *= np.minimum(1.0, max_step / np.maximum(size, 1e-300))[:, None]
            current = ambient.retract(current, scales * step)
    return current


def _converged(mechanism, current, target, tolerance):
    """Which rows close their loops (no half-turn) and reach `target` exactly (the exact chart), shape=[b]."""
    from mechanisms.kinematics import closes, constraint, end_effector, end_effector_chart

    with np.errstate(invalid="ignore", over="ignore"):
        closure = np.linalg.norm(constraint(mechanism, current), axis=-1)
    good = np.isfinite(closure) & (closure <= tolerance)
    if np.any(good):
        good[good] = np.asarray(closes(mechanism, current[good], tolerance), dtype=bool)
    if np.any(good):
        targets = target if np.ndim(target) == np.ndim(end_effector(mechanism, current[:1])) - 1 else target[good]
        values = end_effector(mechanism, current[good])
        reference = np.broadcast_to(targets, values.shape)
        outputs = np.linalg.norm(end_effector_chart(mechanism, values, reference), axis=-1)
        good[good] = outputs / max(float(mechanism.characteristic_length), 1e-300) <= tolerance
    return good


def _solved(mechanism, current, target, tolerance):
    return current[_converged(mechanism, current, target, tolerance)]


def _output_residual(output, values, target):
    """f₀ − f to first order in the chart of :func:`mechanisms.end_effector_jacobian`, shape=[b, n]; `target`
    one value or one per row."""
    if output == "position":
        return target - values
    size = values.shape[-1]
    relative = np.linalg.solve(values, np.broadcast_to(target, values.shape))   # F⁻¹ F₀
    # an orientation is the rotation matrix itself (SO(2) or SO(3)), a pose a homogeneous matrix around it
    rotation = relative if output == "orientation" else relative[..., :size - 1, :size - 1]
    skew = (rotation - np.swapaxes(rotation, -1, -2)) / 2
    if rotation.shape[-1] == 2:   # planar: ω, then the translation
        angular = skew[..., 1, 0][..., None]
    else:
        angular = np.stack([skew[..., 2, 1], skew[..., 0, 2], skew[..., 1, 0]], axis=-1)
    if output == "orientation":
        return angular
    return np.concatenate([angular, relative[..., :size - 1, size - 1]], axis=-1)


def _revolute_columns(mechanism):
    """Whether each coordinate is a revolute (R, U) angle, compared modulo 2π, shape=[k]."""
    widths = {"R": 1, "P": 1, "U": 2, "C": 2, "S": 3}
    return np.concatenate([np.full(widths[joint.type], joint.type in ("R", "U")) for joint in mechanism.joints])


def _wrapped(differences, revolute):
    """Differences of coordinates with the revolute ones wrapped to [−π, π)."""
    return np.where(revolute, (differences + np.pi) % (2 * np.pi) - np.pi, differences)


@dataclass(frozen=True)
class BranchMode(WorkingMode):
    """A general mechanism's working mode (:class:`~classify.working_modes.WorkingMode`), with its multiplicity.

    Attributes
    ----------
    multiplicity : int
        How many working modes meet at this inverse-kinematics root: 1 at a regular root; at a serial
        singularity (serial margin ≤ :data:`SERIAL_TOLERANCE`, where :func:`inverse_kinematics_branches`
        merges the solutions closer than :data:`BRANCH_SEPARATION`) 2 per dimension of the kernel of Df T,
        2^corank (each a fold, as a stretched or folded leg: 1998 §3.3's two modes meeting).
    serial_margin : float or None
        1/κ of H^½ Df T at the root (:func:`serial_margins`).
    """

    multiplicity: int = 1
    serial_margin: float | None = None

    def to_dict(self):
        """As :meth:`WorkingMode.to_dict`, with ``multiplicity`` and ``serial_margin``."""
        result = super().to_dict()
        result["multiplicity"] = int(self.multiplicity)
        if self.serial_margin is not None:
            result["serial_margin"] = float(self.serial_margin)
        return result


def mechanism_working_modes(mechanism, point, rng=None, count=64, rounds=10):
    """The working modes of a general mechanism at the pose of `point`: its inverse-kinematics branches.

    Where B is not diagonal the modes are not sign patterns (:func:`sign_pattern` refuses); they are the
    configurations with the same end-effector value (:func:`inverse_kinematics_branches`), numbered from 1
    by distance from `point` (mode 1 is `point`'s own). Each mode's configuration starts a map on its branch.
    At a serial singularity two (or more) modes meet in one root, listed once with its multiplicity.

    Returns
    -------
    list of BranchMode
        ``angles`` = the actuated coordinates (displacements from home), ``point`` the configuration,
        ``margin`` = 1/κ of the actuator block Λ E^½ Dπ T there (0: an actuator singularity;
        :func:`classify.conditioning.mechanism_jacobians`); ``signs`` and ``diagonal`` empty;
        ``multiplicity`` and ``serial_margin`` as :class:`BranchMode`.
    """
    from .conditioning import inverse_condition, mechanism_jacobians

    branches = inverse_kinematics_branches(mechanism, point, rng, count, rounds)
    if not len(branches):
        return []
    revolute = _revolute_columns(mechanism)
    actuated = [_wrapped(_coordinate_values(mechanism, branch), revolute)[list(mechanism.actuated_coordinates)]
                for branch in branches]
    margins = inverse_condition(mechanism_jacobians(mechanism, branches)[1])
    serial, blocks = serial_margins(mechanism, branches)
    values = np.linalg.svd(blocks, compute_uv=False)
    corank = np.count_nonzero(values <= SERIAL_TOLERANCE * np.maximum(values[:, :1], 1e-300), axis=1)
    corank = np.where(serial <= SERIAL_TOLERANCE, np.maximum(corank, 1), 0)
    return [BranchMode(str(index + 1), (), True, (), tuple(float(value) for value in actuated[index]),
                       branches[index], float(margins[index]), int(2 ** corank[index]), float(serial[index]))
            for index in range(len(branches))]


def _coordinate_values(mechanism, point):
    """The displacements from home of a configuration, one per coordinate (``mechanism.coordinate_names``)."""
    from mechanisms import to_displacements

    displacements = to_displacements(mechanism, point)
    return np.concatenate([np.atleast_1d(np.asarray(displacements[joint.name], dtype=float))
                           for joint in mechanism.joints])


# ------------------------------------------------------------------------------------------------ Cartesian grids

def cartesian_outputs(mechanism, point, names, axes):
    """The output coordinates of every point of a Cartesian grid, shape=[g, d], in C order: (x, y[, z]) of a
    position output, (x, y, φ) of a planar pose (φ, when not on the grid, the configuration's own: its link's
    rotation from home).

    Parameters
    ----------
    mechanism : Mechanism
    point : ndarray, shape=[point_size]
    names : sequence of str
        The grid's axes, among ``x``, ``y``, ``z``, ``φ``.
    axes : sequence of array_like
        The values along each.

    Raises
    ------
    ValueError
        Naming the axes the output needs, when the grid's do not fit it, or for an output that is neither a
        position nor a planar pose.
    """
    from mechanisms.kinematics import end_effector, end_effector_dimension, kinematics_of

    compiled = kinematics_of(mechanism)
    columns = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(axes))
    by_name = dict(zip(names, columns.T))
    if compiled.output == "pose" and compiled.space == "planar":
        if "z" in by_name:
            raise ValueError("a planar pose's Cartesian grid is over x, y and φ, not z")
        frame = end_effector(mechanism, np.asarray(point, dtype=float)[None])[0]
        turn = np.full(len(columns), math.atan2(frame[1, 0], frame[0, 0]))
        return np.stack([by_name["x"], by_name["y"], by_name.get("φ", turn)], axis=-1)
    if compiled.output == "position":
        wanted = ("x", "y", "z")[:end_effector_dimension(mechanism)]
        if set(by_name) != set(wanted):
            raise ValueError(f"{mechanism.name}'s output is a position ({', '.join(wanted)}): the Cartesian grid "
                             f"needs exactly those axes")
        return np.stack([by_name[name] for name in wanted], axis=-1)
    raise ValueError(f"a Cartesian grid needs a position or planar pose output; {_output_phrase(mechanism)} "
                     f"(grid its joint coordinates instead)")


def _output_phrase(mechanism):
    """``"NAME's output is a spatial pose"``, or ``"NAME has no end-effector"``."""
    from mechanisms.kinematics import kinematics_of

    compiled = kinematics_of(mechanism)
    if compiled.output is None:
        return f"{mechanism.name} has no end-effector"
    return f"{mechanism.name}'s output is a {compiled.space} {compiled.output}"


def output_targets(mechanism, values):
    """End-effector values from output coordinates: a position (x, y[, z]) as it is; a planar pose
    (x, y, φ), φ the rotation of the end-effector's link from its home orientation, as its frame.

    Parameters
    ----------
    values : array_like, shape=[g, d]

    Returns
    -------
    ndarray, shape=[g, d] or [g, 3, 3]

    Raises
    ------
    ValueError
        For another output (a spatial pose or an orientation): its grid is not (x, y, z) or (x, y, φ).
    """
    from mechanisms.kinematics import end_effector_dimension, kinematics_of

    compiled = kinematics_of(mechanism)
    values = np.asarray(values, dtype=float)
    dimension = end_effector_dimension(mechanism)
    if compiled.output == "position" and values.shape[-1] == dimension:
        return values
    if compiled.output == "pose" and compiled.space == "planar" and values.shape[-1] == 3:
        cosine, sine = np.cos(values[:, 2]), np.sin(values[:, 2])
        frames = np.zeros((len(values), 3, 3))
        frames[:, 0, 0], frames[:, 0, 1], frames[:, 1, 0], frames[:, 1, 1] = cosine, -sine, sine, cosine
        frames[:, :2, 2], frames[:, 2, 2] = values[:, :2], 1.0
        return frames
    raise ValueError(f"{mechanism.name}: a Cartesian grid needs a position output (x, y[, z]) or a planar pose "
                     f"(x, y, φ); {_output_phrase(mechanism)}")


def follow_working_mode(mechanism, start, targets, shape, tolerance=BRANCH_TOLERANCE, iterations=30,
                        max_step=0.25, jump=STEP_JUMP):
    """The configurations reaching a grid of end-effector values in the working mode of `start`, by continuation.

    The grid points nearest f(start) are tried from `start`, nearest first (up to 8), until a regular one is
    solved (Gauss–Newton on ``Φ = 0, f = f_g``, as :func:`inverse_kinematics_branches`); every other point from
    an already solved regular neighbour (one step along one axis), all the points of a front at once. A step
    is refused when it does not converge, moves the joints more than `jump` (dimensionless: a jump to another
    branch), or changes the sign of det(Df T) with T a tangent basis carried along the path (oriented as its
    neighbour's): the step crossed a serial singularity, where the working mode's branch meets another. So a
    working mode's region ends there (the papers' working modes, 2002 §3.5, 1998 §3.3); points beyond, or
    unreachable, stay NaN.

    A grid point whose serial margin (:func:`serial_margins`) is at most :data:`SERIAL_TOLERANCE` lies on a
    serial singularity: its sign of det(Df T) is rounding. It is reached (both branches meet there) but never
    the origin of a step, so its sign is never the reference: every step compares with the sign of a regular
    point of the mode. A `start` on a serial singularity is a root where several modes meet
    (:class:`BranchMode`'s multiplicity): the continuation starts from a regular configuration next to it on
    each side (along ± the kernel of Df T, :data:`_SIDE_STEPS`) and keeps the side that reaches the most grid
    points (on a tie, the larger sum of serial margins: neither depends on coordinates nor on an SVD's signs);
    the other side's mode is not mapped.

    Parameters
    ----------
    mechanism : Mechanism
    start : array_like, shape=[point_size]
        On M, in the working mode to follow.
    targets : array_like, shape=[g, ...]
        End-effector values (:func:`output_targets`) in C order.
    shape : tuple of int
        The grid's shape (g its product).
    tolerance : float
        Of a solution (:func:`inverse_kinematics_branches`).
    iterations, max_step : int, float
        Gauss–Newton's.
    jump : float
        Largest dimensionless joint move of a step (:data:`STEP_JUMP`).

    Returns
    -------
    points : ndarray, shape=[g, point_size]
        NaN rows where not reached.
    reached : ndarray of bool, shape=[g]
    """
    start = np.asarray(start, dtype=float)
    arguments = (mechanism, targets, shape, tolerance, iterations, max_step, jump)
    if _oriented_output_signs(mechanism, start[None], None)[1][0] != 0:
        return _follow(start, *arguments)
    best, best_key = None, None
    for side in _regular_sides(mechanism, start, tolerance):
        points, reached = _follow(side, *arguments)
        key = (int(reached.sum()), float(np.sum(serial_margins(mechanism, points[reached])[0]))
               if reached.any() else 0.0)
        if best_key is None or key > best_key:
            best, best_key = (points, reached), key
    if best is None:
        count = len(np.asarray(targets))
        return np.full((count, start.size), np.nan), np.zeros(count, dtype=bool)
    return best


def _follow(start, mechanism, targets, shape, tolerance, iterations, max_step, jump):
    """:func:`follow_working_mode` from a regular `start`."""
    from mechanisms.kinematics import end_effector, end_effector_chart, kinematics_of

    from .grid_continuation import grid_neighbours

    ambient = kinematics_of(mechanism).ambient
    scales = ambient.tangent_scales
    targets = np.asarray(targets, dtype=float)
    count = len(targets)
    neighbours = grid_neighbours(tuple(shape))
    points = np.full((count, start.size), np.nan)
    reached = np.zeros(count, dtype=bool)
    regular = np.zeros(count, dtype=bool)     # reached off a serial singularity: may be the origin of a step
    tried = np.zeros(neighbours.shape, dtype=bool)
    value = end_effector(mechanism, start[None])
    distance = np.linalg.norm(end_effector_chart(mechanism, np.broadcast_to(value, targets.shape), targets), axis=-1)

    signs = np.zeros(count)

    def step(origins, origin_bases, origin_signs, indices):
        solved = _output_newton(mechanism, origins, targets[indices], iterations, max_step)
        good = _converged(mechanism, solved, targets[indices], tolerance)
        move = np.linalg.norm(ambient.inverse_retract(origins, solved) / scales, axis=-1)
        good &= move <= jump
        new_bases = np.full(origin_bases.shape, np.nan)
        new_signs = np.zeros(len(indices))
        if np.any(good):
            new_bases[good], new_signs[good], _ = _oriented_output_signs(mechanism, solved[good],
                                                                         origin_bases[good])
            # det(Df T) changed sign: a serial singularity was crossed; 0: on one (reached, not an origin)
            good &= (new_signs == origin_signs) | (new_signs == 0)
        return solved, good, new_bases, new_signs

    start_basis, start_sign, _ = _oriented_output_signs(mechanism, start[None], None)
    bases = np.full((count,) + start_basis.shape[1:], np.nan)
    for first in np.argsort(distance, kind="stable")[:8]:   # the nearest grid points, until a regular one is solved
        solved, good, new_bases, new_signs = step(start[None], start_basis, start_sign, np.array([first]))
        if good[0]:
            points[first], reached[first] = solved[0], True
            bases[first], signs[first] = new_bases[0], new_signs[0]
            regular[first] = new_signs[0] != 0
            if regular[first]:
                break
    candidates = neighbours[regular].reshape(-1)
    candidates = np.unique(candidates[candidates >= 0])
    while candidates.size:
        candidates = candidates[~reached[candidates]]
        around = neighbours[candidates]
        usable = (around >= 0) & regular[np.maximum(around, 0)] & ~tried[candidates]
        keep = usable.any(axis=1)
        candidates, around, usable = candidates[keep], around[keep], usable[keep]
        if not candidates.size:
            break
        direction = np.argmax(usable, axis=1)
        origins = around[np.arange(candidates.size), direction]
        tried[candidates, direction] = True
        solved, good, new_bases, new_signs = step(points[origins], bases[origins], signs[origins], candidates)
        won = candidates[good]
        points[won], reached[won] = solved[good], True
        bases[won], signs[won] = new_bases[good], new_signs[good]
        regular[won] = new_signs[good] != 0
        following = neighbours[won[regular[won]]].reshape(-1)
        following = following[following >= 0]
        candidates = np.unique(np.concatenate([candidates[~good], following[~reached[following]]]))
    return points, reached
