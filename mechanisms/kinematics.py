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

The end-effector map in the exponential chart of N at f(p) uses the body
twists ``ŵ_a = F⁻¹ ∂F/∂v_a`` and the Baker-Campbell-Hausdorff formula::

    log(F(p)⁻¹ F(p ⊕ v)) = Σ_a w_a v_a + ½ Σ_{a before b} [w_a, w_b] v_a v_b + O(|v|³).

All functions take stacks of configurations, ``point`` of shape
``(..., point_size)``.

Sparsity. A loop touches only the joints on it, so DΦ has nonzero entries in
its loop's rows and its joints' columns only, and D²Φ is a small dense block
per loop (rows × the loop's coordinates²). Chains of the same shape (the same
sequence of coordinate slots, e.g. the rungs of a ladder of four-bar loops)
are evaluated together, one array operation per element position, so the
cost grows with the number of joints, not with Python loops over them. The
constant pattern of DΦ (:func:`constraint_pattern`) and its entries
(:func:`constraint_jacobian_entries`) give the manifold its block structure
(:class:`manifold.JacobianPattern`); D²Φ is contracted loop by loop
(:func:`constraint_hessian_form`) without forming the c×k×k array that
:func:`constraint_hessian` returns.
"""

from __future__ import annotations

import weakref
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Optional

import numpy as np

from manifold import AmbientSpace, ImplicitManifold
from manifold.implicit import JacobianPattern

from . import _groups as groups
from .joints import joint_factors

__all__ = [
    "Kinematics", "kinematics_of", "configuration_space",
    "constraint", "constraint_jacobian", "constraint_hessian", "closes",
    "constraint_pattern", "constraint_jacobian_entries", "constraint_hessian_form",
    "end_effector", "end_effector_jacobian", "end_effector_hessian", "end_effector_chart",
    "end_effector_dimension", "actuator_jacobian", "link_pose",
]


@dataclass(frozen=True, eq=False)
class _Element:
    kind: str                 # "rotation", "translation" or "ball"
    point_part: object        # index or slice into the point
    tangent_indices: tuple    # global tangent coordinates moved by this element
    twists: tuple             # constant twist matrices, one per tangent coordinate
    sign: float = 1.0         # -1 for a joint traversed backwards (1-dof elements)
    center: Optional[np.ndarray] = None  # ball joints
    inverse: bool = False     # ball joint traversed backwards (left perturbation)


@dataclass(frozen=True, eq=False)
class _Chain:
    elements: tuple


@dataclass(frozen=True, eq=False)
class _Group:
    """Chains of one shape, evaluated together: one array operation per element position.

    Two chains have the same shape when they have as many elements and their
    coordinates sit at the same slots of the product (the same sequence of
    1-dof elements, forward balls and backward balls); the matrices differ.

    Attributes
    ----------
    chains : ndarray, shape=[g]
        Positions of the chains in their set (loop numbers, or 0 for one link chain).
    slots, numbers : ndarray, shape=[C]
        Per coordinate in product order: the slot of the product where its
        twist is inserted, and its element's position in the chain.
    columns : ndarray, shape=[g, C]
        Tangent index of each coordinate.
    twists : ndarray, shape=[g, C, n, n]
        Twist inserted for each coordinate.
    values : ndarray, shape=[g, L]
        Index into the point of each 1-dof element's value (0 for ball elements).
    signs : ndarray, shape=[g, L]
        -1 for a 1-dof element traversed backwards.
    element_twists, element_squares : ndarray, shape=[g, L, n, n]
        X and X² of each 1-dof element (its forward twist; zero for balls):
        the element is ``I + a X + b X²`` (``a = sin θ, b = 1 − cos θ`` for a
        rotation, ``a = θ, b = 0`` for a translation, θ the signed value).
    rotation : ndarray of bool, shape=[g, L]
    balls : tuple or None
        ``(chain positions [b], element positions [b], point indices [b, 9],
        centres [b, 3], backwards [b])`` of the ball elements.
    """

    chains: np.ndarray
    slots: np.ndarray
    numbers: np.ndarray
    columns: np.ndarray
    twists: np.ndarray
    values: np.ndarray
    signs: np.ndarray
    element_twists: np.ndarray
    element_squares: np.ndarray
    rotation: np.ndarray
    balls: Optional[tuple]

    @property
    def length(self):
        return self.values.shape[1]


@dataclass(frozen=True, eq=False)
class Kinematics:
    """Compiled kinematic structure of a mechanism (derived once, reused).

    Attributes
    ----------
    space : str
    ambient : AmbientSpace
    loops : tuple
        One chain per independent loop (chord of the spanning tree).
    chords : tuple of str
        Names of the chord joints, one per loop.
    link_chains : Mapping
        Link name -> chain from the ground to that link (built on first use).
    point_parts : dict
        Joint name -> tuple of slices of the point array holding its coordinates
        (one per ambient factor: one for R, P, S; two for U, C).
    length : float
        Characteristic length dividing translation rows.
    loop_groups : tuple of _Group
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
    pattern: Optional[JacobianPattern] = None
    point_size: int = 0
    link_groups: dict = None  # link name -> its chain's _Group, built on first use


