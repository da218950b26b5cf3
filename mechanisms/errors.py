"""Exceptions raised by :mod:`mechanisms`."""

__all__ = ["MechanismError", "ConfigurationError"]


class MechanismError(ValueError):
    """A mechanism description is invalid; the message names the joint or field."""


class ConfigurationError(ValueError):
    """A configuration is invalid or does not close the loops."""
