"""Isoconditioning maps: 1/κ over Cartesian or joint grids per working mode, global index, contours.

A map holds 1/κ (in [0, 1], 0 at a singularity, NaN where the grid point is
out of reach in the working mode) of each matrix over a grid. The papers' maps:

* the 3-PRR (Chablat, Caro, Wenger & Angeles 2002 §3.6, Figs. 6-8): over a
  grid of positions P = (x, y), "the optimum conditioning according to the
  orientation of the end-effector": the largest 1/κ over a set of
  orientations φ (all at once per φ, vectorised over the positions);
* the five-bar (Chablat, Wenger & Angeles 1998 §3.4, Figs. 3-5): over (x, y)
  per working mode, or over the actuated angles (θ1, θ2) per assembly branch;
* the hybrid (same paper §5): its in-plane map over (distance to AB, position
  along AB); the 3-D map is that one turned about AB (θ1 enters neither A
  nor B, eqs. 22, 24-25), so isoconditioning surfaces are surfaces of
  revolution.

Any other mechanism (n inputs = n outputs = n dof) is mapped from its batched
Jacobians (:func:`mechanism_map`), over a grid of joint coordinates
(:func:`joint_grid_maps`) or of output coordinates (:func:`cartesian_grid_maps`),
one map per working mode.

The global conditioning index of a mode and a matrix is the mean of 1/κ over
the reachable grid points (Table 1 of the 2002 paper, "the average value of
the condition number in the Cartesian workspace"; the published values are
averages of 1/κ, all below 1).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .conditioning import MATRICES, condition_numbers

__all__ = ["SINGULAR_INVERSE", "ConditioningMap", "three_prr_map", "five_bar_cartesian_map", "five_bar_joint_map",
           "joint_grid_maps", "cartesian_grid_maps",
           "hybrid_plane_map", "hybrid_map", "mechanism_map", "contours"]

#: 1/κ at or below which a reachable grid point counts as singular (κ ≥ 10⁶)
SINGULAR_INVERSE = 1e-6
#: 1/κ(J̄) of a general mechanism's map at or below which it is rounding (σ_s/σ_l of a double-precision SVD,
#: ~1e-16 at an exact singularity): set to 0
ROUNDING_INVERSE = 1e-12


@dataclass(frozen=True, eq=False)
class ConditioningMap:
    """1/κ of each matrix over a grid, for one working mode.

    Attributes
    ----------
    mode : str
    axis_names : tuple of str
        The grid's axes, in the papers' symbols (``"x"``, ``"y"``; ``"θ1"``, ``"θ2"``).
    axes : tuple of ndarray
        The values along each axis.
    inverse : dict of str to ndarray, shape=grid shape
        ``{matrix: 1/κ}`` for the keys of :data:`classify.conditioning.MATRICES` (``"lambda"``: λₙ/λ₁).
    reachable : ndarray of bool, shape=grid shape
    length : float
        The characteristic length used.
    orientation : ndarray or None, shape=grid shape
        Where the map is optimised over an orientation (the 3-PRR), the φ of the best κ(K̄).
    definition : str
    extra : dict
        What else the map was made with (design, orientations).
    """

    mode: str
    axis_names: tuple
    axes: tuple
    inverse: dict
    reachable: np.ndarray
    length: float
    orientation: np.ndarray | None = None
    definition: str = "singular_value_ratio"
    extra: dict = field(default_factory=dict)

    @property
    def shape(self):
        return self.reachable.shape

    def kappa(self, matrix):
        """κ over the grid (∞ at singular points, NaN out of reach)."""
        with np.errstate(divide="ignore"):
            return 1.0 / self.inverse[matrix]

    def global_index(self, matrix):
        """Mean of 1/κ over the reachable grid points (NaN if none is)."""
        values = self.inverse[matrix][self.reachable]
        return float(np.mean(values)) if values.size else float("nan")

    def index_at_best_orientation(self, matrix):
        """A 3-PRR map's mean of 1/κ of `matrix` at the orientation where κ(K̄) is best (NaN for other maps).

        Table 1 of Chablat, Caro, Wenger & Angeles 2002: with this average the κ(Ā) column (0.354, 0.511)
        comes out 0.355 and 0.506 (200 × 200 positions, 360 orientations), where Ā at its own best
        orientation (:meth:`global_index`) gives 0.375 and 0.524. The B column (0.709) is B at its own best
        orientation (at K̄'s it is 0.680): no one orientation per position reproduces every column.
        """
        if "at_best_orientation" not in self.extra:
            return float("nan")
        values = self.extra["at_best_orientation"][matrix][self.reachable]
        return float(np.mean(values)) if values.size else float("nan")

    def summary(self):
        """Per matrix: ``global_index``, ``min_kappa``, ``max_kappa`` (None where ∞), and the grid's shares."""
        size = self.reachable.size
        reachable = int(np.count_nonzero(self.reachable))
        matrices = {}
        for matrix in MATRICES:
            values = self.inverse[matrix][self.reachable]
            if not np.any(np.isfinite(values)):  # not computed (a general mechanism's A, B without --matrix A|B)
                matrices[matrix] = {"global_index": None, "min_kappa": None, "max_kappa": None,
                                    "singular_share": None}
                continue
            finite = values[values > 0]
            matrices[matrix] = {
                "global_index": self.global_index(matrix) if values.size else None,
                **({"global_index_at_best_orientation": self.index_at_best_orientation(matrix)}
                   if "at_best_orientation" in self.extra and values.size else {}),
                "min_kappa": float(1.0 / np.max(finite)) if finite.size else None,
                "max_kappa": (float(1.0 / np.min(values)) if values.size and np.min(values) > 0 else None),
                "singular_share": float(np.count_nonzero(values <= SINGULAR_INVERSE) / size) if size else None,
            }
        summary = {"mode": self.mode, "grid_size": int(size), "shape": list(self.shape),
                   "unreachable_share": float((size - reachable) / size) if size else None,
                   "matrices": matrices}
        if "singular" in self.extra:  # the batched classification's verdict (a general mechanism's map)
            summary["classified_singular_share"] = (float(np.count_nonzero(self.extra["singular"]) / size)
                                                    if size else None)
        return summary


def _inverses(direct, inverse, reachable, length, orientation_columns, definition, scales=None):
    safe_direct = np.where(reachable[..., None, None], direct, np.eye(direct.shape[-1]))
    safe_inverse = np.where(reachable[..., None, None], inverse, np.eye(direct.shape[-1]))
    numbers = condition_numbers(safe_direct, safe_inverse, length, orientation_columns, definition, scales=scales)
    return {matrix: np.where(reachable, numbers.inverse(matrix), np.nan) for matrix in MATRICES}


def three_prr_map(xs, ys, signs, length, orientations, mode="", definition="singular_value_ratio",
                  platform_radius=100.0, base_radius=200.0, leg_length=200.0):
    """The 3-PRR's map over positions, each matrix at its best orientation (2002 §3.6, Figs. 6-8).

    Parameters
    ----------
    xs, ys : array_like, shape=[nx], [ny]
    signs : tuple of three ±1
        The working mode.
    length : float
        L (§3.4: √2 r at γ = π/2).
    orientations : array_like, shape=[nφ]
        The orientations φ searched at each position.
    mode : str
        The label stored on the map.

    Returns
    -------
    ConditioningMap
        A position is reachable when some φ is; each matrix's 1/κ is the largest over the φ's reachable there.
        ``extra["at_best_orientation"]`` holds each matrix's 1/κ at the one orientation of the best κ(K̄)
        instead (the map's ``orientation``): its mean, :func:`index_at_best_orientation`, is what reproduces
        Table 1's κ(Ā) column.
    """
    from .conditioning_matrices import three_prr_matrices

    xs, ys = np.asarray(xs, dtype=float), np.asarray(ys, dtype=float)
    grid_x, grid_y = np.meshgrid(xs, ys, indexing="ij")
    best = {matrix: np.full(grid_x.shape, -1.0) for matrix in MATRICES}
    at_best = {matrix: np.full(grid_x.shape, np.nan) for matrix in MATRICES}
    orientation = np.full(grid_x.shape, np.nan)
    for phi in np.asarray(orientations, dtype=float):
        poses = np.stack([grid_x, grid_y, np.full(grid_x.shape, phi)], axis=-1)
        direct, inverse, reachable = three_prr_matrices(poses, signs, platform_radius, base_radius, leg_length)
        values = _inverses(direct, inverse, reachable, length, (2,), definition, (leg_length, leg_length))
        better = reachable & (values["B-1A"] > best["B-1A"])
        orientation = np.where(better, phi, orientation)
        for matrix in MATRICES:
            at_best[matrix] = np.where(better, values[matrix], at_best[matrix])
            best[matrix] = np.where(reachable, np.fmax(best[matrix], values[matrix]), best[matrix])
    reachable = best["B"] >= 0
    inverse = {matrix: np.where(reachable, best[matrix], np.nan) for matrix in MATRICES}
    return ConditioningMap(mode, ("x", "y"), (xs, ys), inverse, reachable, float(length), orientation, definition,
                           {"signs": tuple(signs), "orientations": np.asarray(orientations, dtype=float),
                            "design": {"r": platform_radius, "R": base_radius, "l": leg_length},
                            "at_best_orientation": at_best})


def five_bar_cartesian_map(xs, ys, signs, mode="", definition="singular_value_ratio", base=6.0, proximal=8.0,
                           distal=5.0, proximal_right=None, distal_right=None):
    """The five-bar's map over P = (x, y) in a working mode (Chablat, Wenger & Angeles 1998 Figs. 3, 5).

    Parameters
    ----------
    xs, ys : array_like, shape=[nx], [ny]
    signs : tuple of two ±1
        The working mode (signs of B's diagonal, eq. 3c).
    mode : str
    definition : str
    base, proximal, distal : float
        L0, L1, L2.
    proximal_right, distal_right : float, optional
        L3, L4 of the right leg (eqs. 3b-c hold for any L1..L4); default L1, L2, the paper's symmetric design.

    Returns
    -------
    ConditioningMap
        With the angles θ1..θ4 of each point in ``extra["angles"]`` (shape=[nx, ny, 4]) and the design
        (L0..L4) in ``extra["design"]``.
    """
    from .conditioning_matrices import five_bar_inverse_kinematics, five_bar_matrices

    proximal_right = proximal if proximal_right is None else proximal_right
    distal_right = distal if distal_right is None else distal_right
    xs, ys = np.asarray(xs, dtype=float), np.asarray(ys, dtype=float)
    points = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1)
    angles, reachable = five_bar_inverse_kinematics(points, signs, base, proximal, distal, proximal_right,
                                                    distal_right)
    direct, inverse = five_bar_matrices(np.where(reachable[..., None], angles, 0.0), proximal, distal,
                                        proximal_right, distal_right)
    scales = (max(distal, distal_right), max(proximal * distal, proximal_right * distal_right))
    values = _inverses(direct, inverse, reachable, 1.0, (), definition, scales)
    return ConditioningMap(mode, ("x", "y"), (xs, ys), values, reachable, 1.0, None, definition,
                           {"signs": tuple(signs), "angles": angles,
                            "design": {"L0": base, "L1": proximal, "L2": distal, "L3": proximal_right,
                                       "L4": distal_right}})


