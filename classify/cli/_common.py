"""What the subcommands share: the input error, options, and reading a mechanism and its configuration."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from mechanisms import MechanismError, catalogue

from ..text import printable

__all__ = [
    "MECHANISM_SUFFIXES", "COUNT_LIMIT", "SEED_LIMIT", "THREAD_LIMIT", "LENGTH_SCALE_RATIO", "PATH_STEP_RANGE",
    "InputError", "Parser", "entry_options", "common_options", "displacements",
    "check_length_scale", "check_count", "check_path_step", "integer", "number", "is_entry", "path_exists",
    "entry_values", "threads_option", "warn_if_serial",
    "source", "joint_list", "finite", "dumps", "write_output", "IMPORT_SUFFIXES", "closures_option", "import_file",
    "check_output", "same_file", "input_files",
]

MECHANISM_SUFFIXES = (".yaml", ".yml", ".json")
#: inputs in other formats, imported and assembled (:mod:`mechanisms.urdf`, :mod:`mechanisms.mjcf`)
IMPORT_SUFFIXES = (".urdf", ".xml")
#: most configurations a count option (--samples, --path) may ask for
COUNT_LIMIT = 10_000
#: largest --seed (NumPy seeds are non-negative integers; 2⁶⁴ − 1 is plenty)
SEED_LIMIT = 2 ** 64 - 1
#: --length-scale within this factor of the mechanism's characteristic length, both ways
LENGTH_SCALE_RATIO = 1e6  # = classify.metrics.LENGTH_SCALE_RATIO, here so that the command starts without NumPy
#: most threads --threads may ask for (each holds a chunk of about 8 MiB of dense arrays and its temporaries)
THREAD_LIMIT = 256
#: --path-step range, in the dimensionless joint coordinates (radians; lengths over the characteristic length)
PATH_STEP_RANGE = (1e-9, 1.0)


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


def closures_option(parser):
    """``--closures FILE``: the loop closures of a URDF input (:mod:`mechanisms.closures`)."""
    parser.add_argument("--closures", default=None, metavar="FILE",
                        help="with a URDF: its loop closures (YAML: closed_loop, type 6d/3d, name_mot, "
                             "joint_name/joint_type)")


def import_file(path, closures=None):
    """Import a URDF (with its closures file) or an MJCF file: :class:`mechanisms.urdf.Imported`.

    A ``.xml`` file whose root element is ``<robot>`` is a URDF (:func:`mechanisms.urdf.looks_like_urdf`); any
    other ``.xml`` file is MJCF.

    Raises
    ------
    InputError
        ``--closures`` given with an MJCF file.
    MechanismError
        From the import, one line naming the file and field.
    """
    from mechanisms.urdf import looks_like_urdf, read_urdf

    _check_regular(path)
    if Path(path).suffix.lower() == ".urdf" or looks_like_urdf(path):
        return read_urdf(path, closures)
    if closures is not None:
        raise InputError(f"--closures: applies to a URDF input, not to {path} (an MJCF file has its loops as "
                         f"<equality> constraints)")
    from mechanisms.mjcf import read_mjcf

    return read_mjcf(path)


def _check_regular(path):
    """Refuse at once a path that is not a regular file (a FIFO would block its reader), with the readers' own
    words (:func:`mechanisms.io.read_text_file`); a path that cannot be looked at is left to the reader."""
    import os
    import stat

    from mechanisms._text import _file_kind

    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return
    if not stat.S_ISREG(mode):
        raise MechanismError(f"{printable(str(path))}: cannot read the file: it is {_file_kind(mode)}, not a "
                             f"regular file")


def integer(text):
    """argparse type: an integer in ASCII decimal notation (``int`` would also read '٣' as 3 and '1_0' as 10)."""
    from mechanisms._numerals import decimal_integer

    try:
        return decimal_integer(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text[:40]!r}") from None


def number(text):
    """argparse type: a number in ASCII decimal notation (:mod:`mechanisms._numerals`)."""
    from mechanisms._numerals import decimal_number

    try:
        return decimal_number(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def seed_type(text):
    """``--seed``: an integer from 0 to :data:`SEED_LIMIT`."""
    from mechanisms._numerals import decimal_integer

    try:
        value = decimal_integer(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer ≥ 0, got {text[:40]!r}") from None
    if not 0 <= value <= SEED_LIMIT:
        shown = str(value) if len(str(value)) <= 40 else "a larger integer"
        raise argparse.ArgumentTypeError(f"expected an integer from 0 to 2**64 - 1, got {shown}")
    return value


def _length_scale(text):
    """``--length-scale``: a positive finite number (its range is checked against the mechanism)."""
    value = number(text)
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"expected a positive finite number, got {text[:40]}")
    return value


def survey_option(parser):
    """``--survey FILE``: a survey cache file (:mod:`classify.survey_cache`), read or written by the command."""
    parser.add_argument("--survey", default=None, metavar="FILE",
                        help="survey cache file: read when it exists and was made for this mechanism, else "
                             "computed and written")


def _threads(text):
    """``--threads``: a positive integer up to :data:`THREAD_LIMIT`, or -1 (every usable core)."""
    value = integer(text)
    if not (1 <= value <= THREAD_LIMIT or value == -1):
        shown = str(value) if len(str(value)) <= 40 else "a larger integer"
        raise argparse.ArgumentTypeError(f"expected a positive integer up to {THREAD_LIMIT}, or -1 (every usable "
                                         f"core), got {shown}")
    return value


def threads_option(parser):
    """``--threads T``: the threads :func:`classify.classify_many` runs its chunks in (its ``workers``); None
    when not given (every usable core)."""
    parser.add_argument("--threads", type=_threads, default=None, metavar="T",
                        help="threads to classify in: a positive integer, or -1 for every usable core (default); "
                             "the result does not depend on it")


def common_options(parser):
    """``--seed`` and ``--length-scale``."""
    parser.add_argument("--seed", type=seed_type, default=0,
                        help="seed of the random sampling, an integer ≥ 0 (default 0)")
    parser.add_argument("--length-scale", type=_length_scale, default=None,
                        help="length scale of the SE(2)/SE(3) and tool (ℝ³ × S²) end-effector metrics (within a "
                             "factor 10⁶ of the mechanism's characteristic length)")


def displacements(text):
    """The joint displacements of ``--at JSON|@file.json`` (empty for None).

    The file is a regular UTF-8 file of at most 1 MiB; the JSON may not nest
    deeper than 20 levels nor hold integers of more than 400 digits
    (:func:`mechanisms.io.parse_json`). The values are checked against the
    joints later (:func:`mechanisms.validate_displacements`).
    """
    from mechanisms.io import parse_json, read_text_file  # imported when used: YAML, NumPy

    if text is None:
        return {}
    where = "--at"
    if text.startswith("@"):
        where = f"--at {text[1:]}"
        try:
            text = read_text_file(text[1:])
        except MechanismError as error:
            raise InputError(f"--at: {error}") from None
    try:
        value = parse_json(text, where)
    except MechanismError as error:
        raise InputError(str(error)) from None
    if not isinstance(value, dict):
        raise InputError(f"{where}: expected a JSON object mapping joint names to displacements, "
                         f"got {type(value).__name__}")
    return value


def finite(value):
    """`value` with every non-finite float (and NumPy scalar or array entry) replaced by None.

    JSON has no NaN or infinity: an undefined quantity is ``null``.
    """
    import numpy as np  # imported here: the command line starts without NumPy

    if isinstance(value, dict):
        return {key: finite(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(item) for item in value]
    if isinstance(value, np.ndarray):
        return finite(value.tolist())
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def dumps(value):
    """The JSON text of a command's result: indented, UTF-8, never NaN or Infinity."""
    return json.dumps(finite(value), indent=2, ensure_ascii=False, allow_nan=False)