_CACHE = weakref.WeakKeyDictionary()


def _joint_elements(mechanism, joint, point_parts, tangent_start):
    """The forward elements of one joint."""
    space = mechanism.space
    elements = []
    if joint.type == "S":
        center = np.asarray(joint.point, dtype=float)
        twists = tuple(groups.rotation_twist(space, axis, center) for axis in np.eye(3))
        elements.append(_Element("ball", point_parts[0], tuple(range(tangent_start, tangent_start + 3)),
                                 twists, center=center))
        return elements
    if joint.type == "R":
        specs = [("rotation", joint.axis)]
    elif joint.type == "P":
        specs = [("translation", joint.axis)]
    elif joint.type == "U":
        specs = [("rotation", joint.axes[0]), ("rotation", joint.axes[1])]
    else:  # C
        specs = [("rotation", joint.axis), ("translation", joint.axis)]
    for offset, (kind, axis) in enumerate(specs):
        if kind == "rotation":
            twist = groups.rotation_twist(space, axis, joint.point)
        else:
            twist = groups.translation_twist(space, axis)
        elements.append(_Element(kind, point_parts[offset].start, (tangent_start + offset,), (twist,)))
    return elements


def _inverted(element):
    """The element of the joint traversed from its second link to its first."""
    twists = tuple(-twist for twist in element.twists)
    if element.kind == "ball":
        return _Element("ball", element.point_part, element.tangent_indices, twists,
                        center=element.center, inverse=not element.inverse)
    return _Element(element.kind, element.point_part, element.tangent_indices, twists,
                    sign=-element.sign)


def _traverse(joint_elements, steps):
    """Elements along a list of (joint index, forward) steps."""
    elements = []
    for index, forward in steps:
        if forward:
            elements += joint_elements[index]
        else:
            elements += [_inverted(element) for element in reversed(joint_elements[index])]
    return _Chain(tuple(elements))


def _coordinates(chain):
    """(tangent index, twist, slot, element number) in product order."""
    coordinates = []
    for number, element in enumerate(chain.elements):
        slot = number if element.inverse else number + 1
        for index, twist in zip(element.tangent_indices, element.twists):
            coordinates.append((index, twist, slot, number))
    coordinates.sort(key=lambda entry: (entry[2], entry[3]))
    return coordinates


def _shape(chain):
    """What chains evaluated together must share: element count and coordinate slots."""
    return len(chain.elements), tuple((slot, number) for _, _, slot, number in _coordinates(chain))


def _group(space, chains, positions):
    """The :class:`_Group` of chains of one shape (:func:`_shape`)."""
    size = groups.MATRIX_SIZE[space]
    coordinates = [_coordinates(chain) for chain in chains]
    length = len(chains[0].elements)
    count = len(chains)
    values = np.zeros((count, length), dtype=np.intp)
    signs = np.ones((count, length))
    element_twists = np.zeros((count, length, size, size))
    rotation = np.zeros((count, length), dtype=bool)
    balls = []
    for row, chain in enumerate(chains):
        for number, element in enumerate(chain.elements):
            if element.kind == "ball":
                start = element.point_part.start
                balls.append((row, number, np.arange(start, start + 9), element.center, element.inverse))
                continue
            values[row, number] = element.point_part
            signs[row, number] = element.sign
            element_twists[row, number] = element.twists[0] * element.sign
            rotation[row, number] = element.kind == "rotation"
    ball_arrays = None
    if balls:
        ball_arrays = (np.array([entry[0] for entry in balls], dtype=np.intp),
                       np.array([entry[1] for entry in balls], dtype=np.intp),
                       np.array([entry[2] for entry in balls], dtype=np.intp),
                       np.array([entry[3] for entry in balls], dtype=float),
                       np.array([entry[4] for entry in balls], dtype=bool))
    return _Group(
        chains=np.asarray(positions, dtype=np.intp),
        slots=np.array([entry[2] for entry in coordinates[0]], dtype=np.intp),
        numbers=np.array([entry[3] for entry in coordinates[0]], dtype=np.intp),
        columns=np.array([[entry[0] for entry in chain] for chain in coordinates], dtype=np.intp)
        .reshape(count, -1),
        twists=np.array([[entry[1] for entry in chain] for chain in coordinates], dtype=float)
        .reshape(count, -1, size, size),
        values=values, signs=signs, element_twists=element_twists,
        element_squares=element_twists @ element_twists, rotation=rotation, balls=ball_arrays,
    )