def five_bar_joint_map(theta1s, theta2s, assembly, mode="", definition="singular_value_ratio", base=6.0,
                       proximal=8.0, distal=5.0):
    """The five-bar's map over the actuated angles (θ1, θ2) on one assembly branch (1998 Fig. 4)."""
    from .conditioning_matrices import five_bar_direct_kinematics, five_bar_matrices

    theta1s, theta2s = np.asarray(theta1s, dtype=float), np.asarray(theta2s, dtype=float)
    inputs = np.stack(np.meshgrid(theta1s, theta2s, indexing="ij"), axis=-1)
    angles, reachable = five_bar_direct_kinematics(inputs, assembly, base, proximal, distal)
    direct, inverse = five_bar_matrices(np.where(reachable[..., None], angles, 0.0), proximal, distal)
    values = _inverses(direct, inverse, reachable, 1.0, (), definition, (distal, proximal * distal))
    return ConditioningMap(mode or f"assembly {assembly:+d}", ("θ1", "θ2"), (theta1s, theta2s), values, reachable,
                           1.0, None, definition, {"assembly": assembly, "angles": angles,
                                                   "design": {"L0": base, "L1": proximal, "L2": distal}})


def hybrid_plane_map(distances, alongs, signs, mode="", definition="singular_value_ratio", base=6.0, proximal=8.0,
                     distal=5.0):
    """The hybrid's map in the plane of its five-bar (1998 §5): over (d₁, position along AB), per mode.

    The five-bar's plane at any θ1: a point at distance d₁ from the axis AB and at ``along`` on it. Turning
    the map about AB gives the 3-D isoconditioning surfaces (surfaces of revolution, §5.1).

    Parameters
    ----------
    distances, alongs : array_like
        d₁ = iᵀp (eq. 27) and jᵀp.
    signs : tuple of two ±1
        The five-bar's working mode: the signs of sin(θ4 − θ2), sin(θ5 − θ3), the opposites of the signs of
        B's last two entries (eq. 22b: L1 L2 sin(θ2 − θ4), L1 L2 sin(θ3 − θ5)).
    """
    from .conditioning_matrices import five_bar_inverse_kinematics, hybrid_matrices

    distances, alongs = np.asarray(distances, dtype=float), np.asarray(alongs, dtype=float)
    grid_d, grid_u = np.meshgrid(distances, alongs, indexing="ij")
    # the five-bar's (u along AB, v across) plane, angles from AB
    points = np.stack([grid_u, grid_d], axis=-1)
    angles, reachable = five_bar_inverse_kinematics(points, signs, base, proximal, distal)
    safe = np.where(reachable[..., None], angles, 0.0)
    direct, inverse = hybrid_matrices(safe, proximal, distal)
    values = _inverses(direct, inverse, reachable, 1.0, (), definition, (distal, proximal * distal))
    return ConditioningMap(mode, ("d1", "y"), (distances, alongs), values, reachable, 1.0, None, definition,
                           {"signs": tuple(signs), "angles": angles,
                            "design": {"L0": base, "L1": proximal, "L2": distal}})


