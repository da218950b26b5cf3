"""The frozen :class:`Mechanism`: a joint graph with ground, actuation and end-effector."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Optional

import networkx as nx
import numpy as np

from .errors import MechanismError
from .joints import (
    SPACES, EndEffector, Joint, check_end_effector, check_joint,
    joint_coordinate_names, joint_factors,
)

__all__ = ["Mechanism"]


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
        if self.space not in SPACES:
            raise MechanismError(f"field 'space': unknown space {self.space!r} "
                                 f"(expected one of {', '.join(SPACES)})")
        if not isinstance(self.ground, str) or not self.ground:
            raise MechanismError(f"field 'ground': expected a link name, got {self.ground!r}")
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
        graph = nx.MultiGraph()
        for joint in joints:
            graph.add_edge(*joint.links, key=joint.name, joint=joint)
        if self.ground not in graph:
            raise MechanismError(f"field 'ground': link {self.ground!r} is not joined to any joint")
        unreachable = set(graph) - nx.node_connected_component(graph, self.ground)
        if unreachable:
            raise MechanismError(f"field 'joints': the graph is not connected to the ground; "
                                 f"links {sorted(unreachable)} are not reachable from {self.ground!r}")
        if self.end_effector is not None:
            if not isinstance(self.end_effector, EndEffector):
                raise MechanismError("field 'end_effector': expected an EndEffector")
            check_end_effector(self.end_effector, self.space, graph)
        object.__setattr__(self, "joints", joints)
        object.__setattr__(self, "graph", graph)

    @property
    def links(self):
        """Link names, the ground first, then in order of first appearance."""
        ordered = [self.ground]
        for joint in self.joints:
            ordered += [link for link in joint.links if link not in ordered]
        return tuple(ordered)

    @property
    def loop_count(self):
        """Number of independent loops, ``joints − links + 1``."""
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

    @cached_property
    def characteristic_length(self):
        """A length that makes the constraint rows dimensionless.

        The largest distance between two points carried by one link (the
        points of the joints on it and the end-effector point): a rigid-body
        invariant, so it does not change with the home configuration, the base
        frame or axis signs. 1 when no link carries two distinct points (e.g.
        spherical mechanisms, whose rows carry no length).
        """
        carried = {link: [] for link in self.graph}
        for joint in self.joints:
            if joint.point is not None:
                for link in joint.links:
                    carried[link].append(joint.point)
        if self.end_effector is not None and self.end_effector.point is not None:
            carried[self.end_effector.link].append(self.end_effector.point)
        spread = 0.0
        for points in carried.values():
            if len(points) > 1:
                points = np.asarray(points)
                spread = max(spread, float(np.max(np.linalg.norm(points[:, None] - points[None], axis=-1))))
        return spread if spread > 1e-12 else 1.0

    def joint(self, name):
        """The joint called `name` (KeyError naming it if there is none)."""
        for joint in self.joints:
            if joint.name == name:
                return joint
        raise KeyError(f"no joint named {name!r} in mechanism {self.name!r}")