def _groups_of(space, chains):
    """The chains sorted into groups of one shape, in order of first appearance."""
    shapes = {}
    for position, chain in enumerate(chains):
        shapes.setdefault(_shape(chain), []).append(position)
    return tuple(_group(space, [chains[position] for position in positions], positions)
                 for positions in shapes.values())


def _pattern(space, loop_groups, loop_count, dim):
    """The constant sparsity pattern of DΦ, entries in the order of :func:`constraint_jacobian_entries`."""
    rows_per_loop = groups.LOOP_ROWS[space]
    rows, columns = [], []
    for group in loop_groups:
        loop_rows = group.chains[:, None] * rows_per_loop + np.arange(rows_per_loop)  # [g, R]
        shape = (len(group.chains), group.columns.shape[1], rows_per_loop)
        rows.append(np.broadcast_to(loop_rows[:, None, :], shape).ravel())
        columns.append(np.broadcast_to(group.columns[:, :, None], shape).ravel())
    rows = np.concatenate(rows) if rows else np.zeros(0, dtype=np.intp)
    columns = np.concatenate(columns) if columns else np.zeros(0, dtype=np.intp)
    return JacobianPattern((rows_per_loop * loop_count, dim), rows, columns)


def kinematics_of(mechanism):
    """The compiled :class:`Kinematics` of a mechanism (cached per mechanism object)."""
    cached = _CACHE.get(mechanism)
    if cached is not None:
        return cached
    factors, scales = [], []
    length = mechanism.characteristic_length
    for joint in mechanism.joints:
        for factor in joint_factors(joint):
            factors.append(factor)
            scales.append(length if factor == "R" else 1.0)
    ambient = AmbientSpace(tuple(factors), tuple(scales))
    joint_elements, point_parts, factor_index, tangent_start = [], {}, 0, 0
    for joint in mechanism.joints:
        count = len(joint_factors(joint))
        parts = ambient.point_slices[factor_index: factor_index + count]
        point_parts[joint.name] = parts
        joint_elements.append(_joint_elements(mechanism, joint, parts, tangent_start))
        factor_index += count
        tangent_start += sum(3 if f == "SO3" else 1 for f in joint_factors(joint))
    # spanning tree by breadth-first search from the ground, joints in file order
    incident = {}
    for index, joint in enumerate(mechanism.joints):
        for link in dict.fromkeys(joint.links):
            incident.setdefault(link, []).append(index)
    parents = {mechanism.ground: None}  # link -> (joint index, forward, parent link) on the tree
    depths = {mechanism.ground: 0}
    tree_joints = set()
    queue = deque([mechanism.ground])
    while queue:
        link = queue.popleft()
        for index in incident.get(link, ()):
            joint = mechanism.joints[index]
            if index in tree_joints:
                continue
            other = joint.links[1] if joint.links[0] == link else joint.links[0]
            if other in parents:
                continue
            parents[other] = (index, joint.links[0] == link, link)
            depths[other] = depths[link] + 1
            tree_joints.add(index)
            queue.append(other)
    loops, chords = [], []
    for index, joint in enumerate(mechanism.joints):
        if index in tree_joints:
            continue
        first, second = _branches(parents, depths, *joint.links)
        steps = first + [(index, True)] + [(i, not forward) for i, forward in reversed(second)]
        loops.append(_traverse(joint_elements, steps))
        chords.append(joint.name)
    link_chains = _LinkChains(lambda link: _traverse(joint_elements, _path(parents, link)), tuple(parents))
    loop_groups = _groups_of(mechanism.space, loops)
    end_effector = mechanism.end_effector
    compiled = Kinematics(
        space=mechanism.space, ambient=ambient, loops=tuple(loops), chords=tuple(chords),
        link_chains=link_chains, point_parts=point_parts, length=length,
        end_effector_link=None if end_effector is None else end_effector.link,
        end_effector_point=None if end_effector is None or end_effector.point is None
        else np.asarray(end_effector.point, dtype=float),
        output=None if end_effector is None else end_effector.output,
        loop_groups=loop_groups, pattern=_pattern(mechanism.space, loop_groups, len(loops), ambient.dim),
        point_size=ambient.point_size, link_groups={},
    )
    _CACHE[mechanism] = compiled
    return compiled


