"""A catalogue entry: a named mechanism family, its builder and its named configurations.

A builder is a function of keyword-only parameters, each with a default
(design dimensions, input values, assembly branch or working mode: the
paper's where it gives numbers, else a design of ours that its docstring states),
returning the :class:`~mechanisms.Mechanism` assembled at that configuration:
its home *is* the requested configuration, so the named configurations of an
entry are parameter presets, and a nearby configuration is the same builder
with a nearby input.
"""

from __future__ import annotations

import inspect
import math
import numbers
from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np

from .._numerals import decimal_integer, decimal_number
from ..errors import MechanismError
from ..joints import COORDINATE_LIMIT, check_text, is_number
from ..mechanism import Mechanism

#: the errors a builder raises when its parameters make no mechanism (besides MechanismError)
_BUILD_ERRORS = (ValueError, ArithmeticError, np.linalg.LinAlgError)

__all__ = ["Entry", "ReadOnly", "parse_parameter", "read_only_with"]


@dataclass(frozen=True)
class ReadOnly:
    """When a builder reads one of its parameters: a parameter that only one variant of the mechanism reads
    (an angle that only a degenerate assembly branch leaves free), refused when set for another variant.

    Parameters
    ----------
    condition : str
        Where the parameter is read, completing "read only …" (``"with assembly = 0"``).
    reads : callable
        ``reads(values) -> bool`` for the full parameter set (:meth:`Entry.values`).
    shown : tuple of str
        Parameters whose values the refusal shows (``("assembly",)``).
    """

    condition: str
    reads: Callable[[Mapping[str, object]], bool]
    shown: tuple = ()


def read_only_with(name, value):
    """A :class:`ReadOnly` for a parameter read only when parameter `name` equals `value`."""
    return ReadOnly(f"with {name} = {value}", lambda values: values[name] == value, (name,))


@dataclass(frozen=True)
class Entry:
    """One mechanism of the catalogue.

    Parameters
    ----------
    name : str
        Catalogue name, lower case with hyphens (``"slider-crank"``).
    build : callable
        ``build(**parameters) -> Mechanism``; keyword-only parameters, each
        with a default; raises :class:`~mechanisms.MechanismError` naming the
        parameter when the mechanism cannot be assembled.
    reference : str
        Paper file, figures and equations the entry comes from.
    configurations : mapping of str to mapping of str to value
        Named configurations: parameter overrides (e.g. the singular
        configurations a paper states), each cited in ``reference`` or in
        the builder's docstring.
    read_only : mapping of str to ReadOnly
        Parameters the builder reads only in some variants, with when: one the
        user sets (:meth:`values`) where it is not read is refused rather than
        silently ignored. The named configurations may set them regardless.
    """

    name: str
    build: Callable[..., Mechanism]
    reference: str
    configurations: Mapping[str, Mapping[str, object]] = field(default_factory=dict)
    read_only: Mapping[str, ReadOnly] = field(default_factory=dict)

    def __post_init__(self):
        for configuration, overrides in self.configurations.items():
            unknown = set(overrides) - set(self.parameters)
            if unknown:
                raise ValueError(f"catalogue entry {self.name!r}: configuration {configuration!r} sets "
                                 f"unknown parameter(s) {sorted(unknown)}")
        unknown = set(self.read_only) - set(self.parameters)
        if unknown:
            raise ValueError(f"catalogue entry {self.name!r}: read_only names unknown parameter(s) "
                             f"{sorted(unknown)}")

    @property
    def parameters(self):
        """Parameter name -> default value, in the builder's order."""
        return {name: parameter.default
                for name, parameter in inspect.signature(self.build).parameters.items()}

    @property
    def summary(self):
        """The first line of the builder's docstring."""
        return (inspect.getdoc(self.build) or self.name).splitlines()[0]

    def mechanism(self, configuration=None, **parameters):
        """The mechanism at a named configuration, with parameters overriding it.

        Parameters
        ----------
        configuration : str, optional
            One of :attr:`configurations`; default: the builder's defaults.
        **parameters
            Values of the builder's parameters (already typed; see
            :func:`parse_parameter` for text).

        Returns
        -------
        Mechanism

        Raises
        ------
        MechanismError
            For an unknown configuration or parameter, a parameter the builder
            does not read with these values (:meth:`values`), or one with
            which the mechanism cannot be assembled.
        """
        return self.assemble(self.values(configuration, **parameters))

    def assemble(self, values):
        """The mechanism for a full parameter set (as from :meth:`values`).

        Parameters
        ----------
        values : mapping of str to value
            Every parameter of the builder.

        Returns
        -------
        Mechanism

        Raises
        ------
        MechanismError
            When the parameters set away from their defaults make no
            mechanism (a non-finite, out-of-range or unreachable geometry):
            one line naming those parameters and the reason.
        """
        defaults = self.parameters
        changed = {name: value for name, value in values.items() if _differs(value, defaults.get(name))}
        try:
            return self.build(**values)
        except _BUILD_ERRORS as error:  # MechanismError included
            if not changed:
                raise
            reason = " ".join((str(error).strip() or type(error).__name__).split())
            raise MechanismError(f"{self.name} with {_settings(changed)}: cannot be built: {reason}") from None

    def values(self, configuration=None, **parameters):
        """The full parameter set: defaults, then the configuration's presets, then `parameters`.

        Parameters
        ----------
        configuration : str, optional
            One of :attr:`configurations`.
        **parameters
            The parameters the user sets (typed).

        Returns
        -------
        dict of str to value
            Every parameter of the builder.

        Raises
        ------
        MechanismError
            For an unknown configuration or parameter, a value of the wrong
            type, or a parameter of `parameters` that the builder does not
            read with these values (:attr:`read_only`): one line naming it
            and where it is read. The configuration's presets are not checked.
        """
        if configuration is not None and configuration not in self.configurations:
            known = ", ".join(self.configurations) or "none"
            raise MechanismError(f"{self.name}: unknown configuration {configuration!r} (known: {known})")
        unknown = sorted(set(parameters) - set(self.parameters))
        if unknown:
            raise MechanismError(f"{self.name}: unknown parameter {unknown[0]!r} "
                                 f"(parameters: {', '.join(self.parameters)})")
        for name, value in parameters.items():
            _check_type(self.name, name, value, self.parameters[name])
        values = dict(self.parameters)
        if configuration is not None:
            values.update(self.configurations[configuration])
        values.update(parameters)
        for name in parameters:
            rule = self.read_only.get(name)
            if rule is not None and not rule.reads(values):
                here = ", ".join(f"{other} = {values[other]!r}" for other in rule.shown)
                raise MechanismError(f"{self.name}: parameter {name!r} is read only {rule.condition}"
                                     f"{f' (here {here})' if here else ''}: it would have no effect (leave it "
                                     f"unset)")
        return values


