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

import weakref
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
    "loop_products", "hessian_blocks", "planar_prefixes", "planar_twists", "planar_loops", "PlanarTree",
    "prefix_tree", "planar_tree", "planar_tree_products", "MatrixTree", "matrix_tree", "matrix_tree_products",
    "carried_twists",
    "loop_first_order", "first_derivatives",
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
    count = len(chains)
    values, signs, element_twists, rotation, balls = _element_arrays(space, [chain.elements for chain in chains])
    return ChainGroup(
        chains=np.asarray(positions, dtype=np.intp),
        slots=np.array([entry[2] for entry in coordinates[0]], dtype=np.intp),
        numbers=np.array([entry[3] for entry in coordinates[0]], dtype=np.intp),
        columns=np.array([[entry[0] for entry in chain] for chain in coordinates], dtype=np.intp)
        .reshape(count, -1),
        twists=np.array([[entry[1] for entry in chain] for chain in coordinates], dtype=float)
        .reshape(count, -1, size, size),
        values=values, signs=signs, element_twists=element_twists,
        element_squares=element_twists @ element_twists, rotation=rotation, balls=balls,
    )


def _element_arrays(space, rows):
    """What :func:`element_matrices` reads of rows of elements, each row as long as the first: ``values``,
    ``signs``, ``element_twists`` [g, L, n, n], ``rotation`` and ``balls`` (see :class:`ChainGroup`)."""
    size = groups.MATRIX_SIZE[space]
    count, length = len(rows), len(rows[0]) if rows else 0
    values = np.zeros((count, length), dtype=np.intp)
    signs = np.ones((count, length))
    element_twists = np.zeros((count, length, size, size))
    rotation = np.zeros((count, length), dtype=bool)
    balls = []
    for row, elements in enumerate(rows):
        for number, element in enumerate(elements):
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
    return values, signs, element_twists, rotation, ball_arrays


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


def chains_of(mechanism, joint_elements, loop_elements=None):
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
    loop_elements : callable, optional
        ``loop_elements(link, index)``: joint `index`'s elements in a loop whose deepest common ancestor is
        `link` (written about a point fixed in that link, :func:`mechanisms.kinematics.loop_origin`); default
        `joint_elements` for every loop.

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
        first, second, ancestor = branches(parents, depths, *joint.links)
        steps = first + [(index, True)] + [(i, not forward) for i, forward in reversed(second)]
        elements = joint_elements if loop_elements is None else {
            step: loop_elements(ancestor, step) for step, _ in steps}
        loops.append(traverse(elements, steps))
        chords.append(joint.name)
    link_chains = LinkChains(joint_elements, parents)
    return tuple(loops), tuple(chords), link_chains


def tree_path(parents, link):
    """The (joint index, forward) steps of the tree from the ground to `link`."""
    steps = []
    while parents[link] is not None:
        index, forward, link = parents[link]
        steps.append((index, forward))
    return steps[::-1]


def branches(parents, depths, first, second):
    """The tree paths to two links from their deepest common ancestor: two lists of (joint index, forward),
    and that ancestor."""
    branches = ([], [])
    links = [first, second]
    while links[0] != links[1]:
        side = 0 if depths[links[0]] >= depths[links[1]] else 1
        index, forward, parent = parents[links[side]]
        branches[side].append((index, forward))
        links[side] = parent
    return branches[0][::-1], branches[1][::-1], links[0]


class LinkChains(Mapping):
    """Link name -> chain from the ground to that link, each built on first use.

    Parameters
    ----------
    joint_elements : list of list of Element
        The forward elements of each joint, in file order.
    parents : dict
        Link -> (joint index, forward, parent link) on the spanning tree, None for the ground (its first key).

    Notes
    -----
    The chains of a serial chain of k joints hold k(k + 1)/2 elements in all:
    what walks many links' chains (:func:`prefix_tree`) goes up the tree one
    step at a time (:meth:`step`) and shares the prefixes instead.
    """

    def __init__(self, joint_elements, parents):
        self._joint_elements, self._parents, self._chains = joint_elements, parents, {}
        self.ground = next(iter(parents))

    def __getitem__(self, link):
        if link not in self._chains:
            if link not in self._parents:
                raise KeyError(link)
            self._chains[link] = traverse(self._joint_elements, tree_path(self._parents, link))
        return self._chains[link]

    def __iter__(self):
        return iter(self._parents)

    def __len__(self):
        return len(self._parents)

    def parent(self, link):
        """The link before `link` on the spanning tree (None for the ground)."""
        return None if self._parents[link] is None else self._parents[link][2]

    def step(self, link):
        """The elements of the tree joint from :meth:`parent` to `link`, in product order (none for the ground)."""
        if self._parents[link] is None:
            return ()
        index, forward, _ = self._parents[link]
        return traverse(self._joint_elements, [(index, forward)]).elements


