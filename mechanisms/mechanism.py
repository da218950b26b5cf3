"""The frozen :class:`Mechanism`: a joint graph with ground, actuation and end-effector."""

from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass, field
from functools import cached_property
from typing import Optional

import networkx as nx
import numpy as np

from ._groups import LOOP_ROWS
from .errors import MechanismError
from .joints import (
    SPACES, EndEffector, Joint, check_end_effector, check_joint, check_name,
    joint_coordinate_names, joint_factors,
)

__all__ = ["Mechanism", "DENSE_MEMORY_LIMIT", "SMALLEST_LENGTH", "dense_memory_estimate"]

#: largest memory (bytes) the dense algorithms may need, as estimated by :func:`dense_memory_estimate`
DENSE_MEMORY_LIMIT = 2 ** 30
#: k×(k − c) arrays a classification holds at once: a tangent basis, its dimensionless copy, a kernel, a product
_BASIS_ARRAYS = 4
#: smallest distance between two points of a link that the rank tolerances resolve
SMALLEST_LENGTH = 1e-9
#: distances below this fraction of the coordinates are rounding noise (coincident points)
_ROUNDING = 1e-12
#: a spread at or below this, or below _ROUNDING times the coordinates, is no length (no link carries two
#: distinct points: :func:`_distinct`)
_SHORTEST_SPREAD = 1e-12
#: how many link names a message lists
_LISTED_LINKS = 12
#: shortest name (the longer of the two) that a one-character slip can be recognised in
_SHORTEST_MISSPELT = 5


def dense_memory_estimate(coordinates, rows):
    """Bytes the dense arrays of a classification need at least, for k joint coordinates and c constraint rows.

    Parameters
    ----------
    coordinates : int
        k, the dimension of the ambient space.
    rows : int
        c, the number of rows of the constraint map Φ.

    Returns
    -------
    int

    Notes
    -----
    The constraint Jacobian DΦ is a dense c×k array, and every tangent
    basis of M a dense k×m array with m ≥ k − c; a classification holds a
    few of them at once (the basis, its dimensionless copy, kernels and
    products: 4 counted). Each entry is a float64 (8 bytes):
    ``8·(c·k + 4·k·max(k − c, 0))``. Everything else grows with the loops,
    not with k²: DΦ is factorised block by block (its blocks are groups of
    loops sharing joints) and D²Φ is kept loop by loop
    (:mod:`mechanisms.kinematics`), never as a c×k×k array. The estimate is
    a lower bound: a mechanism above :data:`DENSE_MEMORY_LIMIT` cannot be
    classified in that memory whatever else it needs.

    Examples
    --------
    >>> dense_memory_estimate(400, 300)  # a ladder of 100 planar four-bar loops
    2240000
    >>> dense_memory_estimate(25_000, 0)  # 25,000 pendulums: one 25,000 × 25,000 tangent basis is 5 GB
    20000000000
    """
    return 8 * (rows * coordinates + _BASIS_ARRAYS * coordinates * max(coordinates - rows, 0))


def _binary_size(size, digits=3):
    """A byte count in the largest binary unit that keeps it at least 1, to `digits` significant digits, e.g.
    ``9.3 GiB``."""
    for unit in ("B", "KiB", "MiB", "GiB", "TiB"):
        if size < 1024 or unit == "TiB":
            return f"{size:.{digits}g} {unit}" if unit != "B" else f"{size} B"
        size /= 1024


def _sizes_apart(size, limit):
    """`size` and `limit` in :func:`_binary_size`'s words with the fewest digits (3 at least) that tell them apart:
    1,073,883,168 bytes against a limit of 2³⁰ read ``1 GiB`` and ``1 GiB`` to 3 digits, ``1.00013 GiB`` and
    ``1 GiB`` to 6."""
    for digits in range(3, 16):
        shown = _binary_size(size, digits), _binary_size(limit, digits)
        if shown[0] != shown[1]:
            return shown
    return f"{size} B", f"{limit} B"


