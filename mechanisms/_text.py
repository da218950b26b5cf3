"""Reading and writing the text of mechanism files safely, and parsing it (private to :mod:`mechanisms.io`).

Files are opened without blocking and checked before they are read (no FIFO,
device or directory; at most :data:`FILE_SIZE_LIMIT` bytes); YAML is read in
the YAML 1.2 core schema with anchors, aliases, merge keys and non-standard
tags refused; YAML and JSON alike refuse duplicate keys, nesting deeper than
:data:`DEPTH_LIMIT` and integers of more than :data:`DIGITS_LIMIT` digits.
Nothing is ever evaluated.
"""

from __future__ import annotations

import errno
import json
import math
import numbers
import os
import re
import stat
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import yaml

from .errors import MechanismError
from ._numerals import Underflow, exact_float


#: largest file read, in bytes (1 MiB)
FILE_SIZE_LIMIT = 2 ** 20
#: deepest nesting of lists and mappings in a document (a mechanism file needs 5)
DEPTH_LIMIT = 20
#: most digits of an integer in a document
DIGITS_LIMIT = 400


def read_text_file(path, limit=FILE_SIZE_LIMIT):
    """The UTF-8 text of a regular file of at most `limit` bytes.

    The file is opened without blocking and checked before it is read, so a
    FIFO, a device (``/dev/zero``) or a directory is refused at once instead
    of hanging or filling the memory.

    Parameters
    ----------
    path : str or os.PathLike
    limit : int
        Largest size in bytes.

    Returns
    -------
    str
        The text, without a byte-order mark.

    Raises
    ------
    MechanismError
        One line starting with the path: cannot be opened, not a regular
        file, too large, or not UTF-8.
    """
    path = _path(path)
    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except (OSError, ValueError) as error:
        raise MechanismError(_one_line(f"{path}: cannot read the file: {_os_reason(error)}")) from None
    try:
        mode, size = _file_status(descriptor)
        if not stat.S_ISREG(mode):
            raise MechanismError(_one_line(f"{path}: cannot read the file: it is {_file_kind(mode)}, "
                                           f"not a regular file"))
        if size > limit:
            raise MechanismError(_one_line(f"{path}: the file is too large: {size} bytes "
                                           f"(the limit is {limit} bytes)"))
        with os.fdopen(descriptor, "rb") as handle:
            descriptor = None
            data = handle.read(limit + 1)
    except OSError as error:
        raise MechanismError(_one_line(f"{path}: cannot read the file: {_os_reason(error)}")) from None
    finally:
        if descriptor is not None:
            os.close(descriptor)
    if len(data) > limit:
        raise MechanismError(_one_line(f"{path}: the file is too large: more than {limit} bytes "
                                       f"(the limit)"))
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        raise MechanismError(_one_line(f"{path}: cannot read the file: not UTF-8 text "
                                       f"({error.reason} at byte {error.start})")) from None


def write_text_file(path, text):
    """Write UTF-8 text to a file and report any failure, including one on the final flush.

    A FIFO nobody reads is refused instead of blocking; a full device
    (``/dev/full``) or disk fails when the text is flushed, and says so.

    Parameters
    ----------
    path : str or os.PathLike
    text : str

    Raises
    ------
    MechanismError
        ``{path}: cannot write the file: {reason}`` (missing folder, a
        folder, no space left, no permission, ...).
    """
    path = _path(path)
    flags = os.O_WRONLY | os.O_CREAT | os.O_TRUNC | getattr(os, "O_NONBLOCK", 0)
    try:
        descriptor = os.open(path, flags, 0o666)
    except (OSError, ValueError) as error:
        reason = ("it is a FIFO that no process is reading" if getattr(error, "errno", None) == errno.ENXIO
                  else _os_reason(error))
        raise MechanismError(_one_line(f"{path}: cannot write the file: {reason}")) from None
    try:
        if hasattr(os, "set_blocking"):
            os.set_blocking(descriptor, True)
        with os.fdopen(descriptor, "w", encoding="utf-8") as handle:
            descriptor = None
            handle.write(text)
    except OSError as error:
        raise MechanismError(_one_line(f"{path}: cannot write the file: {_os_reason(error)}")) from None
    finally:
        if descriptor is not None:
            os.close(descriptor)


def _file_status(descriptor):
    status = os.fstat(descriptor)
    return status.st_mode, status.st_size


def _file_kind(mode):
    """What a non-regular file is, for a message ("a directory", "a FIFO (named pipe)", ...)."""
    kinds = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
             (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
             (stat.S_ISSOCK, "a socket"))
    return next((kind for test, kind in kinds if test(mode)), "a special file")


