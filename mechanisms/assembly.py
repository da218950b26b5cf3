"""Assembly at chosen inputs: hold some joints at given values, close the loops with the others.

A mechanism file holds one assembled configuration, the home; a user who asks
for the mechanism at other inputs (``J1 = −0.373``) needs the passive joints
that close the loops there. :func:`assemble` holds the given joint
coordinates *exactly* at the requested values and solves Φ = 0 for the
others; unlike projection (:func:`mechanisms.configuration` with
``project_onto=True``), it never moves an input. :func:`assemblies` lists
every assembly (assembly mode, branch) found at the same inputs.

Held and free coordinates. The k tangent coordinates of the ambient space K
(one per S¹ or ℝ factor, three per SO(3) factor) split into the held ones,
``h``, and the free ones, ``q`` (k_q of them). The values name joints, as
:func:`mechanisms.configuration` takes displacements from home (a number for
R and P, a pair for U and C, a rotation vector for S), or single coordinates
of U and C joints by their coordinate names (``"U1[2]"``, ``"C1[slide]"``);
a ball joint is held whole. By default the actuated joints the values do not
name are held at home too (``hold_actuated=True``): ``--at`` moves the
inputs it names and leaves the other inputs where they are.

Newton with held coordinates. With the held values fixed, the fibre
``F_h = {q : Φ(h, q) = 0}`` is an implicit manifold in the product of the
free factors, and its points are found by damped Gauss-Newton in the
recentred charts of :class:`manifold.AmbientSpace`::

    q ← q ⊕ t·s·u,   u = −(DΦ_q(q)·diag(s))⁺ Φ(h, q),

where DΦ_q, shape=[c, k_q], are the columns of DΦ of the free coordinates, s
their scales (dimensionless steps, as :func:`manifold.project`), ``|u|`` is
capped at 0.5 and t halves until ‖Φ‖ decreases. The held coordinates
are never part of a step, so they keep, bit for bit, the requested values.
Convergence: ‖Φ‖ ≤ `tolerance` and no loop closes on a half-turn
(:func:`mechanisms.closes`).

Continuation fallback. When Newton from the home fails (the home is far from
the fibre), the held values move from their home values to the targets along
``h(t) = h₀ ⊕ t·δ``, t ∈ [0, 1] (δ the chart vector from home to the
targets, angles by the shorter way); each step predicts the free coordinates
to first order, ``q ⊕ −s·(DΦ_q s)⁺ DΦ_h Δh``, and corrects by Newton. A step
that fails (no convergence, or a correction larger than 0.25 in
dimensionless units, a jump to another branch) is halved; the walk stops when
steps fall below 1e-5 (dimensionless). Continuation stays on the branch of the
home; it cannot pass a fold of the inputs (a turning point, where the branch
ends), so it fails where the inputs leave the branch's reach.

Branches. The assemblies at the same inputs are found by Newton from the
home, then (if that fails) continuation, a `guess` if given, and `count`
random starts of the free coordinates (angles and rotations uniform, lengths
normal about home with the characteristic length as deviation), drawn from
`rng`. Two solutions closer than 1e-5 (dimensionless chart distance) are one
assembly (at a fold, where two branches meet in a double root, Newton converges
only linearly and its limits scatter by about 1e-6); free angles are wrapped
to [−π, π). The search is a sampling, not a proof: an assembly none of the
starts falls into is missed (raise `count`). **Branch n** is the n-th
assembly in order of increasing distance from the home (the dimensionless
norm of the chart vector from home, angles wrapped), ties broken by the
chart vector itself: branch 0 is the assembly nearest the home. The
numbering depends only on the set found, hence is reproducible with a seeded
`rng`; a `guess` (joint displacements from home, as `values`) selects instead
the assembly nearest ``home ⊕ guess``. When the held values leave the other
joints free to move (a self-motion, or fewer held coordinates than degrees of
freedom) the assemblies are not isolated: :func:`assemblies` refuses to
number them, and :func:`assemble` returns one with ``branch = None``.

Nothing to solve. When the held values fix every coordinate (every joint
named, or named and held at home), the configuration they name is the only
candidate: it is the assembly (branch 0 of 1, its method the one asked for,
``"newton"`` by default) if it closes the loops (‖Φ‖ ≤ `tolerance`, no
half-turn, :func:`mechanisms.closes`), and otherwise there is no assembly
(:class:`AssemblyError`, naming the held values and the residual).

=================  ==========================================================
shape              meaning
=================  ==========================================================
[point_size]       a point of K (:attr:`Assembly.point`)
[k]                a chart vector of K (distances)
[c, k_q]           DΦ_q, the constraint Jacobian in the free coordinates
=================  ==========================================================

Examples
--------
The slider-crank of Park & Kim 1999 Fig. 3 (crank 2, coupler 1), built at
crank angle 0.3, put at crank angle 0.4 on both branches:

>>> from mechanisms.catalogue.slider_crank import slider_crank
>>> mechanism = slider_crank(theta=0.3)
>>> found = assemblies(mechanism, {"crank": 0.1})
>>> [(item.branch, item.displacements["crank"]) for item in found]
[(0, 0.1), (1, 0.1)]
>>> reached = assemble(mechanism, {"crank": 0.1})
>>> reached.method, reached.branch, reached.residual < 1e-10
('newton', 0, True)

References
----------
Park & Kim 1999 (C-space as Φ⁻¹(0), the fibre of the actuators);
Gosselin & Angeles 1990 (assembly branches of the slider-crank, eqs. 6-17).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Optional

import numpy as np

from manifold import AmbientSpace, ImplicitManifold, continue_curve, minimum_norm_steps, numerical_rank

from .configuration import from_displacements, home, to_displacements, validate_displacements
from .errors import ConfigurationError, MechanismError
from .io import check_displacement
from .joints import joint_coordinate_names, joint_factors
from .kinematics import closes, configuration_space, constraint, constraint_jacobian, kinematics_of

__all__ = ["AssemblyError", "Assembly", "ASSEMBLY_METHODS", "assemble", "assemblies"]

#: How an assembly was reached: Newton from the home, continuation from the home along the
#: inputs, Newton from the user's guess, Newton from a random start.
ASSEMBLY_METHODS = ("newton", "continuation", "guess", "search")
#: dimensionless chart distance under which two solutions are one assembly: at least _SAME, and _STALL times
#: √tolerance, since Newton stalls about √‖Φ‖ from a double root (an assembly at a singularity: random starts
#: that reach the Eclipse's Fig. 10 home stopped 1.4e-5 to 3.6e-5 from it and from each other)
_SAME = 1e-5
_STALL = 100.0
#: largest dimensionless corrector move a continuation step accepts
_JUMP = 0.25


class AssemblyError(ConfigurationError):
    """No assembly at the requested inputs, or the requested branch does not exist."""


@dataclass(frozen=True, eq=False)
class Assembly:
    """A closed configuration with some joints held at requested values.

    Attributes
    ----------
    point : ndarray, shape=[point_size]
        The configuration, a point of K with ‖Φ‖ ≤ the tolerance.
    displacements : dict
        Joint name -> displacement from home (:func:`mechanisms.to_displacements`);
        the held joints carry exactly the requested values.
    held : dict
        Joint or coordinate name -> the value held, as requested, with the
        actuated joints held at home (0) when `hold_actuated` applied.
    residual : float
        ‖Φ(point)‖.
    distance : float
        Dimensionless norm of the chart vector from the home to `point`
        (angles wrapped to [−π, π), lengths over their scale).
    method : {"newton", "continuation", "guess", "search"}
        How the assembly was reached (:data:`ASSEMBLY_METHODS`).
    branch : int or None
        Index of the assembly among those found at these inputs, sorted by
        distance from home (see the module notes); None when the assemblies
        are not isolated.
    branches : int or None
        How many assemblies were found at these inputs (None when not isolated).
    """

    point: np.ndarray
    displacements: dict
    held: dict
    residual: float
    distance: float
    method: str
    branch: Optional[int]
    branches: Optional[int]

    def to_dict(self):
        """A JSON-ready mapping (the point is given by its displacements)."""
        return {"method": self.method, "branch": self.branch, "branches": self.branches,
                "residual": self.residual, "distance": self.distance,
                "held": dict(self.held), "displacements": dict(self.displacements)}


# ----------------------------------------------------------------------------- the problem

@dataclass(frozen=True, eq=False)
class _Problem:
    """The held values and the split of K into held and free factors."""

    mechanism: object
    held: dict                 # name -> value as requested (floats or lists of floats)
    description: str           # "A = 0.2, B = -0.2", for messages
    home: np.ndarray           # [point_size]
    target: np.ndarray         # the home with the held entries at the requested values
    free_points: np.ndarray    # indices of the free factors' entries in a point
    free_tangent: np.ndarray   # indices of the free coordinates in a tangent vector
    held_tangent: np.ndarray   # indices of the held coordinates
    reduced: AmbientSpace      # the product of the free factors

    def embed(self, free, base=None):
        """Points with free entries `free`, shape=[..., point_size]; held entries from `base` (the targets)."""
        base = self.target if base is None else base
        free = np.asarray(free, dtype=float)
        points = np.array(np.broadcast_to(base, free.shape[:-1] + base.shape[-1:]))
        points[..., self.free_points] = free
        return points

    def fibre(self, base=None, closing=False):
        """The fibre {q : Φ(h, q) = 0} over the held entries of `base` (default the targets); with `closing`, as
        the zero set of the closing map (:func:`mechanisms.kinematics.closing_space`: no half-turn zeros, for
        random starts far from it)."""
        base = self.target if base is None else np.asarray(base, dtype=float)
        mechanism, columns = self.mechanism, self.free_tangent
        space = configuration_space(mechanism)
        space = space.closing if closing else space
        pattern, kept = space.pattern.restricted(columns)  # DΦ's blocks on the free columns, for large fibres

        def entries(free):
            return space.constraint_jacobian_entries(self.embed(free, base))[..., kept]

        return ImplicitManifold(
            ambient=self.reduced,
            constraint=lambda free: space.constraint(self.embed(free, base)),
            constraint_jacobian=lambda free: space.constraint_jacobian(self.embed(free, base))[..., columns],
            is_solution=lambda free: bool(np.all(closes(mechanism, self.embed(free, base), np.inf))),
            pattern=pattern, constraint_jacobian_entries=entries)


def _holdable(mechanism):
    """Name -> (joint, its factor indices) for every joint and every coordinate of a U or C joint."""
    names, start = {}, 0
    for joint in mechanism.joints:
        count = len(joint_factors(joint))
        names[joint.name] = (joint, tuple(range(start, start + count)))
        if joint.type in ("U", "C"):
            for offset, name in enumerate(joint_coordinate_names(joint)):
                names[name] = (joint, (start + offset,))
        start += count
    return names


def _check_value(mechanism, holdable, values, name, where):
    """Validate one held value; ConfigurationError naming the joint or coordinate."""
    if name not in holdable:
        joint = holdable.get(name.split("[")[0], (None,))[0] if isinstance(name, str) else None
        if joint is None:
            raise ConfigurationError(f"{where}: joint {name!r}: unknown joint")
        known = ", ".join(repr(item) for item in joint_coordinate_names(joint)) if joint.type in ("U", "C") else \
            f"none: {'a' if joint.type == 'P' else 'an'} {joint.type} joint is held whole, give {joint.name!r}"
        raise ConfigurationError(f"{where}: joint coordinate {name!r}: unknown coordinate "
                                 f"(coordinates of {joint.name!r}: {known})")
    joint, (factor, *_) = holdable[name]
    if name == joint.name:
        validate_displacements(mechanism, {name: values[name]}, where)
        return
    if joint.name in values:
        raise ConfigurationError(f"{where}: joint {joint.name!r} is given twice ({joint.name!r} and {name!r})")
    scalar = SimpleNamespace(type="R" if kinematics_of(mechanism).ambient.factors[factor] == "S1" else "P")
    try:
        check_displacement(values[name], scalar, f"{where}: joint coordinate {name!r}")
    except MechanismError as error:
        raise ConfigurationError(str(error)) from None


def _problem(mechanism, values, hold_actuated, where):
    """Validate the held values and split K into held and free factors."""
    if not isinstance(values, dict):
        raise ConfigurationError(f"{where}: expected a mapping from joint names to values, "
                                 f"got {type(values).__name__}")
    ambient = kinematics_of(mechanism).ambient
    holdable = _holdable(mechanism)
    for name in values:
        _check_value(mechanism, holdable, values, name, where)
    named = {holdable[name][0].name for name in values}
    at_home = [joint.name for joint in mechanism.joints if hold_actuated and joint.actuated and joint.name not in named]
    held = {name: (np.asarray(value, dtype=float).tolist() if isinstance(value, (list, tuple, np.ndarray))
                   else float(value)) for name, value in values.items()}
    for name in at_home:  # R, P: a number; U, C: a pair (an S joint is never actuated)
        held[name] = 0.0 if len(holdable[name][1]) == 1 else [0.0] * len(holdable[name][1])
    target = from_displacements(mechanism, {name: values[name] for name in values if name in named}, where)
    for name in values:
        if name not in named:  # one coordinate of a U or C joint
            target[ambient.point_slices[holdable[name][1][0]]] = float(values[name])
    held_factors = {factor for name in held for factor in holdable[name][1]}
    free = [factor for factor in range(len(ambient.factors)) if factor not in held_factors]
    free_points = np.array([i for f in free for i in range(ambient.point_size)[ambient.point_slices[f]]], dtype=int)
    free_tangent = np.array([i for f in free for i in range(ambient.dim)[ambient.tangent_slices[f]]], dtype=int)
    given = ", ".join(f"{name} = {_format(held[name])}" for name in values)
    home_note = " and ".join(at_home) + " held at home"
    description = (f"{given} ({home_note})" if at_home else given) if given else \
        (home_note if at_home else "no joint held")
    return _Problem(mechanism, held, description, home(mechanism), target, free_points, free_tangent,
                    np.setdiff1d(np.arange(ambient.dim), free_tangent),
                    AmbientSpace(tuple(ambient.factors[f] for f in free), tuple(ambient.scales[f] for f in free)))


def _format(value):
    if isinstance(value, list):
        return "[" + ", ".join(_format(item) for item in value) + "]"
    return repr(float(value))


# ----------------------------------------------------------------------------- Newton

def _newton(fibre, starts, tolerance, max_iterations=60, max_step=0.5):
    """Damped Gauss-Newton on a fibre from a stack of starts.

    Parameters
    ----------
    fibre : ImplicitManifold
    starts : array_like, shape=[n, r]
        Points of the reduced space.
    tolerance : float
        Iterate until ‖Φ‖ ≤ tolerance · 1e-3 (or no decrease is possible).
    max_step : float
        Cap of the dimensionless step ``|u|``.

    Returns
    -------
    points : ndarray, shape=[n, r]
    residuals : ndarray, shape=[n]
    """
    ambient = fibre.ambient
    scales = ambient.tangent_scales
    points = np.array(starts, dtype=float)
    # with no free coordinate (point_size 0) a stack [n, 0] cannot be reshaped with -1
    points = points.reshape((len(points) if ambient.point_size == 0 else -1, ambient.point_size))
    values = np.asarray(fibre.constraint(points), dtype=float)
    norms = np.linalg.norm(values, axis=-1)
    active = np.isfinite(norms)
    if ambient.dim == 0:
        return points, norms
    earlier = norms.copy()
    for iteration in range(max_iterations):
        if iteration % 20 == 0:  # drop the starts stuck far from a solution (a local minimum of ‖Φ‖)
            if iteration:
                active &= (norms < 0.9 * earlier) | (norms < 1e-3)
            earlier = norms.copy()
        active &= norms > 1e-3 * tolerance
        rows = np.flatnonzero(active)
        if not rows.size:
            break
        steps = -minimum_norm_steps(fibre, points[rows], values[rows], rcond=1e-12)  # block by block if large
        lengths = np.linalg.norm(steps, axis=-1)
        steps *= np.minimum(1.0, max_step / np.maximum(lengths, 1e-300))[:, None]
        fraction = np.ones(rows.size)
        pending = np.ones(rows.size, dtype=bool)
        for _ in range(16):
            trying = np.flatnonzero(pending)
            if not trying.size:
                break
            trial = ambient.retract(points[rows[trying]], fraction[trying, None] * steps[trying] * scales)
            trial_values = np.asarray(fibre.constraint(trial), dtype=float)
            trial_norms = np.linalg.norm(trial_values, axis=-1)
            better = trial_norms < (1.0 - 1e-4 * fraction[trying]) * norms[rows[trying]]
            accepted = rows[trying[better]]
            points[accepted], values[accepted], norms[accepted] = trial[better], trial_values[better], \
                trial_norms[better]
            pending[trying[better]] = False
            fraction[trying[~better]] /= 2.0
        active[rows[pending]] = False  # no decrease along the step: converged to rounding or stalled
    return points, norms


def _wrapped(reduced, points):
    """Free angles wrapped to [−π, π) (others unchanged), shape=[..., r]."""
    points = np.array(points, dtype=float)
    for factor, part in zip(reduced.factors, reduced.point_slices):
        if factor == "S1":
            angle = points[..., part]
            outside = (angle < -np.pi) | (angle >= np.pi)
            points[..., part] = np.where(outside, (angle + np.pi) % (2 * np.pi) - np.pi, angle)
    return points


def _closed(problem, free, residuals, tolerance, base=None):
    """Which solutions count as assemblies: small residual, no half-turn loop, shape=[n]."""
    full = problem.embed(free, base)
    return np.isfinite(residuals) & (residuals <= tolerance) & closes(problem.mechanism, full, tolerance)


# ----------------------------------------------------------------------------- continuation

def _continuation(problem, tolerance, max_steps=2000):
    """Follow the home's branch while the held values move from home to the targets.

    Returns
    -------
    free : ndarray, shape=[r], or None when the walk stops before the targets
    """
    mechanism, ambient = problem.mechanism, kinematics_of(problem.mechanism).ambient
    delta = np.zeros(ambient.dim)
    delta[problem.held_tangent] = ambient.inverse_retract(problem.home, problem.target)[problem.held_tangent]
    size = float(np.linalg.norm(delta / ambient.tangent_scales))
    if size == 0.0:
        return None
    scales = problem.reduced.tangent_scales
    largest = min(1.0, 0.2 / size)
    step, reached = largest, 0.0
    current = problem.home.copy()
    for _ in range(max_steps):
        if step * size < 1e-5:
            return None
        goal = min(1.0, reached + step)
        base = problem.target if goal == 1.0 else ambient.retract(problem.home, goal * delta)
        jacobian = constraint_jacobian(mechanism, current)
        motion = jacobian[:, problem.held_tangent] @ ((goal - reached) * delta[problem.held_tangent])
        solved = minimum_norm_steps(configuration_space(mechanism), current[None], motion[None],
                                    columns=problem.free_tangent, rcond=1e-12)[0]  # block by block if large
        predicted = problem.reduced.retract(current[problem.free_points], -scales * solved)
        fibre = problem.fibre(base)
        corrected, residual = _newton(fibre, predicted[None], tolerance, max_iterations=25, max_step=0.1)
        move = np.linalg.norm(problem.reduced.inverse_retract(predicted, corrected[0]) / scales)
        if _closed(problem, corrected, residual, tolerance, base)[0] and move <= _JUMP:
            current = problem.embed(corrected[0], base)
            reached = goal
            if reached == 1.0:
                return corrected[0]
            step = min(2.0 * step, largest)
        else:
            step /= 2.0
    return None


# ----------------------------------------------------------------------------- candidates and branches

@dataclass(frozen=True, eq=False)
class _Found:
    free: np.ndarray   # [r]
    method: str


def _from_home(problem, method, tolerance):
    """The assembly reached from the home, and the smallest residual seen; (None, residual) on failure."""
    fibre = problem.fibre()
    start = problem.home[problem.free_points]
    smallest = math.inf
    if problem.reduced.dim == 0:  # nothing to solve: the targets are the only candidate, whatever the method
        free, residual = _newton(fibre, start[None], tolerance)
        if _closed(problem, free, residual, tolerance)[0]:
            return _Found(free[0], method or "newton"), float(residual[0])
        return None, float(residual[0])
    if method in (None, "newton"):
        free, residual = _newton(fibre, start[None], tolerance)
        smallest = float(residual[0])
        if _closed(problem, free, residual, tolerance)[0]:
            return _Found(_wrapped(problem.reduced, free[0]), "newton"), smallest
    if method in (None, "continuation"):
        free = _continuation(problem, tolerance)
        if free is not None:
            return _Found(_wrapped(problem.reduced, free), "continuation"), 0.0
        if method == "continuation":
            smallest = float(np.linalg.norm(constraint(problem.mechanism, problem.target)))
    return None, smallest


def _search(problem, rng, count, tolerance, guess_point=None):
    """Newton from the guess and from `count` random starts: the converged ones and the smallest residual."""
    fibre = problem.fibre()
    starts, methods = [], []
    if guess_point is not None:
        starts.append(guess_point[problem.free_points])
        methods.append("guess")
    if count > 0 and problem.reduced.dim > 0:  # with nothing free, every start is the targets (_from_home's)
        randoms = problem.reduced.random_point(rng, center=problem.home[problem.free_points], size=count)
        # onto the closing map first: from far starts, Gauss-Newton on Φ ends at half-turns for most loops
        starts += list(_newton(problem.fibre(closing=True), randoms, tolerance)[0])
        methods += ["search"] * count
    if not starts:
        return [], math.inf
    free, residuals = _newton(fibre, np.array(starts), tolerance)
    closed = _closed(problem, free, residuals, tolerance)
    found = [_Found(_wrapped(problem.reduced, free[i]), methods[i]) for i in np.flatnonzero(closed)]
    # the smallest residual of the candidates other than the zeros of Φ that turn a loop by a half-turn (residual
    # within √tolerance: Newton stalls near some of them): those are no near miss (0 when every finite candidate
    # is one, which _no_assembly says); a candidate far from any zero counts whatever its rotation
    finite = np.isfinite(residuals)
    half_turns = (finite & (residuals <= math.sqrt(tolerance))
                  & ~closes(problem.mechanism, problem.embed(free), np.inf))
    smallest = float(np.min(residuals[finite & ~half_turns], initial=math.inf))
    if not np.isfinite(smallest) and half_turns.any():
        smallest = 0.0
    return found, smallest


def _chart_from_home(problem, free):
    """Dimensionless chart vector from the home to the assembly, shape=[k]."""
    ambient = kinematics_of(problem.mechanism).ambient
    return ambient.inverse_retract(problem.home, problem.embed(free)) / ambient.tangent_scales


def _distinct(problem, found, tolerance):
    """Found solutions without repeats (the first found kept), in order of discovery."""
    kept = []
    scales = problem.reduced.tangent_scales
    same = max(_SAME, _STALL * math.sqrt(tolerance))
    for item in found:
        if all(np.linalg.norm(problem.reduced.inverse_retract(other.free, item.free) / scales) > same
               for other in kept):
            kept.append(item)
    return kept


def _isolated(problem, free):
    """Whether an assembly is an isolated point of its fibre.

    Full column rank of DΦ_q·diag(s) settles it; otherwise (a self-motion, too few held
    coordinates, or a fold where branches meet) a short continuation along the kernel
    (:func:`manifold.continue_curve`) decides: a curve of length 0.05 means not isolated.
    """
    fibre = problem.fibre()
    if problem.reduced.dim == 0:
        return True
    jacobian = np.asarray(fibre.constraint_jacobian(free), dtype=float) * problem.reduced.tangent_scales
    decision = numerical_rank(jacobian)
    if decision.rank == problem.reduced.dim:
        return True
    _, _, vh = np.linalg.svd(jacobian)
    for row in vh[decision.rank:]:
        for sign in (1.0, -1.0):
            curve = continue_curve(fibre, free, sign * row * problem.reduced.tangent_scales,
                                   length=0.05, step=0.01)
            if curve.reached:
                return False
    return True


def _sort_key(problem, item):
    chart = _chart_from_home(problem, item.free)
    return (round(float(np.linalg.norm(chart)), 9), tuple(np.round(chart, 9)))


def _assembly(problem, item, branch, branches):
    point = problem.embed(item.free)
    return Assembly(point=point, displacements=to_displacements(problem.mechanism, point), held=dict(problem.held),
                    residual=float(np.linalg.norm(constraint(problem.mechanism, point))),
                    distance=float(np.linalg.norm(_chart_from_home(problem, item.free))),
                    method=item.method, branch=branch, branches=branches)


def _check_options(method, count, tolerance, rng):
    if method not in (None, "newton", "continuation"):
        raise ConfigurationError(f"method: expected 'newton', 'continuation' or None, got {method!r}")
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 0:
        raise ConfigurationError(f"count: expected a non-negative integer, got {count!r}")
    if not (isinstance(tolerance, (int, float)) and math.isfinite(tolerance) and tolerance > 0):
        raise ConfigurationError(f"tolerance: expected a positive finite number, got {tolerance!r}")
    if rng is None:
        return np.random.default_rng(0)
    if not isinstance(rng, np.random.Generator):
        raise ConfigurationError(f"rng: expected a numpy.random.Generator, got {type(rng).__name__}")
    return rng


def _enumerate(problem, start, rng, count, tolerance, guess_point=None):
    """The distinct assemblies sorted by branch, whether they are isolated, and the smallest residual."""
    found, smallest = _search(problem, rng, count, tolerance, guess_point)
    distinct = _distinct(problem, ([start] if start is not None else []) + found, tolerance)
    isolated = all(_isolated(problem, item.free) for item in distinct)
    return sorted(distinct, key=lambda item: _sort_key(problem, item)), isolated, smallest


def _not_isolated(problem):
    return AssemblyError(f"the assemblies with {problem.description} are not isolated: the other joints can "
                         f"still move, so they have no branch numbers (hold more joints)")


def _no_assembly(problem, smallest, tolerance=1e-10):
    if math.isfinite(smallest) and smallest <= tolerance:
        return AssemblyError(f"no assembly with {problem.description}: the loops cannot close (the only zeros of "
                             f"the loop equations found close a loop with a half-turn)")
    residual = f"{smallest:.3g}" if math.isfinite(smallest) else "not finite"
    return AssemblyError(f"no assembly with {problem.description}: the loops cannot close "
                         f"(smallest residual {residual})")


# ----------------------------------------------------------------------------- public API

def assemblies(mechanism, values, rng=None, *, guess=None, count=128, hold_actuated=True, method=None,
               tolerance=1e-10, where="values"):
    """Every assembly found with the given joints held at the given values, numbered by branch.

    Parameters
    ----------
    mechanism : Mechanism
    values : dict
        Joint name (or coordinate name of a U or C joint) -> value, as
        displacements from home (the mapping ``--at`` gives).
    rng : numpy.random.Generator, optional
        Draws the random starts; default ``numpy.random.default_rng(0)``.
    guess : dict, optional
        Joint displacements from home of one more start.
    count : int
        Number of random starts of the free coordinates.
    hold_actuated : bool
        Hold the actuated joints that `values` does not name at home.
    method : {None, "newton", "continuation"}
        How the start from the home is followed (None: Newton, then continuation).
    tolerance : float
        Largest ‖Φ‖ of an assembly; the default 1e-10 is below
        :data:`mechanisms.CLOSURE_TOLERANCE`, so :func:`mechanisms.configuration`
        accepts the displacements found.
    where : str
        What error messages name the values as (``"--at"`` for the command line).

    Returns
    -------
    tuple of Assembly
        Sorted by branch (distance from home); ``item.branch`` is its index.

    Raises
    ------
    ConfigurationError
        Naming the field, for unknown joints, malformed or non-finite values.
    AssemblyError
        If no assembly is found (the message names the inputs and the smallest
        residual reached), or the assemblies are not isolated.
    """
    rng = _check_options(method, count, tolerance, rng)
    problem = _problem(mechanism, values, hold_actuated, where)
    guess_point = None if guess is None else from_displacements(mechanism, guess, "guess")
    start, smallest = _from_home(problem, method, tolerance)
    found, isolated, searched = _enumerate(problem, start, rng, count, tolerance, guess_point)
    if not found:
        raise _no_assembly(problem, min(smallest, searched))
    if not isolated:
        raise _not_isolated(problem)
    return tuple(_assembly(problem, item, index, len(found)) for index, item in enumerate(found))


def assemble(mechanism, values, branch=None, guess=None, rng=None, *, count=128, hold_actuated=True, method=None,
             tolerance=1e-10, where="values"):
    """The mechanism assembled with the given joints held exactly at the given values.

    Parameters
    ----------
    mechanism : Mechanism
    values : dict
        Joint name (or coordinate name of a U or C joint) -> value, as
        displacements from home: a number for R and P joints, a pair for U and
        C, a rotation vector for S (the mapping ``--at`` gives).
    branch : int, optional
        Select the branch-th assembly of :func:`assemblies` (sorted by distance
        from home). Default: the assembly reached from the home.
    guess : dict, optional
        Joint displacements from home: select the assembly nearest ``home ⊕ guess``
        (Newton from the guess is one more start).
    rng : numpy.random.Generator, optional
        Draws the random starts of the branch search; default
        ``numpy.random.default_rng(0)``, so that calls are reproducible.
    count : int
        Number of random starts of the branch search.
    hold_actuated : bool
        Hold the actuated joints that `values` does not name at home (default).
    method : {None, "newton", "continuation"}
        From the home: Newton, then continuation when Newton fails (None), or
        only one of them. Continuation follows the home's branch.
    tolerance : float
        Largest ‖Φ‖ accepted (default 1e-10, below :data:`mechanisms.CLOSURE_TOLERANCE`).
    where : str
        What error messages name the values as.

    Returns
    -------
    Assembly

    Raises
    ------
    ConfigurationError
        Naming the field, for unknown joints, malformed or non-finite values,
        a bad `branch`, or both `branch` and `guess`.
    AssemblyError
        (a ConfigurationError) If there is no assembly at these values: the
        message names the held values and the smallest residual reached; or the
        requested branch was not found.

    Notes
    -----
    Without `branch` and `guess`: Newton from the home with the held
    coordinates fixed; on failure, continuation from the home along the
    inputs; on failure, the random search (the assembly nearest the home).
    The branch of the result is numbered by the search (its list is that of
    :func:`assemblies` with the same arguments); it is None where the
    assemblies are not isolated.

    Examples
    --------
    >>> from mechanisms.catalogue.five_bar import five_bar
    >>> mechanism = five_bar(theta1=1.8, theta2=1.3)
    >>> reached = assemble(mechanism, {"A": 0.2, "B": -0.2})
    >>> reached.displacements["A"], reached.displacements["B"], reached.method
    (0.2, -0.2, 'newton')
    """
    rng = _check_options(method, count, tolerance, rng)
    if branch is not None and guess is not None:
        raise ConfigurationError("branch, guess: give one of them, not both")
    if branch is not None and (isinstance(branch, bool) or not isinstance(branch, (int, np.integer)) or branch < 0):
        raise ConfigurationError(f"branch: expected a non-negative integer, got {branch!r}")
    problem = _problem(mechanism, values, hold_actuated, where)
    guess_point = None if guess is None else from_displacements(mechanism, guess, "guess")
    start, smallest = _from_home(problem, method, tolerance)
    selecting = branch is not None or guess is not None
    if start is None and method is not None and not selecting:
        raise _no_assembly(problem, smallest)
    found, isolated, searched = _enumerate(problem, start, rng, count, tolerance, guess_point)
    if not found:
        raise _no_assembly(problem, min(smallest, searched))
    if not selecting:
        start = found[0] if start is None else start  # no way from the home: the nearest assembly
        if not isolated:
            return _assembly(problem, start, None, None)
        index = next(index for index, item in enumerate(found) if item is start)
        return _assembly(problem, start, index, len(found))
    if not isolated:
        raise _not_isolated(problem)
    if branch is not None and branch >= len(found):
        known = "branch 0" if len(found) == 1 else f"branches 0 to {len(found) - 1}"
        raise AssemblyError(f"branch {branch}: only {len(found)} assembl{'y' if len(found) == 1 else 'ies'} "
                            f"found with {problem.description} ({known})")
    if guess is not None:
        ambient = kinematics_of(mechanism).ambient
        branch = int(np.argmin([np.linalg.norm(ambient.inverse_retract(guess_point, problem.embed(item.free))
                                               / ambient.tangent_scales) for item in found]))
    return _assembly(problem, found[branch], int(branch), len(found))