@dataclass(frozen=True, eq=False)
class Mechanism:
    """A closed (or open) kinematic chain described by its joint graph.

    Links are the nodes and joints the edges of a networkx multigraph
    (:attr:`graph`, keyed by joint name). Construction validates everything
    the file contract lists and raises :class:`MechanismError` naming the
    joint or field.

    Parameters
    ----------
    name : str
    space : {"planar", "spherical", "spatial"}
    joints : sequence of Joint
    ground : str
        Name of the fixed link (default ``"ground"``).
    end_effector : EndEffector, optional

    Raises
    ------
    MechanismError
        Besides malformed joints, names and graphs: a link joined by a single
        joint that is neither the ground nor the end-effector's link, when
        its name looks like another link's or the mechanism has loops
        (probably a misspelt name); a geometry whose largest distance between
        two points of a link is below :data:`SMALLEST_LENGTH` (but not mere
        rounding); a mechanism whose dense algorithms would need more than
        :data:`DENSE_MEMORY_LIMIT` bytes (:func:`dense_memory_estimate`; a
        ladder of 100 planar four-bar loops, 400 joints, needs 2.2 MB).

    Notes
    -----
    A mechanism without loops (a serial chain or a tree, ``loop_count == 0``)
    is legitimate; the commands say so in their output.

    Examples
    --------
    A four-bar linkage with its crank driven:

    >>> four_bar = Mechanism("four-bar", "planar", [
    ...     Joint("A", "R", ("ground", "crank"), point=(0, 0), actuated=True),
    ...     Joint("B", "R", ("crank", "coupler"), point=(0, 1)),
    ...     Joint("C", "R", ("coupler", "rocker"), point=(2, 1.5)),
    ...     Joint("D", "R", ("rocker", "ground"), point=(2, 0))])
    >>> four_bar.ambient_dimension, four_bar.loop_count
    (4, 1)
    """

    name: str
    space: str
    joints: tuple
    ground: str = "ground"
    end_effector: Optional[EndEffector] = None
    graph: nx.MultiGraph = field(init=False, repr=False)

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise MechanismError(f"field 'name': expected a non-empty string, got {self.name!r}")
        check_name(self.name, "field 'name'")
        if self.space not in SPACES:
            raise MechanismError(f"field 'space': unknown space {self.space!r} "
                                 f"(expected one of {', '.join(SPACES)})")
        if not isinstance(self.ground, str) or not self.ground:
            raise MechanismError(f"field 'ground': expected a link name, got {self.ground!r}")
        check_name(self.ground, "field 'ground'")
        joints = tuple(self.joints)
        if not joints:
            raise MechanismError("field 'joints': a mechanism needs at least one joint")
        seen = set()
        for joint in joints:
            if not isinstance(joint, Joint):
                raise MechanismError(f"field 'joints': expected Joint objects, got {type(joint).__name__}")
            check_joint(joint, self.space)
            if joint.name in seen:
                raise MechanismError(f"joint {joint.name!r}: field 'name': duplicate joint name")
            seen.add(joint.name)
        _check_coordinate_names(joints)
        _check_unicode_forms(joints)
        graph = nx.MultiGraph()
        for joint in joints:
            graph.add_edge(*joint.links, key=joint.name, joint=joint)
        if self.ground not in graph:
            _refuse_unicode_twin(self.ground, graph, joints, "field 'ground'")
            raise MechanismError(f"field 'ground': link {self.ground!r} is not joined to any joint")
        _check_size(joints, graph, self.space)
        unreachable = set(graph) - nx.node_connected_component(graph, self.ground)
        if unreachable:
            listed = sorted(unreachable)
            shown = listed[:_LISTED_LINKS] + (["..."] if len(listed) > _LISTED_LINKS else [])
            raise MechanismError(f"field 'joints': the graph is not connected to the ground; "
                                 f"links {shown} are not reachable from {self.ground!r}")
        if self.end_effector is not None:
            if not isinstance(self.end_effector, EndEffector):
                raise MechanismError("field 'end_effector': expected an EndEffector")
            if isinstance(self.end_effector.link, str) and self.end_effector.link not in graph:
                _refuse_unicode_twin(self.end_effector.link, graph, joints, "end_effector: field 'link'")
            check_end_effector(self.end_effector, self.space, graph)
        _check_dangling_links(joints, graph, self.ground, self.end_effector)
        object.__setattr__(self, "joints", joints)
        object.__setattr__(self, "graph", graph)
        self._check_scale()

    @property
    def links(self):
        """Link names, the ground first, then in order of first appearance."""
        return tuple(dict.fromkeys([self.ground, *(link for joint in self.joints for link in joint.links)]))

    @property
    def loop_count(self):
        """Number of independent loops, ``joints − links + 1`` (0 for a serial chain or a tree)."""
        return len(self.joints) - self.graph.number_of_nodes() + 1

    @property
    def factors(self):
        """Ambient factors of all joints in order, e.g. ``("S1", "S1", "R")``."""
        return tuple(factor for joint in self.joints for factor in joint_factors(joint))

    @property
    def ambient_dimension(self):
        """k = dim K, the number of joint coordinates."""
        return sum(3 if factor == "SO3" else 1 for factor in self.factors)

    @property
    def coordinate_names(self):
        """Names of the k tangent coordinates, joint by joint."""
        return tuple(name for joint in self.joints for name in joint_coordinate_names(joint))

    @property
    def actuated_coordinates(self):
        """Indices (into the k tangent coordinates) of the actuated coordinates."""
        indices, start = [], 0
        for joint in self.joints:
            dim = len(joint_coordinate_names(joint))
            if joint.actuated:
                indices += list(range(start, start + dim))
            start += dim
        return tuple(indices)

    @property
    def actuator_weights(self):
        """Weights of the actuated coordinates, aligned with :attr:`actuated_coordinates`."""
        return tuple(joint.weight for joint in self.joints if joint.actuated
                     for _ in joint_coordinate_names(joint))

    @property
    def dense_memory_estimate(self):
        """Bytes the dense algorithms need for this mechanism (:func:`dense_memory_estimate`)."""
        return dense_memory_estimate(self.ambient_dimension, LOOP_ROWS[self.space] * self.loop_count)

    @cached_property
    def _spread(self):
        """The spread the characteristic length is taken from: ``(spread, extent)``.

        spread is the largest distance between two points carried by one
        link, extent the largest |coordinate| of those points. The points are
        the joints' (they alone describe M); only where no link carries two
        distinct joint points (:func:`_distinct`: a spread of rounding, e.g.
        a loop of rails and single pins) is the end-effector point added, as before
        (so that the length still scales with the unit of length).
        """
        joints = _link_spread(self, with_end_effector=False)
        if _distinct(*joints) or self.end_effector is None or self.end_effector.point is None:
            return joints
        return _link_spread(self, with_end_effector=True)

    def _check_scale(self):
        """Refuse a geometry too small for the rank tolerances (points that are not merely coincident)."""
        spread, extent = self._spread
        if _ROUNDING * extent < spread < SMALLEST_LENGTH:
            raise MechanismError(f"field 'joints': the geometry is too small: the largest distance between "
                                 f"two points of one link is {spread:.3g}, below {SMALLEST_LENGTH:g}; "
                                 f"describe the mechanism in a smaller unit of length")

    @cached_property
    def characteristic_length(self):
        """A length that makes the constraint rows dimensionless.

        The largest distance between two joint points carried by one link
        (the points of the R, S, U and C joints on it): a rigid-body
        invariant, so it does not change with the home configuration, the
        base frame or axis signs, and it scales with the unit of length. It
        divides Φ's translation rows and is the tangent scale of prismatic
        coordinates (:func:`mechanisms.kinematics.kinematics_of`), so M's
        description (DΦ's singular values, the C-space rank and its margin)
        depends on the joints' geometry only: the end-effector point, which
        is no part of M, is left out. It is also the default L of the
        end-effector metric (:func:`classify.metrics.end_effector_metric`)
        and the default length of the conditioning and Gosselin–Angeles
        computations, one length for all of them.

        Where no link carries two distinct joint points (a loop of rails and
        single pins), the end-effector point is counted with them (the
        largest distance between two points of one link, the end-effector's
        included); 1 when no link carries two distinct points at all (e.g.
        spherical mechanisms, whose rows carry no length).
        """
        spread = self._spread[0]
        return spread if _distinct(*self._spread) else 1.0

    def joint(self, name):
        """The joint called `name` (KeyError naming it if there is none)."""
        for joint in self.joints:
            if joint.name == name:
                return joint
        raise KeyError(f"no joint named {name!r} in mechanism {self.name!r}")