def check_length_scale(value, mechanism=None, option="--length-scale"):
    """Refuse a non-positive or non-finite ``--length-scale`` (or `option`), or one out of range for `mechanism`.

    With a mechanism, the scale must lie within a factor :data:`LENGTH_SCALE_RATIO`
    of its characteristic length (the default scale): beyond, the rotation
    and translation parts of the metric differ by more than 10¹² and the
    proper values say nothing.
    """
    if value is None:
        return
    if not math.isfinite(value) or value <= 0:
        raise InputError(f"{option}: expected a positive finite number, got {value}")
    if mechanism is None:
        return
    length = mechanism.characteristic_length
    low, high = length / LENGTH_SCALE_RATIO, length * LENGTH_SCALE_RATIO
    if not low <= value <= high:
        raise InputError(f"{option}: expected a value from {low:.3g} to {high:.3g} (within a factor "
                         f"{LENGTH_SCALE_RATIO:g} of the characteristic length {length:.3g} of the mechanism), "
                         f"got {value:g}")


def check_count(value, option):
    """Refuse a count option (``--samples``, ``--path``) below 0 or above :data:`COUNT_LIMIT`."""
    if not 0 <= value <= COUNT_LIMIT:
        raise InputError(f"{option}: expected a count ≥ 0 and at most {COUNT_LIMIT}, got {value}")