def _path(parents, link):
    """The (joint index, forward) steps of the tree from the ground to `link`."""
    steps = []
    while parents[link] is not None:
        index, forward, link = parents[link]
        steps.append((index, forward))
    return steps[::-1]


def _branches(parents, depths, first, second):
    """The tree paths to two links from their deepest common ancestor: two lists of (joint index, forward)."""
    branches = ([], [])
    links = [first, second]
    while links[0] != links[1]:
        side = 0 if depths[links[0]] >= depths[links[1]] else 1
        index, forward, parent = parents[links[side]]
        branches[side].append((index, forward))
        links[side] = parent
    return branches[0][::-1], branches[1][::-1]


class _LinkChains(Mapping):
    """Link name -> chain from the ground to that link, each built on first use."""

    def __init__(self, build, links):
        self._build, self._links, self._chains = build, links, {}

    def __getitem__(self, link):
        if link not in self._chains:
            if link not in self._links:
                raise KeyError(link)
            self._chains[link] = self._build(link)
        return self._chains[link]

    def __iter__(self):
        return iter(self._links)

    def __len__(self):
        return len(self._links)


def _link_group(compiled, link):
    """The :class:`_Group` of the chain from the ground to `link` (built on first use)."""
    group = compiled.link_groups.get(link)
    if group is None:
        group = _group(compiled.space, [compiled.link_chains[link]], [0])
        compiled.link_groups[link] = group
    return group


# --------------------------------------------------------------------------- chains

def _element_matrices(space, group, point):
    """The element matrices of every chain of a group, shape=[..., g, L, n, n]."""
    size = groups.MATRIX_SIZE[space]
    value = group.signs * point[..., group.values]                 # [..., g, L]
    rotation = group.rotation
    first = np.where(rotation, np.sin(value), value)[..., None, None]
    second = np.where(rotation, 1.0 - np.cos(value), 0.0)[..., None, None]
    matrices = np.eye(size) + first * group.element_twists + second * group.element_squares
    if group.balls is not None:
        chain_positions, element_positions, indices, centers, backwards = group.balls
        rotations = point[..., indices].reshape(point.shape[:-1] + (len(centers), 3, 3))
        ball = np.zeros(point.shape[:-1] + (len(centers), 4, 4))
        ball[..., :3, :3] = rotations
        ball[..., :3, 3] = centers - np.einsum("...bij,bj->...bi", rotations, centers)
        ball[..., 3, 3] = 1.0
        ball = np.where(backwards[:, None, None], groups.inverse(space, ball), ball)
        matrices[..., chain_positions, element_positions, :, :] = ball
    return matrices


def _expand_group(space, group, point, order):
    """T, its first derivatives and (order 2) second derivatives along the chains of a group.

    Returns
    -------
    product : ndarray, shape=[..., g, n, n]
    first : ndarray, shape=[..., g, C, n, n] or None (order 0)
    second : ndarray, shape=[..., g, C, C, n, n] or None (order < 2)
    """
    size = groups.MATRIX_SIZE[space]
    matrices = _element_matrices(space, group, point)                # [..., g, L, n, n]
    length = group.length
    identity = np.broadcast_to(np.eye(size), matrices.shape[:-3] + (size, size))
    prefix = [identity]
    for number in range(length):
        prefix.append(prefix[-1] @ matrices[..., number, :, :])
    if order < 1:
        return prefix[-1], None, None
    suffix = [identity] * (length + 1)
    for number in range(length - 1, -1, -1):
        suffix[number] = matrices[..., number, :, :] @ suffix[number + 1]
    prefix = np.stack(prefix, axis=-3)                               # [..., g, L + 1, n, n]
    suffix = np.stack(suffix, axis=-3)
    slots = group.slots
    first = prefix[..., slots, :, :] @ group.twists @ suffix[..., slots, :, :]
    if order < 2:
        return prefix[..., -1, :, :], first, None
    count = len(slots)
    second = np.zeros(first.shape[:-3] + (count, count, size, size))
    for row in range(count):
        slot, number = slots[row], group.numbers[row]
        inserted = prefix[..., slot, :, :] @ group.twists[:, row]       # [..., g, n, n]
        running = [inserted]                                              # products up to slots slot, slot + 1, ...
        for position in range(slot, length):
            running.append(running[-1] @ matrices[..., position, :, :])
        running = np.stack(running, axis=-3)                              # [..., g, L + 1 − slot, n, n]
        columns = np.arange(row, count)
        values = (running[..., slots[columns] - slot, :, :] @ group.twists[:, columns]
                  @ suffix[..., slots[columns], :, :])                    # [..., g, C − row, n, n]
        same = np.flatnonzero(group.numbers[columns] == number)
        if len(same):
            twist_a = group.twists[:, row][:, None]
            twist_b = group.twists[:, columns[same]]
            values[..., same, :, :] = (0.5 * prefix[..., slot, :, :][..., None, :, :]
                                       @ (twist_a @ twist_b + twist_b @ twist_a)
                                       @ suffix[..., slot, :, :][..., None, :, :])
        second[..., row, row:, :, :] = values
        second[..., row:, row, :, :] = values
    return prefix[..., -1, :, :], first, second