def prefix_tree(link_chains, links):
    """The tree of the prefixes of the chains from the ground to `links`, in O(elements on the spanning tree).

    Chains along a spanning tree share their prefixes: each link's chain is
    its parent's followed by the tree joint's elements (:meth:`LinkChains.step`),
    so the tree has a node per element on the paths to `links`, without
    writing out any chain (a serial chain's k chains hold k(k + 1)/2 elements).

    Parameters
    ----------
    link_chains : LinkChains
    links : sequence of str

    Returns
    -------
    parents : ndarray of int, shape=[p]
        Node 0 is the empty prefix (its own parent); node j > 0 one element longer than its parent.
    last : list of Element, length p − 1
        The last element of nodes 1, …, p − 1.
    ends : ndarray of int, shape=[c]
        The node of each link's chain, in the order of `links`.
    lengths : ndarray of int, shape=[c]
        The number of elements of each link's chain.
    """
    nodes, parents, last, lengths = {link_chains.ground: 0}, [0], [], [0]
    ends = np.zeros(len(links), dtype=np.intp)
    for position, link in enumerate(links):
        path = []
        while link not in nodes:
            path.append(link)
            link = link_chains.parent(link)
        node = nodes[link]
        for link in reversed(path):
            for element in link_chains.step(link):
                parents.append(node)
                last.append(element)
                lengths.append(lengths[node] + 1)
                node = len(parents) - 1
            nodes[link] = node
        ends[position] = node
    return np.array(parents, dtype=np.intp), last, ends, np.array(lengths, dtype=np.intp)[ends]


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




# --------------------------------------------------------------------------- planar chains in complex form

def planar_prefixes(group, point):
    """The prefix products of planar chains as complex numbers: rotations and translations, no 3×3 products.

    A planar rigid motion ``[[R(θ), t], [0, 1]]`` is the pair ``(r, t) = (e^{iθ}, t_x + i t_y)``
    and composes as ``(r₁, t₁)(r₂, t₂) = (r₁ r₂, t₁ + r₁ t₂)``. An element
    ``exp(θ X̂)`` of a rotation about the point c is ``(e^{iθ}, c (1 − e^{iθ}))``,
    one of a translation by d along a is ``(1, d a)``. So the prefix
    rotations are a cumulative product and the prefix translations a
    cumulative sum: ``t_j = Σ_{i ≤ j} r_{i−1} t_i``. The same products as
    :func:`expand_group` (``prefix``), to rounding.

    Parameters
    ----------
    group : ChainGroup
        Of a planar mechanism.
    point : ndarray, shape=[..., point_size]

    Returns
    -------
    rotations, translations : ndarray of complex, shape=[..., g, L + 1]
        Entry j is the product of the first j elements (entry 0 the identity, entry L the chain's product).
    """
    value = group.signs * point[..., group.values]                       # [..., g, L]
    centres, directions, rotating = _planar_constants(group)
    if rotating:  # revolute joints only
        turn = np.exp(1j * value)
        moves = centres * (1.0 - turn)
    else:
        turn = np.where(group.rotation, np.exp(1j * value), 1.0 + 0j)
        moves = np.where(group.rotation, centres * (1.0 - turn), value * directions)
    shape = value.shape[:-1] + (value.shape[-1] + 1,)
    rotations, translations = np.empty(shape, dtype=complex), np.empty(shape, dtype=complex)
    rotations[..., 0], translations[..., 0] = 1.0, 0.0
    np.cumprod(turn, axis=-1, out=rotations[..., 1:])
    np.cumsum(rotations[..., :-1] * moves, axis=-1, out=translations[..., 1:])
    return rotations, translations


_PLANAR_CONSTANTS = weakref.WeakKeyDictionary()


def _planar_constants(group):
    """Per element of a planar group: its centre c (rotations, ``v = (c_y, −c_x)``) and direction a
    (translations) as complex numbers, shape=[g, L], and whether every element is a rotation (cached)."""
    constants = _PLANAR_CONSTANTS.get(group)
    if constants is None:
        constants = _centres_and_directions(group.element_twists) + (bool(np.all(group.rotation)),)
        _PLANAR_CONSTANTS[group] = constants
    return constants