def _check_type(entry, name, value, default):
    """MechanismError unless `value` has the type of the parameter's default (a bool, an integer, a real number,
    text): a builder given the wrong type failed deep inside (a TypeError, an AttributeError) or misread it."""
    if isinstance(default, bool):
        expected, ok = "true or false (a bool)", isinstance(value, (bool, np.bool_))
    elif isinstance(default, numbers.Integral):
        expected = "an integer"
        ok = isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_))
    elif is_number(default):
        expected = "a number"
        ok = isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))
    elif isinstance(default, str):
        expected, ok = "text", isinstance(value, str)
    else:
        return
    if not ok:
        shown = repr(value) if len(repr(value)) <= 40 else f"a {type(value).__name__}"
        raise MechanismError(f"{entry}: parameter {name!r}: expected {expected}, as its default {default!r}, "
                             f"got {shown}")


def _differs(value, default):
    try:
        return bool(value != default)
    except (TypeError, ValueError):  # arrays compare element-wise
        return True


def _settings(values):
    return ", ".join(f"{name}={value!r}" for name, value in values.items())


def parse_parameter(entry, text):
    """Read ``name=value`` text as a typed parameter of `entry` (never evaluated).

    The type is that of the parameter's default: a finite float, an int, a
    boolean (``true``/``false``) or a string.

    Examples
    --------
    >>> from mechanisms.catalogue import entry, parse_parameter
    >>> parse_parameter(entry("slider-crank"), "theta=0.5")
    ('theta', 0.5)

    Raises
    ------
    MechanismError
        Naming the parameter, for an unknown name or a value of the wrong type.
    """
    name, separator, value = text.partition("=")
    name, value = name.strip(), value.strip()
    if not separator or not name:
        raise MechanismError(f"--param: expected name=value, got {text[:40]!r}")
    parameters = entry.parameters
    if name not in parameters:
        raise MechanismError(f"--param {name}: {entry.name} has no parameter {name!r} "
                             f"(parameters: {', '.join(parameters)})")
    default = parameters[name]
    if isinstance(default, bool):
        if value.lower() not in ("true", "false"):
            raise MechanismError(f"--param {name}: expected true or false, got {value!r}")
        return name, value.lower() == "true"
    if isinstance(default, int):
        try:
            number = decimal_integer(value)
        except ValueError:
            raise MechanismError(f"--param {name}: expected an integer, got {value[:40]!r}") from None
        return name, _in_range(number, name)
    if is_number(default):
        try:
            number = decimal_number(value)
        except ValueError as error:
            raise MechanismError(f"--param {name}: {error}") from None
        if not math.isfinite(number):
            raise MechanismError(f"--param {name}: expected a finite number, got {value[:40]!r}")
        return name, _in_range(number, name)
    check_text(value, f"--param {name}")
    return name, value


def _in_range(number, name):
    if abs(number) > COORDINATE_LIMIT:
        raise MechanismError(f"--param {name}: {number:g} is out of range (at most {COORDINATE_LIMIT:g} "
                             f"in absolute value)")
    return number