def _distinct(spread, extent):
    """Whether a spread is a length, not rounding: above :data:`_SHORTEST_SPREAD` and above :data:`_ROUNDING`
    times the coordinates (the cut of :meth:`Mechanism._check_scale`, which takes such points as coincident:
    two pins 1e-10 apart at coordinates of 1000 are one point, in any unit of length)."""
    return spread > max(_SHORTEST_SPREAD, _ROUNDING * extent)


def _link_spread(mechanism, with_end_effector):
    """(largest distance between two points carried by one link, largest |coordinate| of a point): the points
    of the joints, and the end-effector point if `with_end_effector`."""
    carried = {link: [] for link in mechanism.graph}
    for joint in mechanism.joints:
        if joint.point is not None:
            for link in joint.links:
                carried[link].append(joint.point)
    end_effector = mechanism.end_effector
    if with_end_effector and end_effector is not None and end_effector.point is not None:
        carried[end_effector.link].append(end_effector.point)
    spread, extent = 0.0, 0.0
    for points in carried.values():
        if points:
            extent = max(extent, float(np.max(np.abs(points))))
    for points in carried.values():
        if len(points) > 1 and extent > 0:  # distances in units of the extent: no squares underflow to 0
            spread = max(spread, extent * _diameter(np.asarray(points, dtype=float) / extent))
    return spread, extent


