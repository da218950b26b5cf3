"""Rotations in a rotation-vector chart, written so that SymPy can differentiate them at r = 0.

Q = expm([r]×) by Rodrigues' formula with the entire functions gₘ(s) of
:class:`RodriguesSeries` (s = ‖r‖²), so that a relation and its symbolic
derivatives are finite at r = 0; the left Jacobian ω = J_left(r) ṙ; the
orientation that best maps body vectors to world vectors (Kabsch). Used by the
spherical 3-RRR and Gough–Stewart relations of Gosselin & Angeles
(Gosselin & Angeles 1990, eqs. 67 and 79, whose A multiplies ω).
"""

from __future__ import annotations

import functools
import math

import numpy as np
import sympy

__all__ = [
    "planar_angle", "rodrigues_series", "RodriguesSeries", "skew_matrix", "rotation_matrix", "left_jacobian", "rotated",
    "row_times_left_jacobian", "orientation_from_vectors",
]

#: terms of the series of :func:`rodrigues_series` (exact to rounding, 1e-16, for ‖r‖ ≤ 2π)
_SERIES_TERMS = 40


@functools.lru_cache(maxsize=None)
def _series_coefficients(order, derivative):
    """The series of the j-th derivative of gₘ: its coefficients in powers of s, highest first."""
    return tuple((-1) ** term * (math.factorial(term) // math.factorial(term - derivative))
                 / math.factorial(2 * term + order) for term in range(derivative, _SERIES_TERMS))[::-1]


def rodrigues_series(order, derivative, square):
    """The j-th derivative of gₘ(s) = Σₖ (−s)ᵏ / (2k + m)!, evaluated by its series (Horner).

    g₀(‖r‖²) = cos‖r‖, g₁(‖r‖²) = sin‖r‖/‖r‖, g₂(‖r‖²) = (1 − cos‖r‖)/‖r‖²,
    g₃(‖r‖²) = (‖r‖ − sin‖r‖)/‖r‖³: the coefficients of Rodrigues' formula (:func:`rotation_matrix`)
    and of the left Jacobian (:func:`left_jacobian`), entire in s = ‖r‖², so
    finite with their derivatives at r = 0.

    Parameters
    ----------
    order : int
        m ≥ 0.
    derivative : int
        j ≥ 0.
    square : array_like, shape=[...]
        s.

    Returns
    -------
    float or ndarray, shape=[...]
    """
    coefficients = _series_coefficients(int(order), int(derivative))
    if np.ndim(square) == 0:  # a scalar: Horner in floats (the lambdified relations call it per entry)
        value, square = 0.0, float(square)
        for coefficient in coefficients:
            value = value * square + coefficient
        return value
    return np.polyval(np.array(coefficients), np.asarray(square, dtype=float))


class RodriguesSeries(sympy.Function):
    """SymPy function ``RodriguesSeries(m, j, s)``: the j-th derivative of gₘ at s (:func:`rodrigues_series`).

    Differentiating with respect to s raises j by one (``fdiff``), so that
    :meth:`sympy.Matrix.jacobian` of an expression in it is again in it;
    :func:`sympy.lambdify` evaluates it with :func:`rodrigues_series`
    (the ``_imp_`` attribute).
    """

    nargs = 3

    def fdiff(self, argindex=3):
        if argindex != 3:
            raise sympy.core.function.ArgumentIndexError(self, argindex)
        order, derivative, square = self.args
        return RodriguesSeries(order, derivative + 1, square)

    @staticmethod
    def _imp_(order, derivative, square):
        return rodrigues_series(order, derivative, square)


def skew_matrix(vector):
    """[v]×, the matrix of v × (·), as a SymPy matrix, shape=[3, 3].

    Parameters
    ----------
    vector : sequence of sympy.Expr, length 3
    """
    first, second, third = vector
    return sympy.Matrix([[0, -third, second], [third, 0, -first], [-second, first, 0]])


def _series_polynomial(vector, order):
    """1 + g_order(‖r‖²)[r]× + g_(order+1)(‖r‖²)[r]×², SymPy, shape=[3, 3]."""
    square = sum(component ** 2 for component in vector)
    skew = skew_matrix(vector)
    return (sympy.eye(3) + RodriguesSeries(order, 0, square) * skew
            + RodriguesSeries(order + 1, 0, square) * skew * skew)


def rotation_matrix(vector):
    """expm([r]×) = 1 + g₁(‖r‖²)[r]× + g₂(‖r‖²)[r]×² (Rodrigues), SymPy, shape=[3, 3].

    Parameters
    ----------
    vector : sequence of sympy.Expr, length 3
        The rotation vector r.
    """
    return _series_polynomial(vector, 1)


def left_jacobian(vector):
    """J_left(r) = 1 + g₂(‖r‖²)[r]× + g₃(‖r‖²)[r]×², SymPy, shape=[3, 3].

    With Q = expm([r]×) Q_reference the angular velocity (``Q̇ Qᵀ = [ω]×``) is
    ω = J_left(r) ṙ; J_left(0) = 1.

    Parameters
    ----------
    vector : sequence of sympy.Expr, length 3
        The rotation vector r.
    """
    return _series_polynomial(vector, 2)


def rotated(vector, rotation_vector):
    """expm([r]×) v = g₀(‖r‖²) v + g₁(‖r‖²) r × v + g₂(‖r‖²) (r·v) r, SymPy, shape=[3, 1].

    Rodrigues' formula in vector form (g₀(‖r‖²) = cos‖r‖ = 1 − ‖r‖² g₂(‖r‖²)),
    with fewer terms than ``rotation_matrix(r) * v`` once v is numeric.

    Parameters
    ----------
    vector : array_like or sympy.Matrix, shape=[3]
        v.
    rotation_vector : sequence of sympy.Expr, length 3
        r.
    """
    square = sum(component ** 2 for component in rotation_vector)
    vector, axis = sympy.Matrix(list(vector)), sympy.Matrix(list(rotation_vector))
    return (RodriguesSeries(0, 0, square) * vector + RodriguesSeries(1, 0, square) * axis.cross(vector)
            + RodriguesSeries(2, 0, square) * axis.dot(vector) * axis)


def row_times_left_jacobian(row, rotation_vector):
    """aᵀ J_left(r) = g₁(‖r‖²) a + g₂(‖r‖²) a × r + g₃(‖r‖²) (a·r) r, SymPy, shape=[1, 3].

    The vector form of ``row * left_jacobian(r)`` (:func:`left_jacobian`), since
    aᵀ[r]× = (a × r)ᵀ, aᵀ[r]×² = ((a·r) r − ‖r‖² a)ᵀ and 1 − ‖r‖² g₃ = g₁.

    Parameters
    ----------
    row : sympy.Matrix, shape=[3] or [1, 3]
        a.
    rotation_vector : sequence of sympy.Expr, length 3
        r.
    """
    square = sum(component ** 2 for component in rotation_vector)
    row, axis = sympy.Matrix(list(row)), sympy.Matrix(list(rotation_vector))
    return (RodriguesSeries(1, 0, square) * row + RodriguesSeries(2, 0, square) * row.cross(axis)
            + RodriguesSeries(3, 0, square) * row.dot(axis) * axis).T


def orientation_from_vectors(body_vectors, world_vectors):
    """The rotation Q with Q bᵢ ≈ aᵢ (least squares, det Q = +1; Kabsch), and the largest residual.

    Parameters
    ----------
    body_vectors, world_vectors : array_like, shape=[k, 3]
        bᵢ in a body frame and aᵢ in the ground frame (k ≥ 2, the bᵢ not all parallel).

    Returns
    -------
    rotation : ndarray, shape=[3, 3]
    residual : float
        max ‖Q bᵢ − aᵢ‖.
    """
    body_vectors, world_vectors = np.asarray(body_vectors, dtype=float), np.asarray(world_vectors, dtype=float)
    left, _, right = np.linalg.svd(world_vectors.T @ body_vectors)
    sign = np.sign(np.linalg.det(left @ right)) or 1.0
    rotation = left @ np.diag([1.0, 1.0, sign]) @ right
    return rotation, float(np.max(np.linalg.norm(body_vectors @ rotation.T - world_vectors, axis=1)))


def planar_angle(pose):
    """The rotation angle of a planar homogeneous pose, shape=[3, 3] -> float in (−π, π]."""
    return math.atan2(pose[1, 0], pose[0, 0])
