"""The coordinates a locus is traced over and shown in: joint displacements from home, or the end-effector point.

References
----------
Park & Kim 1999, Section 3; Chablat, Wenger & Angeles 1998 (the loci shown).
"""

from __future__ import annotations

import numpy as np

__all__ = ["default_columns", "locus_coordinates"]


def _is_angle(mechanism, column):
    from mechanisms.kinematics import kinematics_of

    ambient = kinematics_of(mechanism).ambient
    for factor, part in zip(ambient.factors, ambient.tangent_slices):
        if part.start <= column < part.stop:
            return factor != "R"
    return False


def default_columns(mechanism, dof, point=None):
    """The tangent coordinates a locus is traced over and shown in, when the user names none.

    2 dof: the two actuated coordinates, else the first two. 1 dof: the first
    actuated coordinate (else the first) and the next one. 3 dof: the two
    grid axes then the section coordinate: with three actuated coordinates
    the last two and the first, else the second and third coordinates and
    the first.

    Given `point` (2 and 3 dof), the choice must also be independent
    coordinates of M there or at a neighbour on M
    (:func:`classify.grid_continuation.regular_start`; at an actuator
    singularity the actuated coordinates fail at the point only), as the grid
    continuation holds them (:func:`classify.grid_continuation.held_margins`
    above :data:`classify.grid_continuation.REGULAR_RTOL`). Where the rule's
    choice fails (an idle spin that no actuated coordinate moves, say), the
    independent actuated coordinates are kept, in order, and completed by
    the coordinates a column-pivoted QR of the other columns of DΦ·s leaves
    after the r it picks to solve the loops for (r the rank of DΦ·s).

    Parameters
    ----------
    mechanism : Mechanism
    dof : int
        1, 2 or 3.
    point : ndarray, shape=[point_size], optional
        A configuration of M.

    Returns
    -------
    list of int
    """
    actuated = list(mechanism.actuated_coordinates)
    if dof == 1:
        first = actuated[0] if actuated else 0
        return [first, (first + 1) % mechanism.ambient_dimension]
    if dof == 2:
        columns = actuated if len(actuated) == 2 else [0, 1]
    else:
        columns = actuated[1:] + actuated[:1] if len(actuated) == 3 else [1, 2, 0]
    if point is None:
        return columns
    import scipy.linalg

    from manifold import rank_of_values
    from mechanisms.kinematics import constraint_jacobian, kinematics_of

    from .grid_continuation import REGULAR_RTOL, held_margins, regular_start

    if regular_start(mechanism, point, columns).margin > REGULAR_RTOL:
        return columns
    chosen = []
    for column in actuated:
        if len(chosen) < dof and held_margins(mechanism, point, chosen + [column])[0] > REGULAR_RTOL:
            chosen.append(column)
    rest = [column for column in range(mechanism.ambient_dimension) if column not in chosen]
    scaled = constraint_jacobian(mechanism, point) * kinematics_of(mechanism).ambient.tangent_scales
    rank = rank_of_values(np.linalg.svd(scaled, compute_uv=False)).rank
    order = scipy.linalg.qr(scaled[:, rest], pivoting=True)[2]
    chosen += [rest[index] for index in order[rank:]][: dof - len(chosen)]
    if dof == 3 and len(actuated) >= 2 and chosen[0] in actuated and chosen[1] in actuated:
        return chosen  # the actuated coordinates as the grid's axes, the added one the section's
    return chosen[1:] + chosen[:1] if dof == 3 else chosen


def locus_coordinates(mechanism, points, coordinates):
    """The coordinates a locus is shown in.

    Parameters
    ----------
    mechanism : Mechanism
    points : ndarray, shape=[n, point_size]
    coordinates : sequence of int or "end-effector"
        Tangent coordinate columns (joint displacements from home, angles
        wrapped to [−π, π)), or the end-effector point (position, pose and
        tool outputs: its position).

    Returns
    -------
    values : ndarray, shape=[n, d]
    names : tuple of str
    """
    from mechanisms.kinematics import end_effector, kinematics_of

    from .displacements import displacements_of

    points = np.atleast_2d(points)
    if isinstance(coordinates, str):
        value = end_effector(mechanism, points)
        if value.ndim == 3:  # a frame: its origin
            value = value[..., :-1, -1]
        elif kinematics_of(mechanism).output == "tool":  # (point, axis): the point
            value = value[..., :3]
        names = ("x", "y", "z")[: value.shape[-1]]
        return np.asarray(value, dtype=float), names
    columns = list(coordinates)
    values = displacements_of(mechanism, points)[:, columns]
    for index, column in enumerate(columns):
        if _is_angle(mechanism, column):
            values[:, index] = (values[:, index] + np.pi) % (2 * np.pi) - np.pi
    return values, tuple(mechanism.coordinate_names[column] for column in columns)
