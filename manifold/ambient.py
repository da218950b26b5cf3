"""Ambient spaces: products of joint factors with recentred charts.

A point of the ambient space K is stored as a flat array of shape
``(..., point_size)``; a tangent vector as an array of shape ``(..., dim)``.
Each factor is one of

=========  ==========  ===========  ==========================================
factor     point size  tangent dim  retraction ``point ⊕ tangent``
=========  ==========  ===========  ==========================================
``"R"``    1           1            ``x + v``
``"S1"``   1           1            ``θ + v`` (angles are not wrapped)
``"SO3"``  9           3            ``R · exp(v̂)`` (row-major rotation matrix)
=========  ==========  ===========  ==========================================

A torus T² is two ``"S1"`` factors, a cylinder S¹×ℝ is ``("S1", "R")``.

Charts are *recentred*: every derivative is taken in the chart
``v ↦ point ⊕ v`` at the current point, so no rotation is ever described by
three angles and no parametrisation can create a singularity (no gimbal lock).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["FACTORS", "AmbientSpace", "rotation_exp", "rotation_log"]

#: factor name -> (point size, tangent dimension)
FACTORS = {"R": (1, 1), "S1": (1, 1), "SO3": (9, 3)}


def rotation_exp(rotation_vector):
    """Rotation matrices from rotation vectors (Rodrigues' formula).

    Parameters
    ----------
    rotation_vector : array_like, shape=[..., 3]

    Returns
    -------
    rotation : ndarray, shape=[..., 3, 3]
    """
    from scipy.spatial.transform import Rotation  # imported when used: scipy.spatial is slow to import

    rotation_vector = np.asarray(rotation_vector, dtype=float)
    flat = np.array(rotation_vector.reshape(-1, 3))
    matrices = Rotation.from_rotvec(flat).as_matrix()
    return matrices.reshape(rotation_vector.shape[:-1] + (3, 3))


def rotation_log(rotation):
    """Rotation vectors of rotation matrices (principal logarithm, angle ≤ π).

    Parameters
    ----------
    rotation : array_like, shape=[..., 3, 3]

    Returns
    -------
    rotation_vector : ndarray, shape=[..., 3]
    """
    from scipy.spatial.transform import Rotation  # imported when used: scipy.spatial is slow to import

    rotation = np.asarray(rotation, dtype=float)
    flat = np.array(rotation.reshape(-1, 3, 3))
    vectors = Rotation.from_matrix(flat).as_rotvec()
    return vectors.reshape(rotation.shape[:-2] + (3,))


def _factor_indices(factors, point_slices, tangent_slices):
    """Factor name -> (indices into a point, indices into a tangent vector) of all factors of that kind,
    in order (an SO3 factor's nine entries, then the next one's)."""
    indices = {}
    for name in FACTORS:
        chosen = [index for index, factor in enumerate(factors) if factor == name]
        indices[name] = tuple(
            np.array([position for index in chosen for position in range(parts[index].start, parts[index].stop)],
                     dtype=np.intp)
            for parts in (point_slices, tangent_slices))
    return indices


def _wrap(angle):
    """Wrap angles to [-π, π)."""
    return (np.asarray(angle) + np.pi) % (2.0 * np.pi) - np.pi


@dataclass(frozen=True, eq=False)
class AmbientSpace:
    """A product of joint factors ℝ, S¹ and SO(3).

    Parameters
    ----------
    factors : tuple of str
        Each ``"R"``, ``"S1"`` or ``"SO3"``.
    scales : tuple of float, optional
        A typical size of each factor's coordinates (1 for angles, a
        characteristic length for translations). They size random samples
        and steps, and make tangent coordinates dimensionless (u = v / s) for
        every rank decision and minimum-norm step (see :mod:`manifold.implicit`),
        so that no decision depends on the unit of length. Default all 1.

    Examples
    --------
    >>> space = AmbientSpace(("S1", "R", "SO3"))
    >>> space.dim, space.point_size
    (5, 11)
    >>> point = space.neutral()
    >>> moved = space.retract(point, [0.1, 2.0, 0.0, 0.0, 0.3])
    >>> np.allclose(space.inverse_retract(point, moved), [0.1, 2.0, 0.0, 0.0, 0.3])
    True
    """

    factors: tuple
    scales: tuple = None
    point_slices: tuple = field(init=False, repr=False)
    tangent_slices: tuple = field(init=False, repr=False)
    _dim: int = field(init=False, repr=False)
    _point_size: int = field(init=False, repr=False)
    _tangent_scales: np.ndarray = field(init=False, repr=False)
    _indices: dict = field(init=False, repr=False)

    def __post_init__(self):
        factors = tuple(self.factors)
        for factor in factors:
            if factor not in FACTORS:
                raise ValueError(
                    f"Expected each factor to be one of {sorted(FACTORS)}, got {factor!r}"
                )
        scales = (1.0,) * len(factors) if self.scales is None else tuple(map(float, self.scales))
        if len(scales) != len(factors):
            raise ValueError(
                f"Expected {len(factors)} scales, one per factor, got {len(scales)}"
            )
        for index, scale in enumerate(scales):
            if not (np.isfinite(scale) and scale > 0):  # a zero scale erases its coordinates from every decision
                raise ValueError(f"Expected every scale to be a finite positive number, got {scale!r} "
                                 f"(factor {index})")
        point_slices, tangent_slices = [], []
        point_start = tangent_start = 0
        for factor in factors:
            point_size, dim = FACTORS[factor]
            point_slices.append(slice(point_start, point_start + point_size))
            tangent_slices.append(slice(tangent_start, tangent_start + dim))
            point_start += point_size
            tangent_start += dim
        tangent_scales = np.concatenate(
            [np.full(FACTORS[f][1], s) for f, s in zip(factors, scales)]
        ) if factors else np.zeros(0)
        tangent_scales.setflags(write=False)
        object.__setattr__(self, "factors", factors)
        object.__setattr__(self, "scales", scales)
        object.__setattr__(self, "point_slices", tuple(point_slices))
        object.__setattr__(self, "tangent_slices", tuple(tangent_slices))
        object.__setattr__(self, "_dim", tangent_start)
        object.__setattr__(self, "_point_size", point_start)
        object.__setattr__(self, "_tangent_scales", tangent_scales)
        object.__setattr__(self, "_indices", _factor_indices(factors, point_slices, tangent_slices))

    @property
    def dim(self):
        """Dimension k of the space (length of a tangent vector)."""
        return self._dim

    @property
    def point_size(self):
        """Number of floats that store one point."""
        return self._point_size

    @property
    def tangent_scales(self):
        """Per tangent coordinate, the scale of its factor, shape=[dim] (read-only, computed once)."""
        return self._tangent_scales

    def neutral(self):
        """The point with all coordinates zero and all rotations identity, shape=[point_size]."""
        point = np.zeros(self.point_size)
        rotations = self._indices["SO3"][0]
        point[rotations] = np.tile(np.eye(3).ravel(), len(rotations) // 9)
        return point

    def retract(self, point, tangent_vec):
        """The point ``point ⊕ tangent_vec`` of the recentred chart at `point`.

        Parameters
        ----------
        point : array_like, shape=[..., point_size]
        tangent_vec : array_like, shape=[..., dim]

        Returns
        -------
        moved : ndarray, shape=[..., point_size]
        """
        point = np.asarray(point, dtype=float)
        tangent_vec = np.asarray(tangent_vec, dtype=float)
        shape = np.broadcast_shapes(point.shape[:-1], tangent_vec.shape[:-1])
        moved = np.array(np.broadcast_to(point, shape + (self.point_size,)))
        for factor in ("R", "S1"):
            point_indices, tangent_indices = self._indices[factor]
            moved[..., point_indices] = moved[..., point_indices] + tangent_vec[..., tangent_indices]
        point_indices, tangent_indices = self._indices["SO3"]
        if point_indices.size:
            count = len(point_indices) // 9
            rotation = moved[..., point_indices].reshape(shape + (count, 3, 3))
            step = rotation_exp(np.broadcast_to(tangent_vec[..., tangent_indices].reshape(
                tangent_vec.shape[:-1] + (count, 3)), shape + (count, 3)))
            moved[..., point_indices] = (rotation @ step).reshape(shape + (9 * count,))
        return moved

    def bracket(self, first, second):
        """The mixed second-order term of two charts composed: ``point ⊕ u ⊕ w = point ⊕ (u + w + B(u, w) + …)``.

        ``B(u, w) = ½ u × w`` on each ``"SO3"`` factor (Baker–Campbell–Hausdorff:
        ``exp(û) exp(ŵ) = exp((u + w + ½ u × w)^ + …)``), 0 on ``"R"`` and
        ``"S1"``. It is what a derivative taken in the recentred chart at
        ``point ⊕ u`` lacks to be one in the chart at `point`: for a map F,
        ``d/du [DF(point ⊕ u) w] = D²F(u, w) + DF · B(u, w)`` at u = 0.

        Parameters
        ----------
        first : array_like, shape=[dim, i]
        second : array_like, shape=[dim, j]
            Tangent vectors (columns).

        Returns
        -------
        bracket : ndarray, shape=[dim, i, j]

        Examples
        --------
        >>> space = AmbientSpace(("R", "SO3"))
        >>> space.bracket(np.eye(4)[:, [1]], np.eye(4)[:, [2]])[:, 0, 0].tolist()
        [0.0, 0.0, 0.0, 0.5]
        """
        first = np.asarray(first, dtype=float)
        second = np.asarray(second, dtype=float)
        bracket = np.zeros((self.dim, first.shape[1], second.shape[1]))
        tangent_indices = self._indices["SO3"][1].reshape(-1, 3)
        for indices in tangent_indices:
            bracket[indices] = 0.5 * np.cross(first[indices].T[:, None, :], second[indices].T[None, :, :]).transpose(
                2, 0, 1)
        return bracket

    def inverse_retract(self, point, other):
        """The tangent vector ``v`` with ``point ⊕ v = other`` (angles wrapped to [-π, π)).

        Parameters
        ----------
        point, other : array_like, shape=[..., point_size]

        Returns
        -------
        tangent_vec : ndarray, shape=[..., dim]
        """
        point = np.asarray(point, dtype=float)
        other = np.asarray(other, dtype=float)
        shape = np.broadcast_shapes(point.shape[:-1], other.shape[:-1])
        tangent_vec = np.zeros(shape + (self.dim,))
        point_indices, tangent_indices = self._indices["R"]
        tangent_vec[..., tangent_indices] = other[..., point_indices] - point[..., point_indices]
        point_indices, tangent_indices = self._indices["S1"]
        tangent_vec[..., tangent_indices] = _wrap(other[..., point_indices] - point[..., point_indices])
        point_indices, tangent_indices = self._indices["SO3"]
        if point_indices.size:
            count = len(point_indices) // 9
            rotation = point[..., point_indices].reshape(point.shape[:-1] + (count, 3, 3))
            target = rotation if other is point else other[..., point_indices].reshape(
                other.shape[:-1] + (count, 3, 3))
            relative = np.swapaxes(rotation, -1, -2) @ target
            tangent_vec[..., tangent_indices] = rotation_log(relative).reshape(shape + (3 * count,))
        return tangent_vec

    def random_point(self, rng, center=None, size=None):
        """Random points: angles uniform, rotations uniform, reals ``center + scale·N(0, 1)``.

        Parameters
        ----------
        rng : numpy.random.Generator
        center : array_like, shape=[point_size], optional
            Where the real coordinates are centred; default the neutral point.
        size : int, optional
            Number of points; default one.

        Returns
        -------
        point : ndarray, shape=[point_size] or [size, point_size]
        """
        count = 1 if size is None else int(size)
        center = self.neutral() if center is None else np.asarray(center, dtype=float)
        points = np.tile(center, (count, 1))
        for factor, part, scale in zip(self.factors, self.point_slices, self.scales):
            if factor == "SO3":
                from scipy.spatial.transform import Rotation  # imported when used

                matrices = Rotation.random(count, random_state=rng).as_matrix()
                points[:, part] = matrices.reshape(count, 9)
            elif factor == "S1":
                points[:, part] = rng.uniform(-np.pi, np.pi, size=(count, 1))
            else:
                points[:, part] += scale * rng.standard_normal((count, 1))
        return points[0] if size is None else points