def hybrid_map(xs, ys, zs, signs, mode="", definition="singular_value_ratio", base=6.0, proximal=8.0, distal=5.0):
    """The hybrid's 3-D map over Cartesian points P = (x, y, z) in a working mode (1998 §5, Fig. 6).

    The catalogue's frame: AB is the y axis (A at the origin), the base revolute turns the five-bar's plane
    about it. A point is at d₁ = √(x² + z²) from AB (eq. 27) and at y along it; the plane through P has
    θ1 = atan2(−z, x). Since θ1 enters neither A nor B (eqs. 22a-b), 1/κ depends on (d₁, y) only: the
    isoconditioning surfaces are the curves of :func:`hybrid_plane_map` turned about AB (surfaces of
    revolution, §5.1). Each point is taken in the plane where it lies on the side d₁ ≥ 0.

    Parameters
    ----------
    xs, ys, zs : array_like, shape=[nx], [ny], [nz]
    signs : tuple of two ±1
        The five-bar's working mode: the signs of sin(θ4 − θ2), sin(θ5 − θ3), the opposites of the signs of
        B's last two entries (eq. 22b: L1 L2 sin(θ2 − θ4), L1 L2 sin(θ3 − θ5)).

    Returns
    -------
    ConditioningMap
        Three-dimensional (axes ``"x"``, ``"y"``, ``"z"``); ``extra["distance"]`` holds d₁ and
        ``extra["theta1"]`` θ1 at each point, ``extra["angles"]`` θ2..θ5.
    """
    from .conditioning_matrices import five_bar_inverse_kinematics, hybrid_matrices

    xs, ys, zs = (np.asarray(values, dtype=float) for values in (xs, ys, zs))
    grid_x, grid_y, grid_z = np.meshgrid(xs, ys, zs, indexing="ij")
    distance = np.hypot(grid_x, grid_z)
    points = np.stack([grid_y, distance], axis=-1)
    angles, reachable = five_bar_inverse_kinematics(points, signs, base, proximal, distal)
    safe = np.where(reachable[..., None], angles, 0.0)
    direct, inverse = hybrid_matrices(safe, proximal, distal)
    values = _inverses(direct, inverse, reachable, 1.0, (), definition, (distal, proximal * distal))
    return ConditioningMap(mode, ("x", "y", "z"), (xs, ys, zs), values, reachable, 1.0, None, definition,
                           {"signs": tuple(signs), "angles": angles, "distance": distance,
                            "theta1": np.arctan2(-grid_z, grid_x),
                            "design": {"L0": base, "L1": proximal, "L2": distal}})


