"""Loop constraints Φ and the end-effector map f, with analytic derivatives.

The joint graph is cut along a spanning tree grown from the ground; every
chord closes one loop. Each joint is a product of *elements* ``A(q) exp(X̂ v)``
(a rotation or translation about a home-frame twist ``X̂``, or a ball joint
``[R, c − R c]`` moved by ``R exp(v̂)``), so a chain of joints is::

    T(q ⊕ v) = A₁ e^{X̂₁ v₁} A₂ e^{X̂₂ v₂} ⋯ Aₙ e^{X̂ₙ vₙ}.

Derivatives in the recentred chart are products with twists *inserted*::

    ∂T/∂v_a      = A₁ ⋯ A_i  X̂_a  A_{i+1} ⋯ Aₙ
    ∂²T/∂v_a∂v_b = A₁ ⋯ A_i  X̂_a  A_{i+1} ⋯ A_j  X̂_b  A_{j+1} ⋯ Aₙ   (i < j)
                 = ½ A₁ ⋯ A_i (X̂_a X̂_b + X̂_b X̂_a) A_{i+1} ⋯ Aₙ   (same element)

At a closed configuration (T = I) the first column is the joint twist carried
to the current configuration, ``Ad_{A₁⋯A_i} X_a`` (Park & Kim, 1999, eq. 8
is the planar five-bar case), and on tangent vectors the second-order term
equals the Lie-bracket form ``½ Σ_{i<j} [Z_i, Z_j]`` of the carried twists.
The loop rows ``L(T)`` (:mod:`._groups`) are linear in T, so ``DΦ = L(DT)``
and ``D²Φ = L(D²T)`` exactly, at every configuration, on or off M.

First derivatives need no suffix products: with the prefix P up to a
coordinate's slot, ``∂T/∂v_a = P X̂_a P⁻¹ T = Ŵ_a T`` for the carried twist
``W_a = Ad_P X_a``, on or off M, and ``L(Ŵ T)`` has a closed form
(:func:`mechanisms._chains.loop_first_order`). Planar chains are evaluated
in complex form, a rigid motion ``(e^{iθ}, t)``, with no 3×3 products at all
(:func:`mechanisms._chains.planar_loops`).

The end-effector map in the exponential chart of N at f(p) uses the body
twists ``ŵ_a = F⁻¹ ∂F/∂v_a`` and the Baker-Campbell-Hausdorff formula::

    log(F(p)⁻¹ F(p ⊕ v)) = Σ_a w_a v_a + ½ Σ_{a before b} [w_a, w_b] v_a v_b + O(|v|³).

All functions take stacks of configurations, ``point`` of shape
``(..., point_size)``.

Sparsity. A loop touches only the joints on it, so DΦ has nonzero entries in
its loop's rows and its joints' columns only, and D²Φ is a small dense block
per loop (rows × the loop's coordinates²). Chains of the same shape (the same
sequence of coordinate slots, e.g. the rungs of a ladder of four-bar loops)
are evaluated together (:mod:`mechanisms._chains`), one array operation per
element position, so the cost grows with the number of joints, not with
Python loops over them. The
constant pattern of DΦ (:func:`constraint_pattern`) and its entries
(:func:`constraint_jacobian_entries`) give the manifold its block structure
(:class:`manifold.JacobianPattern`); D²Φ is contracted loop by loop
(:func:`constraint_hessian_form`) without forming the c×k×k array that
:func:`constraint_hessian` returns.
"""

from __future__ import annotations

import functools
import math
import weakref
from dataclasses import dataclass, replace
from typing import Optional

import numpy as np

from manifold import AmbientSpace, ImplicitManifold
from manifold.blocks import JacobianPattern

from . import _chains as chains
from . import _groups as groups
from .joints import joint_factors

__all__ = [
    "Kinematics", "kinematics_of", "configuration_space",
    "constraint", "constraint_jacobian", "closure_and_jacobian", "closure_and_entries", "constraint_hessian", "closes",
    "closure_failure",
    "constraint_pattern", "constraint_jacobian_entries", "constraint_hessian_form",
    "end_effector", "end_effector_jacobian", "end_effector_reference", "end_effector_hessian",
    "end_effector_chart",
    "end_effector_dimension", "actuator_jacobian", "link_pose", "tool_basis", "loop_origin",
]


@dataclass(frozen=True, eq=False)
class Kinematics:
    """Compiled kinematic structure of a mechanism (derived once, reused).

    Attributes
    ----------
    space : str
    ambient : AmbientSpace
    loops : tuple
        One chain per independent loop (chord of the spanning tree), its twists written about
        :func:`loop_origin` of its root (the link chains' about the base frame's origin).
    chords : tuple of str
        Names of the chord joints, one per loop.
    link_chains : Mapping
        Link name -> chain from the ground to that link (built on first use).
    point_parts : dict
        Joint name -> tuple of slices of the point array holding its coordinates
        (one per ambient factor: one for R, P, S; two for U, C).
    length : float
        Characteristic length dividing translation rows, and the tangent scale
        of prismatic coordinates: :attr:`mechanisms.Mechanism.characteristic_length`,
        taken from the joints' points only, so that the end-effector point (no
        part of M) changes neither Φ nor the C-space rank and its margin.
    loop_groups : tuple of ChainGroup
        The loops sorted into groups of one shape (evaluated together).
    pattern : JacobianPattern
        Where DΦ can be nonzero: each loop's rows by its coordinates' columns.
    """

    space: str
    ambient: AmbientSpace
    loops: tuple
    chords: tuple
    link_chains: dict
    point_parts: dict
    length: float
    end_effector_link: Optional[str]
    end_effector_point: Optional[np.ndarray]
    output: Optional[str]
    loop_groups: tuple = ()
    end_effector_axis: Optional[np.ndarray] = None  # the unit tool axis at home (output "tool")
    pattern: Optional[JacobianPattern] = None
    point_size: int = 0
    link_groups: dict = None  # link name -> its chain's ChainGroup, built on first use


_CACHE = weakref.WeakKeyDictionary()


def kinematics_of(mechanism):
    """The compiled :class:`Kinematics` of a mechanism (cached per mechanism object)."""
    cached = _CACHE.get(mechanism)
    if cached is not None:
        return cached
    factors, scales = [], []
    length = mechanism.characteristic_length  # of the joints' points: M's description ignores the end-effector
    for joint in mechanism.joints:
        for factor in joint_factors(joint):
            factors.append(factor)
            scales.append(length if factor == "R" else 1.0)
    ambient = AmbientSpace(tuple(factors), tuple(scales))
    joint_elements, placements, point_parts, factor_index, tangent_start = [], [], {}, 0, 0
    for joint in mechanism.joints:
        count = len(joint_factors(joint))
        parts = ambient.point_slices[factor_index: factor_index + count]
        point_parts[joint.name] = parts
        joint_elements.append(chains.elements_of_joint(mechanism, joint, parts, tangent_start))
        placements.append((parts, tangent_start))
        factor_index += count
        tangent_start += sum(3 if f == "SO3" else 1 for f in joint_factors(joint))

    origins = functools.lru_cache(maxsize=None)(functools.partial(loop_origin, mechanism))

    def loop_elements(link, index):
        """Joint `index`'s elements about :func:`loop_origin` of `link`, for a loop whose root it is."""
        origin, joint = origins(link), mechanism.joints[index]
        if origin is None or joint.point is None:
            return joint_elements[index]
        moved = replace(joint, point=tuple(float(value) for value in np.subtract(joint.point, origin)))
        return chains.elements_of_joint(mechanism, moved, *placements[index])

    loops, chords, link_chains = chains.chains_of(mechanism, joint_elements, loop_elements)
    loop_groups = chains.groups_of(mechanism.space, loops)
    end_effector = mechanism.end_effector
    compiled = Kinematics(
        space=mechanism.space, ambient=ambient, loops=loops, chords=chords,
        link_chains=link_chains, point_parts=point_parts, length=length,
        end_effector_link=None if end_effector is None else end_effector.link,
        end_effector_point=None if end_effector is None or end_effector.point is None
        else np.asarray(end_effector.point, dtype=float),
        output=None if end_effector is None else end_effector.output,
        end_effector_axis=None if end_effector is None or end_effector.axis is None
        else np.asarray(end_effector.axis, dtype=float) / np.linalg.norm(end_effector.axis),
        loop_groups=loop_groups, pattern=chains.loop_pattern(mechanism.space, loop_groups, len(loops), ambient.dim),
        point_size=ambient.point_size, link_groups={},
    )
    _CACHE[mechanism] = compiled
    return compiled


