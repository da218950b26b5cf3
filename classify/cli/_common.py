"""What the subcommands share: the input error, options, and reading a mechanism and its configuration."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from mechanisms import catalogue
from mechanisms.io import read

__all__ = [
    "MECHANISM_SUFFIXES", "InputError", "Parser", "entry_options", "common_options", "displacements",
    "check_length_scale", "is_entry", "entry_values", "source", "joint_list", "finite", "dumps",
]

MECHANISM_SUFFIXES = (".yaml", ".yml", ".json")


class InputError(Exception):
    """Bad input from the command line: exit status 2."""


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are :class:`InputError` (one line, exit 2)."""

    def error(self, message):
        raise InputError(message)


def entry_options(parser):
    """``--configuration`` and ``--param``: which catalogue design or named configuration."""
    parser.add_argument("--configuration", default=None, metavar="C",
                        help="a named configuration (of the catalogue entry, or of the file)")
    parser.add_argument("--param", action="append", default=[], metavar="K=V",
                        help="a catalogue parameter (repeatable); see `closedchain catalog NAME`")


def common_options(parser):
    """``--seed`` and ``--length-scale``."""
    parser.add_argument("--seed", type=int, default=0, help="seed of the random sampling (default 0)")
    parser.add_argument("--length-scale", type=float, default=None,
                        help="length scale of the SE(2)/SE(3) end-effector metric")


def displacements(text):
    """The joint displacements of ``--at JSON|@file.json`` (empty for None)."""
    if text is None:
        return {}
    if text.startswith("@"):
        try:
            text = Path(text[1:]).read_text()
        except OSError as error:
            raise InputError(f"--at: cannot read {text[1:]!r}: {error.strerror}") from None
    try:
        value = json.loads(text)
    except json.JSONDecodeError as error:
        raise InputError(f"--at: invalid JSON: {error.msg} (line {error.lineno}, column {error.colno})") from None
    if not isinstance(value, dict):
        raise InputError(f"--at: expected a JSON object mapping joint names to displacements, "
                         f"got {type(value).__name__}")
    return value


def finite(value):
    """`value` with every non-finite float (and NumPy scalar or array entry) replaced by None.

    JSON has no NaN or infinity: an undefined quantity is ``null``.
    """
    if isinstance(value, dict):
        return {key: finite(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(item) for item in value]
    if isinstance(value, np.ndarray):
        return finite(value.tolist())
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


def dumps(value):
    """The JSON text of a command's result: indented, UTF-8, never NaN or Infinity."""
    return json.dumps(finite(value), indent=2, ensure_ascii=False, allow_nan=False)


def check_length_scale(value):
    """Refuse a non-positive or non-finite ``--length-scale``."""
    if value is not None and (not np.isfinite(value) or value <= 0):
        raise InputError(f"--length-scale: expected a positive finite number, got {value}")


def is_entry(text):
    """Whether a FILE|NAME argument names a catalogue entry (an existing path always wins)."""
    return text in catalogue.names() and not Path(text).exists()


def entry_values(item, arguments):
    """The entry's parameters: defaults, then the --configuration presets, then the --param texts."""
    return item.values(arguments.configuration,
                       **dict(catalogue.parse_parameter(item, text) for text in arguments.param))


def source(arguments):
    """(mechanism, displacements of the named configuration) for FILE or catalogue NAME."""
    if is_entry(arguments.file):
        item = catalogue.entry(arguments.file)
        return item.build(**entry_values(item, arguments)), {}
    path = Path(arguments.file)
    if not path.exists() and path.suffix not in MECHANISM_SUFFIXES:
        raise InputError(f"{arguments.file}: no such file or catalogue entry (see `closedchain catalog`)")
    if arguments.param:
        raise InputError(f"--param: applies to catalogue entries, not to the file {arguments.file}")
    document = read(path)
    if arguments.configuration is None:
        return document.mechanism, {}
    if arguments.configuration not in document.configurations:
        known = ", ".join(document.configurations) or "none"
        raise InputError(f"--configuration: {path} has no configuration {arguments.configuration!r} "
                         f"(known: {known})")
    return document.mechanism, document.configurations[arguments.configuration]


def joint_list(text, where):
    """Comma-separated joint names."""
    names = [name.strip() for name in text.split(",")]
    if not all(names):
        raise InputError(f"{where}: expected comma-separated joint names, got {text!r}")
    return names
