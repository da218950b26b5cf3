"""Forward kinematics of line-plane 5-SPU platforms: every assembly mode from the five leg lengths.

Three routes, which the tests hold against each other:

1. **The paper's polynomial route** (:func:`assembly_modes`; Borràs, Thomas &
   Torras 2011 Section II-B, Section IV-C). Leg k closes when
   ‖p + zₖ i − aₖ‖² = lₖ², i.e.

       s + 2zₖ t − 2xₖ pₓ − 2yₖ p_y − 2xₖzₖ u − 2yₖzₖ v = lₖ² − xₖ² − yₖ² − zₖ²,

   linear in the six unknowns (s, t, pₓ, p_y, u, v) = (‖p‖², p·i, pₓ, p_y, u, v)
   with the rows (1, 2zₖ, −2xₖ, −2yₖ, −2xₖzₖ, −2yₖzₖ) of (12) up to column
   scales. Its solutions form a line X(τ) = X₀ + τN (N ∝ the cofactors
   C₁ … C₆, the paper's (7) with τ in place of t, which also covers
   C₁ = 0). The three remaining conditions p_z² = s − pₓ² − p_y²,
   w² = 1 − u² − v², p_z w = t − pₓu − p_yv give

       g(τ) = (t − pₓu − p_yv)² − (s − pₓ² − p_y²)(1 − u² − v²) = 0,

   the paper's polynomial (10): its τ⁴ coefficient is −(N_pₓN_v − N_p_yN_u)²
   ∝ (C₂C₅ − C₃C₄)², which vanishes when B is at infinity, and its τ³
   coefficient vanishes too when B∞ is at infinity (Section IV-C). Each root
   gives pₓ, p_y, u, v and two (p_z, w) of opposite signs (the mirror images
   in the base plane): 8, 6 or 4 assembly modes for the quartic, cubic and
   quadratic families, complex ones included. The coefficients above the
   family's degree (:func:`classify.line_plane_pencil.family`) are dropped (they
   are rounding). Computed on the normalised design
   (:func:`classify.line_plane_design.normalised`), then mapped back.

   A mode is *real* when the imaginary parts of p (over L) and i are at most
   :data:`REAL_TOLERANCE`; real modes are then polished by Newton's method on
   the six equations ‖bₖ − aₖ‖² = lₖ², ‖i‖² = 1. At leg lengths of a
   singular configuration (a zero of (17)) g has a double root, which
   rounding splits into two nearby roots giving the same two poses: real
   modes closer than :data:`REAL_TOLERANCE` (‖Δp‖/L + ‖Δi‖) are one mode,
   listed once with its ``multiplicity``.

2. **The framework's general route** (:func:`framework_assembly_modes`). The
   5-SPU is built as a closedchain joint graph
   (:func:`mechanisms.catalogue.five_spu.five_spu`, spin locked so that the
   assemblies are isolated) at a start pose, and :func:`mechanisms.assemble`
   moves its five actuated prismatic joints to the requested lengths (Newton
   from the start, else continuation along the inputs). The platform pose
   of the assembly, read with :func:`mechanisms.link_pose`, is one mode;
   many random starts (and the mirror image in the base plane of each mode
   found, a symmetry of every line-plane 5-SPU) give the set. This route
   knows nothing of the cofactors.

3. **The quadratic family's closed forms** (:func:`quadratic_assembly_modes`,
   eqs. 26-32), after the change of frame that brings a quadratic design to
   the paper's normal form zᵢ = δxᵢ, x₁ = y₁ = 0 (:func:`quadratic_normal_form`).

The paper's (7) defines E₂ … E₅ but is lost from the text; they are
reconstructed here as Cramer's numerators (see :func:`quadratic_quantities`),
and the paper's n₂, n₁, n₀ and (29)-(32) are checked against them in the
tests.

References
----------
Borràs, Thomas & Torras 2011 Sections II-B, IV-C, V-A, eqs. (10), (26)-(32).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .line_plane import DesignError, family, normalised, cofactors

__all__ = [
    "REAL_TOLERANCE", "AssemblyMode", "leg_lengths", "check_lengths", "mode_residual", "assembly_modes",
    "polynomial_coefficients", "framework_assembly_modes", "QuadraticNormalForm", "quadratic_normal_form",
    "quadratic_quantities", "quadratic_assembly_modes", "same_modes",
]

#: a mode is real when the imaginary parts of p/L and i are at most this, and real modes closer than this are one
#: (:func:`_merge_coincident`). At a singularity g has a double root, which leg lengths off by δ (relative) split
#: by about c √δ: c ≈ 16 at the catalogue 5-SPU's eq. 33 (1.6e-5 at δ = 1e-12). With 1e-6 a rounding of 1e-14
#: (a design read 150 lengths from the origin) or lengths off by 1e-12 turned its two double modes into four
#: real or four complex ones; 1e-4 merges them for δ up to ~4e-11, and merges distinct modes only that close to
#: a singularity (where their count changes: legs farther off have their own four modes, as they should)
REAL_TOLERANCE = 1e-4


@dataclass(frozen=True, eq=False)
class AssemblyMode:
    """One assembly mode: the pose (p, i) of the platform line.

    Attributes
    ----------
    position : ndarray, shape=[3]
        p (complex for a complex mode).
    direction : ndarray, shape=[3]
        i, with i·i = 1 (complex for a complex mode).
    real : bool
    residual : float
        :func:`mode_residual`: the largest leg-length error (a length).
    closure : float or None
        ‖Φ‖ of the closedchain assembly (framework route only).
    multiplicity : int
        How many roots of (10), counted with multiplicity, give this pose: 2
        (or more) at the leg lengths of a singular configuration.
    """

    position: np.ndarray
    direction: np.ndarray
    real: bool
    residual: float
    closure: Optional[float] = None
    multiplicity: int = 1

    def to_dict(self):
        """JSON-ready: real modes as lists of floats; complex ones as {"real": [...], "imag": [...]}."""
        def vector(values):
            if self.real:
                return np.real(values).tolist()
            return {"real": np.real(values).tolist(), "imag": np.imag(values).tolist()}
        result = {"real": self.real, "p": vector(self.position), "i": vector(self.direction),
                  "residual": self.residual, "multiplicity": self.multiplicity}
        if self.closure is not None:
            result["closure"] = self.closure
        return result


# ------------------------------------------------------------------------------------------------ inverse kinematics

def _base3(design):
    return np.column_stack([design.base, np.zeros(5)])


def leg_lengths(design, position, direction):
    """The leg lengths lₖ = ‖p + zₖ i − aₖ‖ at poses, shape=[..., 5].

    Parameters
    ----------
    design : LinePlaneDesign
    position, direction : array_like, shape=[..., 3]
        p and i (normalised here).
    """
    position = np.asarray(position, dtype=float)
    direction = np.asarray(direction, dtype=float)
    direction = direction / np.linalg.norm(direction, axis=-1, keepdims=True)
    attachments = position[..., None, :] + design.platform[:, None] * direction[..., None, :]
    return np.linalg.norm(attachments - _base3(design), axis=-1)


def check_lengths(lengths):
    """Five positive finite leg lengths, shape=[5]; DesignError (field ``legs``) otherwise."""
    try:
        lengths = np.array(lengths, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise DesignError("legs: expected five numbers", "legs") from None
    if lengths.shape[0] != 5:
        raise DesignError(f"legs: a line-plane 5-SPU has five legs, got {lengths.shape[0]} lengths", "legs")
    if not np.all(np.isfinite(lengths)) or np.any(lengths <= 0):
        raise DesignError("legs: the lengths must be positive finite numbers", "legs")
    return lengths


def mode_residual(design, lengths, position, direction):
    """max(``|(bₖ − aₖ)·(bₖ − aₖ) − lₖ²|`` / (2lₖ), L·``|i·i − 1|``): a length (bilinear, so complex poses too)."""
    legs = position[None, :] + design.platform[:, None] * direction[None, :] - _base3(design)
    squared = np.sum(legs * legs, axis=1)
    errors = np.abs(squared - lengths ** 2) / (2 * lengths)
    unit = abs(np.sum(direction * direction) - 1.0) * design.characteristic_length
    return float(max(np.max(errors), unit))


# ------------------------------------------------------------------------------------------------ polynomial route

def _linear_system(design, lengths):
    """Rows (1, 2z, −2x, −2y, −2xz, −2yz) and right-hand sides lₖ² − xₖ² − yₖ² − zₖ² (5 equations in X)."""
    x, y, z = design.base[:, 0], design.base[:, 1], design.platform
    matrix = np.column_stack([np.ones(5), 2 * z, -2 * x, -2 * y, -2 * x * z, -2 * y * z])
    return matrix, lengths ** 2 - x ** 2 - y ** 2 - z ** 2


def _line_of_solutions(design, lengths):
    """X₀ (least norm) and N (unit null vector) of the linear system: X(τ) = X₀ + τN, each shape=[6]."""
    matrix, right = _linear_system(design, lengths)
    _, _, rows = np.linalg.svd(matrix)
    null = rows[-1]
    particular = np.linalg.lstsq(matrix, right, rcond=None)[0]
    return particular - (particular @ null) * null, null


def polynomial_coefficients(design, lengths, degree=None):
    """The coefficients of g(τ) (the paper's (10) in the parameter τ), lowest first, shape=[degree + 1].

    Parameters
    ----------
    design : LinePlaneDesign
        Taken as given (normalise it first for a well-scaled polynomial).
    lengths : array_like, shape=[5]
    degree : int, optional
        Keep the coefficients up to this degree (default 4: all).
    """
    from numpy.polynomial import polynomial as P

    origin, null = _line_of_solutions(design, np.asarray(lengths, dtype=float))
    s, t, p_x, p_y, u, v = ([o, n] for o, n in zip(origin, null))
    left = P.polysub(t, P.polyadd(P.polymul(p_x, u), P.polymul(p_y, v)))
    height = P.polysub(s, P.polyadd(P.polymul(p_x, p_x), P.polymul(p_y, p_y)))
    vertical = P.polysub([1.0], P.polyadd(P.polymul(u, u), P.polymul(v, v)))
    coefficients = np.zeros(5)
    value = P.polysub(P.polymul(left, left), P.polymul(height, vertical))
    coefficients[:len(value)] = value
    return coefficients[:(4 if degree is None else degree) + 1]


def _poses_of_root(origin, null, root):
    """The two poses (p, i) of one root τ (complex arithmetic), each a pair of arrays shape=[3]."""
    s, t, p_x, p_y, u, v = origin + root * null
    vertical = 1 - u * u - v * v
    height = s - p_x * p_x - p_y * p_y
    product = t - p_x * u - p_y * v
    poses = []
    for sign in (1.0, -1.0):
        if abs(vertical) >= abs(height):
            w = sign * np.sqrt(complex(vertical))
            p_z = product / w if w != 0 else 0.0
        else:
            p_z = sign * np.sqrt(complex(height))
            w = product / p_z if p_z != 0 else 0.0
        poses.append((np.array([p_x, p_y, p_z], dtype=complex), np.array([u, v, w], dtype=complex)))
    return poses


def _polish(design, lengths, position, direction, iterations=8):
    """Newton's method on ‖bₖ − aₖ‖² = lₖ², ‖i‖² = 1 in the six unknowns (p, i) (real poses)."""
    base = _base3(design)
    best = (position, direction, mode_residual(design, lengths, position, direction))
    for _ in range(iterations):
        legs = position[None, :] + design.platform[:, None] * direction[None, :] - base
        values = np.append(np.sum(legs ** 2, axis=1) - lengths ** 2, direction @ direction - 1.0)
        jacobian = np.zeros((6, 6))
        jacobian[:5, :3] = 2 * legs
        jacobian[:5, 3:] = 2 * design.platform[:, None] * legs
        jacobian[5, 3:] = 2 * direction
        step = np.linalg.lstsq(jacobian, -values, rcond=None)[0]
        position, direction = position + step[:3], direction + step[3:]
        residual = mode_residual(design, lengths, position, direction)
        if residual < best[2]:
            best = (position, direction, residual)
        else:
            break
    return best


def _sort(modes):
    """Real modes first (by decreasing p_z, then pₓ, p_y), then complex ones (by real parts)."""
    def key(mode):
        p = np.real(mode.position)
        return (not mode.real, -round(p[2], 9), round(p[0], 9), round(p[1], 9),
                tuple(np.round(np.real(mode.direction), 9)), tuple(np.round(np.imag(mode.position), 9)))
    return tuple(sorted(modes, key=key))


def assembly_modes(design, lengths, rtol=None):
    """Every assembly mode at the given leg lengths, by the paper's polynomial route (module notes, route 1).

    Parameters
    ----------
    design : LinePlaneDesign
    lengths : array_like, shape=[5]
    rtol : float, optional
        Family cut (:func:`classify.line_plane_pencil.family`); its default when None.

    Returns
    -------
    tuple of AssemblyMode
        2 × (the family's degree) modes — 8, 6, 4 — counted with their
        ``multiplicity`` (coincident real modes are listed once), real ones
        first.

    Raises
    ------
    DesignError
        For bad lengths (field ``legs``), or an architecturally singular design
        (its assembly modes are not isolated).

    References
    ----------
    Borràs, Thomas & Torras 2011 Section II-B (eq. 10 and the two (p_z, w)
    per root), Section IV-C (degrees 4, 3, 2).
    """
    lengths = check_lengths(lengths)
    kind = family(design) if rtol is None else family(design, rtol)
    if kind.degree is None:
        raise DesignError("base: the design is architecturally singular: its assembly modes are not isolated")
    unit = normalised(design)
    centre, length = design.centre, design.characteristic_length
    unit_lengths = lengths / length
    coefficients = polynomial_coefficients(unit, unit_lengths, kind.degree)
    roots = np.roots(coefficients[::-1])
    origin, null = _line_of_solutions(unit, unit_lengths)
    modes = []
    shift = np.array([centre[0], centre[1], 0.0])
    for root in roots:
        for position, direction in _poses_of_root(origin, null, root):
            imaginary = max(np.max(np.abs(position.imag)), np.max(np.abs(direction.imag)))
            real = bool(imaginary <= REAL_TOLERANCE)
            if real:
                position, direction, _ = _polish(unit, unit_lengths, position.real, direction.real)
            # back to the design's frame: p = L p' + (x̄, ȳ, 0) − z̄ i
            position = length * position + shift - centre[2] * direction
            residual = mode_residual(design, lengths, position, direction)
            modes.append(AssemblyMode(position, direction, real, residual))
    return _sort(_merge_coincident(modes, length))


def _merge_coincident(modes, length):
    """The modes with real ones closer than REAL_TOLERANCE (``_distance``) merged into one, multiplicities added."""
    merged = []
    for mode in modes:
        twin = next((index for index, kept in enumerate(merged) if mode.real and kept.real and _distance(
            mode.position, mode.direction, kept.position, kept.direction, length) <= REAL_TOLERANCE), None)
        if twin is None:
            merged.append(mode)
            continue
        kept = merged[twin]
        best = kept if kept.residual <= mode.residual else mode
        merged[twin] = AssemblyMode(best.position, best.direction, True, best.residual, best.closure,
                                    kept.multiplicity + mode.multiplicity)
    return merged


# ------------------------------------------------------------------------------------------------ framework route

def _start_poses(design, lengths, rng, count):
    """Random line poses about the base: p over the base (spread L), |p_z| about the mean leg length."""
    centre, length = design.centre, design.characteristic_length
    directions = rng.normal(size=(count, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    heights = np.abs(rng.normal(np.mean(lengths), length, size=count)) * rng.choice([-1.0, 1.0], size=count)
    positions = np.column_stack([centre[0] + length * rng.normal(size=count),
                                 centre[1] + length * rng.normal(size=count), heights])
    return positions - centre[2] * directions, directions


def _assemble_from(design, lengths, position, direction):
    """Build the 5-SPU at the pose, move its legs to `lengths`; (p, i, ‖Φ‖) or None."""
    from mechanisms import AssemblyError, MechanismError, assemble, link_pose
    from mechanisms.catalogue.five_spu import five_spu

    parameters = {}
    for index in range(5):
        parameters[f"x{index + 1}"], parameters[f"y{index + 1}"] = (float(value) for value in design.base[index])
        parameters[f"z{index + 1}"] = float(design.platform[index])
    try:
        mechanism = five_spu(**parameters, p_x=float(position[0]), p_y=float(position[1]), p_z=float(position[2]),
                             u=float(direction[0]), v=float(direction[1]), w=float(direction[2]),
                             spin="locked", end_effector="none")
        start = leg_lengths(design, position, direction)
        reached = assemble(mechanism, {f"P{index + 1}": float(lengths[index] - start[index]) for index in range(5)},
                           count=0)
    except (AssemblyError, MechanismError):
        return None
    transform = link_pose(mechanism, "platform", reached.point)
    rotation, translation = transform[:3, :3], transform[:3, 3]
    return rotation @ position + translation, rotation @ direction, float(reached.residual)


def framework_assembly_modes(design, lengths, rng=None, starts=24, expected=None, mirror=True):
    """The real assembly modes found by the framework's general route (module notes, route 2).

    Parameters
    ----------
    design : LinePlaneDesign
    lengths : array_like, shape=[5]
    rng : numpy.random.Generator, optional
        Draws the start poses; default ``numpy.random.default_rng(0)``.
    starts : int
        Random start poses.
    expected : int, optional
        Stop once this many distinct modes are found (a search cannot find
        more modes than exist; the poses are still compared by the caller).
    mirror : bool
        Also start from the mirror image (p_z, w) → (−p_z, −w) of each mode found.

    Returns
    -------
    tuple of AssemblyMode
        Real modes, distinct to 1e-6·L, sorted as :func:`assembly_modes`;
        ``closure`` is ‖Φ‖ of the closedchain assembly.
    """
    lengths = check_lengths(lengths)
    rng = np.random.default_rng(0) if rng is None else rng
    length = design.characteristic_length
    positions, directions = _start_poses(design, lengths, rng, starts)
    queue = list(zip(positions, directions))
    found = []
    tried = 0
    while queue and tried < 4 * starts and (expected is None or len(found) < expected):
        position, direction = queue.pop(0)
        tried += 1
        result = _assemble_from(design, lengths, position, direction)
        if result is None:
            continue
        position, direction, closure = result
        if any(_distance(position, direction, mode.position, mode.direction, length) < 1e-6 for mode in found):
            continue
        found.append(AssemblyMode(position, direction, True, mode_residual(design, lengths, position, direction),
                                  closure))
        if expected is not None and len(found) >= expected:
            break
        if mirror:
            queue.insert(0, (position * np.array([1, 1, -1]), direction * np.array([1, 1, -1])))
    return _sort(found)


def _distance(position, direction, other_position, other_direction, length):
    return float(np.linalg.norm(position - other_position) / length + np.linalg.norm(direction - other_direction))


def same_modes(modes, others, length, tolerance=1e-6):
    """Whether two lists of real modes hold the same poses (to `tolerance`·L and `tolerance` in i), any order."""
    first = [mode for mode in modes if mode.real]
    second = [mode for mode in others if mode.real]
    if len(first) != len(second):
        return False
    unused = list(range(len(second)))
    for mode in first:
        gaps = [_distance(np.real(mode.position), np.real(mode.direction), np.real(second[index].position),
                          np.real(second[index].direction), length) for index in unused]
        if not gaps or min(gaps) > tolerance:
            return False
        unused.pop(int(np.argmin(gaps)))
    return True


# ------------------------------------------------------------------------------------------------ quadratic family

@dataclass(frozen=True, eq=False)
class QuadraticNormalForm:
    """A quadratic design in the paper's frame: zᵢ' = δxᵢ', x₁' = y₁' = 0 (eq. 26).

    The frame: a' = Q(a − a₁) (Q a rotation about the vertical taking the
    normal of the B-lines to ±x, the sign that makes δ ≥ 0), z' = z − z₁; a pose maps as
    p' = Q(p + z₁ i − a₁), i' = Q i.

    Attributes
    ----------
    x, y : ndarray, shape=[5]
        The base attachments in the new frame (x[0] = y[0] = 0).
    delta : float
        δ of (26).
    rotation : ndarray, shape=[3, 3]
        Q.
    origin : ndarray, shape=[3]
        a₁ (with 0 height).
    shift : float
        z₁.
    deviation : float
        max ``|zᵢ' − δxᵢ'|`` / L: how far the design is from the form (26).
    """

    x: np.ndarray
    y: np.ndarray
    delta: float
    rotation: np.ndarray
    origin: np.ndarray
    shift: float
    deviation: float

    def pose_from_paper(self, position, direction):
        """(p, i) in the design's frame from (p', i') in the paper's."""
        direction = self.rotation.T @ direction
        return self.rotation.T @ position + self.origin - self.shift * direction, direction


def quadratic_normal_form(design):
    """The change of frame to the paper's normal form (26) of a quadratic design.

    Raises
    ------
    DesignError
        If the design is not of the quadratic family.
    """
    name = family(design).name
    if name != "quadratic":
        raise DesignError(f"base: the closed forms (29)-(32) are for quadratic designs, this one is {name}")
    c1, c2, c3, c4, c5, c6 = cofactors(design)
    angle = np.arctan2(c3, c2)
    z = design.platform - design.platform[0]
    origin = np.array([design.base[0, 0], design.base[0, 1], 0.0])
    for turn in (0.0, np.pi):   # the half-turn that makes δ positive
        cosine, sine = np.cos(angle + turn), np.sin(angle + turn)
        rotation = np.array([[cosine, sine, 0.0], [-sine, cosine, 0.0], [0.0, 0.0, 1.0]])
        local = (rotation @ (_base3(design) - origin).T).T
        x, y = local[:, 0], local[:, 1]
        delta = float(x @ z / (x @ x))
        if delta >= 0:
            break
    deviation = float(np.max(np.abs(z - delta * x)) / design.characteristic_length)
    return QuadraticNormalForm(x, y, delta, rotation, origin, float(design.platform[0]), deviation)


def quadratic_quantities(x, y, delta, lengths):
    """F (28), E₂ … E₅ (the lost (7), as Cramer's numerators), n₂, n₁, n₀ and Δ (30) of a normal-form design.

    With x₁ = y₁ = 0 and zₖ = δxₖ, leg 1 gives ‖p‖² = l₁², and legs k = 2…5

        xₖ(pₓ − δt) + yₖp_y + δxₖ²u + δxₖyₖv = hₖ = (l₁² − lₖ² + (1 + δ²)xₖ² + yₖ²)/2,

    a 4 × 4 system M (pₓ − δt, p_y, u, v)ᵀ = h with det M = δ²F. Eₖ is the
    determinant of M with column k − 1 replaced by h, so that
    pₓ = (δ³Ft + E₂)/(δ²F), p_y = E₃/(δ²F), u = E₄/(δ²F), v = E₅/(δ²F),
    as (31), (32) read.

    Parameters
    ----------
    x, y : array_like, shape=[5]
        Base attachments, x[0] = y[0] = 0.
    delta : float
    lengths : array_like, shape=[5]

    Returns
    -------
    dict
        ``F``, ``E`` (E₂, E₃, E₄, E₅), ``n`` (n₂, n₁, n₀ as printed in
        Section V-A), ``discriminant`` (Δ as printed in (30)).

    References
    ----------
    Borràs, Thomas & Torras 2011 eqs. (28), (30) and the coefficients of (10) in Section V-A.
    """
    x, y, lengths = (np.asarray(values, dtype=float) for values in (x, y, lengths))
    xs, ys = x[1:], y[1:]
    F = float(np.linalg.det(np.column_stack([xs ** 2, xs * ys, xs, ys])))
    matrix = np.column_stack([xs, ys, delta * xs ** 2, delta * xs * ys])
    right = (lengths[0] ** 2 - lengths[1:] ** 2 + (1 + delta ** 2) * xs ** 2 + ys ** 2) / 2
    E = []
    for column in range(4):
        replaced = matrix.copy()
        replaced[:, column] = right
        E.append(float(np.linalg.det(replaced)))
    E2, E3, E4, E5 = E
    d, l1 = delta, lengths[0]
    n2 = ((d ** 2 + 1) * d ** 2 * F ** 2 - 2 * d * F * E4 - E5 ** 2) / (d ** 2 * F ** 2)
    n1 = 2 * (E2 * d ** 4 * F ** 2 - F * d * (E4 * E2 + E5 * E3) - E5 * (E2 * E5 - E3 * E4)) / (d ** 5 * F ** 3)
    n0 = ((E2 ** 2 + E3 ** 2 + l1 ** 2 * (E4 ** 2 + E5 ** 2)) * F ** 2 * d ** 4 - (E2 * E5 - E4 * E3) ** 2) \
        / (d ** 8 * F ** 4) - l1 ** 2
    discriminant = d * F * (E5 ** 2 + E4 ** 2 - d ** 4 * F ** 2) * (
        2 * d ** 4 * F ** 2 * E4 * l1 ** 2 + d ** 3 * F * (E5 ** 2 * l1 ** 2 + E3 ** 2) + d * F * (E2 ** 2 + E3 ** 2)
        - (d ** 2 + 1) * d ** 5 * F ** 3 * l1 ** 2 + 2 * E3 * (E2 * E5 - E4 * E3))
    return {"F": F, "E": (E2, E3, E4, E5), "n": (n2, n1, n0), "discriminant": discriminant}


def quadratic_assembly_modes(design, lengths, pairing=-1):
    """The four assembly modes of a quadratic design by the closed forms (29), (31), (32).

    t = [δ⁴F²E₂ − δF(E₂E₄ + E₅E₃) + E₅(E₃E₄ − E₂E₅) ± √Δ'] / [δ³F(2δFE₄ + E₅² − (δ² + 1)δ²F²)]   (29)
    p = ((δ³Ft + E₂)/(δ²F), E₃/(δ²F), ±[(E₄ − δF)δ³Ft + E₄E₂ + E₅E₃]/(δ²F√S))   (31)
    i = (E₄/(δ²F), E₅/(δ²F), ±√S/(δ²F)),  S = δ⁴F² − E₅² − E₄²   (32)

    Parameters
    ----------
    design : LinePlaneDesign
        A quadratic design (any frame: :func:`quadratic_normal_form`).
    lengths : array_like, shape=[5]
    pairing : {-1, 1}
        The sign of p_z's ± relative to w's. The printed (31), (32) leave it
        open; t = p·i forces p_z w = t − pₓu − p_yv, which holds with opposite
        signs (−1, the default); +1 gives the poses as printed with equal signs.

    Returns
    -------
    tuple of AssemblyMode
        The four modes (complex ones included), real ones first, in the design's frame.

    Notes
    -----
    Δ' is the discriminant of n₂t² + n₁t + n₀ scaled by (δ⁵F³/2)²,
    Δ' = δ¹⁰F⁶(n₁² − 4n₂n₀)/4, which is what (29) needs; the printed (30) is
    compared with it in the tests.

    References
    ----------
    Borràs, Thomas & Torras 2011 eqs. (26)-(32).
    """
    lengths = check_lengths(lengths)
    form = quadratic_normal_form(design)
    quantities = quadratic_quantities(form.x, form.y, form.delta, lengths)
    F, (E2, E3, E4, E5), (n2, n1, n0) = quantities["F"], quantities["E"], quantities["n"]
    d = form.delta
    scaled = d ** 10 * F ** 6 * (n1 ** 2 - 4 * n2 * n0) / 4
    numerator = d ** 4 * F ** 2 * E2 - d * F * (E2 * E4 + E5 * E3) + E5 * (E3 * E4 - E2 * E5)
    denominator = d ** 3 * F * (2 * d * F * E4 + E5 ** 2 - (d ** 2 + 1) * d ** 2 * F ** 2)
    root = np.sqrt(complex(scaled))
    S = np.sqrt(complex(d ** 4 * F ** 2 - E5 ** 2 - E4 ** 2))
    modes = []
    for t in ((numerator + root) / denominator, (numerator - root) / denominator):
        for sign in (1.0, -1.0):
            p_z = pairing * sign * ((E4 - d * F) * d ** 3 * F * t + E4 * E2 + E5 * E3) / (d ** 2 * F * S)
            position = np.array([(d ** 3 * F * t + E2) / (d ** 2 * F), E3 / (d ** 2 * F), p_z], dtype=complex)
            direction = np.array([E4 / (d ** 2 * F), E5 / (d ** 2 * F), sign * S / (d ** 2 * F)], dtype=complex)
            position, direction = form.pose_from_paper(position, direction)
            imaginary = max(np.max(np.abs(position.imag)) / design.characteristic_length,
                            np.max(np.abs(direction.imag)))
            real = bool(imaginary <= REAL_TOLERANCE)
            if real:
                position, direction = position.real, direction.real
            modes.append(AssemblyMode(position, direction, real,
                                      mode_residual(design, lengths, position, direction)))
    return _sort(modes)