def loop_origin(mechanism, link=None):
    """The point the loops rooted at `link` are written about, shape=[2] or [3], or None (the base frame's origin).

    A loop's closure is the product of its joints' motions from the deepest
    common ancestor of its chord's links on the spanning tree (the ground for
    most loops; :func:`mechanisms._chains.chains_of`), its root, and Φ's
    translation rows are the velocity of the loop's closing point at a point
    fixed in the root. That point is the centroid of the points the root's
    joints carry fixed in it: the points of its R, U and S joints (fixed in
    both of their links) and of the C joints whose first link it is (a C
    joint's point slides along its axis in its second link). It is a
    material point of the root, so it moves with the base frame and not with
    the home configuration, the joint zeros or the axis signs: the loop's
    rows then change with the base frame or the home only by a rotation, and
    the singular values of DΦ (the C-space rank's cut and margins) not at
    all. About the base frame's origin, a base frame 100 lengths away would
    scale the translation rows by about 100 and move the cut.

    A root that carries no such point, only P joints (the rails of a 3-PRR)
    or C joints whose second link it is, still carries lines fixed in it:
    the axis of such a C joint, and the line each fixed point of a link the
    root moves by one P joint alone slides along (parallel to the axis);
    another home only slides the points along them. The point is then the
    one nearest to these lines in the least-squares sense (:func:`_nearest_point`).

    None for a spherical mechanism (no translation rows); where the root
    carries neither points nor lines (the singular values of DΦ then depend
    on where the base frame is); and where the point is the base frame's
    origin to rounding (within 64 ε of the characteristic length: a base
    centred on its joints, as most are, keeps its twists exactly as
    written).

    Parameters
    ----------
    mechanism : Mechanism
    link : str, optional
        The loops' root; default the ground.
    """
    if mechanism.space == "spherical":
        return None
    link = mechanism.ground if link is None else link
    points = _fixed_points(mechanism, link)
    if points:
        centre = np.mean(np.asarray(points, dtype=float), axis=0)
    else:
        lines = _fixed_lines(mechanism, link)
        if not lines:
            return None
        centre = _nearest_point(*map(np.asarray, zip(*lines)))
    return None if np.linalg.norm(centre) <= 64 * np.finfo(float).eps * mechanism.characteristic_length else centre


def _fixed_points(mechanism, link):
    """The joint points fixed in `link` at home: of its R, U and S joints, and of the joints whose first link it
    is (a C joint's point slides along its axis in its second link)."""
    return [joint.point for joint in mechanism.joints if joint.point is not None and link in joint.links
            and (joint.type in ("R", "U", "S") or joint.links[0] == link)]


def _fixed_lines(mechanism, link):
    """(point, unit axis) of the lines fixed in `link` (:func:`loop_origin`): the axes of the C joints whose second
    link it is, and the lines the fixed points of a link it moves by one P joint alone slide along."""
    unit = lambda axis: np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    lines = [(np.asarray(joint.point, dtype=float), unit(joint.axis)) for joint in mechanism.joints
             if joint.type == "C" and joint.links[1] == link and joint.links[0] != link]
    touching = {}
    for joint in mechanism.joints:
        if link in joint.links and joint.links[0] != joint.links[1]:
            touching.setdefault(joint.links[1] if joint.links[0] == link else joint.links[0], []).append(joint)
    for other, joints in touching.items():
        if len(joints) == 1 and joints[0].type == "P":
            axis = unit(joints[0].axis)
            lines += [(np.asarray(point, dtype=float), axis) for point in _fixed_points(mechanism, other)]
    return lines


#: the nearest point of lines is taken along the directions where ΣPᵢ has an eigenvalue above
#: WELL_CROSSED · its largest, the centroid below WELL_CROSSED / 4, blended linearly in between
WELL_CROSSED = 0.2


def _nearest_point(points, axes):
    """The point nearest to lines (points pᵢ, unit axes aᵢ; shape=[lines, n] each), kept near the points.

    With Pᵢ = I − aᵢaᵢᵀ (the projection across line i), p̄ the centroid of the pᵢ and
    ΣPᵢ = Σ λ e eᵀ,

        c = p̄ + Σ_e w(λ / λ_max) (eᵀ Σ Pᵢ(pᵢ − p̄) / λ) e,

    w = 1 above :data:`WELL_CROSSED` (the least-squares point along e: the lines cross there, and the
    point is the same for any points on them), 0 below a quarter of it (the centroid: lines close to
    parallel along e, whose crossing would be about 1/angle lengths away and would scale σ₁(DΦ) with
    it), linear in between (no jump). The sum is over eigenspaces, so it does not depend on the
    eigenvectors' signs or on the basis of a repeated eigenvalue.
    """
    centroid = np.mean(points, axis=0)
    across = np.eye(points.shape[1]) - axes[:, :, None] * axes[:, None, :]
    values, vectors = np.linalg.eigh(np.sum(across, axis=0))
    shift = vectors.T @ np.einsum("lij,lj->i", across, points - centroid)
    ratio = values / values[-1]
    weight = np.clip((ratio - WELL_CROSSED / 4) / (WELL_CROSSED - WELL_CROSSED / 4), 0.0, 1.0)
    return centroid + vectors @ np.divide(weight * shift, values, out=np.zeros_like(shift), where=weight > 0)


def _link_group(compiled, link):
    """The :class:`~mechanisms._chains.ChainGroup` of the chain from the ground to `link` (built on first use)."""
    group = compiled.link_groups.get(link)
    if group is None:
        group = chains.chain_group(compiled.space, [compiled.link_chains[link]], [0])
        compiled.link_groups[link] = group
    return group


def _as_points(mechanism, point):
    point = np.asarray(point, dtype=float)
    size = kinematics_of(mechanism).point_size
    if point.shape[-1:] != (size,):
        raise ValueError(f"Expected `point` to have shape (..., {size}), got {point.shape}")
    return point


# --------------------------------------------------------------------------- constraints