def mechanism_map(mechanism, points, reachable, axes, axis_names, length=None, mode="", derived=False,
                  survey=None, rtol=1e-6):
    """The conditioning map of any mechanism (n inputs = n outputs = n dof) over an assembled grid, batched.

    Parameters
    ----------
    mechanism : Mechanism
    points : array_like, shape=[g, point_size]
        The grid's configurations in C order (NaN rows where not reached), e.g. from the continuation of
        ``closedchain map`` (every point on the starting configuration's branch).
    reachable : array_like of bool, shape=[g]
    axes : sequence of array_like
        The values along each grid axis (g = the product of their lengths).
    axis_names : sequence of str
    length : float, optional
        The characteristic length L of the end-effector metric (default: the mechanism's).
    mode : str
        The label stored on the map (the working mode or branch the grid was assembled on).
    derived : bool
        Also κ(A), κ(B) of the derived relation (:func:`classify.conditioning.mechanism_condition_numbers`,
        one configuration at a time, ~10 ms each); otherwise they are NaN (not computed).
    survey : classify.survey.Survey, optional
        For the batched classification.
    rtol : float
        The classification's relative rank tolerance.

    Returns
    -------
    ConditioningMap
        ``inverse["A-1B"]`` = ``inverse["B-1A"]`` = 1/κ(J̄) from the batched Jacobians
        (:func:`classify.conditioning.mechanism_jacobians`; 0 where the actuators do not parametrise M or
        1/κ ≤ :data:`ROUNDING_INVERSE`);
        ``inverse["lambda"]`` = λₙ/λ₁ (Park & Kim 1999 eq. 3) = (1/κ(J̄))², the λ's being J̄'s squared
        singular values with G on the actuated rates in units of length
        (:func:`classify.conditioning.mechanism_condition_numbers`); 0 where
        :func:`classify.batch.classify_many`'s ``condition_number`` is undefined (an actuator or end-effector
        singularity). The classification's own λ weighs the actuated rates as given, which changes with the
        unit of length where revolute and prismatic joints are both actuated.
        ``extra["singular"]`` (bool, grid shape): the batched classification finds a singularity of any kind;
        ``extra["kinds"]`` its columns, shape ``[*shape, 3]`` (:data:`classify.report.KINDS` order);
        ``extra["points"]`` the configurations.
    """
    from .batch import classify_many
    from .conditioning import inverse_condition, mechanism_condition_numbers, mechanism_jacobians
    from .model import model_of

    axes = tuple(np.asarray(values, dtype=float) for values in axes)
    shape = tuple(len(values) for values in axes)
    points = np.asarray(points, dtype=float).reshape(-1, np.shape(points)[-1])
    reachable = np.asarray(reachable, dtype=bool).reshape(-1)
    model = model_of(mechanism, length_scale=length)
    resolved = float(model.mechanism.characteristic_length if length is None else length)
    rows = np.flatnonzero(reachable)
    inverse = {matrix: np.full(reachable.size, np.nan) for matrix in MATRICES}
    kinds = np.zeros((reachable.size, 3), dtype=bool)
    if rows.size:
        jacobians = mechanism_jacobians(mechanism, points[rows], length)[0]
        defined = np.all(np.isfinite(jacobians), axis=(-2, -1))
        values = np.zeros(rows.size)
        values[defined] = inverse_condition(jacobians[defined])
        values[values <= ROUNDING_INVERSE] = 0.0   # σ_s/σ_l at the rounding unit: singular
        inverse["A-1B"][rows] = values
        inverse["B-1A"][rows] = values
        result = classify_many(model, points[rows], survey=survey, rtol=rtol)
        condition = np.asarray(result.condition_number, dtype=float)
        inverse["lambda"][rows] = np.where(np.isfinite(condition) & (condition > 0), values ** 2, 0.0)
        kinds[rows] = result.singular
        if derived:
            numbers = mechanism_condition_numbers(mechanism, points[rows], length, rtol=max(rtol, 1e-9))
            for matrix in ("A", "B"):
                inverse[matrix][rows] = np.nan_to_num(numbers.inverse(matrix), nan=0.0)
    grid_inverse = {matrix: values.reshape(shape) for matrix, values in inverse.items()}
    return ConditioningMap(mode, tuple(axis_names), axes, grid_inverse, reachable.reshape(shape), resolved, None,
                           "singular_value_ratio",
                           {"singular": kinds.any(axis=1).reshape(shape), "kinds": kinds.reshape(shape + (3,)),
                            "points": points.reshape(shape + (points.shape[-1],)), "derived": bool(derived)})