def _os_reason(error):
    """The reason of an OSError, without the path; for the ValueError ``os.open`` raises only for a path with a
    NUL byte, words of our own (Python's differ between versions)."""
    if isinstance(error, ValueError):
        return "the path has a NUL byte in it"
    if isinstance(error, OSError) and error.strerror:
        return error.strerror
    return _reason(error)


def _is_sequence(value):
    return isinstance(value, (list, tuple, np.ndarray))


def _describe(value, limit=40):
    """A short, one-line description of a value for an error message."""
    if value is None:
        return "null"
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, Mapping):
        return "a mapping"
    if _is_sequence(value):
        return f"a list of {len(value)} item{'' if len(value) == 1 else 's'}"
    if isinstance(value, str):
        text = repr(value)
    elif isinstance(value, (float, np.floating)):
        text = repr(float(value))
    elif isinstance(value, numbers.Integral):
        text = str(value) if abs(int(value)).bit_length() <= 128 else "a very large integer"
    else:
        return f"a {type(value).__name__}"
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _one_line(text):
    return " ".join(part.strip() for part in str(text).splitlines() if part.strip())


def _path(path):
    try:
        return Path(os.fspath(path))
    except TypeError:
        raise MechanismError(f"expected a file path, got {_describe(path)}") from None


# ------------------------------------------------------------------- parsing

_BOOL_TAG = "tag:yaml.org,2002:bool"
_INT_TAG = "tag:yaml.org,2002:int"
_FLOAT_TAG = "tag:yaml.org,2002:float"
#: YAML 1.2 core-schema implicit types (first characters, pattern)
_CORE_RESOLVERS = (
    (_BOOL_TAG, "tTfF", r"true|True|TRUE|false|False|FALSE"),
    (_INT_TAG, "-+0123456789", r"[-+]?[0-9]+|0o[0-7]+|0x[0-9a-fA-F]+"),
    (_FLOAT_TAG, "-+.0123456789",
     r"[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?"
     r"|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN)"),
)


_YAML_PREFIX = "tag:yaml.org,2002:"
#: the explicit tags a mechanism file may use: plain data ("!" is the non-specific tag of a quoted scalar)
_PLAIN_TAGS = {"!"} | {_YAML_PREFIX + name for name in ("str", "int", "float", "bool", "null", "seq", "map")}

try:  # libyaml's parser: fast, and not recursive however deep the document nests
    from yaml._yaml import CParser as _EventParser
except ImportError:  # pragma: no cover - PyYAML built without libyaml
    _EventParser = None


class _Parser(*((_EventParser,) if _EventParser is not None
                else (yaml.reader.Reader, yaml.scanner.Scanner, yaml.parser.Parser))):
    """The YAML event parser: libyaml's when PyYAML has it, else PyYAML's own."""

    def __init__(self, stream):
        if _EventParser is not None:
            _EventParser.__init__(self, stream)
        else:  # pragma: no cover - PyYAML built without libyaml
            yaml.reader.Reader.__init__(self, stream)
            yaml.scanner.Scanner.__init__(self)
            yaml.parser.Parser.__init__(self)


class _Loader(yaml.composer.Composer, _Parser, yaml.constructor.SafeConstructor, yaml.resolver.Resolver):
    """A safe loader: YAML 1.2 core scalars, no duplicate keys, plain data only.

    The composer (PyYAML's, in Python, over the events of :class:`_Parser`)
    refuses anchors and aliases (so no "billion laughs"), every explicit tag
    but the plain ones, and nesting deeper than :data:`DEPTH_LIMIT`, before
    anything is constructed; the constructor refuses merge keys.
    """

    def __init__(self, stream):
        _Parser.__init__(self, stream)
        yaml.composer.Composer.__init__(self)
        yaml.constructor.SafeConstructor.__init__(self)
        yaml.resolver.Resolver.__init__(self)
        self._depth = 0

    def compose_node(self, parent, index):
        event = self.peek_event()
        if isinstance(event, yaml.AliasEvent):
            self._refuse(f"found an alias *{event.anchor[:40]}: anchors and aliases are not allowed in a "
                         f"mechanism file", event)
        if event.anchor is not None:
            self._refuse(f"found an anchor &{event.anchor[:40]}: anchors and aliases are not allowed in a "
                         f"mechanism file", event)
        tag = getattr(event, "tag", None)
        if tag is not None and tag not in _PLAIN_TAGS:
            shown = "!!" + tag[len(_YAML_PREFIX):] if tag.startswith(_YAML_PREFIX) else tag
            self._refuse(f"found the tag {_describe(shown)}: a mechanism file holds plain data, with no "
                         f"tags but !!str, !!int, !!float, !!bool, !!null, !!seq and !!map", event)
        if self._depth >= DEPTH_LIMIT:
            self._refuse(f"the document nests deeper than {DEPTH_LIMIT} levels", event)
        self._depth += 1
        try:
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    @staticmethod
    def _refuse(problem, event):
        raise yaml.composer.ComposerError(None, None, problem, event.start_mark)

    def construct_mapping(self, node, deep=False):
        if isinstance(node, yaml.MappingNode):
            seen = set()
            for key_node, _ in node.value:
                if key_node.tag == "tag:yaml.org,2002:merge":
                    raise yaml.constructor.ConstructorError(
                        None, None, "found a merge key '<<': merge keys are not allowed in a mechanism file",
                        key_node.start_mark)
                key = self.construct_object(key_node, deep=True)
                try:
                    duplicate = key in seen
                    seen.add(key)
                except TypeError:  # unhashable: the base class reports it
                    continue
                if duplicate:
                    raise yaml.constructor.ConstructorError(
                        "while constructing a mapping", node.start_mark,
                        f"found duplicate key {_describe(key)}", key_node.start_mark)
        return super().construct_mapping(node, deep=deep)