def configuration_space(mechanism):
    """The C-space of a mechanism as an :class:`~manifold.ImplicitManifold`, with the block structure
    of DΦ (:attr:`Kinematics.pattern`) and the loop-by-loop contraction of D²Φ."""
    compiled = kinematics_of(mechanism)
    return ImplicitManifold(
        ambient=compiled.ambient,
        constraint=lambda point: constraint(mechanism, point),
        constraint_jacobian=lambda point: constraint_jacobian(mechanism, point),
        constraint_hessian=lambda point: constraint_hessian(mechanism, point),
        is_solution=lambda point: bool(np.all(closes(mechanism, point, tolerance=np.inf))),
        pattern=compiled.pattern,
        constraint_jacobian_entries=lambda point: constraint_jacobian_entries(mechanism, point),
        constraint_hessian_form=lambda point, left, right: constraint_hessian_form(mechanism, point, left, right),
        closing=closing_space(mechanism),
    )


def closing_space(mechanism):
    """M as the zero set of the *closing map*, which has no spurious zero: for far starts of Gauss-Newton.

    Φ's rotation rows ``½ vee(R − Rᵀ) = sin φ n`` vanish at the half-turns too (φ = π), and Gauss-Newton
    from a random point of K ends there for most loops: the rotation angle of a random rotation exceeds
    π/2 with probability 0.82, so with 5 loops (a Gough-Stewart platform) every one of 24 random starts of
    the survey did. The closing map's rotation rows are the rotation vector φ n (the angle arg r in the
    plane), zero only at R = I, discontinuous across φ = π (where Φ has its half-turns); its Jacobian is
    its derivative (:func:`mechanisms._chains.loop_closing`), equal to DΦ on M, so Gauss-Newton converges
    to the same points of M (:func:`manifold.sample_manifold` projects onto this map, then onto Φ). Same
    rows, pattern and scaling as Φ.
    """
    compiled = kinematics_of(mechanism)
    last = [None]  # ((shape, bytes), (rows, entries)) of the last point: Gauss-Newton asks rows, then entries

    def rows_and_entries(point):
        point = _as_points(mechanism, point)
        key = (point.shape, point.tobytes())
        cached = last[0]
        if cached is not None and cached[0] == key:
            return tuple(array.copy() for array in cached[1])  # copies: a caller may write into its arrays
        batch = point.shape[:-1]
        rows, entries = [], []
        for group in compiled.loop_groups:
            if compiled.space == "planar":
                group_rows, _, group_entries = chains.planar_loops(group, point, compiled.length, closing=True)
            else:
                group_rows, group_entries = chains.loop_closing(compiled.space, group, point, compiled.length)
            rows.append((group.chains, group_rows))
            entries.append(_flattened(group_entries, batch))
        values = np.zeros(batch + (len(compiled.loops), groups.LOOP_ROWS[compiled.space]))
        for chains_of_group, group_rows in rows:
            values[..., chains_of_group, :] = group_rows
        result = (_flattened(values, batch), np.concatenate(entries, axis=-1) if entries else np.zeros(batch + (0,)))
        last[0] = (key, result)  # one assignment: another thread sees the old pair or the new one
        return tuple(array.copy() for array in result)

    return ImplicitManifold(ambient=compiled.ambient, constraint=lambda point: rows_and_entries(point)[0],
                            constraint_jacobian=lambda point: compiled.pattern.dense(rows_and_entries(point)[1]),
                            pattern=compiled.pattern,
                            constraint_jacobian_entries=lambda point: rows_and_entries(point)[1])


def _flattened(array, batch):
    """`array` of shape [*batch, ...] with its trailing axes as one, shape=[*batch, size] (a reshape with -1
    would fail on an empty stack)."""
    return array.reshape(batch + (math.prod(array.shape[len(batch):]),))


def constraint(mechanism, point):
    """Loop-closure map Φ(point), rows loop by loop, shape=[..., c].

    Rotation rows ``½ vee(R − Rᵀ)`` then translation rows over the
    characteristic length, for each loop product R, p written about
    :func:`loop_origin` (docs/conventions.rst, "Loop rows").
    """
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    if compiled.space == "planar":
        return _planar_closure(compiled, point, 0)[0]
    rows = groups.loop_rows(compiled.space, chains.loop_products(compiled, point), compiled.length)
    return _flattened(rows, point.shape[:-1])


def _planar_closure(compiled, point, order):
    """Φ, the half-turn test and DΦ's entries of a planar mechanism in complex form
    (:func:`mechanisms._chains.planar_loops`): ``(rows [..., c], turns [...], entries [..., nnz] or None)``."""
    batch = point.shape[:-1]
    rows = np.zeros(batch + (len(compiled.loops), 3))
    turns = np.ones(batch, dtype=bool)
    entries = []
    for group in compiled.loop_groups:
        group_rows, group_turns, group_entries = chains.planar_loops(group, point, compiled.length, order)
        rows[..., group.chains, :] = group_rows
        turns &= np.all(group_turns, axis=-1)
        if order >= 1:
            entries.append(_flattened(group_entries, batch))
    if order < 1:
        return _flattened(rows, batch), turns, None
    entries = np.concatenate(entries, axis=-1) if entries else np.zeros(batch + (0,))
    return _flattened(rows, batch), turns, entries


def constraint_pattern(mechanism):
    """Where DΦ can be nonzero (:class:`manifold.JacobianPattern`): the rows of each loop by the
    columns of the coordinates on it."""
    return kinematics_of(mechanism).pattern


def constraint_jacobian_entries(mechanism, point):
    """The entries of DΦ(point) at :func:`constraint_pattern`, in its order, shape=[..., nnz]."""
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    if compiled.space == "planar":
        return _planar_closure(compiled, point, 1)[2]
    entries = [_flattened(chains.loop_first_order(compiled.space, group, point, compiled.length)[1],
                          point.shape[:-1]) for group in compiled.loop_groups]  # [..., g, C, R] each
    return np.concatenate(entries, axis=-1) if entries else np.zeros(point.shape[:-1] + (0,))


def constraint_jacobian(mechanism, point):
    """DΦ(point) in the recentred chart, shape=[..., c, k]."""
    return kinematics_of(mechanism).pattern.dense(constraint_jacobian_entries(mechanism, point))


def closure_and_jacobian(mechanism, point):
    """Φ(point), whether no loop is a half-turn, and DΦ(point), from one expansion of each loop.

    What :func:`constraint`, :func:`closes` (its half-turn test) and
    :func:`constraint_jacobian` compute, for the price of one: the loop
    products are the last prefix products of the first-order expansion.
    It is :func:`closure_and_entries` (the same parameters, `rows` and `turns`) with DΦ's entries at
    :func:`constraint_pattern` made dense.

    Returns
    -------
    rows, turns : ndarray
        As :func:`closure_and_entries`.
    jacobian : ndarray, shape=[..., c, k]
        DΦ, as :func:`constraint_jacobian`.
    """
    rows, turns, entries = closure_and_entries(mechanism, point)
    return rows, turns, kinematics_of(mechanism).pattern.dense(entries)


