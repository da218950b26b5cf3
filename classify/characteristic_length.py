"""The characteristic length L and the isotropic postures (Chablat, Caro, Wenger & Angeles 2002 §3.3-3.4).

The orientation columns of the direct-kinematics matrix A have units of
length², the others of length; dividing them by L makes A (eq. 7) and the
Jacobians J̄ = Ā⁻¹B, K̄ = B⁻¹Ā dimensionless. L is found three ways:

* in closed form where the isotropy conditions K̄K̄ᵀ = τ²1 (eqs. 9a-f) have a
  solution: for the 3-PRR, L = √(−k₁k₂ / l₁ᵀl₂) (from eq. 9d), which under
  the conditions (10a-d) is L = √2 r sin γ (§3.4), γ = ∠BᵢCᵢP; the isotropic
  postures form a family (one L per γ), and the paper's choice γ = π/2
  (Fig. 4a) is its largest L, so the length reported is the largest L at which
  an isotropic posture exists (:func:`three_prr_characteristic_length`): √2 r
  where γ = π/2 is reachable;
* by minimising κ(K̄) over L *and* the posture (scipy.optimize), reported with
  the optimal posture (:func:`optimal_characteristic_length`);
* for any other mechanism with a pose output, by minimising κ(J̄) over L
  and the posture in a chart of M (:func:`mechanism_optimal_length`); where
  κ = 1 is reached, along the family of isotropic postures to its largest L
  (:func:`largest_isotropic_length`), so that L depends neither on the
  optimiser's start nor on the chart, axis signs or units.

Isotropic postures (κ = 1) are located by minimising κ over postures from
several starts and keeping the minima with κ − 1 ≤ a tolerance
(:func:`isotropic_postures`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .conditioning import condition_numbers, singular_value_ratio
from .conditioning_matrices import three_prr_matrices

__all__ = [
    "CharacteristicLength", "three_prr_length", "three_prr_leg_angles", "isotropy_length", "isotropy_residuals",
    "three_prr_kappa", "optimal_characteristic_length", "isotropic_postures",
    "mechanism_optimal_length", "largest_isotropic_length", "length_window",
    "three_prr_characteristic_length",
]

#: κ − 1 below which a minimum counts as isotropic (the optimiser reaches ~1e-10 on the 3-PRR)
ISOTROPY_TOLERANCE = 1e-6


@dataclass(frozen=True)
class CharacteristicLength:
    """A characteristic length and how it was found.

    Attributes
    ----------
    value : float
        L (the mechanism's units of length); None when no output is an orientation (no L is needed).
    method : str
        ``"closed_form"``, ``"optimised"``, ``"given"`` or ``"not_needed"``.
    posture : tuple of float or None
        The posture where it was found (the 3-PRR: x, y, φ).
    kappa : float or None
        κ(K̄) there (1 at an isotropic posture).
    reference : str
    """

    value: float | None
    method: str
    posture: tuple | None = None
    kappa: float | None = None
    reference: str = ""

    def to_dict(self):
        return {"value": self.value, "method": self.method,
                "posture": None if self.posture is None else [float(value) for value in self.posture],
                "kappa": self.kappa, "reference": self.reference}


def three_prr_length(platform_radius, gamma):
    """L = √2 r sin γ (Chablat, Caro, Wenger & Angeles 2002 §3.4), shape of `gamma`."""
    return np.sqrt(2.0) * platform_radius * np.sin(gamma)


def three_prr_leg_angles(poses, signs, platform_radius=100.0, base_radius=200.0, leg_length=200.0):
    """γᵢ = ∠BᵢCᵢP (eq. 8d) of the 3-PRR at stacks of poses, shape=[..., 3], in [0, π]."""
    from .conditioning_matrices import _unit

    poses = np.asarray(poses, dtype=float)
    direct, _, _ = three_prr_matrices(poses, signs, platform_radius, base_radius, leg_length)
    legs = direct[..., :2]                                    # lᵢ = cᵢ − bᵢ
    vertex_angles = np.radians([210.0, 330.0, 90.0])
    to_centre = -platform_radius * _unit(vertex_angles + poses[..., 2:3])   # p − cᵢ
    cosine = -np.einsum("...ij,...ij->...i", legs, to_centre) / (
        np.linalg.norm(legs, axis=-1) * platform_radius)
    return np.arccos(np.clip(cosine, -1.0, 1.0))


def isotropy_length(direct, orientation_column=2):
    """L from eq. 9d, √(−k₁k₂ / l₁ᵀl₂), for stacks of (unnormalised) A; NaN where it has no real value.

    Parameters
    ----------
    direct : array_like, shape=[..., n, n]
        A with rows [lᵢᵀ, kᵢ] (kᵢ the orientation entry).
    orientation_column : int
    """
    direct = np.asarray(direct, dtype=float)
    legs = np.delete(direct, orientation_column, axis=-1)
    moments = direct[..., orientation_column]
    with np.errstate(invalid="ignore", divide="ignore"):
        squared = -moments[..., 0] * moments[..., 1] / np.einsum("...i,...i->...", legs[..., 0, :], legs[..., 1, :])
    return np.where(squared > 0, np.sqrt(np.where(squared > 0, squared, 0.0)), np.nan)


def isotropy_residuals(direct, inverse, length, orientation_column=2):
    """The isotropy conditions (eqs. 9a-f) at L, relative: K̄K̄ᵀ/τ² − 1 with τ² the mean of K̄K̄ᵀ's diagonal.

    Returns
    -------
    ndarray, shape=[..., n, n]
        0 exactly where K̄ = B⁻¹Ā is isotropic; the diagonal entries are (9a-c), the others (9d-f).
    """
    from .conditioning import normalise_orientation

    normalised = normalise_orientation(direct, length, (orientation_column,))
    diagonal = np.diagonal(np.asarray(inverse, dtype=float), axis1=-2, axis2=-1)
    rows = normalised / diagonal[..., :, None]
    product = rows @ np.swapaxes(rows, -1, -2)
    scale = np.mean(np.diagonal(product, axis1=-2, axis2=-1), axis=-1)[..., None, None]
    return product / scale - np.eye(product.shape[-1])


def three_prr_kappa(length, poses, signs, matrix="B-1A", platform_radius=100.0, base_radius=200.0,
                    leg_length=200.0):
    """κ of one matrix of the 3-PRR at stacks of poses (∞ out of reach or singular), shape=[...]."""
    direct, inverse, reachable = three_prr_matrices(poses, signs, platform_radius, base_radius, leg_length)
    safe_direct = np.where(reachable[..., None, None], direct, np.eye(3))
    safe_inverse = np.where(reachable[..., None, None], inverse, np.eye(3))
    values = condition_numbers(safe_direct, safe_inverse, length, (2,)).values[matrix]
    return np.where(reachable, values, np.inf)


def optimal_characteristic_length(kappa, start_length, start_posture, length_bounds=None, rng=None, restarts=4,
                                  spread=0.2, scales=None):
    """Minimise κ over L and the posture (scipy.optimize, Nelder–Mead on (log L, posture / `scales`)).

    Parameters
    ----------
    kappa : callable
        ``kappa(length, posture) -> float`` (∞ where the posture is out of reach or singular).
    start_length : float
    start_posture : array_like, shape=[p]
    length_bounds : tuple of float, optional
        (low, high) for L; default start_length · (1e-3, 1e3).
    rng : numpy.random.Generator, optional
        Perturbs the starts of the restarts (default seeded 0).
    restarts : int
        Extra starts, each the best so far moved by `spread` (relative in L, in the scaled posture by its
        size + 1).
    scales : array_like, shape=[p], optional
        A size of each posture coordinate (the 3-PRR: l, l, 1 for x, y, φ): the search runs on posture /
        `scales`, so that it takes the same steps in any unit of length (default 1: the posture's own units).

    Returns
    -------
    CharacteristicLength
        ``method="optimised"``, with the optimal posture and κ there.
    """
    from scipy.optimize import minimize

    rng = np.random.default_rng(0) if rng is None else rng
    low, high = (start_length * 1e-3, start_length * 1e3) if length_bounds is None else length_bounds
    start_posture = np.asarray(start_posture, dtype=float)
    scales = np.ones_like(start_posture) if scales is None else np.asarray(scales, dtype=float)
    reference = float(start_length)

    def objective(variables):
        length = reference * float(np.exp(variables[0]))
        if not low <= length <= high:
            return 1e12
        value = float(kappa(length, variables[1:] * scales))
        return value if np.isfinite(value) else 1e12

    best = np.concatenate([[0.0], start_posture / scales])
    best_value = objective(best)
    for attempt in range(restarts + 1):
        start = best if attempt == 0 else best + spread * rng.standard_normal(best.shape) * (np.abs(best) + 1)
        result = minimize(objective, start, method="Nelder-Mead",
                          options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 4000, "maxfev": 8000})
        if result.fun < best_value:
            best, best_value = result.x, float(result.fun)
    return CharacteristicLength(reference * float(np.exp(best[0])), "optimised",
                                tuple(float(value) for value in best[1:] * scales), best_value,
                                "Chablat, Caro, Wenger & Angeles 2002 §3.2 (κ(Ā) minimised over L and the posture)")


def isotropic_postures(kappa, starts, tolerance=ISOTROPY_TOLERANCE, separation=1e-4, max_evaluations=8000,
                       scales=None):
    """Postures where κ = 1, by minimising κ over the posture from each start (Nelder–Mead).

    Parameters
    ----------
    kappa : callable
        ``kappa(posture) -> float``.
    starts : array_like, shape=[s, p]
    tolerance : float
        κ − 1 ≤ tolerance counts as isotropic (the margin is returned with each posture).
    separation : float
        Postures closer than this in every coordinate, in units of `scales`, are the same.
    max_evaluations : int
        Of κ, per start.
    scales : array_like, shape=[p], optional
        A size of each posture coordinate (the 3-PRR: l, l, 1 for x, y, φ): the search runs on posture /
        `scales` and compares postures there, so that neither the steps nor the count of postures found depend
        on the unit of length (default 1: the posture's own units).

    Returns
    -------
    list of (ndarray shape=[p], float)
        (posture, κ − 1), in the order found.
    """
    from scipy.optimize import minimize

    starts = np.atleast_2d(np.asarray(starts, dtype=float))
    scales = np.ones(starts.shape[-1]) if scales is None else np.asarray(scales, dtype=float)
    found = []
    for start in starts / scales:
        def objective(scaled):
            value = float(kappa(scaled * scales))
            return value if np.isfinite(value) else 1e12
        result = minimize(objective, start, method="Nelder-Mead",
                          options={"xatol": 1e-10, "fatol": 1e-13, "maxiter": max_evaluations,
                                   "maxfev": max_evaluations})
        margin = float(result.fun) - 1.0
        if margin > tolerance:
            continue
        scaled = np.asarray(result.x, dtype=float)
        if not any(np.max(np.abs(scaled - known / scales)) < separation for known, _ in found):
            found.append((scaled * scales, margin))
    return found


#: relative width of the bracket at which the largest isotropic L is taken as found (well below the precision
#: that ISOTROPY_TOLERANCE on κ gives L: near the largest L, κ − 1 grows like the relative excess of L)
LENGTH_PRECISION = 1e-8
#: windows (κ's minima at trial lengths) the sweep of :func:`largest_isotropic_length` takes down from `high`
#: before it bisects; on the 3-PRR and the planar 3-RRR the first window already ends at the largest L
SWEEP_STEPS = 8


def length_window(length, value, tolerance=0.0, exponent=1):
    """The lengths excluded by κ's minimum over the postures at one L: no posture has κ ≤ 1 + `tolerance` there.

    D(L') = D(L) diag(L'/L on the rotation rows, 1 on the others) changes every singular value of J̄ by a factor
    between min(ρ, 1) and max(ρ, 1), ρ = L'/L, so κ(L', q) ≥ κ(L, q) / max(ρ, 1/ρ) at every posture q. If
    κ(L, q) ≥ `value` at every q, then κ(L', q) > 1 + `tolerance` for ρ strictly between (1 + `tolerance`) /
    `value` and `value` / (1 + `tolerance`). At an isotropic posture q of length L_q (J̄(L_q) J̄(L_q)ᵀ = τ² 1,
    Chablat, Caro, Wenger & Angeles 2002 §3.3) κ(L, q) = max(L/L_q, L_q/L) exactly, so the window is as wide
    as it can be: at L above the largest isotropic L, L/`value` is that largest L wherever the minimum of κ
    over the postures is reached on the isotropic family (the 3-PRR, the planar 3-RRR). Where L also divides
    the columns of some actuated rates (angular ones, beside prismatic ones:
    :func:`classify.conditioning.actuator_lengths`), κ changes by up to max(ρ, 1/ρ)² (`exponent` 2) and the
    window is that of (`value` / (1 + `tolerance`))^½.

    Parameters
    ----------
    length : float
        L, where κ's minimum over the postures is `value`.
    value : float
        min over the postures of κ(J̄(L)) (≥ 1); only a global minimum excludes anything.
    tolerance : float
    exponent : int
        κ(L', q) ≥ κ(L, q) / max(ρ, 1/ρ)^`exponent`.

    Returns
    -------
    tuple of float
        (low, high): no L' in the open interval has a posture with κ ≤ 1 + `tolerance` (empty where `value` ≤
        1 + `tolerance`).
    """
    ratio = (float(value) / (1.0 + tolerance)) ** (1.0 / exponent)
    if not ratio > 1.0:
        return float(length), float(length)
    return float(length) / ratio, float(length) * ratio


def largest_isotropic_length(kappa, length, posture, high, tolerance=ISOTROPY_TOLERANCE, max_evaluations=600,
                             precision=LENGTH_PRECISION, length_at=None, sweep_steps=SWEEP_STEPS, exponent=1):
    """The largest L at which an isotropic posture exists, at most `high`, given an isotropic (L, posture).

    Where κ = 1 is reached, it is reached along a family: on the 3-PRR every γ gives an isotropic posture
    with L = √2 r sin γ (Chablat, Caro, Wenger & Angeles 2002 §3.4), so "the L minimising κ over L and the
    posture" is whichever member an optimiser reaches, and it changes with the chart, axis signs and units.
    The canonical member is the largest L: for the 3-PRR it is the paper's √2 r (γ = π/2, "a configuration
    furthest away from parallel singularities", §3.4) wherever γ = π/2 is reachable, and the γ closest to
    π/2 otherwise. It depends on the mechanism only (scaled with its lengths).

    The isotropic lengths are the image of the isotropic postures under q ↦ L_q, so they form an interval only
    where the isotropic postures within reach are connected (on the 3-PRR, one arc of φ at P = O, where
    L = √2 r sin γ, §3.4); the search does not assume one. It sweeps down from `high`: at a trial L, κ is
    minimised over the postures (Nelder–Mead, from the last posture found); a minimum κ_min above
    1 + `tolerance` excludes every L' from L (1 + `tolerance`) / κ_min to L (:func:`length_window`), and the
    next trial is just below that edge (relative `precision` / 2). The first isotropic trial ends the sweep:
    within `precision` of the edge above it, it is the largest isotropic L wherever the minima found are
    global, however the isotropic lengths are split (a local minimum can hide a larger one, as in any local
    search). One more trial, just above the edge (relative `tolerance`), checks that the edge's minimum was
    global. Where κ_min = L / L_max above the largest L (the minimum on the isotropic family: the 3-PRR, the
    planar 3-RRR) the first window ends at the largest L, and the search takes three minimisations. After
    `sweep_steps` windows (κ_min growing more slowly than L), or where the check is isotropic, the rest is
    bisected (geometrically) between the largest isotropic trial and the smallest non-isotropic one (or an
    edge) until the bracket's relative width is below `precision`, which assumes one interval there.

    A posture counts as isotropic with κ − 1 ≤ `tolerance`, so the L found can be up to about `tolerance`
    (relative) above the largest L; with `length_at`, L is then replaced by the isotropic L of the posture
    found (its minimiser of κ over L, ≤ the largest L), which removes that excess where the largest L is a
    smooth maximum over the family (γ = π/2 on the 3-PRR: the error becomes quadratic).

    Parameters
    ----------
    kappa : callable
        ``kappa(length, posture) -> float`` (∞ where undefined).
    length : float
        An L at which `posture` is isotropic.
    posture : array_like, shape=[p]
    high : float
        The largest L tried.
    tolerance : float
        κ − 1 ≤ tolerance counts as isotropic.
    max_evaluations : int
        Of κ, per posture minimisation.
    precision : float
    length_at : callable, optional
        ``length_at(posture) -> (L, κ)``: the L minimising κ at a posture, and κ there.
    sweep_steps : int
        Windows swept down from `high` before bisecting (at least 1: `high` is always tried).
    exponent : int
        Of :func:`length_window`: 2 where L also scales some actuated rates.

    Returns
    -------
    length : float
        The largest isotropic L found (the largest isotropic trial, or `length_at` there).
    posture : ndarray, shape=[p]
        An isotropic posture there.
    kappa : float
        κ there (≤ 1 + tolerance).
    """
    from scipy.optimize import minimize

    def isotropic_at(trial, start):
        result = minimize(lambda variables: _finite(kappa(trial, variables)), start, method="Nelder-Mead",
                          options={"xatol": 1e-12, "fatol": 1e-14, "maxiter": max_evaluations,
                                   "maxfev": max_evaluations})
        return float(result.fun) - 1.0 <= tolerance, np.asarray(result.x, dtype=float), float(result.fun)

    posture = np.asarray(posture, dtype=float)
    best = _finite(kappa(length, posture))
    start, upper, excluded = posture, None, None   # upper: the smallest non-isotropic trial; excluded: an edge
    trial, steps = float(high), 0
    while length < high and steps < max(sweep_steps, 1) and trial > length:   # the sweep, down from `high`
        isotropic, found, value = isotropic_at(trial, start)
        if isotropic:
            length, posture, best = trial, found, value
            break
        steps, upper, start = steps + 1, trial, found
        excluded = length_window(trial, value, tolerance, exponent)[0] if value < 1e12 else None
        if excluded is None:
            break
        trial = excluded * (1.0 - precision / 2.0)
    if upper is not None and excluded is not None:
        if max(excluded, length) / length - 1.0 <= precision:   # landed: was the window's minimum global?
            check = min(max(excluded, length) * (1.0 + max(tolerance, precision)), upper)
            isotropic, found, value = isotropic_at(check, posture) if check < upper else (False, None, None)
            if isotropic:
                length, posture, best = check, found, value
            else:
                upper = max(excluded, length)
        elif excluded > length:   # the sweep stopped: nothing isotropic above its last edge
            upper = excluded
    while upper is not None and upper / length - 1.0 > precision:   # bisection: one interval assumed
        trial = float(np.sqrt(length * upper))
        isotropic, found, value = isotropic_at(trial, posture)
        if isotropic:
            length, posture, best = trial, found, value
        else:
            low, top = length_window(trial, value, tolerance, exponent)
            upper = low if length < low and top >= upper and value < 1e12 else trial
    if length_at is not None:
        snapped, value = length_at(posture)
        if value - 1.0 <= tolerance:
            length, best = snapped, value
    return float(length), posture, float(best)


#: orientations φ sampled per working mode by :func:`three_prr_characteristic_length` before refinement
THREE_PRR_ORIENTATION_SAMPLES = 3600
#: relative isotropy residual (eqs. 9a-f, :func:`isotropy_residuals`) below which a posture counts as isotropic
ISOTROPY_RESIDUAL_TOLERANCE = 1e-8
#: ‖mᵢ‖ below this fraction of l: B singular (a serial singularity; K̄ undefined)
SERIAL_TOLERANCE = 1e-9


def _three_prr_isotropic_lengths(orientations, signs, platform_radius, base_radius, leg_length):
    """L of eq. 9d at P = O and the given orientations, NaN where the posture is not isotropic, shape=[s]."""
    orientations = np.atleast_1d(np.asarray(orientations, dtype=float))
    poses = np.stack([np.zeros_like(orientations), np.zeros_like(orientations), orientations], axis=-1)
    direct, inverse, reachable = three_prr_matrices(poses, signs, platform_radius, base_radius, leg_length)
    diagonal = np.abs(np.diagonal(np.nan_to_num(inverse), axis1=-2, axis2=-1))
    regular = reachable & np.all(diagonal > SERIAL_TOLERANCE * leg_length, axis=-1)
    safe_direct = np.where(regular[:, None, None], direct, np.eye(3))
    safe_inverse = np.where(regular[:, None, None], inverse, np.eye(3))
    lengths = isotropy_length(safe_direct)
    residual = np.abs(isotropy_residuals(safe_direct, safe_inverse, np.where(np.isfinite(lengths), lengths, 1.0)))
    isotropic = regular & np.isfinite(lengths) & (np.max(residual, axis=(-2, -1)) <= ISOTROPY_RESIDUAL_TOLERANCE)
    return np.where(isotropic, lengths, np.nan)


def three_prr_characteristic_length(platform_radius=100.0, base_radius=200.0, leg_length=200.0,
                                    samples=THREE_PRR_ORIENTATION_SAMPLES):
    """The 3-PRR's characteristic length: the largest L at which an isotropic posture exists (2002 §3.3-3.4).

    The isotropy conditions (eqs. 9a-f, 10a-d) put the isotropic postures of this layout at P = O (the
    centre of the base triangle: the legs, pivots and rails then all turn by 2π/3 from leg to leg), with equal
    γᵢ and L = √(−k₁k₂ / l₁ᵀl₂) = √2 r sin γ (§3.4), one for each reachable orientation φ. They form a
    family, so minimising κ over (L, posture) does not fix L. The paper takes γ = π/2 (Fig. 4a, "furthest
    away from parallel singularities"), the largest L of the family: this function returns that largest L,
    which is √2 r whenever γ = π/2 is reachable (r² + l² ≥ R²/4 at the catalogue's layout) and
    √2 r sin γ at the reachable γ closest to π/2 otherwise. It depends on (r, R, l) only, and scales with
    them.

    Parameters
    ----------
    platform_radius, base_radius, leg_length : float
        r, R, l.
    samples : int
        Orientations sampled over [−π, π) per working mode; the best is refined by a bounded scalar search
        between its neighbours.

    Returns
    -------
    CharacteristicLength
        ``method="closed_form"`` (L = √2 r sin γ at the isotropic posture found), the posture (0, 0, φ) and
        κ(K̄) there (1 up to rounding), or None when no posture of any working mode is isotropic.
    """
    from mechanisms.catalogue.three_prr import WORKING_MODES
    from scipy.optimize import minimize_scalar

    orientations = np.linspace(-np.pi, np.pi, samples, endpoint=False)
    step = orientations[1] - orientations[0]
    best = None
    for mode in sorted(WORKING_MODES):
        signs = WORKING_MODES[mode]
        lengths = _three_prr_isotropic_lengths(orientations, signs, platform_radius, base_radius, leg_length)
        if not np.any(np.isfinite(lengths)):
            continue
        index = int(np.nanargmax(lengths))
        centre = orientations[index]

        def negative_length(orientation):
            value = _three_prr_isotropic_lengths(orientation, signs, platform_radius, base_radius, leg_length)[0]
            return -value if np.isfinite(value) else 0.0

        refined = minimize_scalar(negative_length, bounds=(centre - step, centre + step), method="bounded",
                                  options={"xatol": 1e-12})
        orientation, value = (refined.x, -refined.fun) if -refined.fun >= lengths[index] else (centre,
                                                                                              lengths[index])
        if best is None or value > best[0] * (1 + 1e-12):
            best = (float(value), float(orientation), signs)
    if best is None:
        return None
    value, orientation, signs = best
    pose = np.array([0.0, 0.0, orientation])
    gamma = float(three_prr_leg_angles(pose, signs, platform_radius, base_radius, leg_length)[0])
    kappa = float(three_prr_kappa(value, pose, signs, "B-1A", platform_radius, base_radius, leg_length))
    return CharacteristicLength(value, "closed_form", (0.0, 0.0, orientation), kappa,
                                f"Chablat, Caro, Wenger & Angeles 2002 §3.4: L = √2 r sin γ at the isotropic "
                                f"posture with γ closest to π/2 (the largest isotropic L; γ = "
                                f"{np.degrees(gamma):.6g}°, working mode signs {tuple(signs)})")


# ------------------------------------------------------------------------------------------------ any mechanism

def _posture_chart(mechanism, point, length):
    """``v -> (q, J̄)``: the configuration ``project(point ⊕ T v)`` (T a tangent basis at `point`, orthonormal
    for the dimensionless inner product ⟨·,·⟩_s, so v is dimensionless; m = dim M entries) and its J̄ at
    L = `length` (:func:`classify.conditioning.mechanism_jacobians`); (None, None) where the projection fails."""
    from manifold import ProjectionError, project, tangent_basis

    from .conditioning import mechanism_jacobians
    from .model import model_of

    manifold = model_of(mechanism, length_scale=length).manifold
    basis = tangent_basis(manifold, point)[0]

    def chart(posture):
        try:
            configuration = project(manifold, manifold.ambient.retract(point, basis @ np.asarray(posture)))
        except ProjectionError:   # this posture is not on M nearby
            return None, None
        configuration = np.asarray(configuration, dtype=float)
        jacobian = mechanism_jacobians(mechanism, configuration[None], length)[0][0]
        return configuration, jacobian
    return chart, basis.shape[1]


def mechanism_optimal_length(mechanism, point, rng=None, restarts=3, spread=0.5, max_evaluations=400,
                             length_bounds=None, tolerance=ISOTROPY_TOLERANCE):
    """L minimising κ(J̄) over L and the posture, for any mechanism with a pose output, and its isotropic postures.

    With ρ = L / L₀, L₀ the mechanism's characteristic length, J̄(L) = D(ρ) J̄(L₀) C(ρ), D = diag(ρ on the
    rotation rows, 1 on the others) (the end-effector metric H = diag(L², …, 1, …),
    :func:`classify.metrics.end_effector_metric`) and C = diag(1/ρ on the angular actuated rates, 1 on the
    others) (:func:`classify.conditioning.actuator_lengths`; a common factor, without effect on κ, unless
    revolute and prismatic joints are both actuated), so for each posture the best L is a 1-D bounded
    minimisation (``minimize_scalar`` on log ρ); the posture is minimised over by Nelder–Mead in a chart of M
    at `point` (``project(point ⊕ T v)``, T a tangent basis orthonormal for the dimensionless inner product,
    v ∈ ℝ^m, m = dim M) from `point` and `restarts` random starts (v ~ `spread`·N(0, 1)). Every quantity
    searched over or compared (log ρ, v, the distance between two postures in units of the tangent scales s)
    is dimensionless, so the search takes the same steps in any unit of length and L scales with it. Postures
    with κ − 1 ≤ `tolerance` at the optimal L are isotropic (Chablat, Caro, Wenger & Angeles 2002 §3.3:
    K̄K̄ᵀ = τ²1). Where the minimum is isotropic, κ = 1 holds along a family of (L, posture) (§3.4:
    L = √2 r sin γ on the 3-PRR), and the minimiser is an arbitrary member: L is then continued to the
    family's largest value (:func:`largest_isotropic_length`), the paper's γ = π/2 on the 3-PRR, which
    depends neither on the start nor on the chart, axis signs or units.

    Parameters
    ----------
    mechanism : Mechanism
        n actuators = n outputs = dim M, a pose or orientation output.
    point : array_like, shape=[point_size]
        On M; the chart's centre.
    rng : numpy.random.Generator, optional
        Default seeded 0.
    restarts : int
    spread : float
    max_evaluations : int
        Of the posture objective, per start.
    length_bounds : tuple of float, optional
        Default the mechanism's characteristic length × (1e-3, 1e3).
    tolerance : float

    Returns
    -------
    found : CharacteristicLength
        ``method="optimised"``, ``posture`` = the optimal configuration's joint displacements from home (one
        per coordinate, ``mechanism.coordinate_names``), ``kappa`` = κ(J̄) there.
    isotropic : list of (dict, float)
        (joint displacements, κ − 1) of the minima with κ − 1 ≤ `tolerance` at the L found, distinct (apart by
        more than :data:`POSTURE_SEPARATION` in some coordinate, in units of its tangent scale); the posture of
        the largest isotropic L first.
    """
    from mechanisms import to_displacements
    from mechanisms.kinematics import kinematics_of
    from scipy.optimize import minimize, minimize_scalar

    from .conditioning import actuator_lengths
    from .metrics import end_effector_metric
    from .model import model_of

    rng = np.random.default_rng(0) if rng is None else rng
    point = np.asarray(point, dtype=float)
    base = float(mechanism.characteristic_length)
    low, high = (base * 1e-3, base * 1e3) if length_bounds is None else length_bounds
    rotation_rows = np.diag(end_effector_metric(mechanism, 2.0 * base)) != np.diag(end_effector_metric(mechanism,
                                                                                                        base))
    if not np.any(rotation_rows):
        raise ValueError(f"{mechanism.name}: no orientation output: no characteristic length is needed")
    angular_columns = actuator_lengths(mechanism, model_of(mechanism).actuators, 2.0) != 1.0
    exponent = 2 if np.any(angular_columns) and not np.all(angular_columns) else 1
    chart, dimension = _posture_chart(mechanism, point, base)
    cache = {}

    def evaluate(posture):
        key = tuple(np.round(posture, 14))
        if key not in cache:
            cache[key] = chart(posture)
        return cache[key]

    def scaled(jacobian, ratio):   # J̄ at L = ρ L₀ from J̄ at L₀
        return (np.where(rotation_rows, ratio, 1.0)[:, None] * jacobian
                * np.where(angular_columns, 1.0 / ratio, 1.0)[None, :])

    bounds = (float(np.log(low / base)), float(np.log(high / base)))

    def best_length(jacobian, refine=False):
        def value(logarithm):
            return _finite(singular_value_ratio(scaled(jacobian, np.exp(logarithm))))
        result = minimize_scalar(value, bounds=bounds, method="bounded", options={"xatol": 1e-10})
        logarithm, kappa = float(result.x), float(result.fun)
        if refine:   # the bounded search stops within √ε ‖log ρ‖ (≤ 1e-7): once more about its minimiser
            offsets = (max(bounds[0] - logarithm, -REFINE_WIDTH), min(bounds[1] - logarithm, REFINE_WIDTH))
            again = minimize_scalar(lambda offset: value(logarithm + offset), bounds=offsets, method="bounded",
                                    options={"xatol": 1e-13})
            if again.fun <= kappa:
                logarithm, kappa = logarithm + float(again.x), float(again.fun)
        return base * float(np.exp(logarithm)), kappa

    def objective(posture):
        _, jacobian = evaluate(posture)
        if jacobian is None or not np.all(np.isfinite(jacobian)):
            return 1e12
        return best_length(jacobian)[1]

    starts = [np.zeros(dimension)] + [spread * rng.standard_normal(dimension) for _ in range(restarts)]
    minima = []
    for start in starts:
        result = minimize(objective, start, method="Nelder-Mead",
                          options={"xatol": 1e-9, "fatol": 1e-12, "maxiter": max_evaluations,
                                   "maxfev": max_evaluations})
        minima.append((float(result.fun), np.asarray(result.x)))
    value, posture = min(minima, key=lambda item: item[0])
    configuration, jacobian = evaluate(posture)
    length, kappa = best_length(jacobian, refine=True)
    reference = ("κ(J̄) minimised over L and the posture (Chablat, Caro, Wenger & Angeles 2002 §3.2-3.4), "
                 "J̄ = H^½ Df T (Λ E^½ Dπ T)⁻¹")
    if kappa - 1.0 <= tolerance:   # an isotropic family: its largest L (2002 §3.4), not the optimiser's pick
        def kappa_at(trial_length, trial_posture):
            _, trial_jacobian = evaluate(trial_posture)
            if trial_jacobian is None or not np.all(np.isfinite(trial_jacobian)):
                return np.inf
            return singular_value_ratio(scaled(trial_jacobian, trial_length / base))

        def length_at(trial_posture):
            _, trial_jacobian = evaluate(trial_posture)
            return best_length(trial_jacobian, refine=True)

        largest, top, top_kappa = largest_isotropic_length(kappa_at, length, posture, high, tolerance,
                                                           max_evaluations=max(max_evaluations, 600),
                                                           length_at=length_at, exponent=exponent)
        if top_kappa - 1.0 <= max(FAMILY_FACTOR * (kappa - 1.0), FAMILY_FLOOR):
            length, posture, kappa = largest, top, top_kappa
            minima.insert(0, (kappa, posture))
            reference += ("; κ = 1 on a family of (L, posture): the largest L with an isotropic posture (2002 "
                          "§3.4: L = √2 r sin γ is largest at γ = π/2, the isotropic posture furthest from "
                          "parallel singularities)")
        else:   # the search climbed the band κ ≤ 1 + tolerance about an isolated isotropic posture: no family
            reference += "; κ = 1 at an isolated posture (no family of isotropic postures through it)"
        configuration, jacobian = evaluate(posture)
    else:
        reference += "; no isotropic posture found (κ > 1 at the minimum)"

    def displacements(configuration):
        return {name: value for name, value in to_displacements(mechanism, configuration).items()}

    ambient = kinematics_of(mechanism).ambient

    def distinct(configuration, known):   # dimensionless: coordinate differences in units of their scales
        difference = ambient.inverse_retract(known, configuration) / ambient.tangent_scales
        return np.max(np.abs(difference)) >= POSTURE_SEPARATION

    found = CharacteristicLength(length, "optimised",
                                 tuple(float(entry) for entry in _coordinates(displacements(configuration))),
                                 kappa, reference)
    isotropic, seen = [], []
    for _, candidate in minima[:1] + sorted(minima[1:], key=lambda item: item[0]):
        configuration, jacobian = evaluate(candidate)
        if jacobian is None:
            continue
        margin = float(singular_value_ratio(scaled(jacobian, length / base))) - 1.0
        if margin <= tolerance and all(distinct(configuration, known) for known in seen):
            seen.append(configuration)
            isotropic.append((displacements(configuration), margin))
    return found, isotropic


#: the largest isotropic L of :func:`mechanism_optimal_length` stands where its posture is isotropic to within
#: FAMILY_FACTOR times the optimiser's own κ − 1 (or FAMILY_FLOOR): on a family the posture of the largest L is
#: isotropic to rounding (κ − 1 ≈ 1e-15 on the 3-PRR and the planar 3-RRR); about an isolated isotropic posture
#: (a 3-PRR with a rail turned 25°) the search only climbs the band κ ≤ 1 + tolerance, to κ − 1 ≈ 1e-6 and an L
#: 1.6e-5 above the isotropic one, and the optimiser's posture and L (κ − 1 ≈ 2e-10) stand
FAMILY_FACTOR = 10.0
FAMILY_FLOOR = 1e-9
#: half-width (in log ρ) of :func:`mechanism_optimal_length`'s second search for the best L at a posture, about
#: the first one's minimiser (which is within √ε ‖log ρ‖ ≤ 1e-7 of it, ρ ≤ 1e3)
REFINE_WIDTH = 1e-6
#: two isotropic postures of :func:`mechanism_optimal_length` are the same when no coordinate differs by this
#: much in units of its tangent scale (radians; lengths over the characteristic length)
POSTURE_SEPARATION = 1e-6


def _finite(value):
    value = float(value)
    return value if np.isfinite(value) else 1e12


def _coordinates(displacements):
    return np.concatenate([np.atleast_1d(np.asarray(value, dtype=float)) for value in displacements.values()])
