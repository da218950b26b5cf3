"""Joint displacements from the home ↔ points of the ambient space, for stacks of configurations.

A displacement matrix, shape=[n, k], holds one row per configuration and one
column per tangent coordinate in the order of ``mechanism.coordinate_names``
(``A``, ``S1[x]``, ``S1[y]``, ``S1[z]``, ``U1[1]``, …): a number for R and P
joints, a pair for U and C, a rotation vector for S — what
:func:`mechanisms.from_displacements` takes and
:func:`mechanisms.to_displacements` gives, row by row and vectorised.

NumPy and the kinematics are imported when a function runs (the command
line's start-up imports this module's names without them).
"""

from __future__ import annotations

from mechanisms.joints import joint_coordinate_names

__all__ = ["coordinate_columns", "displacement_vector", "points_of", "displacements_of", "joint_displacements"]


def coordinate_columns(mechanism):
    """Joint name → the indices of its tangent coordinates (columns of a displacement matrix), in order.

    Parameters
    ----------
    mechanism : Mechanism

    Returns
    -------
    dict of str to tuple of int
    """
    columns, start = {}, 0
    for joint in mechanism.joints:
        count = len(joint_coordinate_names(joint))
        columns[joint.name] = tuple(range(start, start + count))
        start += count
    return columns


def displacement_vector(mechanism, displacements):
    """The displacement row, shape=[k], of a mapping joint name → displacement (checked before).

    Joints not named are at home (0).
    """
    import numpy as np

    vector = np.zeros(len(mechanism.coordinate_names))
    columns = coordinate_columns(mechanism)
    for name, value in displacements.items():
        vector[list(columns[name])] = np.atleast_1d(np.asarray(value, dtype=float))
    return vector


def points_of(mechanism, matrix):
    """The configurations ``home ⊕ displacements`` of a displacement matrix.

    Row by row what :func:`mechanisms.from_displacements` builds: each joint's
    entries set to its values, an S joint's rotation matrix the exponential of
    its rotation vector.

    Parameters
    ----------
    mechanism : Mechanism
    matrix : ndarray, shape=[n, k]

    Returns
    -------
    points : ndarray, shape=[n, point_size]
    """
    import numpy as np

    from manifold import rotation_exp
    from mechanisms.kinematics import kinematics_of

    compiled = kinematics_of(mechanism)
    matrix = np.asarray(matrix, dtype=float).reshape(-1, len(mechanism.coordinate_names))
    points = np.array(np.broadcast_to(compiled.ambient.neutral(), (len(matrix), compiled.ambient.point_size)))
    columns = coordinate_columns(mechanism)
    for joint in mechanism.joints:
        parts, indices = compiled.point_parts[joint.name], columns[joint.name]
        if joint.type == "S":
            points[:, parts[0]] = rotation_exp(matrix[:, list(indices)]).reshape(len(matrix), 9)
        else:
            for part, index in zip(parts, indices):
                points[:, part] = matrix[:, index:index + 1]
    return points


def displacements_of(mechanism, points):
    """The displacement matrix of configurations (the inverse of :func:`points_of`).

    Row by row :func:`mechanisms.to_displacements`: joint values as they are,
    an S joint's rotation vector the principal logarithm of its rotation.

    Parameters
    ----------
    mechanism : Mechanism
    points : ndarray, shape=[n, point_size]

    Returns
    -------
    matrix : ndarray, shape=[n, k]
    """
    import numpy as np

    from manifold import rotation_log
    from mechanisms.kinematics import kinematics_of

    compiled = kinematics_of(mechanism)
    points = np.asarray(points, dtype=float).reshape(-1, compiled.ambient.point_size)
    matrix = np.zeros((len(points), len(mechanism.coordinate_names)))
    columns = coordinate_columns(mechanism)
    for joint in mechanism.joints:
        parts, indices = compiled.point_parts[joint.name], columns[joint.name]
        if joint.type == "S":
            matrix[:, list(indices)] = rotation_log(points[:, parts[0]].reshape(-1, 3, 3))
        else:
            for part, index in zip(parts, indices):
                matrix[:, index] = points[:, part][:, 0]
    return matrix


def joint_displacements(mechanism, matrix):
    """The mappings joint name → displacement (a float for R and P, a list for S, U and C) of displacement rows.

    Parameters
    ----------
    mechanism : Mechanism
    matrix : ndarray, shape=[n, k] or [k]

    Returns
    -------
    list of dict (n of them), or one dict for a single row
    """
    import numpy as np

    matrix = np.asarray(matrix, dtype=float)
    layout = [(name, indices[0] if mechanism.joint(name).type in ("R", "P") else list(indices))
              for name, indices in coordinate_columns(mechanism).items()]
    rows = [{name: (values[where] if isinstance(where, int) else [values[index] for index in where])
             for name, where in layout} for values in np.atleast_2d(matrix).tolist()]
    return rows[0] if matrix.ndim == 1 else rows