def closure_and_entries(mechanism, point):
    """Φ(point), whether no loop is a half-turn, and DΦ(point)'s entries at :func:`constraint_pattern`, from one
    expansion of each loop: :func:`closure_and_jacobian` without the dense c × k matrices (a large mechanism's
    DΦ has a few entries per row).

    Parameters
    ----------
    mechanism : Mechanism
    point : array_like, shape=[..., point_size]

    Returns
    -------
    rows : ndarray, shape=[..., c]
        Φ, as :func:`constraint`.
    turns : ndarray of bool, shape=[...]
        Whether every loop's rotation is the identity rather than a half-turn (whose rotation rows vanish
        too), as in :func:`closes`.
    entries : ndarray, shape=[..., nnz]
        DΦ's entries in the pattern's order, as :func:`constraint_jacobian_entries`.
    """
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    if compiled.space == "planar":
        return _planar_closure(compiled, point, 1)
    size = groups.MATRIX_SIZE[compiled.space]
    products = np.zeros(point.shape[:-1] + (len(compiled.loops), size, size))
    entries = []
    for group in compiled.loop_groups:
        product, group_entries = chains.loop_first_order(compiled.space, group, point, compiled.length)
        products[..., group.chains, :, :] = product
        entries.append(_flattened(group_entries, point.shape[:-1]))
    entries = np.concatenate(entries, axis=-1) if entries else np.zeros(point.shape[:-1] + (0,))
    rows = _flattened(groups.loop_rows(compiled.space, products, compiled.length), point.shape[:-1])
    turns = np.all(groups.is_identity_rotation(compiled.space, products), axis=-1)
    return rows, turns, entries


def constraint_hessian(mechanism, point):
    """D²Φ(point) in the recentred chart, shape=[..., c, k, k].

    A dense array of c·k² entries: for large mechanisms use
    :func:`constraint_hessian_form`, which contracts it loop by loop.
    """
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    hessian = np.zeros(point.shape[:-1] + compiled.pattern.shape + (compiled.ambient.dim,))
    for rows, columns, values in chains.hessian_blocks(compiled, point):
        hessian[..., rows[:, :, None, None], columns[:, None, :, None], columns[:, None, None, :]] = values
    return hessian


def constraint_hessian_form(mechanism, point, left, right=None):
    """``D²Φ(point)(left[:, i], right[:, j])`` loop by loop, without the c×k×k Hessian.

    Parameters
    ----------
    mechanism : Mechanism
    point : array_like, shape=[..., point_size]
    left : array_like, shape=[k, i]
    right : array_like, shape=[k, j], optional
        Default `left`.

    Returns
    -------
    form : ndarray, shape=[..., c, i, j]
    """
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    left = np.asarray(left, dtype=float)
    right = left if right is None else np.asarray(right, dtype=float)
    form = np.zeros(point.shape[:-1] + (compiled.pattern.shape[0], left.shape[1], right.shape[1]))
    for rows, columns, values in chains.hessian_blocks(compiled, point):
        form[..., rows, :, :] = np.einsum("...grab,gai,gbj->...grij", values, left[columns], right[columns],
                                          optimize=True)
    return form


#: Largest ‖RᵀR − I‖ (Frobenius) and |det R − 1| of a ball joint's block R that :func:`closes` accepts as a
#: rotation: far above the rounding of the chart steps (‖RᵀR − I‖ about 1e-13 after 20,000 retractions),
#: far below any block that is not a rotation.
ROTATION_TOLERANCE = 1e-9


def rotation_blocks(mechanism, point):
    """Which SO(3) blocks of `point` are rotations, within :data:`ROTATION_TOLERANCE`.

    Φ's rotation rows ``½ vee(R − Rᵀ)`` do not see the symmetric part of a
    ball joint's block (``diag(1.5, 1.5, 1)`` gives Φ = 0), so a point of K
    must have its blocks checked apart: ``‖RᵀR − I‖ ≤ ROTATION_TOLERANCE``
    (Frobenius) and ``|det R − 1| ≤ ROTATION_TOLERANCE``. Elementwise
    arithmetic only, so that a stack gives, bit for bit, the answers of its
    points one at a time. A non-finite block is no rotation.

    Parameters
    ----------
    mechanism : Mechanism
    point : array_like, shape=[..., point_size]

    Returns
    -------
    names : tuple of str
        The joints with an SO(3) factor (ball joints), in order, one per block.
    rotations : ndarray of bool, shape=[..., len(names)]
        Whether each joint's block is a rotation.
    """
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    ambient = compiled.ambient
    # each factor's position among the point's slices, keyed by (start, stop): a slice has no hash before 3.12
    positions = {(part.start, part.stop): index for index, part in enumerate(ambient.point_slices)}
    names, parts = [], []
    for name, slices in compiled.point_parts.items():
        for part in slices:
            if ambient.factors[positions[part.start, part.stop]] == "SO3":
                names.append(name)
                parts.append(part)
    if not parts:
        return (), np.ones(point.shape[:-1] + (0,), dtype=bool)
    blocks = np.stack([point[..., part] for part in parts], axis=-2).reshape(point.shape[:-1] + (len(parts), 3, 3))
    columns = [blocks[..., :, column] for column in range(3)]  # R's columns, shape=[..., n, 3]
    gram_error = np.zeros(blocks.shape[:-2])
    for i in range(3):
        for j in range(3):
            entry = (columns[i][..., 0] * columns[j][..., 0] + columns[i][..., 1] * columns[j][..., 1]
                     + columns[i][..., 2] * columns[j][..., 2]) - (1.0 if i == j else 0.0)
            gram_error = gram_error + entry * entry
    first, second, third = columns
    determinant = (first[..., 0] * (second[..., 1] * third[..., 2] - second[..., 2] * third[..., 1])
                   - first[..., 1] * (second[..., 0] * third[..., 2] - second[..., 2] * third[..., 0])
                   + first[..., 2] * (second[..., 0] * third[..., 1] - second[..., 1] * third[..., 0]))
    rotations = (np.sqrt(gram_error) <= ROTATION_TOLERANCE) & (np.abs(determinant - 1.0) <= ROTATION_TOLERANCE)
    return tuple(names), rotations


def closes(mechanism, point, tolerance=1e-9):
    """Whether `point` is a point of M: every loop closes and every ball joint's block is a rotation.

    Parameters
    ----------
    mechanism : Mechanism
    point : array_like, shape=[..., point_size]
    tolerance : float
        Largest ‖Φ‖ of a closed loop (per loop); ``np.inf`` keeps only the
        half-turn and rotation tests.

    Returns
    -------
    ndarray of bool, shape=[...]
        True where ‖Φ‖ ≤ `tolerance` for every loop, no loop closes on a
        half-turn (whose rotation rows vanish too), and every SO(3) block is a
        rotation within ``ROTATION_TOLERANCE`` = 1e-9 (:func:`rotation_blocks`:
        Φ cannot see a block's symmetric part). A stack gives the answers of
        its points one at a time.
    """
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    rotations = np.all(rotation_blocks(mechanism, point)[1], axis=-1)
    if compiled.space == "planar":
        rows, turns, _ = _planar_closure(compiled, point, 0)
        rows = rows.reshape(point.shape[:-1] + (len(compiled.loops), 3))
        return np.all(np.linalg.norm(rows, axis=-1) <= tolerance, axis=-1) & turns & rotations
    products = chains.loop_products(compiled, point)
    rows = groups.loop_rows(compiled.space, products, compiled.length)
    return (np.all(np.linalg.norm(rows, axis=-1) <= tolerance, axis=-1)
            & np.all(groups.is_identity_rotation(compiled.space, products), axis=-1) & rotations)


