"""Numbers written as text (command-line options, CSV cells, catalogue parameters): plain decimal notation.

Python's ``float`` and ``int`` also read other scripts' digits (``'٣'`` is 3),
underscores between digits (``'1_0'`` is 10) and round a nonzero number below
the smallest float to 0 (``'1e-400'``): a value the user did not write. These
read only ASCII digits, an optional sign, point and exponent, and the words
``inf``, ``infinity`` and ``nan`` (which the callers refuse as not finite,
saying so); the standard library only, so the command can use them at start.
"""

from __future__ import annotations

import re

__all__ = ["decimal_number", "decimal_integer", "exact_float", "is_word", "Underflow"]

_DECIMAL = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?", re.ASCII)
_WORD = re.compile(r"[+-]?(?:inf|infinity|nan)", re.ASCII | re.IGNORECASE)
_INTEGER = re.compile(r"[+-]?\d+", re.ASCII)


class Underflow(ValueError):
    """A nonzero number written below the smallest float (``float`` would read it as 0)."""


def decimal_number(text):
    """The float written in `text` (surrounding spaces allowed).

    Raises
    ------
    ValueError
        If `text` is not plain decimal notation ("expected a number, got '…'", ready for a message after the
        field's name), or (:class:`Underflow`) names a nonzero number too small for a float (it would read
        as 0).
    """
    stripped = text.strip()
    if is_word(stripped):
        return float(stripped)
    if not _DECIMAL.fullmatch(stripped):
        raise ValueError(f"expected a number, got {text[:40]!r}")
    return exact_float(stripped)


def is_word(text):
    """Whether `text` (surrounding spaces allowed) is one of the words :func:`decimal_number` reads: inf,
    infinity or nan, either case, with a sign or not."""
    return _WORD.fullmatch(text.strip()) is not None


def exact_float(text):
    """``float(text)`` of a decimal literal (as JSON and YAML write numbers), refusing one that names a nonzero
    number below the smallest float.

    Raises
    ------
    Underflow
        "{text} is nonzero but below the smallest float (it would read as 0)".
    """
    value = float(text)
    if value == 0.0 and re.search(r"[1-9]", re.split(r"[eE]", text)[0]):
        raise Underflow(f"{text} is nonzero but below the smallest float (it would read as 0)")
    return value


def decimal_integer(text):
    """The integer written in `text` with ASCII digits (an optional sign; surrounding spaces allowed).

    Raises
    ------
    ValueError
        If `text` is anything else.
    """
    stripped = text.strip()
    if not _INTEGER.fullmatch(stripped):
        raise ValueError(f"not an integer in decimal notation: {text!r}")
    return int(stripped)