def _centres_and_directions(twists):
    """Of planar elements' signed twists [..., 3, 3]: the centre c of each rotation (``v = (c_y, −c_x)``) and
    the direction a of each translation, as complex numbers, shape=[...] each."""
    return -twists[..., 1, 2] + 1j * twists[..., 0, 2], twists[..., 0, 2] + 1j * twists[..., 1, 2]


@dataclass(frozen=True, eq=False)
class PlanarTree:
    """Chains of a planar mechanism from the ground as one tree of their prefixes (:func:`planar_tree`),
    for the products of all of them in a few array operations (:func:`planar_tree_products`).

    Attributes
    ----------
    parents : ndarray of int, shape=[p]
        Node 0 is the empty prefix (the identity, its own parent); node j > 0 a prefix, its parent the prefix
        one element shorter.
    values, signs : ndarray, shape=[p]
        The last element's point index and sign (as :class:`ChainGroup`'s; 0 at node 0).
    centres, directions : ndarray of complex, shape=[p]
        As :func:`_planar_constants` (0 at node 0).
    rotation : ndarray of bool, shape=[p]
    ends : ndarray of int, shape=[c]
        The node of each chain's whole product, by the chains' positions in their set.
    rounds : int
        ⌈log₂⌉ of the longest chain's length: the doubling steps of :func:`planar_tree_products`.
    """

    parents: np.ndarray
    values: np.ndarray
    signs: np.ndarray
    centres: np.ndarray
    directions: np.ndarray
    rotation: np.ndarray
    ends: np.ndarray
    rounds: int


def planar_tree(link_chains, links):
    """The :class:`PlanarTree` of the chains from the ground to `links` of a planar mechanism: a node per
    element on their paths along the spanning tree (:func:`prefix_tree`), in O(k) memory for k joints."""
    parents, last, ends, lengths = prefix_tree(link_chains, links)
    values, signs, element_twists, rotation, _ = _element_arrays("planar", [[element] for element in last])
    centres, directions = _centres_and_directions(element_twists.reshape(-1, 3, 3))
    return PlanarTree(parents, np.concatenate([[0], values.ravel()]).astype(np.intp),
                      np.concatenate([[0.0], signs.ravel()]), np.concatenate([[0j], centres]),
                      np.concatenate([[0j], directions]), np.concatenate([[True], rotation.ravel()]), ends,
                      int(np.ceil(np.log2(np.max(lengths, initial=1)))))


def planar_tree_products(tree, point):
    """The products of the chains of a :class:`PlanarTree` as complex numbers ``(r, t)`` (see
    :func:`planar_prefixes`), shape=[..., c] each, by doubling: each node's product from its ancestor 2ʲ
    elements up, ``(r, t) ← (r_a r, t_a + r_a t)``, ⌈log₂ L⌉ times — a few array operations over all prefixes
    where :func:`planar_prefixes` takes one call per shape of chain (a ladder of loops has as many shapes as
    rungs). The same products to rounding (another order of the same multiplications)."""
    value = tree.signs * point[..., tree.values]                         # [..., p]
    rotations = np.where(tree.rotation, np.exp(1j * value), 1.0 + 0j)
    translations = np.where(tree.rotation, tree.centres * (1.0 - rotations), value * tree.directions)
    ancestors = tree.parents
    for _ in range(tree.rounds):
        above_rotations, above_translations = rotations[..., ancestors], translations[..., ancestors]
        rotations, translations = above_rotations * rotations, above_translations + above_rotations * translations
        ancestors = ancestors[ancestors]
    return rotations[..., tree.ends], translations[..., tree.ends]


@dataclass(frozen=True, eq=False)
class MatrixTree:
    """Chains as one tree of their prefixes (:func:`matrix_tree`), for the products of all of them in a few
    array operations (:func:`matrix_tree_products`): the matrix form of :class:`PlanarTree`, for every space.

    Attributes
    ----------
    values, signs, element_twists, element_squares, rotation, balls
        Node j's last element, as a :class:`ChainGroup`'s of p chains of one element each (what
        :func:`element_matrices` reads); node 0 is the empty prefix, the identity.
    parents : ndarray of int, shape=[p]
        Each node's prefix one element shorter (node 0 its own).
    ends : ndarray of int, shape=[c]
        The node of each chain's whole product, in the chains' order.
    rounds : int
        ⌈log₂⌉ of the longest chain's length: the doubling steps of :func:`matrix_tree_products`.
    """

    values: np.ndarray
    signs: np.ndarray
    element_twists: np.ndarray
    element_squares: np.ndarray
    rotation: np.ndarray
    balls: Optional[tuple]
    parents: np.ndarray
    ends: np.ndarray
    rounds: int