def closure_failure(mechanism, point, tolerance=1e-9):
    """Why one point is not a point of M, or None where it is (:func:`closes`).

    Parameters
    ----------
    mechanism : Mechanism
    point : array_like, shape=[point_size]
    tolerance : float

    Returns
    -------
    tuple of (str, str) or None
        ``(kind, text)``: ``"rotation"`` (a ball joint's block is no rotation, the joint named),
        ``"half-turn"`` (Φ = 0 at a loop turned by π: a spurious zero of Φ) or ``"residual"`` (‖Φ‖ above
        `tolerance`), with a phrase saying so.
    """
    point = _as_points(mechanism, point)
    if bool(closes(mechanism, point, tolerance)):
        return None
    names, rotations = rotation_blocks(mechanism, point)
    wrong = [name for name, rotation in zip(names, np.atleast_1d(rotations)) if not rotation]
    if wrong:
        return "rotation", (f"the block of ball joint {wrong[0]!r} is not a rotation (‖RᵀR − I‖ or |det R − 1| "
                            f"above {ROTATION_TOLERANCE:g})")
    residual = float(np.linalg.norm(constraint(mechanism, point)))
    if residual <= tolerance:  # Φ = 0, yet no point of M: a loop turned by π (a loop merely far off is no half-turn)
        return "half-turn", (f"a loop closes only at a half-turn (|Φ| = {residual:.3g}: Φ's rotation rows vanish "
                             f"there too, a spurious zero of Φ, not a point of the C-space)")
    return "residual", f"the configuration does not close the loops (|Φ| = {residual:.3g} > {tolerance:g})"


def link_pose(mechanism, link, point):
    """Pose of a link relative to its home pose, in the ground frame, shape=[..., n, n]."""
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    return chains.expand_group(compiled.space, _link_group(compiled, link), point, 0)[0][..., 0, :, :]


def link_poses(mechanism, point):
    """The pose of every link, as :func:`link_pose`, in one pass over the spanning tree.

    :func:`link_pose` multiplies the element matrices of the whole path from
    the ground, O(depth) for one link and O(k²) for all of them along a chain
    of k joints. Here each link's pose is its parent's on the tree (the tree
    of :func:`mechanisms._chains.chains_of`: its joints are those that are no
    chord) times the element matrices of the tree joint between them, in the
    order :func:`link_pose` multiplies them, so the poses are the same, and
    all of them cost O(k).

    Parameters
    ----------
    mechanism : Mechanism
    point : ndarray, shape=[..., point_size]

    Returns
    -------
    dict of str to ndarray, shape=[..., n, n]
        Link name -> pose, for the ground (the identity) and every link the tree reaches, in breadth-first order.
    """
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    space, chords = compiled.space, set(compiled.chords)
    size = groups.MATRIX_SIZE[space]
    joint_elements, incident, tangent_start = [], {}, 0
    for index, joint in enumerate(mechanism.joints):
        joint_elements.append(chains.elements_of_joint(mechanism, joint, compiled.point_parts[joint.name],
                                                       tangent_start))
        tangent_start += sum(len(element.twists) for element in joint_elements[-1])
        if joint.name not in chords:
            for link in dict.fromkeys(joint.links):
                incident.setdefault(link, []).append(index)
    steps, order, reached = [], [mechanism.ground], {mechanism.ground}  # steps: (link, parent, (joint, forward))
    for link in order:  # grows while it is read: breadth-first from the ground
        for index in incident.get(link, ()):
            joint = mechanism.joints[index]
            other = joint.links[1] if joint.links[0] == link else joint.links[0]
            if other in reached:
                continue
            steps.append((other, link, (index, joint.links[0] == link)))
            order.append(other)
            reached.add(other)
    step_chains = [chains.traverse(joint_elements, [step]) for _, _, step in steps]
    located = {}  # step number -> (element matrices of its group [..., g, L, n, n], row in the group)
    for group in chains.groups_of(space, step_chains):
        matrices = chains.element_matrices(space, group, point)
        located.update((number, (matrices, row)) for row, number in enumerate(group.chains))
    poses = {mechanism.ground: np.broadcast_to(np.eye(size), point.shape[:-1] + (size, size)).copy()}
    for number, (link, parent, _) in enumerate(steps):
        matrices, row = located[number]
        pose = poses[parent]
        for position in range(matrices.shape[-3]):
            pose = pose @ matrices[..., row, position, :, :]
        poses[link] = pose
    return poses


def actuator_jacobian(mechanism):
    """Dπ: the selection of the actuated coordinates, shape=[a, k] (constant in the chart)."""
    compiled = kinematics_of(mechanism)
    selection = np.zeros((len(mechanism.actuated_coordinates), compiled.ambient.dim))
    for row, index in enumerate(mechanism.actuated_coordinates):
        selection[row, index] = 1.0
    return selection


# --------------------------------------------------------------------------- end-effector

_OUTPUT_DIMENSION = {
    ("planar", "position"): 2, ("planar", "orientation"): 1, ("planar", "pose"): 3,
    ("spherical", "orientation"): 3,
    ("spatial", "position"): 3, ("spatial", "orientation"): 3, ("spatial", "pose"): 6, ("spatial", "tool"): 5,
}


def end_effector_dimension(mechanism):
    """n = dim N (0 when the mechanism has no end-effector)."""
    compiled = kinematics_of(mechanism)
    return 0 if compiled.output is None else _OUTPUT_DIMENSION[(compiled.space, compiled.output)]


def _offset(compiled):
    size = groups.MATRIX_SIZE[compiled.space]
    offset = np.eye(size)
    if compiled.end_effector_point is not None and compiled.space != "spherical":
        offset[: size - 1, size - 1] = compiled.end_effector_point
    return offset


def _twist_components(compiled):
    """Which twist coordinates the output keeps."""
    rotation_rows = groups.ROTATION_ROWS[compiled.space]
    if compiled.output == "orientation":
        return slice(0, rotation_rows)
    return slice(None)


def _require_end_effector(mechanism):
    compiled = kinematics_of(mechanism)
    if compiled.output is None:
        raise ValueError(f"mechanism {mechanism.name!r} has no end-effector")
    return compiled


def end_effector(mechanism, point):
    """f(point): the position, shape=[..., d], the frame matrix, shape=[..., n, n], or the tool, shape=[..., 6].

    For ``orientation`` and ``pose`` outputs the value is the homogeneous
    matrix of the end-effector frame (orientation of its link, origin at the
    end-effector point). For ``tool`` it is ``(x, u)``: the tool point x ∈ ℝ³
    and the unit direction u ∈ S² of the tool's axis, both carried by the
    link's pose. Local coordinates are given by :func:`end_effector_chart`.
    """
    compiled = _require_end_effector(mechanism)
    point = _as_points(mechanism, point)
    product = link_pose(mechanism, compiled.end_effector_link, point)
    if compiled.output == "position":
        size = groups.MATRIX_SIZE[compiled.space]
        return (product @ _offset(compiled))[..., : size - 1, size - 1]
    if compiled.output == "tool":
        carried = product @ _tool_vectors(compiled)  # [..., 4, 2]: the point and the axis
        return np.concatenate([carried[..., :3, 0], carried[..., :3, 1]], axis=-1)
    return product @ _offset(compiled)


def _tool_vectors(compiled):
    """The tool point and axis at home as homogeneous columns ``[[x, a], [1, 0]]``, shape=[4, 2]."""
    vectors = np.zeros((4, 2))
    vectors[:3, 0], vectors[3, 0] = compiled.end_effector_point, 1.0
    vectors[:3, 1] = compiled.end_effector_axis
    return vectors