def _diameter(points, block=256):
    """Largest distance between two of the points, shape=[n, d], in O(n) memory.

    Exact. A lower bound L comes from farthest-point steps; a point p can
    only end a longer pair when ``|p − c| + R > L`` (c the centroid, R the
    largest distance to it), so only those points are compared with all the
    others: for the points of one link (a few, or many in a line) this is
    close to linear in n.
    """
    points = np.asarray(points, dtype=float)
    if len(points) <= block:
        return float(np.max(np.linalg.norm(points[:, None] - points[None], axis=-1), initial=0.0))
    current, largest = 0, 0.0
    for _ in range(3):
        distances = np.linalg.norm(points - points[current], axis=-1)
        current = int(np.argmax(distances))
        largest = max(largest, float(distances[current]))
    centre = points.mean(axis=0)
    reach = np.linalg.norm(points - centre, axis=-1)
    candidates = points[reach + reach.max() > largest]
    for start in range(0, len(candidates), block):
        rows = candidates[start:start + block]
        largest = max(largest, float(np.max(np.linalg.norm(rows[:, None] - points[None], axis=-1))))
    return largest


def _check_size(joints, graph, space):
    """Refuse a mechanism whose dense arrays would need more than :data:`DENSE_MEMORY_LIMIT`."""
    coordinates = sum(3 if factor == "SO3" else 1 for joint in joints for factor in joint_factors(joint))
    rows = LOOP_ROWS[space] * max(len(joints) - graph.number_of_nodes() + 1, 0)
    estimate = dense_memory_estimate(coordinates, rows)
    if estimate > DENSE_MEMORY_LIMIT:
        needed, limit = _sizes_apart(estimate, DENSE_MEMORY_LIMIT)
        raise MechanismError(
            f"field 'joints': the mechanism is too large for the dense algorithms: {coordinates} joint "
            f"coordinates and {rows} constraint rows need at least {needed} "
            f"(8·(c·k + 4·k·(k − c)) bytes: DΦ and the tangent bases of M), more than the limit of {limit}")


