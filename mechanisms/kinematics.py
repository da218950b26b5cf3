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
"""

from __future__ import annotations

import weakref
from collections import deque
from dataclasses import dataclass
from typing import Optional

import numpy as np
from scipy.linalg import logm

from manifold import AmbientSpace, ImplicitManifold

from . import _groups as groups
from .joints import joint_factors

__all__ = [
    "Kinematics", "kinematics_of", "configuration_space",
    "constraint", "constraint_jacobian", "constraint_hessian", "closes",
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
    link_chains : dict
        Link name -> chain from the ground to that link.
    point_parts : dict
        Joint name -> tuple of slices of the point array holding its coordinates
        (one per ambient factor: one for R, P, S; two for U, C).
    length : float
        Characteristic length dividing translation rows.
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
    paths = {mechanism.ground: []}
    tree_joints = set()
    queue = deque([mechanism.ground])
    while queue:
        link = queue.popleft()
        for index, joint in enumerate(mechanism.joints):
            if link not in joint.links or index in tree_joints:
                continue
            other = joint.links[1] if joint.links[0] == link else joint.links[0]
            if other in paths:
                continue
            paths[other] = paths[link] + [(index, joint.links[0] == link)]
            tree_joints.add(index)
            queue.append(other)
    loops, chords = [], []
    for index, joint in enumerate(mechanism.joints):
        if index in tree_joints:
            continue
        first, second = (paths[link] for link in joint.links)
        common = 0
        while common < min(len(first), len(second)) and first[common] == second[common]:
            common += 1
        steps = first[common:] + [(index, True)] + [(i, not forward) for i, forward in reversed(second[common:])]
        loops.append(_traverse(joint_elements, steps))
        chords.append(joint.name)
    link_chains = {link: _traverse(joint_elements, steps) for link, steps in paths.items()}
    end_effector = mechanism.end_effector
    compiled = Kinematics(
        space=mechanism.space, ambient=ambient, loops=tuple(loops), chords=tuple(chords),
        link_chains=link_chains, point_parts=point_parts, length=length,
        end_effector_link=None if end_effector is None else end_effector.link,
        end_effector_point=None if end_effector is None or end_effector.point is None
        else np.asarray(end_effector.point, dtype=float),
        output=None if end_effector is None else end_effector.output,
    )
    _CACHE[mechanism] = compiled
    return compiled


# --------------------------------------------------------------------------- chains

def _element_matrix(space, element, point):
    if element.kind == "ball":
        rotation = point[..., element.point_part].reshape(point.shape[:-1] + (3, 3))
        matrix = groups.ball_matrix(rotation, element.center)
        return groups.inverse(space, matrix) if element.inverse else matrix
    value = element.sign * point[..., element.point_part]
    if element.kind == "rotation":
        return groups.exp_rotation(element.twists[0] * element.sign, value)
    return groups.exp_translation(element.twists[0] * element.sign, value)


def _coordinates(chain):
    """(tangent index, twist, slot, element number) in product order."""
    coordinates = []
    for number, element in enumerate(chain.elements):
        slot = number if element.inverse else number + 1
        for index, twist in zip(element.tangent_indices, element.twists):
            coordinates.append((index, twist, slot, number))
    coordinates.sort(key=lambda entry: (entry[2], entry[3]))
    return coordinates


def _expand(space, chain, point, order):
    """T, its first derivatives and (order 2) second derivatives along a chain.

    Returns
    -------
    product : ndarray, shape=[..., n, n]
    coordinates : list
    first : ndarray, shape=[..., c, n, n]
    second : ndarray, shape=[..., c, c, n, n] or None
    """
    size = groups.MATRIX_SIZE[space]
    batch = point.shape[:-1]
    identity = np.broadcast_to(np.eye(size), batch + (size, size))
    matrices = [_element_matrix(space, element, point) for element in chain.elements]
    prefix = [identity]
    for matrix in matrices:
        prefix.append(prefix[-1] @ matrix)
    suffix = [identity] * (len(matrices) + 1)
    for number in range(len(matrices) - 1, -1, -1):
        suffix[number] = matrices[number] @ suffix[number + 1]
    coordinates = _coordinates(chain)
    count = len(coordinates)
    first = np.zeros(batch + (count, size, size))
    for column, (_, twist, slot, _) in enumerate(coordinates):
        first[..., column, :, :] = prefix[slot] @ twist @ suffix[slot]
    if order < 2:
        return prefix[-1], coordinates, first, None
    second = np.zeros(batch + (count, count, size, size))
    for row, (_, twist_a, slot_a, element_a) in enumerate(coordinates):
        running = prefix[slot_a] @ twist_a
        current = slot_a
        for column in range(row, count):
            _, twist_b, slot_b, element_b = coordinates[column]
            if element_b == element_a:
                value = 0.5 * prefix[slot_a] @ (twist_a @ twist_b + twist_b @ twist_a) @ suffix[slot_a]
            else:
                while current < slot_b:
                    running = running @ matrices[current]
                    current += 1
                value = running @ twist_b @ suffix[slot_b]
            second[..., row, column, :, :] = value
            second[..., column, row, :, :] = value
    return prefix[-1], coordinates, first, second


def _as_points(mechanism, point):
    point = np.asarray(point, dtype=float)
    size = kinematics_of(mechanism).ambient.point_size
    if point.shape[-1:] != (size,):
        raise ValueError(f"Expected `point` to have shape (..., {size}), got {point.shape}")
    return point


# --------------------------------------------------------------------------- constraints

def configuration_space(mechanism):
    """The C-space of a mechanism as an :class:`~manifold.ImplicitManifold`."""
    return ImplicitManifold(
        ambient=kinematics_of(mechanism).ambient,
        constraint=lambda point: constraint(mechanism, point),
        constraint_jacobian=lambda point: constraint_jacobian(mechanism, point),
        constraint_hessian=lambda point: constraint_hessian(mechanism, point),
        is_solution=lambda point: bool(np.all(closes(mechanism, point, tolerance=np.inf))),
    )


def _loop_values(mechanism, point, order):
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    for chain in compiled.loops:
        yield _expand(compiled.space, chain, point, order)


def constraint(mechanism, point):
    """Loop-closure map Φ(point), rows loop by loop, shape=[..., c].

    Rotation rows ``½ vee(R − Rᵀ)`` then translation rows over the
    characteristic length, for each loop product R, p.
    """
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    rows = [groups.loop_rows(compiled.space, product, compiled.length)
            for product, _, _, _ in _loop_values(mechanism, point, 0)]
    if not rows:
        return np.zeros(point.shape[:-1] + (0,))
    return np.concatenate(rows, axis=-1)


def constraint_jacobian(mechanism, point):
    """DΦ(point) in the recentred chart, shape=[..., c, k]."""
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    rows_per_loop = groups.LOOP_ROWS[compiled.space]
    jacobian = np.zeros(point.shape[:-1] + (rows_per_loop * len(compiled.loops), compiled.ambient.dim))
    for loop, (_, coordinates, first, _) in enumerate(_loop_values(mechanism, point, 1)):
        rows = slice(loop * rows_per_loop, (loop + 1) * rows_per_loop)
        values = groups.loop_rows(compiled.space, first, compiled.length)  # [..., c_loop, rows]
        for column, (index, _, _, _) in enumerate(coordinates):
            jacobian[..., rows, index] = values[..., column, :]
    return jacobian


def constraint_hessian(mechanism, point):
    """D²Φ(point) in the recentred chart, shape=[..., c, k, k]."""
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    rows_per_loop = groups.LOOP_ROWS[compiled.space]
    k = compiled.ambient.dim
    hessian = np.zeros(point.shape[:-1] + (rows_per_loop * len(compiled.loops), k, k))
    for loop, (_, coordinates, _, second) in enumerate(_loop_values(mechanism, point, 2)):
        rows = slice(loop * rows_per_loop, (loop + 1) * rows_per_loop)
        values = groups.loop_rows(compiled.space, second, compiled.length)  # [..., c, c, rows]
        values = np.moveaxis(values, -1, -3)  # [..., rows, c, c]
        indices = [entry[0] for entry in coordinates]
        grid = np.ix_(indices, indices)
        hessian[..., rows, grid[0], grid[1]] = values
    return hessian


def closes(mechanism, point, tolerance=1e-9):
    """Whether every loop closes: ‖Φ‖ ≤ tolerance and no loop is a half-turn, shape=[...]."""
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    result = np.ones(point.shape[:-1], dtype=bool)
    for product, _, _, _ in _loop_values(mechanism, point, 0):
        rows = groups.loop_rows(compiled.space, product, compiled.length)
        result &= np.linalg.norm(rows, axis=-1) <= tolerance
        result &= groups.is_identity_rotation(compiled.space, product)
    return result


def link_pose(mechanism, link, point):
    """Pose of a link relative to its home pose, in the ground frame, shape=[..., n, n]."""
    compiled = kinematics_of(mechanism)
    point = _as_points(mechanism, point)
    product, _, _, _ = _expand(compiled.space, compiled.link_chains[link], point, 0)
    return product


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
    relative = groups.inverse(compiled.space, np.asarray(base_value)) @ np.asarray(value)
    flat = relative.reshape((-1,) + relative.shape[-2:])
    logs = np.array([np.real(logm(matrix)) for matrix in flat]).reshape(relative.shape)
    return groups.vee(compiled.space, logs)[..., _twist_components(compiled)]


def _end_effector_expansion(mechanism, point, order):
    compiled = _require_end_effector(mechanism)
    point = _as_points(mechanism, point)
    product, coordinates, first, second = _expand(
        compiled.space, compiled.link_chains[compiled.end_effector_link], point, order)
    return compiled, point, product, coordinates, first, second


def end_effector_jacobian(mechanism, point):
    """Df(point) in the chart of N at f(point), shape=[..., n, k].

    Position outputs: ∂(T x)/∂v. Orientation and pose outputs: body twists
    ``vee(F⁻¹ ∂F/∂v)``.
    """
    compiled, point, product, coordinates, first, _ = _end_effector_expansion(mechanism, point, 1)
    jacobian = np.zeros(point.shape[:-1] + (end_effector_dimension(mechanism), compiled.ambient.dim))
    columns = _end_effector_columns(compiled, product, first)
    for column, (index, _, _, _) in enumerate(coordinates):
        jacobian[..., :, index] = columns[..., column, :]
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
    compiled, point, product, coordinates, first, second = _end_effector_expansion(mechanism, point, 2)
    k = compiled.ambient.dim
    n = end_effector_dimension(mechanism)
    hessian = np.zeros(point.shape[:-1] + (n, k, k))
    indices = [entry[0] for entry in coordinates]
    if compiled.output == "position":
        size = groups.MATRIX_SIZE[compiled.space]
        values = (second @ _offset(compiled))[..., : size - 1, size - 1]  # [..., c, c, n]
    else:
        offset = _offset(compiled)
        frame = product @ offset
        body = groups.inverse(compiled.space, frame)[..., None, :, :] @ first @ offset  # [..., c, s, s]
        count = len(coordinates)
        values = np.zeros(point.shape[:-1] + (count, count, n))
        for row in range(count):
            for column in range(row + 1, count):
                if coordinates[row][3] == coordinates[column][3]:
                    continue
                bracket = body[..., row, :, :] @ body[..., column, :, :] - body[..., column, :, :] @ body[..., row, :, :]
                value = 0.5 * groups.vee(compiled.space, bracket)[..., _twist_components(compiled)]
                values[..., row, column, :] = value
                values[..., column, row, :] = value
    values = np.moveaxis(values, -1, -3)  # [..., n, c, c]
    grid = np.ix_(indices, indices)
    hessian[..., grid[0], grid[1]] = values
    return hessian