def tool_basis(direction):
    """An orthonormal basis (e₁, e₂) of the plane u^⊥, the tangent plane of S² at u: the chart of a
    ``tool`` output's direction.

    e₁ is the unit projection onto u^⊥ of the coordinate axis least aligned
    with u, e₂ = u × e₁. Nothing computed from a ``tool`` output depends on
    this choice: another orthonormal basis turns the direction rows of Df by
    a 2 × 2 rotation (or reflection), which H = diag(I₃, L² I₂) does not see.
    Reversing u keeps e₁ and reverses e₂.

    Parameters
    ----------
    direction : array_like, shape=[..., 3]
        Unit vectors u.

    Returns
    -------
    ndarray, shape=[..., 2, 3]
        The rows e₁, e₂.
    """
    direction = np.asarray(direction, dtype=float)
    least = np.argmin(np.abs(direction), axis=-1)
    axis = np.zeros(direction.shape)
    np.put_along_axis(axis, least[..., None], 1.0, axis=-1)
    first = axis - np.sum(axis * direction, axis=-1, keepdims=True) * direction
    first = first / np.linalg.norm(first, axis=-1, keepdims=True)
    return np.stack([first, np.cross(direction, first)], axis=-2)


def end_effector_chart(mechanism, base_value, value):
    """Local coordinates of `value` in the chart of N centred at `base_value`.

    Position outputs: the difference. Orientation and pose outputs: the twist
    coordinates of ``log(F₀⁻¹ F)`` (rotation components only for orientation).
    Tool outputs ``(x, u)``: ``(x − x₀, E(u₀) log_{u₀} u)``, where
    ``log_{u₀} u = θ (u − cos θ u₀) / sin θ`` (θ the angle from u₀ to u) is
    the Riemannian logarithm of S² and E(u₀) the rows of :func:`tool_basis`
    — shape=[..., 5]; ``|chart|²`` with the direction part times L² is the
    squared distance of the metric ``|dx|² + L²|du|²`` to second order.
    """
    compiled = _require_end_effector(mechanism)
    if compiled.output == "position":
        return np.asarray(value) - np.asarray(base_value)
    if compiled.output == "tool":
        return _tool_chart(np.asarray(base_value, dtype=float), np.asarray(value, dtype=float))
    from scipy.linalg import logm

    relative = groups.inverse(compiled.space, np.asarray(base_value)) @ np.asarray(value)
    flat = relative.reshape((-1,) + relative.shape[-2:])
    logs = np.array([np.real(logm(matrix)) for matrix in flat]).reshape(relative.shape)
    return groups.vee(compiled.space, logs)[..., _twist_components(compiled)]


def _tool_chart(base_value, value):
    """``(x − x₀, E(u₀) log_{u₀} u)`` for tool values ``(x₀, u₀)``, ``(x, u)``, shape=[..., 5]."""
    base_direction, direction = base_value[..., 3:], value[..., 3:]
    cosine = np.clip(np.sum(base_direction * direction, axis=-1, keepdims=True), -1.0, 1.0)
    normal = direction - cosine * base_direction
    sine = np.linalg.norm(normal, axis=-1, keepdims=True)
    angle = np.arctan2(sine, cosine)
    factor = np.divide(angle, sine, out=np.ones_like(sine), where=sine > 1e-300)  # θ / sin θ → 1
    logarithm = factor * normal
    coordinates = np.einsum("...ij,...j->...i", tool_basis(base_direction), logarithm)
    return np.concatenate([value[..., :3] - base_value[..., :3], coordinates], axis=-1)


def _end_effector_expansion(mechanism, point, order):
    """The chain to the end-effector's link: (compiled, point, group, product, first, second), the chain
    axis of :func:`~mechanisms._chains.expand_group` removed."""
    compiled = _require_end_effector(mechanism)
    point = _as_points(mechanism, point)
    group = _link_group(compiled, compiled.end_effector_link)
    if order == 1 and compiled.space != "planar":
        (product, first), second = chains.first_derivatives(compiled.space, group, point), None
    else:
        product, first, second = chains.expand_group(compiled.space, group, point, order)
    return (compiled, point, group, product[..., 0, :, :], None if first is None else first[..., 0, :, :, :],
            None if second is None else second[..., 0, :, :, :, :])


def end_effector_jacobian(mechanism, point):
    """Df(point) in the chart of N at f(point), shape=[..., n, k].

    Position outputs: ∂(T x)/∂v. Orientation and pose outputs: body twists
    ``vee(F⁻¹ ∂F/∂v)``. Tool outputs: ∂(T x)/∂v, then ``E(u) ∂(T a)/∂v``
    (the rate ω × u of the direction in the basis :func:`tool_basis` of u^⊥).
    """
    compiled = _require_end_effector(mechanism)
    if compiled.space == "planar":
        point = _as_points(mechanism, point)
        group = _link_group(compiled, compiled.end_effector_link)
        columns = _planar_end_effector_columns(compiled, group, point)
    else:
        compiled, point, group, product, first, _ = _end_effector_expansion(mechanism, point, 1)
        columns = _end_effector_columns(compiled, product, first)
    jacobian = np.zeros(point.shape[:-1] + (end_effector_dimension(mechanism), compiled.ambient.dim))
    jacobian[..., :, group.columns[0]] = np.swapaxes(columns, -1, -2)
    return jacobian


def end_effector_reference(mechanism, point):
    """Rows whose σ₁ is the reference scale of the end-effector rank decision, before H^½: ``R(p)·diag(s)`` up to
    an orthogonal change of its columns, shape=[..., n, r].

    R(p) gives every joint coordinate a column: the rate of f its screw at p
    would give the end-effector. Df (:func:`end_effector_jacobian`) is
    nonzero only on the spanning tree's path from the ground to the
    end-effector's link, and which joints the tree puts there depends on the
    order the file lists them in: σ₁(H^½ Df·diag(s)) moved by up to 37 %
    with that order alone (a 3-PRR), and so did a verdict near the cut.
    R(p) depends neither on the order nor on the direction a joint is
    written in; on the path's coordinates its columns are Df's.

    With ξ⁰ a coordinate's twist at home (twist coordinates, as
    :func:`mechanisms._groups.vee`), carried by the pose g of a link its
    axis is fixed in — ξ = Ad_g ξ⁰; on M the same for either link of an R,
    P, C or S joint; a U joint's first axis is fixed in its first link
    only, its second in its second —
    and A(p) the map from a twist ξ to the rate of f its motion ∂F = ξ̂ F
    of the end-effector frame gives (in the chart of
    :func:`end_effector_jacobian`), the column is A(p) ξ. The coordinates
    carried by one link c make ``A Ad_{g_c} Ξ⁰_c diag(s_c)``: the rows are
    these blocks side by side, zero-padded (a block of more than d columns
    replaced by d of the same Gram; the columns of a ball's three
    coordinates are its chart's up to a rotation among them, which no
    singular value sees).

    Parameters
    ----------
    mechanism : Mechanism
    point : ndarray, shape=[..., point_size]

    Returns
    -------
    ndarray, shape=[..., n, r]
        r = the links carrying axes (the ground and the end-effector's link
        counted) times the most coordinates one of them carries (at most
        the twists' dimension d: 3 or 6).
    """
    compiled = _require_end_effector(mechanism)
    point = _as_points(mechanism, point)
    plan = _reference_plan(mechanism)
    if compiled.space == "planar":
        return _planar_reference(compiled, plan, point)
    return _screw_reference(mechanism, compiled, plan, point)