def check_path_step(value):
    """Refuse a ``--path-step`` outside :data:`PATH_STEP_RANGE` (dimensionless joint coordinates)."""
    low, high = PATH_STEP_RANGE
    if not (math.isfinite(value) and low <= value <= high):
        raise InputError(f"--path-step: expected a step from {low:g} to {high:g} (joint coordinates: radians, "
                         f"and lengths in units of the mechanism's characteristic length), got {value:g}")


def path_exists(text):
    """Whether a path exists; False for a name no file can have (a NUL byte, too long)."""
    try:
        return Path(text).exists()
    except (OSError, ValueError):
        return False


def is_entry(text):
    """Whether a FILE|NAME argument names a catalogue entry (an existing path always wins)."""
    return text in catalogue.names() and not path_exists(text)


def entry_values(item, arguments):
    """The entry's parameters: defaults, then the --configuration presets, then the --param texts (each
    parameter once: a second value would silently replace the first)."""
    given = {}
    for text in arguments.param:
        name, value = catalogue.parse_parameter(item, text)
        if name in given:
            raise InputError(f"--param {name}: given twice")
        given[name] = value
    return item.values(arguments.configuration, **given)


def file_after_grid(arguments):
    """Take FILE|NAME back from ``--grid`` (several values), which argparse gives every word after it: in
    ``closedchain map --grid J1=0:1:9 J5=0:1:9 five-bar`` the name was read as a grid axis. The commands
    with ``--grid`` declare FILE|NAME optional and call this first: a missing one is the last ``--grid`` word
    when it has no ``=``, else the error argparse would have given."""
    grid = arguments.grid
    if arguments.file is None:
        if not grid or "=" in grid[-1]:
            raise InputError("the following arguments are required: FILE|NAME")
        arguments.file = grid.pop()


def source(arguments):
    """(mechanism, displacements of the named configuration) for FILE or catalogue NAME.

    A catalogue entry is built with :meth:`mechanisms.catalogue.Entry.assemble` (a
    ``--param`` that makes no mechanism is an error naming it); ``--length-scale``,
    when the command has it, is checked against the mechanism (:func:`check_length_scale`).
    """
    mechanism, named = _source(arguments)
    check_length_scale(getattr(arguments, "length_scale", None), mechanism)
    return mechanism, named


def _source(arguments):
    from mechanisms.io import read  # imported when used: YAML, NumPy

    closures = getattr(arguments, "closures", None)
    if not arguments.file:
        raise InputError("FILE|NAME: an empty path (a mechanism file or a catalogue name is expected)")
    if is_entry(arguments.file):
        if closures is not None:
            raise InputError("--closures: applies to a URDF input, not to a catalogue entry")
        item = catalogue.entry(arguments.file)
        return item.assemble(entry_values(item, arguments)), {}
    path = Path(arguments.file)
    if path.suffix.lower() in IMPORT_SUFFIXES and path_exists(arguments.file):
        for option, given in (("--param", arguments.param), ("--configuration", arguments.configuration)):
            if given:
                raise InputError(f"{option}: does not apply to the imported file {arguments.file}")
        imported = import_file(path, closures)
        arguments.imported = imported
        return imported.mechanism, {}
    if closures is not None:
        if not path_exists(arguments.file):
            raise InputError(f"{printable(arguments.file)}: no such file")
        raise InputError(f"--closures: applies to a URDF input (.urdf), not to {printable(arguments.file)}")
    if not path_exists(arguments.file) and path.suffix.lower() not in MECHANISM_SUFFIXES:
        raise InputError(f"{arguments.file}: no such file or catalogue entry (see `closedchain catalog`)")
    if arguments.param:
        raise InputError(f"--param: applies to catalogue entries, not to the file {arguments.file}")
    document = read(path)
    arguments.document = document  # its named configurations and description, for `convert`
    if arguments.configuration is None:
        return document.mechanism, {}
    if arguments.configuration not in document.configurations:
        known = ", ".join(document.configurations) or "none"
        raise InputError(f"--configuration: {path} has no configuration {arguments.configuration!r} "
                         f"(known: {known})")
    return document.mechanism, document.configurations[arguments.configuration]


def configuration_options(arguments, at):
    """The options that gave a configuration, to start a message about it: ``--configuration NAME``, ``--at`` or
    ``--configuration NAME with --at`` (a named configuration of a file may not close: the message names it, not an
    ``--at`` that was not given)."""
    named = getattr(arguments, "configuration", None)
    given = ([f"--configuration {printable(named)}"] if named is not None else []) + (["--at"] if at else [])
    return " with ".join(given) or "--at"


