"""Mechanisms as joint graphs: joints, loop constraints, end-effectors, files.

Builds, from a description (Python objects or a JSON/YAML file), the
constraint map Φ with analytic DΦ, D²Φ, the actuator projection π and the
end-effector map f with Df, D²f. Never imports :mod:`classify`.

The names below are imported on first use (PEP 562), so that the errors and
the catalogue's list (:mod:`mechanisms.catalogue`) cost no numerical import:
``from mechanisms import Mechanism`` works as usual.
"""

from manifold._lazy import attach

#: exported name → the submodule that defines it (imported when the name is first used)
_SOURCES = {
    "actuate": ".actuation", "checked_joint_names": ".actuation",
    **dict.fromkeys(("ASSEMBLY_METHODS", "Assembly", "AssemblyError", "assemble", "assemblies"), ".assembly"),
    **dict.fromkeys(("CLOSURE_TOLERANCE", "Projected", "configuration", "from_displacements", "home",
                     "to_displacements", "validate_displacements"), ".configuration"),
    **dict.fromkeys(("ConfigurationError", "MechanismError"), ".errors"),
    **dict.fromkeys(("JOINT_TYPES", "OUTPUTS", "SPACES", "EndEffector", "Joint"), ".joints"),
    **dict.fromkeys(("Kinematics", "actuator_jacobian", "closes", "configuration_space", "constraint",
                     "closure_and_entries", "closure_and_jacobian", "constraint_hessian", "constraint_hessian_form",
                     "constraint_jacobian", "constraint_jacobian_entries", "constraint_pattern", "end_effector",
                     "end_effector_chart", "end_effector_dimension", "end_effector_hessian", "end_effector_jacobian",
                     "kinematics_of", "link_pose"), ".kinematics"),
    "Mechanism": ".mechanism",
    **dict.fromkeys(("flip_axis", "move_base", "rehome", "scale_lengths"), ".rehome"),
    **dict.fromkeys(("MechanismDocument", "load", "loads", "read", "save"), ".io"),
}

__getattr__, __dir__, __all__ = attach(__name__, _SOURCES)