#: the text each core-schema tag reads, whether the tag is implicit or written (``!!bool yes`` is no boolean of
#: YAML 1.2, ``!!int '١'`` no integer in ASCII digits, ``!!float '1_0'`` no decimal)
_CORE_TEXT = {tag: (re.compile(pattern), what) for (tag, _, pattern), what in
              zip(_CORE_RESOLVERS, ("a boolean (true or false)", "an integer (ASCII digits, or 0o/0x)",
                                    "a number (plain decimal, .inf or .nan)"))}


def _core_text(loader, node):
    """The scalar text of `node`, refused unless the YAML 1.2 core schema reads it as the node's type."""
    text = loader.construct_scalar(node)
    pattern, what = _CORE_TEXT[node.tag]
    if pattern.fullmatch(text) is None:
        shown = "!!" + node.tag[len(_YAML_PREFIX):]
        raise yaml.constructor.ConstructorError(
            None, None, f"{shown} {_describe(text)} is not {what} of the YAML 1.2 core schema", node.start_mark)
    return text


def _construct_bool(loader, node):
    return _core_text(loader, node).lower() == "true"


def _construct_int(loader, node):
    text = _core_text(loader, node)
    if len(text) > DIGITS_LIMIT:
        raise yaml.constructor.ConstructorError(
            None, None, f"an integer of {len(text)} digits is out of range (at most {DIGITS_LIMIT})",
            node.start_mark)
    if text.startswith("0o"):
        return int(text[2:], 8)
    if text.startswith("0x"):
        return int(text[2:], 16)
    return int(text)


def _construct_float(loader, node):
    text = _core_text(loader, node)
    lowered = text.lower()
    if lowered.endswith(".inf"):
        return -math.inf if text.startswith("-") else math.inf
    if lowered == ".nan":
        return math.nan
    try:
        return exact_float(text)
    except Underflow as error:
        raise yaml.constructor.ConstructorError(None, None, str(error), node.start_mark) from None


