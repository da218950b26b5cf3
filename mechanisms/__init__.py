"""Mechanisms as joint graphs: joints, loop constraints, end-effectors, files.

Builds, from a description (Python objects or a JSON/YAML file), the
constraint map Φ with analytic DΦ, D²Φ, the actuator projection π and the
end-effector map f with Df, D²f. Never imports :mod:`classify`.

The names below are imported on first use (PEP 562), so that the errors and
the catalogue's list (:mod:`mechanisms.catalogue`) cost no numerical import:
``from mechanisms import Mechanism`` works as usual.
"""

import importlib
import sys
import types

#: exported name → the submodule that defines it (imported when the name is first used)
_SOURCES = {
    "actuate": ".actuation",
    **dict.fromkeys(("ASSEMBLY_METHODS", "Assembly", "AssemblyError", "assemble", "assemblies"), ".assembly"),
    **dict.fromkeys(("CLOSURE_TOLERANCE", "Projected", "configuration", "from_displacements", "home",
                     "to_displacements", "validate_displacements"), ".configuration"),
    **dict.fromkeys(("ConfigurationError", "MechanismError"), ".errors"),
    **dict.fromkeys(("JOINT_TYPES", "OUTPUTS", "SPACES", "EndEffector", "Joint"), ".joints"),
    **dict.fromkeys(("Kinematics", "actuator_jacobian", "closes", "configuration_space", "constraint",
                     "closure_and_jacobian", "constraint_hessian", "constraint_hessian_form", "constraint_jacobian",
                     "constraint_jacobian_entries", "constraint_pattern", "end_effector", "end_effector_chart",
                     "end_effector_dimension", "end_effector_hessian", "end_effector_jacobian", "kinematics_of",
                     "link_pose"), ".kinematics"),
    "Mechanism": ".mechanism",
    **dict.fromkeys(("flip_axis", "move_base", "rehome", "scale_lengths"), ".rehome"),
    **dict.fromkeys(("MechanismDocument", "load", "loads", "read", "save"), ".io"),
}

__all__ = list(_SOURCES)


def __getattr__(name):
    """The exported `name`, its submodule imported on first use (``catalogue`` is a subpackage: ``from
    mechanisms import catalogue`` imports it as usual)."""
    if name not in _SOURCES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(_SOURCES[name], __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_SOURCES))


class _Package(types.ModuleType):
    """This package, whose exported ``configuration`` (the function) a later import of
    :mod:`mechanisms.configuration` (the module, which the import system sets as an attribute of its package)
    does not hide."""

    def __setattr__(self, name, value):
        if name in _SOURCES and isinstance(value, types.ModuleType):
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package
