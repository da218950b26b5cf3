"""Mechanisms as joint graphs: joints, loop constraints, end-effectors, files.

Builds, from a description (Python objects or a JSON/YAML file), the
constraint map Φ with analytic DΦ, D²Φ, the actuator projection π and the
end-effector map f with Df, D²f. Never imports :mod:`classify`.
"""

from .actuation import actuate
from .assembly import ASSEMBLY_METHODS, Assembly, AssemblyError, assemble, assemblies
from .configuration import (
    CLOSURE_TOLERANCE, Projected, configuration, from_displacements, home,
    to_displacements, validate_displacements,
)
from .errors import ConfigurationError, MechanismError
from .joints import JOINT_TYPES, OUTPUTS, SPACES, EndEffector, Joint
from .kinematics import (
    Kinematics, actuator_jacobian, closes, configuration_space, constraint,
    constraint_hessian, constraint_jacobian, end_effector, end_effector_chart,
    end_effector_dimension, end_effector_hessian, end_effector_jacobian,
    kinematics_of, link_pose,
)
from .io import MechanismDocument, load, loads, read, save
from .mechanism import Mechanism
from .rehome import flip_axis, move_base, rehome, scale_lengths

__all__ = [
    "actuate",
    "ASSEMBLY_METHODS", "Assembly", "AssemblyError", "assemble", "assemblies",
    "CLOSURE_TOLERANCE", "Projected", "configuration", "from_displacements", "home",
    "to_displacements", "validate_displacements",
    "ConfigurationError", "MechanismError",
    "JOINT_TYPES", "OUTPUTS", "SPACES", "EndEffector", "Joint",
    "Kinematics", "actuator_jacobian", "closes", "configuration_space", "constraint",
    "constraint_hessian", "constraint_jacobian", "end_effector", "end_effector_chart",
    "end_effector_dimension", "end_effector_hessian", "end_effector_jacobian",
    "kinematics_of", "link_pose", "Mechanism", "flip_axis", "move_base", "rehome", "scale_lengths",
    "MechanismDocument", "load", "loads", "read", "save",
]