def joint_grid_maps(mechanism, modes, grid, length=None, derived=False):
    """Maps of any mechanism over a grid of its joint coordinates, one per working mode, as ``closedchain
    conditioning --grid NAME=a:b:n …`` draws them.

    Each mode's grid is assembled by continuation from the mode's
    configuration (:func:`classify.grid_continuation.assemble_grid`, the
    grid's coordinates held as :func:`~classify.grid_continuation.held_columns`
    says), so it stays on that branch; then :func:`mechanism_map`.

    Parameters
    ----------
    mechanism : Mechanism
    modes : sequence of WorkingMode
        E.g. :func:`classify.inverse_kinematics_branches.mechanism_working_modes`.
    grid : classify.grid_continuation.Grid
    length : float, optional
        The characteristic length L (default the mechanism's).
    derived : bool
        Also κ(A), κ(B) of the derived relation (:func:`mechanism_map`).

    Returns
    -------
    list of ConditioningMap
        One per mode, labelled with the mode's label.
    """
    from .grid_continuation import assemble_grid, grid_targets, held_columns

    held = held_columns(mechanism, grid)
    maps = []
    for mode in modes:
        points, reachable = assemble_grid(mechanism, mode.point, grid_targets(mechanism, grid, mode.point),
                                          grid.shape, held)
        maps.append(mechanism_map(mechanism, points, reachable, grid.axes(), grid.names, length, mode.label,
                                  derived=derived))
    return maps