def matrix_tree(space, link_chains, links):
    """The :class:`MatrixTree` of the chains from the ground to `links`: a node per element on their paths
    along the spanning tree (:func:`prefix_tree`), in O(k) memory for k joints."""
    parents, last, ends, lengths = prefix_tree(link_chains, links)
    values, signs, element_twists, rotation, balls = _element_arrays(space, [[element] for element in last])
    size = groups.MATRIX_SIZE[space]
    # node 0: a translation by zero along no axis, the identity
    values = np.concatenate([np.zeros((1, 1), dtype=np.intp), values.reshape(-1, 1)])
    signs = np.concatenate([np.zeros((1, 1)), signs.reshape(-1, 1)])
    element_twists = np.concatenate([np.zeros((1, 1, size, size)), element_twists.reshape(-1, 1, size, size)])
    rotation = np.concatenate([np.zeros((1, 1), dtype=bool), rotation.reshape(-1, 1)])
    if balls is not None:
        balls = (balls[0] + 1,) + balls[1:]
    return MatrixTree(values, signs, element_twists, element_twists @ element_twists, rotation, balls,
                      parents, ends, int(np.ceil(np.log2(np.max(lengths, initial=1)))))


def matrix_tree_products(space, tree, point):
    """The products of the chains of a :class:`MatrixTree`, shape=[..., c, n, n], by doubling: each node's
    product from its ancestor 2ʲ elements up, ``T ← T_a T``, ⌈log₂ L⌉ times — a few array operations over all
    prefixes where :func:`expand_group` takes one call per shape of chain, L products each. The same products
    to rounding (another order of the same multiplications)."""
    products = element_matrices(space, tree, point)[..., 0, :, :]          # [..., p, n, n]
    ancestors = tree.parents
    for _ in range(tree.rounds):
        products = products[..., ancestors, :, :] @ products
        ancestors = ancestors[ancestors]
    return products[..., tree.ends, :, :]


def planar_twists(group, rotations, translations):
    """Each coordinate's twist carried by its prefix, ``Ad_{P} X`` in the ground frame (planar chains).

    For ``X = (ω, v)`` and the prefix ``P = (r, t)`` at the coordinate's
    slot: ``(ω, r v − i ω t)`` (v complex): the twist of the joint where it
    now stands. ``∂T/∂v_a = P X̂_a P⁻¹ T`` is this twist's matrix times T.

    Returns
    -------
    angular : ndarray, shape=[g, C]
        ω of each coordinate (constant).
    linear : ndarray of complex, shape=[..., g, C]
    """
    angular = group.twists[:, :, 1, 0]
    linear = group.twists[:, :, 0, 2] + 1j * group.twists[:, :, 1, 2]
    slots = group.slots
    return angular, rotations[..., slots] * linear - 1j * angular * translations[..., slots]