def _screw_reference(mechanism, compiled, plan, point):
    """:func:`end_effector_reference` with matrices, for every space and output: the blocks
    ``A Ad_{g_c} Ξ⁰_c diag(s_c)`` side by side, shape=[..., n, r]."""
    size = groups.MATRIX_SIZE[compiled.space]
    product = link_pose(mechanism, compiled.end_effector_link, point)                     # [..., s, s]
    poses = np.empty(point.shape[:-1] + (len(plan.carriers), size, size))
    poses[..., 0, :, :] = np.eye(size)                                                    # the ground
    poses[..., plan.chained - 1, :, :] = product            # the end-effector's link (unless it is the ground)
    # every other carrier's pose from the tree of their chains' prefixes, in a few array operations
    poses[..., plan.chained:, :, :] = chains.matrix_tree_products(compiled.space, plan.tree, point)
    carried = _adjoint(compiled.space, poses) @ plan.twists                               # [..., c, d, w]
    count, dimension, width = carried.shape[-3:]
    twists = np.moveaxis(carried, -3, -2).reshape(carried.shape[:-3] + (dimension, count * width))  # [..., d, c·w]
    return _twist_rates(compiled, product) @ twists


def _narrowed(twists):
    """A link's carried twists Ξ [d, w] as at most d columns of the same Gram: where w > d (the Gough–Stewart's
    platform carries its six balls' 18), Rᵀ of the QR factorisation Ξᵀ = Q R (Ξ Ξᵀ = Rᵀ R) — any matrix of that
    Gram gives the same singular values once carried and mapped (both are linear). Householder QR is accurate
    row by row of Ξ (column by column of Ξᵀ), so rotation rows of size 1 beside translation rows of size 10⁶
    (a mechanism in micrometres) keep their digits, which an eigendecomposition of Ξ Ξᵀ would not."""
    dimension, width = twists.shape
    if width <= dimension:
        return twists
    return np.linalg.qr(twists.T, mode="r").T


def _planar_reference(compiled, plan, point):
    """:func:`end_effector_reference` of a planar mechanism in complex form, in Df's chart, shape=[..., n, r].

    With the carriers' poses ``(r, t)`` (:func:`mechanisms._chains.planar_prefixes`), a coordinate's home twist
    ``(ω, v)`` (v complex, times its scale) moves the end-effector point x at ``z = r v + i ω (x − t)`` (its twist
    carried, ``(ω, r v − i ω t)``, at x). A point's rows are Re z, Im z; an orientation's the rates ω; a pose's
    body twist ω, Re, Im of ``r̄_F z`` (r_F the frame's rotation), as :func:`_planar_end_effector_columns`.
    """
    batch = point.shape[:-1]
    angular = plan.twists[:, 0, :].ravel()                                                   # [c·w]
    if compiled.output == "orientation":
        return np.broadcast_to(angular, batch + (1, angular.size))
    rotations = np.ones(batch + (len(plan.carriers),), dtype=complex)
    translations = np.zeros(batch + (len(plan.carriers),), dtype=complex)
    if plan.chained == 2:  # the end-effector's link (unless it is the ground): as Df takes it
        prefix_rotations, prefix_translations = chains.planar_prefixes(
            _link_group(compiled, compiled.end_effector_link), point)
        rotations[..., 1], translations[..., 1] = prefix_rotations[..., 0, -1], prefix_translations[..., 0, -1]
    # every other carrier's pose from the tree of their chains' prefixes, in a few array operations
    rotations[..., plan.chained:], translations[..., plan.chained:] = chains.planar_tree_products(plan.tree, point)
    rotation, translation = rotations[..., plan.chained - 1], translations[..., plan.chained - 1]
    position = _planar_point(compiled, rotation, translation)
    linear = plan.twists[:, 1, :] + 1j * plan.twists[:, 2, :]                                  # [c, w]
    rates = rotations[..., None] * linear + 1j * plan.twists[:, 0, :] * (position[..., None, None]
                                                                         - translations[..., None])
    rates = rates.reshape(batch + (angular.size,))
    if compiled.output == "position":
        return np.stack([rates.real, rates.imag], axis=-2)
    body = np.conj(rotation)[..., None] * rates
    return np.stack([np.broadcast_to(angular, rates.shape), body.real, body.imag], axis=-2)


def _twist_rates(compiled, product):
    """A(p): the rates of f that twists ξ (twist coordinates) give the end-effector, shape=[..., n, d] — with F
    the end-effector frame (the link's pose `product` times its offset), x its origin and R its rotation: a
    position moves at v + ω × x (``[−x̂ | I]``), an orientation at the body rate Rᵀω, a pose at the body twist
    Ad_{F⁻¹} ξ, a tool's direction u at E(u)(ω × u) (:func:`tool_basis`); the rows of Df's chart."""
    space, output = compiled.space, compiled.output
    size = groups.MATRIX_SIZE[space]
    frame = product @ _offset(compiled)
    if output == "pose":
        return _adjoint(space, groups.inverse(space, frame))
    if output == "orientation":
        if space == "planar":
            return np.broadcast_to(np.array([[1.0, 0.0, 0.0]]), frame.shape[:-2] + (1, 3))
        rotation_t = np.swapaxes(frame[..., :3, :3], -1, -2)
        if space == "spherical":
            return rotation_t
        return np.concatenate([rotation_t, np.zeros(rotation_t.shape)], axis=-1)
    if space == "planar":  # position
        x, y = frame[..., 0, 2], frame[..., 1, 2]
        rates = np.zeros(frame.shape[:-2] + (2, 3))
        rates[..., 0, 0], rates[..., 1, 0] = -y, x
        rates[..., 0, 1] = rates[..., 1, 2] = 1.0
        return rates
    position = (product @ _tool_vectors(compiled))[..., :3, 0] if output == "tool" else frame[..., :3, size - 1]
    rates = np.concatenate([-_skew(position), np.broadcast_to(np.eye(3), position.shape[:-1] + (3, 3))], axis=-1)
    if output == "position":
        return rates
    direction = (product @ _tool_vectors(compiled))[..., :3, 1]
    turned = -tool_basis(direction) @ _skew(direction)                       # E(u)(ω × u) = −E(u) û ω
    return np.concatenate([rates, np.concatenate([turned, np.zeros(turned.shape)], axis=-1)], axis=-2)


def _skew(vectors):
    """v̂ of vectors, shape=[..., 3, 3]."""
    matrices = np.zeros(vectors.shape[:-1] + (3, 3))
    matrices[..., 0, 1], matrices[..., 0, 2], matrices[..., 1, 2] = -vectors[..., 2], vectors[..., 1], -vectors[..., 0]
    return matrices - np.swapaxes(matrices, -1, -2)


def _adjoint(space, poses):
    """Ad_g of poses g, acting on twist coordinates (:func:`mechanisms._groups.vee`), shape=[..., d, d]."""
    if space == "spherical":
        return poses
    if space == "planar":
        adjoint = np.zeros(poses.shape[:-2] + (3, 3))
        adjoint[..., 0, 0] = 1.0
        adjoint[..., 1:, 1:] = poses[..., :2, :2]
        adjoint[..., 1, 0], adjoint[..., 2, 0] = poses[..., 1, 2], -poses[..., 0, 2]
        return adjoint
    rotation, translation = poses[..., :3, :3], poses[..., :3, 3]
    adjoint = np.zeros(poses.shape[:-2] + (6, 6))
    adjoint[..., :3, :3] = adjoint[..., 3:, 3:] = rotation
    adjoint[..., 3:, :3] = _skew(translation) @ rotation
    return adjoint