def _expand(space, chain, point, order):
    """T, its first derivatives and (order 2) second derivatives along one chain.

    Returns
    -------
    product : ndarray, shape=[..., n, n]
    coordinates : list
        (tangent index, twist, slot, element number) in product order.
    first : ndarray, shape=[..., C, n, n] or None (order 0)
    second : ndarray, shape=[..., C, C, n, n] or None (order < 2)
    """
    product, first, second = _expand_group(space, _group(space, [chain], [0]), point, order)
    return (product[..., 0, :, :], _coordinates(chain), None if first is None else first[..., 0, :, :, :],
            None if second is None else second[..., 0, :, :, :, :])


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
    )


def _loop_products(compiled, point):
    """Every loop product, shape=[..., loops, n, n]."""
    size = groups.MATRIX_SIZE[compiled.space]
    products = np.zeros(point.shape[:-1] + (len(compiled.loops), size, size))
    for group in compiled.loop_groups:
        products[..., group.chains, :, :] = _expand_group(compiled.space, group, point, 0)[0]
    return products


def constraint(mechanism, point):
    """Loop-closure map Φ(point), rows loop by loop, shape=[..., c].

    Rotation rows ``½ vee(R − Rᵀ)`` then translation rows over the
    characteristic length, for each loop product R, p.
    """
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    rows = groups.loop_rows(compiled.space, _loop_products(compiled, point), compiled.length)
    return rows.reshape(point.shape[:-1] + (-1,))


def constraint_pattern(mechanism):
    """Where DΦ can be nonzero (:class:`manifold.JacobianPattern`): the rows of each loop by the
    columns of the coordinates on it."""
    return kinematics_of(mechanism).pattern


def constraint_jacobian_entries(mechanism, point):
    """The entries of DΦ(point) at :func:`constraint_pattern`, in its order, shape=[..., nnz]."""
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    entries = [groups.loop_rows(compiled.space, _expand_group(compiled.space, group, point, 1)[1], compiled.length)
               .reshape(point.shape[:-1] + (-1,)) for group in compiled.loop_groups]  # [..., g, C, R] each
    return np.concatenate(entries, axis=-1) if entries else np.zeros(point.shape[:-1] + (0,))


def constraint_jacobian(mechanism, point):
    """DΦ(point) in the recentred chart, shape=[..., c, k]."""
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    pattern = compiled.pattern
    jacobian = np.zeros(point.shape[:-1] + pattern.shape)
    jacobian[..., pattern.rows, pattern.columns] = constraint_jacobian_entries(mechanism, point)
    return jacobian


def _hessian_blocks(compiled, point):
    """D²Φ loop by loop: per group ``(rows [g, R], columns [g, C], values [..., g, R, C, C])``."""
    rows_per_loop = groups.LOOP_ROWS[compiled.space]
    for group in compiled.loop_groups:
        second = _expand_group(compiled.space, group, point, 2)[2]
        values = np.moveaxis(groups.loop_rows(compiled.space, second, compiled.length), -1, -3)
        yield group.chains[:, None] * rows_per_loop + np.arange(rows_per_loop), group.columns, values


