"""Exceptions raised by :mod:`manifold`."""

__all__ = ["ManifoldError", "ProjectionError", "ContinuationError"]


class ManifoldError(Exception):
    """Base class of the errors of :mod:`manifold`."""


class ProjectionError(ManifoldError):
    """Gauss-Newton projection onto an implicit manifold did not converge."""


class ContinuationError(ManifoldError):
    """A curve on an implicit manifold could not be continued."""
