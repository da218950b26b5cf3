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
           "hybrid_plane_map", "contours"]

#: 1/κ at or below which a reachable grid point counts as singular (κ ≥ 10⁶)
SINGULAR_INVERSE = 1e-6


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

    def summary(self):
        """Per matrix: ``global_index``, ``min_kappa``, ``max_kappa`` (None where ∞), and the grid's shares."""
        size = self.reachable.size
        reachable = int(np.count_nonzero(self.reachable))
        matrices = {}
        for matrix in MATRICES:
            values = self.inverse[matrix][self.reachable]
            finite = values[values > 0]
            matrices[matrix] = {
                "global_index": self.global_index(matrix) if values.size else None,
                "min_kappa": float(1.0 / np.max(finite)) if finite.size else None,
                "max_kappa": (float(1.0 / np.min(values)) if values.size and np.min(values) > 0 else None),
                "singular_share": float(np.count_nonzero(values <= SINGULAR_INVERSE) / size) if size else None,
            }
        return {"mode": self.mode, "grid_size": int(size), "shape": list(self.shape),
                "unreachable_share": float((size - reachable) / size) if size else None,
                "matrices": matrices}


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
    """
    from .conditioning_matrices import three_prr_matrices

    xs, ys = np.asarray(xs, dtype=float), np.asarray(ys, dtype=float)
    grid_x, grid_y = np.meshgrid(xs, ys, indexing="ij")
    best = {matrix: np.full(grid_x.shape, -1.0) for matrix in MATRICES}
    orientation = np.full(grid_x.shape, np.nan)
    for phi in np.asarray(orientations, dtype=float):
        poses = np.stack([grid_x, grid_y, np.full(grid_x.shape, phi)], axis=-1)
        direct, inverse, reachable = three_prr_matrices(poses, signs, platform_radius, base_radius, leg_length)
        values = _inverses(direct, inverse, reachable, length, (2,), definition, (leg_length, leg_length))
        better = reachable & (values["B-1A"] > best["B-1A"])
        orientation = np.where(better, phi, orientation)
        for matrix in MATRICES:
            best[matrix] = np.where(reachable, np.fmax(best[matrix], values[matrix]), best[matrix])
    reachable = best["B"] >= 0
    inverse = {matrix: np.where(reachable, best[matrix], np.nan) for matrix in MATRICES}
    return ConditioningMap(mode, ("x", "y"), (xs, ys), inverse, reachable, float(length), orientation, definition,
                           {"signs": tuple(signs), "orientations": np.asarray(orientations, dtype=float),
                            "design": {"r": platform_radius, "R": base_radius, "l": leg_length}})


def five_bar_cartesian_map(xs, ys, signs, mode="", definition="singular_value_ratio", base=6.0, proximal=8.0,
                           distal=5.0):
    """The five-bar's map over P = (x, y) in a working mode (Chablat, Wenger & Angeles 1998 Figs. 3, 5).

    Returns
    -------
    ConditioningMap
        With the angles θ1..θ4 of each point in ``extra["angles"]`` (shape=[nx, ny, 4]).
    """
    from .conditioning_matrices import five_bar_inverse_kinematics, five_bar_matrices

    xs, ys = np.asarray(xs, dtype=float), np.asarray(ys, dtype=float)
    points = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1)
    angles, reachable = five_bar_inverse_kinematics(points, signs, base, proximal, distal)
    direct, inverse = five_bar_matrices(np.where(reachable[..., None], angles, 0.0), proximal, distal)
    values = _inverses(direct, inverse, reachable, 1.0, (), definition, (distal, proximal * distal))
    return ConditioningMap(mode, ("x", "y"), (xs, ys), values, reachable, 1.0, None, definition,
                           {"signs": tuple(signs), "angles": angles,
                            "design": {"L0": base, "L1": proximal, "L2": distal}})


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
        The five-bar's working mode (signs of sin(θ4 − θ2), sin(θ5 − θ3)).
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
