"""Exceptions raised by :mod:`manifold`."""

__all__ = ["ManifoldError", "ProjectionError"]


class ManifoldError(Exception):
    """Base class of the errors of :mod:`manifold`."""


class ProjectionError(ManifoldError):
    """Gauss-Newton projection onto an implicit manifold did not converge."""
