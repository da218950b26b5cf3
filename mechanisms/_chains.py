"""Chains of joint elements: how :mod:`mechanisms.kinematics` evaluates loop and link products.

Each joint is a product of *elements* ``A(q) exp(X̂ v)`` (a rotation or
translation about a home-frame twist ``X̂``, or a ball joint ``[R, c − R c]``
moved by ``R exp(v̂)``); a loop or the path from the ground to a link is a
:class:`Chain` of elements along the spanning tree of the joint graph
(:func:`chains_of`). Chains of the same shape (:func:`chain_shape`) form a
:class:`ChainGroup` and are expanded together (:func:`expand_group`): the
product, its first derivatives and its second derivatives in the recentred
chart, one array operation per element position.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Optional

import numpy as np

from manifold.blocks import JacobianPattern

from . import _groups as groups

__all__ = [
    "Element", "Chain", "ChainGroup", "LinkChains", "elements_of_joint", "chains_of", "chain_coordinates",
    "chain_shape", "chain_group", "groups_of", "loop_pattern", "element_matrices", "expand_group", "expand",
    "loop_products", "hessian_blocks",
]


@dataclass(frozen=True, eq=False)
class Element:
    """One factor ``A(q) exp(X̂ v)`` of a joint, as it stands in a chain."""

    kind: str                 # "rotation", "translation" or "ball"
    point_part: object        # index or slice into the point
    tangent_indices: tuple    # global tangent coordinates moved by this element
    twists: tuple             # constant twist matrices, one per tangent coordinate
    sign: float = 1.0         # -1 for a joint traversed backwards (1-dof elements)
    center: Optional[np.ndarray] = None  # ball joints
    inverse: bool = False     # ball joint traversed backwards (left perturbation)


@dataclass(frozen=True, eq=False)
class Chain:
    """The elements of a loop or a link path, in product order."""

    elements: tuple


@dataclass(frozen=True, eq=False)
class ChainGroup:
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


def elements_of_joint(mechanism, joint, point_parts, tangent_start):
    """The forward elements of one joint."""
    space = mechanism.space
    elements = []
    if joint.type == "S":
        center = np.asarray(joint.point, dtype=float)
        twists = tuple(groups.rotation_twist(space, axis, center) for axis in np.eye(3))
        elements.append(Element("ball", point_parts[0], tuple(range(tangent_start, tangent_start + 3)),
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
        elements.append(Element(kind, point_parts[offset].start, (tangent_start + offset,), (twist,)))
    return elements


def inverted(element):
    """The element of the joint traversed from its second link to its first."""
    twists = tuple(-twist for twist in element.twists)
    if element.kind == "ball":
        return Element("ball", element.point_part, element.tangent_indices, twists,
                       center=element.center, inverse=not element.inverse)
    return Element(element.kind, element.point_part, element.tangent_indices, twists, sign=-element.sign)


def traverse(joint_elements, steps):
    """Elements along a list of (joint index, forward) steps."""
    elements = []
    for index, forward in steps:
        if forward:
            elements += joint_elements[index]
        else:
            elements += [inverted(element) for element in reversed(joint_elements[index])]
    return Chain(tuple(elements))


def chain_coordinates(chain):
    """(tangent index, twist, slot, element number) in product order."""
    coordinates = []
    for number, element in enumerate(chain.elements):
        slot = number if element.inverse else number + 1
        for index, twist in zip(element.tangent_indices, element.twists):
            coordinates.append((index, twist, slot, number))
    coordinates.sort(key=lambda entry: (entry[2], entry[3]))
    return coordinates


def chain_shape(chain):
    """What chains evaluated together must share: element count and coordinate slots."""
    return len(chain.elements), tuple((slot, number) for _, _, slot, number in chain_coordinates(chain))


def chain_group(space, chains, positions):
    """The :class:`ChainGroup` of chains of one shape (:func:`chain_shape`)."""
    size = groups.MATRIX_SIZE[space]
    coordinates = [chain_coordinates(chain) for chain in chains]
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
    return ChainGroup(
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


def groups_of(space, chains):
    """The chains sorted into groups of one shape, in order of first appearance."""
    shapes = {}
    for position, chain in enumerate(chains):
        shapes.setdefault(chain_shape(chain), []).append(position)
    return tuple(chain_group(space, [chains[position] for position in positions], positions)
                 for positions in shapes.values())


def loop_pattern(space, loop_groups, loop_count, dim):
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


def chains_of(mechanism, joint_elements):
    """The loops of a mechanism and the paths to its links, along a spanning tree of its joint graph.

    The tree is grown by breadth-first search from the ground, joints in file
    order; every joint off the tree (a chord) closes one loop: the tree path
    from the chord's first link up to the deepest common ancestor of its
    links, the chord, and the path down to its second link.

    Parameters
    ----------
    mechanism : Mechanism
    joint_elements : list of list of Element
        The forward elements of each joint, in file order (:func:`elements_of_joint`).

    Returns
    -------
    loops : tuple of Chain
    chords : tuple of str
        The chord joints' names, one per loop.
    link_chains : LinkChains
        Link name -> chain from the ground to that link (built on first use).
    """
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
        first, second = branches(parents, depths, *joint.links)
        steps = first + [(index, True)] + [(i, not forward) for i, forward in reversed(second)]
        loops.append(traverse(joint_elements, steps))
        chords.append(joint.name)
    link_chains = LinkChains(lambda link: traverse(joint_elements, tree_path(parents, link)), tuple(parents))
    return tuple(loops), tuple(chords), link_chains


def tree_path(parents, link):
    """The (joint index, forward) steps of the tree from the ground to `link`."""
    steps = []
    while parents[link] is not None:
        index, forward, link = parents[link]
        steps.append((index, forward))
    return steps[::-1]


def branches(parents, depths, first, second):
    """The tree paths to two links from their deepest common ancestor: two lists of (joint index, forward)."""
    branches = ([], [])
    links = [first, second]
    while links[0] != links[1]:
        side = 0 if depths[links[0]] >= depths[links[1]] else 1
        index, forward, parent = parents[links[side]]
        branches[side].append((index, forward))
        links[side] = parent
    return branches[0][::-1], branches[1][::-1]


class LinkChains(Mapping):
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


def element_matrices(space, group, point):
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


def expand_group(space, group, point, order):
    """T, its first derivatives and (order 2) second derivatives along the chains of a group.

    Returns
    -------
    product : ndarray, shape=[..., g, n, n]
    first : ndarray, shape=[..., g, C, n, n] or None (order 0)
    second : ndarray, shape=[..., g, C, C, n, n] or None (order < 2)
    """
    size = groups.MATRIX_SIZE[space]
    matrices = element_matrices(space, group, point)                # [..., g, L, n, n]
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


def expand(space, chain, point, order):
    """T, its first derivatives and (order 2) second derivatives along one chain.

    Returns
    -------
    product : ndarray, shape=[..., n, n]
    coordinates : list
        (tangent index, twist, slot, element number) in product order.
    first : ndarray, shape=[..., C, n, n] or None (order 0)
    second : ndarray, shape=[..., C, C, n, n] or None (order < 2)
    """
    product, first, second = expand_group(space, chain_group(space, [chain], [0]), point, order)
    return (product[..., 0, :, :], chain_coordinates(chain), None if first is None else first[..., 0, :, :, :],
            None if second is None else second[..., 0, :, :, :, :])


def loop_products(compiled, point):
    """Every loop product, shape=[..., loops, n, n]."""
    size = groups.MATRIX_SIZE[compiled.space]
    products = np.zeros(point.shape[:-1] + (len(compiled.loops), size, size))
    for group in compiled.loop_groups:
        products[..., group.chains, :, :] = expand_group(compiled.space, group, point, 0)[0]
    return products


def hessian_blocks(compiled, point):
    """D²Φ loop by loop: per group ``(rows [g, R], columns [g, C], values [..., g, R, C, C])``."""
    rows_per_loop = groups.LOOP_ROWS[compiled.space]
    for group in compiled.loop_groups:
        second = expand_group(compiled.space, group, point, 2)[2]
        values = np.moveaxis(groups.loop_rows(compiled.space, second, compiled.length), -1, -3)
        yield group.chains[:, None] * rows_per_loop + np.arange(rows_per_loop), group.columns, values