def planar_loops(group, point, length, order=1, closing=False):
    """Φ's rows, the half-turn test and DΦ's entries of planar loops, without 3×3 products.

    With the loop product ``T = (r, t)`` the rows ``L(T)`` are
    ``(Im r, Re t / ℓ, Im t / ℓ)`` and ``Re r > 0`` excludes the half-turn;
    with a coordinate's carried twist ``(ω, w)`` (:func:`planar_twists`),
    ``L(∂T/∂v) = L(Ŵ T) = (ω Re r, Re(w + i ω t) / ℓ, Im(w + i ω t) / ℓ)``:
    :func:`mechanisms._groups.loop_rows` of :func:`expand_group`'s
    derivatives, to rounding.

    With `closing`, those of the closing map
    (:func:`mechanisms.kinematics.closing_space`): the rotation row is
    ``arg r``, zero only where T = I (the half-turn r = −1, a zero of
    ``Im r``, gives ±π), and its entries ω, the exact ``∂ arg r/∂v``.

    Parameters
    ----------
    group : ChainGroup
    point : ndarray, shape=[..., point_size]
    length : float
        ℓ, the characteristic length.
    order : int
        0: rows and turns only.
    closing : bool

    Returns
    -------
    rows : ndarray, shape=[..., g, 3]
    turns : ndarray of bool, shape=[..., g]
    entries : ndarray, shape=[..., g, C, 3] or None (order 0)
    """
    rotations, translations = planar_prefixes(group, point)
    rotation, translation = rotations[..., -1], translations[..., -1]
    turned = np.angle(rotation) if closing else rotation.imag
    rows = np.empty(turned.shape + (3,))
    rows[..., 0], rows[..., 1], rows[..., 2] = turned, translation.real / length, translation.imag / length
    turns = rotation.real > 0.0
    if order < 1:
        return rows, turns, None
    angular, linear = planar_twists(group, rotations, translations)
    moved = linear + 1j * angular * translation[..., None]
    entries = np.empty(moved.shape + (3,))
    entries[..., 0] = angular if closing else angular * rotation.real[..., None]
    entries[..., 1], entries[..., 2] = moved.real / length, moved.imag / length
    return rows, turns, entries


# --------------------------------------------------------------------------- first order from prefixes only

def carried_twists(space, group, point):
    """The chains' products and each coordinate's twist carried to the ground frame, from prefix products only.

    ``∂T/∂v_a = P X̂_a S`` with ``P S = T`` (P the prefix up to the
    coordinate's slot, S the suffix), so ``∂T/∂v_a = Ŵ_a T`` with
    ``Ŵ_a = P X̂_a P⁻¹``, i.e. ``W_a = Ad_P X_a``: for ``X = (ω, v)``,
    ``(R ω, R v + p × R ω)`` with ``P = [R, p]``. No suffix products
    (:func:`expand_group` forms both), the same derivatives to rounding.
    Spherical and spatial chains (planar ones: :func:`planar_twists`).

    Returns
    -------
    product : ndarray, shape=[..., g, n, n]
    angular : ndarray, shape=[..., g, C, 3]
    linear : ndarray, shape=[..., g, C, 3] or None (spherical)
    """
    matrices = element_matrices(space, group, point)                # [..., g, L, n, n]
    prefix = [np.broadcast_to(np.eye(matrices.shape[-1]), matrices.shape[:-3] + matrices.shape[-2:])]
    for number in range(group.length):
        prefix.append(prefix[-1] @ matrices[..., number, :, :])
    slots = group.slots
    at_slots = (np.stack([prefix[slot] for slot in slots], axis=-3) if len(slots)   # [..., g, C, n, n]
                else np.zeros(prefix[0].shape[:-2] + (0,) + prefix[0].shape[-2:]))  # no coordinate: the ground's
    twists = group.twists                                             # [g, C, n, n]
    axes = np.stack([twists[..., 2, 1], twists[..., 0, 2], twists[..., 1, 0]], axis=-1)  # ω, [g, C, 3]
    rotations = at_slots[..., :3, :3]
    angular = _times(rotations, axes)
    if space == "spherical":
        return prefix[-1], angular, None
    linear = _times(rotations, twists[..., :3, 3]) + _cross(at_slots[..., :3, 3], angular)
    return prefix[-1], angular, linear


def _times(matrices, vectors):
    """``M v`` for stacks of 3×3 matrices and 3-vectors, as a sum of scaled columns (faster than
    ``einsum``/``matmul`` on many tiny matrices), shape=[..., 3]."""
    return (matrices[..., 0] * vectors[..., 0, None] + matrices[..., 1] * vectors[..., 1, None]
            + matrices[..., 2] * vectors[..., 2, None])