def cartesian_grid_maps(mechanism, modes, names, axes, point, length=None, derived=False):
    """Maps of any mechanism over a grid of its output coordinates, one per working mode, as ``closedchain
    conditioning --grid X=a:b:n Y=a:b:n …`` draws them.

    Each mode is followed over the grid without crossing a serial
    singularity (:func:`classify.inverse_kinematics_branches.follow_working_mode`);
    then :func:`mechanism_map`.

    Parameters
    ----------
    mechanism : Mechanism
        With a position output, or a planar pose output.
    modes : sequence of WorkingMode
    names : sequence of str
        The grid's axes: ``x``, ``y``, ``z`` or ``φ``
        (:func:`classify.inverse_kinematics_branches.cartesian_outputs`).
    axes : sequence of ndarray
        The values along each axis.
    point : ndarray, shape=[point_size]
        A configuration: a planar pose's φ when it is not on the grid.
    length, derived
        As :func:`joint_grid_maps`.

    Returns
    -------
    list of ConditioningMap

    Raises
    ------
    ValueError
        For axes that do not fit the output (:func:`~classify.inverse_kinematics_branches.cartesian_outputs`).
    """
    from .inverse_kinematics_branches import cartesian_outputs, follow_working_mode, output_targets

    targets = output_targets(mechanism, cartesian_outputs(mechanism, point, names, axes))
    shape = tuple(len(axis) for axis in axes)
    maps = []
    for mode in modes:
        points, reachable = follow_working_mode(mechanism, mode.point, targets, shape)
        maps.append(mechanism_map(mechanism, points, reachable, axes, names, length, mode.label, derived=derived))
    return maps


def contours(conditioning_map, matrix, levels):
    """Isoconditioning curves: the level sets 1/κ = level of one matrix (contourpy, marching squares).

    Parameters
    ----------
    conditioning_map : ConditioningMap
        Two-dimensional.
    matrix : str
    levels : sequence of float
        Values of 1/κ in (0, 1].

    Returns
    -------
    dict of float to list of ndarray
        ``{level: [vertices shape=[v, 2], ...]}`` in the map's axis coordinates.
    """
    import contourpy

    first, second = conditioning_map.axes
    grid_first, grid_second = np.meshgrid(first, second, indexing="ij")
    values = np.ma.masked_invalid(conditioning_map.inverse[matrix])
    generator = contourpy.contour_generator(grid_first, grid_second, values, line_type="Separate")
    return {float(level): [np.asarray(line) for line in generator.lines(level)] for level in levels}