def _one_edit_apart(first, second):
    """Whether one character inserted, deleted, replaced, or two adjacent ones swapped, turn one into the other."""
    if len(first) > len(second):
        first, second = second, first
    if len(second) - len(first) == 1:
        return any(second[:index] + second[index + 1:] == first for index in range(len(second)))
    if len(first) != len(second):
        return False
    differences = [index for index, (a, b) in enumerate(zip(first, second)) if a != b]
    return len(differences) == 1 or (
        len(differences) == 2 and differences[1] == differences[0] + 1
        and first[differences[0]] == second[differences[1]] and first[differences[1]] == second[differences[0]])


def _deletions(name):
    """`name` and every string one deletion away: two names one edit apart share one of these."""
    return {name} | {name[:index] + name[index + 1:] for index in range(len(name))}


class _LookAlikes:
    """Names indexed by their deletions, to find a name's probable misspellings among many in linear time."""

    def __init__(self, names):
        self._index = {}
        self._without_digits = {}
        for name in names:
            self._without_digits[name] = re.sub(r"[0-9]", "", name.lower())
            for key in _deletions(name.lower()):
                self._index.setdefault(key, []).append(name)

    def of(self, name, among):
        """A name of `among` that `name` is probably a misspelling of, or None.

        One edit apart ignoring case (:func:`_one_edit_apart`), the longer at
        least :data:`_SHORTEST_MISSPELT` characters, and not differing only in
        digits (``link1``, ``link2`` are different names).
        """
        lowered = name.lower()
        digitless = self._without_digits.get(name, re.sub(r"[0-9]", "", lowered))
        candidates = {candidate for key in _deletions(lowered) for candidate in self._index.get(key, ())
                      if self._without_digits[candidate] != digitless}
        for candidate in sorted(candidates & among - {name}):
            other = candidate.lower()
            if (max(len(lowered), len(other)) >= _SHORTEST_MISSPELT
                    and (lowered == other or _one_edit_apart(lowered, other))):
                return candidate
        return None


def _known_links(graph, ground, excluded):
    """The link names for a message: the ground first, then in order of appearance, at most a dozen."""
    names = [link for link in [ground, *graph] if link not in excluded]
    names = list(dict.fromkeys(names))
    shown = names[:_LISTED_LINKS] + (["..."] if len(names) > _LISTED_LINKS else [])
    return ", ".join(shown)


def _joint_of(joints, link):
    return next(joint.name for joint in joints if link in joint.links)


def _check_coordinate_names(joints):
    """Refuse two coordinates of one name (:attr:`Mechanism.coordinate_names`): a joint named like a coordinate of
    another joint (an R joint ``U1[1]`` beside the U joint ``U1``), whose values text, CSV and ``--grid`` could not
    tell apart."""
    owners = {}
    for joint in joints:
        for coordinate in joint_coordinate_names(joint):
            owner = owners.setdefault(coordinate, joint)
            if owner is joint:
                continue
            named, other = (joint, owner) if coordinate == joint.name else (owner, joint)
            raise MechanismError(f"joint {named.name!r}: field 'name': {coordinate!r} is also the name of a "
                                 f"coordinate of joint {other.name!r} (coordinates are named after their joint: "
                                 f"rename one of the joints)")