def constraint_hessian(mechanism, point):
    """D²Φ(point) in the recentred chart, shape=[..., c, k, k].

    A dense array of c·k² entries: for large mechanisms use
    :func:`constraint_hessian_form`, which contracts it loop by loop.
    """
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    hessian = np.zeros(point.shape[:-1] + compiled.pattern.shape + (compiled.ambient.dim,))
    for rows, columns, values in _hessian_blocks(compiled, point):
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
    for rows, columns, values in _hessian_blocks(compiled, point):
        form[..., rows, :, :] = np.einsum("...grab,gai,gbj->...grij", values, left[columns], right[columns],
                                          optimize=True)
    return form


def closes(mechanism, point, tolerance=1e-9):
    """Whether every loop closes: ‖Φ‖ ≤ tolerance and no loop is a half-turn, shape=[...]."""
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    products = _loop_products(compiled, point)
    rows = groups.loop_rows(compiled.space, products, compiled.length)
    return (np.all(np.linalg.norm(rows, axis=-1) <= tolerance, axis=-1)
            & np.all(groups.is_identity_rotation(compiled.space, products), axis=-1))


def link_pose(mechanism, link, point):
    """Pose of a link relative to its home pose, in the ground frame, shape=[..., n, n]."""
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    return _expand_group(compiled.space, _link_group(compiled, link), point, 0)[0][..., 0, :, :]


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
    ("spatial", "position"): 3, ("spatial", "orientation"): 3, ("spatial", "pose"): 6,
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
    """f(point): the position, shape=[..., d], or the frame matrix, shape=[..., n, n].

    For ``orientation`` and ``pose`` outputs the value is the homogeneous
    matrix of the end-effector frame (orientation of its link, origin at the
    end-effector point); local coordinates are given by
    :func:`end_effector_chart`.
    """
    compiled = _require_end_effector(mechanism)
    point = _as_points(mechanism, point)
    product = link_pose(mechanism, compiled.end_effector_link, point)
    if compiled.output == "position":
        size = groups.MATRIX_SIZE[compiled.space]
        return (product @ _offset(compiled))[..., : size - 1, size - 1]
    return product @ _offset(compiled)


def end_effector_chart(mechanism, base_value, value):
    """Local coordinates of `value` in the chart of N centred at `base_value`.

    Position outputs: the difference. Orientation and pose outputs: the twist
    coordinates of ``log(F₀⁻¹ F)`` (rotation components only for orientation).
    """
    compiled = _require_end_effector(mechanism)
    if compiled.output == "position":
        return np.asarray(value) - np.asarray(base_value)
    from scipy.linalg import logm

    relative = groups.inverse(compiled.space, np.asarray(base_value)) @ np.asarray(value)
    flat = relative.reshape((-1,) + relative.shape[-2:])
    logs = np.array([np.real(logm(matrix)) for matrix in flat]).reshape(relative.shape)
    return groups.vee(compiled.space, logs)[..., _twist_components(compiled)]


def _end_effector_expansion(mechanism, point, order):
    """The chain to the end-effector's link: (compiled, point, group, product, first, second), the chain
    axis of :func:`_expand` removed."""
    compiled = _require_end_effector(mechanism)
    point = _as_points(mechanism, point)
    group = _link_group(compiled, compiled.end_effector_link)
    product, first, second = _expand_group(compiled.space, group, point, order)
    return (compiled, point, group, product[..., 0, :, :], None if first is None else first[..., 0, :, :, :],
            None if second is None else second[..., 0, :, :, :, :])


def end_effector_jacobian(mechanism, point):
    """Df(point) in the chart of N at f(point), shape=[..., n, k].

    Position outputs: ∂(T x)/∂v. Orientation and pose outputs: body twists
    ``vee(F⁻¹ ∂F/∂v)``.
    """
    compiled, point, group, product, first, _ = _end_effector_expansion(mechanism, point, 1)
    jacobian = np.zeros(point.shape[:-1] + (end_effector_dimension(mechanism), compiled.ambient.dim))
    jacobian[..., :, group.columns[0]] = np.swapaxes(_end_effector_columns(compiled, product, first), -1, -2)
    return jacobian


def _end_effector_columns(compiled, product, derivative):
    size = groups.MATRIX_SIZE[compiled.space]
    offset = _offset(compiled)
    if compiled.output == "position":
        return (derivative @ offset)[..., : size - 1, size - 1]
    frame = product @ offset
    body = groups.inverse(compiled.space, frame)[..., None, :, :] @ derivative @ offset
    return groups.vee(compiled.space, body)[..., _twist_components(compiled)]


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