def warn_if_serial(mechanism):
    """A warning on stderr for a mechanism without loops (e.g. a URDF read without its --closures), naming its free
    end links: two that differ in a digit (``distal2``, ``distal3``) may be one misspelt name that opened a loop."""
    if mechanism.loop_count == 0:
        graph = mechanism.graph  # links joined by joints, keyed by joint name
        ends = [f"{printable(link)} (joint {printable(joint)})" for link in graph
                if link != mechanism.ground and graph.degree(link) == 1 for *_, joint in graph.edges(link, keys=True)]
        shown = ", ".join(ends[:_LISTED_ENDS]) + (", ..." if len(ends) > _LISTED_ENDS else "")
        print(f"closedchain: warning: {printable(mechanism.name)} has no loop (a serial chain; free end "
              f"link{'s' if len(ends) > 1 else ''}: {shown})", file=sys.stderr)


#: most free end links a warning names
_LISTED_ENDS = 6


def joint_list(text, where):
    """Comma-separated joint names."""
    names = [name.strip() for name in text.split(",")]
    if not all(names):
        raise InputError(f"{where}: expected comma-separated joint names, got {text!r}")
    return names


def same_file(path, other):
    """Whether two paths name one file: the same resolved path (whether or not it exists yet), or one existing
    file through a symbolic or a hard link (:func:`os.path.samefile`); False for a name no file can have (too
    long, a NUL byte).

    Parameters
    ----------
    path, other : str or os.PathLike

    Returns
    -------
    bool
    """
    import os

    try:
        if Path(path).resolve() == Path(other).resolve():
            return True
        return os.path.samefile(path, other)
    except (OSError, ValueError, RuntimeError):  # RuntimeError: a loop of symbolic links (Python < 3.13)
        return False


def input_files(arguments):
    """``(what, path)`` of the files a command reads (and its ``--survey`` cache, which it may write): FILE
    (not a catalogue entry), ``--closures``, ``--at @FILE``, ``--batch`` and ``--survey``, those it has and
    was given; for :func:`check_output`."""
    files = []
    file = getattr(arguments, "file", None)
    if file and not is_entry(file):
        files.append(("the input file", file))
    at = getattr(arguments, "at", None)
    for what, path in (("the --closures file", getattr(arguments, "closures", None)),
                       ("the --at file", at[1:] if at and at.startswith("@") else None),
                       ("the --batch file", getattr(arguments, "batch", None)),
                       ("the --survey cache", getattr(arguments, "survey", None))):
        if path:
            files.append((what, path))
    return files


def check_output(path, option, inputs=()):
    """Refuse, before any work, an output file the command could not write or that would overwrite an input.

    Parameters
    ----------
    path : str or None
        The output file (None: not asked for, nothing checked).
    option : str
        The option that named it (``--out``, ``--output``), for the message.
    inputs : iterable of (str, str or None)
        ``(what, path)`` of every file the command reads or writes besides (``("the --batch file", "b.json")``);
        a None path is skipped.

    Raises
    ------
    InputError
        One line naming `option`: an empty path, a folder, a missing folder, a folder this process cannot
        write in, or ``{path} is {what}: it would be overwritten (write elsewhere)``.
    """
    import os

    if path is None:
        return
    if not path:
        raise InputError(f"{option}: an empty path")
    shown = printable(str(path))
    for what, other in inputs:
        if other is not None and other != "" and same_file(path, other):
            raise InputError(f"{option}: {shown} is {what}: it would be overwritten (write elsewhere)")
    target = Path(path)
    try:
        if target.is_dir():
            raise InputError(f"{option}: {shown}: cannot write the file: it is a folder")
        folder = target.parent
        if not folder.is_dir():
            raise InputError(f"{option}: {shown}: cannot write the file: no folder {printable(str(folder))}")
        if target.exists() and not os.access(target, os.W_OK):
            raise InputError(f"{option}: {shown}: cannot write the file: Permission denied")
        if not target.exists() and not os.access(folder, os.W_OK | os.X_OK):
            raise InputError(f"{option}: {shown}: cannot write the file: the folder {printable(str(folder))} is "
                             f"not writable")
    except (OSError, ValueError):  # a name no file can have: said when the file is written
        return


def write_output(path, text, option):
    """Write a command's output file, reporting every failure as an :class:`InputError`.

    The text is flushed before the function returns, so a full device or
    disk (``/dev/full``) is reported, not claimed written; a missing folder,
    a folder, a FIFO nobody reads or a missing permission is refused with the
    operating system's reason.

    Parameters
    ----------
    path : str
    text : str
    option : str
        The option that named the file (``--write``, ``--output``), for the message.

    Raises
    ------
    InputError
        ``{option}: {path}: cannot write the file: {reason}``.
    """
    from mechanisms.io import write_text_file  # imported when used: YAML, NumPy

    try:
        write_text_file(path, text)
    except MechanismError as error:
        raise InputError(f"{option}: {error}") from None