@dataclass(frozen=True)
class _ReferencePlan:
    """What :func:`end_effector_reference` evaluates: the links carrying axes (the ground and the end-effector's
    link first: `chained` of them), the chains of the others as the tree of their prefixes (`tree`: a
    :class:`~mechanisms._chains.PlanarTree` for a planar mechanism, else a :class:`~mechanisms._chains.MatrixTree`),
    and the twists each carries times its coordinates' scales [c, d, w] (zero-padded; at most d columns of their
    Gram where a link carries more, :func:`_narrowed`)."""

    carriers: tuple
    chained: int
    tree: object
    twists: np.ndarray


_REFERENCE_PLANS = weakref.WeakKeyDictionary()


def _reference_plan(mechanism):
    plan = _REFERENCE_PLANS.get(mechanism)
    if plan is not None:
        return plan
    compiled = kinematics_of(mechanism)
    space, scales = compiled.space, compiled.ambient.tangent_scales
    first = tuple(dict.fromkeys((mechanism.ground, compiled.end_effector_link)))
    # of two links that carry an axis: the ground's pose costs nothing and the end-effector link's is computed
    # anyway; else the nearer the ground
    lengths = dict(zip(mechanism.links, chains.prefix_tree(compiled.link_chains, mechanism.links)[3]))
    cost = lambda link: (-1 if link in first else lengths[link])
    carried, tangent_start = {link: [] for link in first}, 0
    for joint in mechanism.joints:
        elements = chains.elements_of_joint(mechanism, joint, compiled.point_parts[joint.name], tangent_start)
        for number, element in enumerate(elements):
            # a U joint's first axis is fixed in its first link, its second in its second; any other axis in both
            link = joint.links[number] if joint.type == "U" else min(joint.links, key=cost)
            for index, twist in zip(element.tangent_indices, element.twists):
                carried.setdefault(link, []).append(scales[index] * groups.vee(space, twist))
        tangent_start += sum(len(element.twists) for element in elements)
    links = (*first, *[link for link in carried if link not in first])
    dimension = groups.vee(space, np.zeros((groups.MATRIX_SIZE[space],) * 2)).shape[-1]
    blocks = [_narrowed(np.array(carried.get(link, []), dtype=float).reshape(-1, dimension).T) for link in links]
    twists = np.zeros((len(links), dimension, max(block.shape[1] for block in blocks)))
    for position, block in enumerate(blocks):
        twists[position, :, :block.shape[1]] = block
    carriers = links[len(first):]
    tree = (chains.planar_tree(compiled.link_chains, carriers) if space == "planar"
            else chains.matrix_tree(space, compiled.link_chains, carriers))
    plan = _ReferencePlan(links, len(first), tree, twists)
    _REFERENCE_PLANS[mechanism] = plan
    return plan


def _planar_end_effector_columns(compiled, group, point):
    """Df's columns of a planar end-effector in complex form, shape=[..., C, n].

    With the link's pose ``(r, t)``, the end-effector point ``x = r x₀ + t``
    and a coordinate's carried twist ``(ω, w)``
    (:func:`mechanisms._chains.planar_twists`): the point moves at
    ``w + i ω x``; the body twist of the frame is ``(ω, r̄ (w + i ω x))``.
    """
    rotations, translations = chains.planar_prefixes(group, point)
    rotation, translation = rotations[..., 0, -1], translations[..., 0, -1]
    angular, linear = chains.planar_twists(group, rotations, translations)
    angular, linear = angular[0], linear[..., 0, :]                      # [C], [..., C]
    position = _planar_point(compiled, rotation, translation)
    moved = linear + 1j * angular * position[..., None]
    if compiled.output == "position":
        return np.stack([moved.real, moved.imag], axis=-1)
    spin = np.broadcast_to(angular, moved.shape)
    if compiled.output == "orientation":
        return spin[..., None]
    body = np.conj(rotation)[..., None] * moved
    return np.stack([spin, body.real, body.imag], axis=-1)


def _planar_point(compiled, rotation, translation):
    """The end-effector point of a planar link at pose ``(rotation, translation)`` (complex), its origin without
    an end-effector point."""
    home_point = compiled.end_effector_point
    return translation if home_point is None else rotation * complex(*home_point[:2]) + translation


def _end_effector_columns(compiled, product, derivative):
    size = groups.MATRIX_SIZE[compiled.space]
    offset = _offset(compiled)
    if compiled.output == "position":
        return (derivative @ offset)[..., : size - 1, size - 1]
    if compiled.output == "tool":
        return _tool_rows(compiled, product, derivative)
    frame = product @ offset
    body = groups.inverse(compiled.space, frame)[..., None, :, :] @ derivative @ offset
    return groups.vee(compiled.space, body)[..., _twist_components(compiled)]


def _tool_rows(compiled, product, derivative):
    """Derivatives of the tool point and direction in the chart of :func:`end_effector_chart`.

    With ``(x, u)`` the carried columns of :func:`_tool_vectors`: the point
    rows are ``∂x``, the direction rows ``E(u) ∂u`` — on a first derivative
    ``∂u = ω × u``, whose component along u is zero; on a second
    derivative the chart's ``θ / sin θ = 1 + O(θ²)`` adds nothing, so the
    same projection holds.

    Parameters
    ----------
    product : ndarray, shape=[..., 4, 4]
        The link's pose.
    derivative : ndarray, shape=[..., C, 4, 4] or [..., C, C, 4, 4]
        First or second derivatives of the pose.

    Returns
    -------
    ndarray, shape=[..., C, 5] or [..., C, C, 5]
    """
    vectors = _tool_vectors(compiled)
    basis = tool_basis((product @ vectors)[..., :3, 1])  # [..., 2, 3]
    carried = (derivative @ vectors)[..., :3, :]  # [..., (C,) C, 3, 2]
    extra = derivative.ndim - product.ndim
    basis = basis.reshape(basis.shape[:-2] + (1,) * extra + basis.shape[-2:])
    directions = np.einsum("...ij,...j->...i", basis, carried[..., 1])
    return np.concatenate([carried[..., 0], directions], axis=-1)


def end_effector_hessian(mechanism, point):
    """D²f(point) in the chart of N at f(point), shape=[..., n, k, k]."""
    compiled, point, group, product, first, second = _end_effector_expansion(mechanism, point, 2)
    k = compiled.ambient.dim
    n = end_effector_dimension(mechanism)
    hessian = np.zeros(point.shape[:-1] + (n, k, k))
    indices = group.columns[0]
    if compiled.output == "position":
        size = groups.MATRIX_SIZE[compiled.space]
        values = (second @ _offset(compiled))[..., : size - 1, size - 1]  # [..., C, C, n]
    elif compiled.output == "tool":
        values = _tool_rows(compiled, product, second)  # [..., C, C, 5]
    else:
        offset = _offset(compiled)
        frame = product @ offset
        body = groups.inverse(compiled.space, frame)[..., None, :, :] @ first @ offset  # [..., C, s, s]
        rows, columns = body[..., :, None, :, :], body[..., None, :, :, :]
        brackets = 0.5 * groups.vee(compiled.space, rows @ columns - columns @ rows)[..., _twist_components(compiled)]
        numbers = group.numbers
        upper = np.triu(numbers[:, None] != numbers[None, :], k=1)          # row before column, other element
        values = np.where(upper[..., None], brackets, 0.0)                    # [..., C, C, n]
        values = values + np.swapaxes(values, -2, -3)
    values = np.moveaxis(values, -1, -3)  # [..., n, C, C]
    hessian[..., indices[:, None], indices[None, :]] = values
    return hessian