_Loader.yaml_implicit_resolvers = {
    first: [(tag, pattern) for tag, pattern in resolvers
            if tag not in (_BOOL_TAG, _INT_TAG, _FLOAT_TAG, "tag:yaml.org,2002:timestamp",
                           "tag:yaml.org,2002:value")]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
_Loader.add_constructor(_BOOL_TAG, _construct_bool)
_Loader.add_constructor(_INT_TAG, _construct_int)
_Loader.add_constructor(_FLOAT_TAG, _construct_float)


class _Dumper(yaml.SafeDumper):
    """``yaml.SafeDumper`` that quotes every string YAML 1.1 *or* 1.2 would read as non-string, and writes a
    string holding one of Unicode's line breaks other than ``\\n`` (NEL U+0085, U+2028, U+2029) double-quoted,
    escaped: in a plain or single-quoted scalar PyYAML writes them raw, and a reader folds them into spaces."""

    def represent_str(self, data):
        if any(character in data for character in _OTHER_LINE_BREAKS):
            return self.represent_scalar("tag:yaml.org,2002:str", data, style='"')
        return super().represent_str(data)


_OTHER_LINE_BREAKS = "\x85\u2028\u2029"
_Dumper.add_representer(str, _Dumper.represent_str)


for _tag, _first, _pattern in _CORE_RESOLVERS:
    _Loader.add_implicit_resolver(_tag, re.compile(f"^(?:{_pattern})$"), list(_first))
    _Dumper.add_implicit_resolver(_tag, re.compile(f"^(?:{_pattern})$"), list(_first))


def _parse_yaml(text, source):
    try:
        return yaml.load(text, Loader=_Loader)  # a SafeLoader: constructs plain data only
    except yaml.MarkedYAMLError as error:
        problem = ": ".join(part for part in (error.context, error.problem) if part)
        mark = error.problem_mark or error.context_mark
        if mark is not None:
            problem += f" at line {mark.line + 1}, column {mark.column + 1}"
        raise MechanismError(_one_line(f"{source}: cannot parse YAML: {problem}")) from None
    except (yaml.YAMLError, ValueError, TypeError, OverflowError, RecursionError) as error:
        raise MechanismError(_one_line(f"{source}: cannot parse YAML: {_reason(error)}")) from None


class DuplicateKey(Exception):
    """A JSON object with the same key twice (raised by :data:`JSON_DECODER`)."""


class TooManyDigits(Exception):
    """A JSON integer of more than :data:`DIGITS_LIMIT` digits (raised by :data:`JSON_DECODER`)."""


def _json_integer(text):
    if len(text.lstrip("-")) > DIGITS_LIMIT:
        raise TooManyDigits(len(text.lstrip("-")))
    return int(text)


def _json_object(pairs):
    data = {}
    for key, value in pairs:
        if key in data:
            raise DuplicateKey(key)
        data[key] = value
    return data


#: decodes JSON refusing duplicate keys (:class:`DuplicateKey`), integers of more than
#: :data:`DIGITS_LIMIT` digits (:class:`TooManyDigits`) and nonzero numbers below the smallest float
#: (:class:`mechanisms._numerals.Underflow`, a ValueError); ``raw_decode`` reads one value of a longer text
JSON_DECODER = json.JSONDecoder(object_pairs_hook=_json_object, parse_int=_json_integer, parse_float=exact_float)


def _nesting_depth_exceeds(data, limit):
    """Whether lists and mappings nest deeper than `limit` levels in `data` (iteratively)."""
    pending = [(data, 1)]
    while pending:
        value, depth = pending.pop()
        if isinstance(value, (list, dict)):
            if depth > limit:
                return True
            pending.extend((item, depth + 1) for item in (value.values() if isinstance(value, dict) else value))
    return False


def parse_json(text, source):
    """Parse JSON text into plain data, refusing what no mechanism file or displacement needs.

    Duplicate keys, integers of more than :data:`DIGITS_LIMIT` digits and
    nesting deeper than :data:`DEPTH_LIMIT` levels are refused. ``NaN`` and
    ``Infinity`` are parsed (the fields that receive them refuse them, naming
    the field).

    Parameters
    ----------
    text : str
    source : str
        Where the text came from; it starts every error message.

    Returns
    -------
    object
        Dicts, lists, strings, numbers, booleans and None.

    Raises
    ------
    MechanismError
        ``{source}: cannot parse JSON: {reason}``, one line.
    """
    data = _parse_json(text, source)
    if _nesting_depth_exceeds(data, DEPTH_LIMIT):
        raise MechanismError(f"{source}: cannot parse JSON: the document nests deeper than {DEPTH_LIMIT} levels")
    return data


def _parse_json(text, source):
    try:
        return JSON_DECODER.decode(text)
    except TooManyDigits as error:
        raise MechanismError(f"{source}: cannot parse JSON: an integer of {error.args[0]} digits is out of "
                             f"range (at most {DIGITS_LIMIT})") from None
    except RecursionError:
        raise MechanismError(f"{source}: cannot parse JSON: the document nests deeper than {DEPTH_LIMIT} "
                             f"levels") from None
    except json.JSONDecodeError as error:
        raise MechanismError(_one_line(f"{source}: cannot parse JSON: {error.msg} at line "
                                       f"{error.lineno}, column {error.colno}")) from None
    except DuplicateKey as error:
        raise MechanismError(f"{source}: cannot parse JSON: found duplicate key "
                             f"{_describe(error.args[0])}") from None
    except (ValueError, RecursionError) as error:
        raise MechanismError(_one_line(f"{source}: cannot parse JSON: {_reason(error)}")) from None


#: a JSON array with no array or object inside it (strings matched whole)
_FLAT_JSON_ARRAY = re.compile(r'\[(?:[^\[\]{}"]|"(?:[^"\\]|\\.)*")*\]')


def _json_text(data):
    """Indented JSON with arrays of numbers or strings kept on one line."""
    text = json.dumps(data, indent=2, ensure_ascii=False, allow_nan=False)
    # json.dumps escapes newlines inside strings, so raw newlines are layout only
    text = _FLAT_JSON_ARRAY.sub(lambda match: re.sub(r"\[\n\s*", "[", re.sub(
        r",\n\s*", ", ", re.sub(r"\n\s*\]", "]", match.group()))), text)
    return text + "\n"


def _reason(error):
    text = str(error).strip()
    return text if text else type(error).__name__
