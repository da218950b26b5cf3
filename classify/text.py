"""Text safe to print: names from files and the command line with every non-printable character escaped.

A light module (the standard library only), so that the command line can
escape what it prints without importing the numerical code.
"""

from __future__ import annotations

__all__ = ["printable", "drawn"]


def printable(name):
    """`name` as text safe to print: every non-printable character escaped.

    Control characters (ESC, NUL, newline, …) and other non-printable
    characters (zero-width or bidirectional marks, separators) are written as
    Python escapes (``\\x1b``, ``\\n``, ``\\u200b``), so a name from a file or
    the command line cannot move the cursor, colour the terminal or forge a
    line of output. JSON output needs none of this: JSON escapes them itself.

    Parameters
    ----------
    name : object
        A joint, mechanism, configuration or file name (converted with ``str``).

    Returns
    -------
    str

    Examples
    --------
    >>> printable("J\\x1b[31m")
    'J\\\\x1b[31m'
    >>> print(printable("J\\nclosedchain: error: forged"))
    J\\nclosedchain: error: forged
    """
    text = str(name)
    if text.isprintable():
        return text
    return "".join(character if character.isprintable() else _escaped(character) for character in text)


def _escaped(character):
    """The Python escape of one character (``\\n``, ``\\x00``, ``\\u202e``)."""
    return character.encode("unicode_escape").decode("ascii")


def drawn(name):
    """`name` as matplotlib text that shows it as written: :func:`printable`, and every dollar sign escaped
    (matplotlib reads the text between two of them as mathtext; ``$$`` in a name made a figure fail)."""
    return printable(name).replace("$", r"\$")