def _check_unicode_forms(joints):
    """Refuse two joint names, or two link names, that are one text in two Unicode forms (``é`` as one character
    and as ``e`` with a combining accent, U+0301): they print alike but are different names, so a loop would open
    without a word. Nothing is normalised: the user writes them alike."""
    joint_names, link_names = {}, {}
    for joint in joints:
        named = ((joint_names, joint.name, "field 'name'", "joint"),
                 *((link_names, link, f"field 'links': item {index}", "link")
                   for index, link in enumerate(joint.links)))
        for names, name, field_name, what in named:
            other, owner = names.setdefault(unicodedata.normalize("NFC", name), (name, joint.name))
            if other != name:
                raise MechanismError(_two_forms(f"joint {joint.name!r}: {field_name}", what, name, other,
                                                None if what == "joint" else owner))


def _refuse_unicode_twin(name, links, joints, where):
    """Refuse `name` (the ground, the end-effector's link) where a link of the joints is the same text in another
    Unicode form: "unknown link" would name a link that prints exactly like a known one."""
    composed = unicodedata.normalize("NFC", name)
    twin = next((link for link in links if unicodedata.normalize("NFC", link) == composed), None)
    if twin is not None:
        raise MechanismError(_two_forms(where, "link", name, twin, _joint_of(joints, twin)))


def _two_forms(where, what, name, other, joint=None):
    """The message for two names that are one text in two Unicode forms, both shown with ``ascii()`` so that the
    difference shows (and `joint`, the other's, where it is not the one named in `where`)."""
    owner = "" if joint is None else f" (joint {joint!r})"
    return (f"{where}: {what} name {ascii(name)} and {ascii(other)}{owner} are one text in two Unicode forms: they "
            f"print alike but are different names; write them alike")


def _check_dangling_links(joints, graph, ground, end_effector):
    """Refuse a link that only one joint names and that nothing uses: probably a misspelt name.

    A link joined by a single joint that is neither the ground nor the
    end-effector's link moves freely and carries nothing. It is refused when
    its name looks like another link's name (one character inserted,
    deleted, replaced or two swapped, ignoring case: ``copuler`` and
    ``coupler``, ``grund`` and ``ground``; names under 5 characters or
    differing only in digits do not count),
    and in a mechanism with loops whatever its name (a dangling link there is
    an idle freedom, most likely a misspelt name). A mechanism without loops
    (a serial chain, a tree) with distinct names is legitimate.
    """
    explained = {ground} | ({end_effector.link} if end_effector is not None else set())
    loops = len(joints) - graph.number_of_nodes() + 1
    dangling = {link for link in graph if graph.degree(link) == 1 and link not in explained}
    used = set(graph) - dangling
    look_alikes = _LookAlikes(graph)
    for joint in joints:
        for index, link in enumerate(joint.links):
            if link in dangling:
                _refuse_dangling(joints, f"joint {joint.name!r}: field 'links': item {index}", link,
                                 look_alikes.of(link, used), look_alikes.of(link, dangling), loops,
                                 lambda excluded: f"(known links: {_known_links(graph, ground, excluded)})")


def _refuse_dangling(joints, where, link, original, twin, loops, known_links):
    """Raise the message for a dangling link (see :func:`_check_dangling_links`), if it is refused;
    `known_links(excluded)` is the list of links the message ends with: all of them for two dangling look-alikes
    (both spellings), else without `link`."""
    alone = "appears in no other joint and is neither the ground nor the end-effector's link"
    if original is None and twin is None and loops == 0:
        return
    known = known_links(set() if original is None and twin is not None else {link})
    if original is not None:
        raise MechanismError(f"{where}: link {link!r} {alone}: probably a misspelling of {original!r} {known}")
    if twin is not None:
        raise MechanismError(f"{where}: links {link!r} and {twin!r} (joint {_joint_of(joints, twin)!r}) each "
                             f"appear in one joint only, and neither is the ground nor the end-effector's link: "
                             f"one is probably a misspelling of the other {known}")
    if loops > 0:
        raise MechanismError(f"{where}: link {link!r} {alone}: probably a misspelt name {known}")
