"""Packages whose exported names are imported on first use (PEP 562), as SPEC 1's ``lazy_loader.attach``.

A package lists ``name → submodule`` and calls :func:`attach` once; ``from
package import name`` then imports only that name's submodule, so a light
submodule (the errors, the command line's text helpers) costs no numerical
import.
"""

import importlib
import sys
import types


def attach(package, sources):
    """Make the package `package` export `sources` lazily.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    sources : dict
        Exported name → the submodule defining it (relative, e.g. ``".batch"``).

    Returns
    -------
    tuple
        ``(__getattr__, __dir__, __all__)`` for the package's namespace.

    Notes
    -----
    A name exported from a submodule of the same name (``classify.survey``
    the function, from ``classify.survey`` the module) is not hidden by the
    submodule when something imports it later: the import system's setting
    of the submodule as the package's attribute is ignored for exported names.
    """
    module = sys.modules[package]

    def __getattr__(name):
        """The exported `name`, its submodule imported on first use."""
        if name not in sources:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(sources[name], package), name)
        setattr(module, name, value)
        return value

    def __dir__():
        return sorted(set(vars(module)) | set(sources))

    class Package(types.ModuleType):
        def __setattr__(self, name, value):
            if name in sources and isinstance(value, types.ModuleType):
                return
            super().__setattr__(name, value)

    module.__class__ = Package
    return __getattr__, __dir__, list(sources)