def _cross(first, second):
    """``a × b`` for stacks of 3-vectors, shape=[..., 3]."""
    a0, a1, a2 = first[..., 0], first[..., 1], first[..., 2]
    b0, b1, b2 = second[..., 0], second[..., 1], second[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def loop_first_order(space, group, point, length):
    """Loop products and DΦ's entries of spherical or spatial loops, from :func:`carried_twists`.

    ``L(Ŵ T)`` in closed form, with ``T = [R, p]`` and ``W = (ω, v)``:
    the rotation rows ``½ vee(ω̂R − Rᵀω̂ᵀ) = ½ (tr R · ω − R ω)``, the
    translation rows ``(ω × p + v) / ℓ``.

    Returns
    -------
    product : ndarray, shape=[..., g, n, n]
    entries : ndarray, shape=[..., g, C, R]
    """
    product, angular, linear = carried_twists(space, group, point)
    rotation = product[..., :3, :3]
    trace = np.trace(rotation, axis1=-2, axis2=-1)[..., None, None]  # [..., g, 1, 1]
    rows = 0.5 * (trace * angular - _times(rotation[..., None, :, :], angular))
    if space == "spherical":
        return product, rows
    return product, np.concatenate([rows, _point_rates(product, angular, linear, length)], axis=-1)


def _point_rates(product, angular, linear, length):
    """The translation rows' entries ``(ω × p + v) / ℓ`` of loops ``T = [R, p]`` with carried twists
    ``(ω, v)``: ∂p/∂v over ℓ, shape=[..., g, C, 3]."""
    return (_cross(angular, np.broadcast_to(product[..., None, :3, 3], angular.shape)) + linear) / length


def loop_closing(space, group, point, length):
    """Rows and entries of the closing map of spherical or spatial loops
    (:func:`mechanisms.kinematics.closing_space`).

    Rows ``(r, p / ℓ)`` for the loop product ``T = [R, p]``, r = φ n the rotation vector of R (zero only where
    R = I: the half-turns, zeros of Φ's ``½ vee(R − Rᵀ) = sin φ n``, give φ = π). Entries, exact everywhere,
    ``(J⁻¹(r) ω, (ω × p + v) / ℓ)`` for the carried twists ``W = (ω, v)``
    (:func:`carried_twists`: ``Ṙ Rᵀ = ω̂``),
    with the inverse left Jacobian of SO(3)

        J⁻¹(r) = I − ½ r̂ + (1/φ² − 1/(2 φ tan(φ/2))) r̂²

    (``dr = J⁻¹(r) ω``; its last factor is 1/12 + φ²/720 + … near φ = 0 and 1/π² at φ = π). At R = I it is
    the identity, so on M the entries are DΦ's.

    Returns
    -------
    rows : ndarray, shape=[..., g, rows]
    entries : ndarray, shape=[..., g, C, rows]
    """
    from scipy.spatial.transform import Rotation  # here, not at start-up: only far projections need it

    product, angular, linear = carried_twists(space, group, point)
    rotation = product[..., :3, :3]
    flat = rotation.reshape(-1, 3, 3)
    finite = np.all(np.isfinite(flat), axis=(-2, -1))       # NaN rows where the point is not finite, as Φ's
    vectors = np.full(flat.shape[:-1], np.nan)
    if finite.any():
        vectors[finite] = Rotation.from_matrix(flat[finite]).as_rotvec()
    vectors = vectors.reshape(rotation.shape[:-1])                      # r, [..., g, 3]
    angle = np.linalg.norm(vectors, axis=-1)[..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        factor = np.where(angle < 1e-4, 1.0 / 12.0 + angle ** 2 / 720.0,
                          1.0 / angle ** 2 - 1.0 / (2.0 * angle * np.tan(angle / 2.0)))
    broadcast = np.broadcast_to(vectors[..., None, :], angular.shape)
    across = _cross(broadcast, angular)                                  # r̂ ω
    rates = angular - 0.5 * across + factor[..., None, :] * _cross(broadcast, across)
    if space == "spherical":
        return vectors, rates
    rows = np.concatenate([vectors, product[..., :3, 3] / length], axis=-1)
    return rows, np.concatenate([rates, _point_rates(product, angular, linear, length)], axis=-1)


def first_derivatives(space, group, point):
    """T and ``∂T/∂v_a = Ŵ_a T`` along the chains of a group (:func:`carried_twists`): what
    :func:`expand_group` returns at order 1, without suffix products (spherical and spatial chains).

    Returns
    -------
    product : ndarray, shape=[..., g, n, n]
    first : ndarray, shape=[..., g, C, n, n]
    """
    product, angular, linear = carried_twists(space, group, point)
    x, y, z = angular[..., 0], angular[..., 1], angular[..., 2]
    zero = np.zeros_like(x)
    size = product.shape[-1]
    hats = np.zeros(angular.shape[:-1] + (size, size))
    hats[..., :3, :3] = np.stack([np.stack([zero, -z, y], -1), np.stack([z, zero, -x], -1),
                                  np.stack([-y, x, zero], -1)], -2)
    if linear is not None:
        hats[..., :3, 3] = linear
    return product, hats @ product[..., None, :, :]
