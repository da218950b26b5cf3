"""Batch files of configurations for ``closedchain classify --batch FILE``, and the ``--survey`` cache file.

Configurations are *joint displacements from the mechanism's home*, exactly
as ``--at`` takes them (:mod:`classify.cli._configurations`); a batch is read
into a displacement matrix, shape=[n, k], one column per tangent coordinate
in the order of ``mechanism.coordinate_names`` (:mod:`classify.cli._names`).

Batch files (the format from the suffix):

=========  ===============================================================
``.json``  a list of objects ``{joint: value | [values]}``, one per row
``.jsonl`` one such object per line (blank lines are skipped)
``.csv``   a header of coordinate names (``A``, ``S1[x]``, …; an R or P
           joint's name is its coordinate's), then one row of numbers per
           configuration (blank lines are skipped)
``.npy``   an array [n, k] of displacements in coordinate order
=========  ===============================================================

Coordinates a row does not give keep the value of the configuration the
command starts from (``--configuration``, else the home). Rows are numbered
from 1 (the CSV header is not a row). A file larger than
:data:`BATCH_FILE_LIMIT` bytes or with more than :data:`BATCH_ROW_LIMIT` rows
is refused, and so is every malformed row: bad JSON or CSV, a row that is not
an object, an unknown joint or coordinate, a value of the wrong shape, a
non-finite number or one beyond 10¹² in absolute value. Each refusal is one
line naming the file, the row (and, for text files, the line) and the field.
Nothing from a file is ever evaluated.

This module imports NumPy: the commands import it when they run, not at
start-up.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import stat

import numpy as np

from mechanisms import MechanismError
from mechanisms._text import JSON_DECODER, DuplicateKey, TooManyDigits, _os_reason
from mechanisms.io import DIGITS_LIMIT, check_displacement, read_text_file
from mechanisms.joints import COORDINATE_LIMIT

from ..text import printable
from ._common import InputError
from ._names import coordinate_column, coordinate_columns, coordinate_number, known, shown

__all__ = ["BATCH_SUFFIXES", "BATCH_ROW_LIMIT", "BATCH_FILE_LIMIT", "read_batch", "model_survey"]

BATCH_SUFFIXES = (".json", ".jsonl", ".csv", ".npy")
#: most configurations in one batch file
BATCH_ROW_LIMIT = 1_000_000
#: largest batch file read, in bytes (256 MiB)
BATCH_FILE_LIMIT = 2 ** 28


# ------------------------------------------------------------------------------------------------ reading

def read_batch(path, mechanism, base):
    """The displacement matrix of a batch file.

    Parameters
    ----------
    path : str
        A ``.json``, ``.jsonl``, ``.csv`` or ``.npy`` file (see the module notes).
    mechanism : Mechanism
    base : ndarray, shape=[k]
        The displacements of the starting configuration: the coordinates a row does not give.

    Returns
    -------
    matrix : ndarray, shape=[n, k]
        n ≥ 1 rows, every entry finite and at most 10¹² in absolute value.

    Raises
    ------
    InputError
        ``--batch: FILE: row R: ...`` (one line) for a malformed file or row.
    """
    suffix = os.path.splitext(path)[1].lower()
    where = f"--batch: {printable(path)}"
    if suffix not in BATCH_SUFFIXES:
        raise InputError(f"{where}: unknown batch format {shown(suffix or 'no extension')} "
                         f"(expected {', '.join(BATCH_SUFFIXES)})")
    if suffix == ".npy":
        matrix = _read_npy(path, mechanism, where)
    else:
        try:
            text = read_text_file(path, limit=BATCH_FILE_LIMIT)
        except MechanismError as error:
            raise InputError(f"--batch: {error}") from None
        reader = {".json": _read_json, ".jsonl": _read_json_lines, ".csv": _read_csv}[suffix]
        matrix = reader(text, mechanism, np.asarray(base, dtype=float), where)
    if not len(matrix):
        raise InputError(f"{where}: no configurations (the file has no rows)")
    return matrix


_WHITESPACE = " \t\n\r"


def _skip(text, index):
    while index < len(text) and text[index] in _WHITESPACE:
        index += 1
    return index


def _position(text, index):
    """'line L, column C' of a character index."""
    line = text.count("\n", 0, index) + 1
    column = index - text.rfind("\n", 0, index)
    return f"line {line}, column {column}"


def _decode(text, index, where):
    """(value, end) of the JSON value starting at `index`; InputError naming `where` and the position."""
    try:
        return JSON_DECODER.raw_decode(text, index)
    except json.JSONDecodeError as error:
        raise InputError(f"{where}: cannot parse JSON: {error.msg} at {_position(text, error.pos)}") from None
    except DuplicateKey as error:
        raise InputError(f"{where}: cannot parse JSON: duplicate key {shown(error.args[0])}") from None
    except TooManyDigits as error:
        raise InputError(f"{where}: cannot parse JSON: an integer of {error.args[0]} digits "
                         f"(at most {DIGITS_LIMIT})") from None
    except (RecursionError, ValueError) as error:
        reason = "it nests too deeply" if isinstance(error, RecursionError) else printable(str(error))
        raise InputError(f"{where}: cannot parse JSON: {reason}") from None


class _Rows:
    """Rows of a batch as they are read: checked against the joints, then stacked."""

    def __init__(self, mechanism, base, where):
        self.joints = {joint.name: joint for joint in mechanism.joints}
        self.columns = coordinate_columns(mechanism)
        self.base = base
        self.where = where
        self.rows = []

    def count_check(self, row):
        if row > BATCH_ROW_LIMIT:
            raise InputError(f"{self.where}: row {row}: too many rows (at most {BATCH_ROW_LIMIT})")

    def add_object(self, value, where):
        """A JSON row: an object mapping joint names to displacements, as ``--at`` takes."""
        if not isinstance(value, dict):
            kind = {list: "a list", str: "a string", bool: "a boolean", type(None): "null"}.get(
                type(value), "a number")
            raise InputError(f"{where}: expected a JSON object mapping joint names to displacements, got {kind}")
        vector = self.base.copy()
        for name, item in value.items():
            joint = self.joints.get(name)
            if joint is None:
                raise InputError(f"{where}: joint {shown(name)}: unknown joint (known: {known(self.joints)})")
            columns = self.columns[name]
            if type(item) is float and len(columns) == 1 and abs(item) <= COORDINATE_LIMIT:  # the common case
                vector[columns[0]] = item
                continue
            try:
                checked = check_displacement(item, joint, f"{where}: joint {shown(name)}")
            except MechanismError as error:
                raise InputError(str(error)) from None
            vector[list(columns)] = np.atleast_1d(np.asarray(checked, dtype=float))
        self.rows.append(vector)

    def matrix(self):
        return np.array(self.rows, dtype=float).reshape(len(self.rows), len(self.base))


def _read_json(text, mechanism, base, where):
    """A JSON list of row objects, parsed row by row so that an error names its row."""
    rows = _Rows(mechanism, base, where)
    index = _skip(text, 0)
    if index >= len(text) or text[index] != "[":
        found = "nothing" if index >= len(text) else shown(text[index])
        raise InputError(f"{where}: expected a JSON list of objects (one per configuration), found {found} at "
                         f"{_position(text, index)}")
    index = _skip(text, index + 1)
    if index < len(text) and text[index] == "]":
        index += 1
    else:
        while True:
            row = len(rows.rows) + 1
            rows.count_check(row)
            value, index = _decode(text, index, f"{where}: row {row}")
            rows.add_object(value, f"{where}: row {row}")
            index = _skip(text, index)
            if index < len(text) and text[index] == ",":
                index = _skip(text, index + 1)
                continue
            if index < len(text) and text[index] == "]":
                index += 1
                break
            raise InputError(f"{where}: row {row}: cannot parse JSON: expected ',' or ']' after the row at "
                             f"{_position(text, index)}")
    index = _skip(text, index)
    if index < len(text):
        raise InputError(f"{where}: cannot parse JSON: extra data after the list at {_position(text, index)}")
    return rows.matrix()


def _read_json_lines(text, mechanism, base, where):
    """One row object per line."""
    rows = _Rows(mechanism, base, where)
    for number, line in enumerate(text.split("\n"), start=1):
        line = line.rstrip("\r")
        if not line.strip():
            continue
        row = len(rows.rows) + 1
        rows.count_check(row)
        here = f"{where}: row {row} (line {number})"
        start = _skip(line, 0)
        value, end = _decode(line, start, here)
        if _skip(line, end) < len(line):
            raise InputError(f"{here}: cannot parse JSON: extra data after the object at column "
                             f"{_skip(line, end) + 1} (one object per line)")
        rows.add_object(value, here)
    return rows.matrix()


def _read_csv(text, mechanism, base, where):
    """A header of coordinate names, then one row of numbers per configuration."""
    reader = csv.reader(io.StringIO(text, newline=""))
    try:
        header = next((record for record in reader if any(cell.strip() for cell in record)), None)
        if header is None:
            raise InputError(f"{where}: no header (expected a first line of coordinate names)")
        names = [cell.strip() for cell in header]
        columns = []
        for position, name in enumerate(names, start=1):
            column = coordinate_column(mechanism, name, f"{where}: header (line {reader.line_num}), column {position}")
            if column in columns:
                raise InputError(f"{where}: header (line {reader.line_num}), column {position}: coordinate "
                                 f"{shown(name)} is given twice")
            columns.append(column)
        rows = []
        for record in reader:
            if not any(cell.strip() for cell in record):
                continue
            row = len(rows) + 1
            here = f"{where}: row {row} (line {reader.line_num})"
            if row > BATCH_ROW_LIMIT:
                raise InputError(f"{here}: too many rows (at most {BATCH_ROW_LIMIT})")
            if len(record) != len(names):
                raise InputError(f"{here}: expected {len(names)} values (one per header column), got {len(record)}")
            vector = base.copy()
            for name, column, cell in zip(names, columns, record):
                vector[column] = coordinate_number(cell, f"{here}: column {shown(name)}", empty="an empty cell")
            rows.append(vector)
    except csv.Error as error:
        raise InputError(f"{where}: line {reader.line_num}: cannot parse CSV: {printable(str(error))}") from None
    return np.array(rows, dtype=float).reshape(len(rows), len(base))


def _read_npy(path, mechanism, where):
    """An array [n, k] of displacements in coordinate order; its header is checked before it is read."""
    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except (OSError, ValueError) as error:
        raise InputError(f"{where}: cannot read the file: {printable(_os_reason(error))}") from None
    try:
        status = os.fstat(descriptor)
    finally:
        os.close(descriptor)
    if not stat.S_ISREG(status.st_mode):
        raise InputError(f"{where}: cannot read the file: not a regular file")
    if status.st_size > BATCH_FILE_LIMIT:
        raise InputError(f"{where}: the file is too large: {status.st_size} bytes (the limit is "
                         f"{BATCH_FILE_LIMIT} bytes)")
    try:
        mapped = np.load(path, mmap_mode="r", allow_pickle=False)
    except (OSError, ValueError, EOFError) as error:
        raise InputError(f"{where}: not a NumPy .npy array file of numbers ({printable(str(error)[:120])})") \
            from None
    names = mechanism.coordinate_names
    if not isinstance(mapped, np.ndarray) or mapped.dtype.names is not None or mapped.dtype.kind not in "fiu":
        kind = getattr(getattr(mapped, "dtype", None), "str", type(mapped).__name__)
        raise InputError(f"{where}: expected an array of real numbers, got dtype {shown(kind)}")
    if mapped.dtype.kind == "f" and mapped.dtype.itemsize > 8:  # its values would be rounded, tiny ones to 0
        raise InputError(f"{where}: expected float64 or a narrower type, got dtype {shown(mapped.dtype.str)} "
                         f"(its values would be rounded: convert them yourself)")
    if mapped.ndim != 2 or mapped.shape[1] != len(names):
        raise InputError(f"{where}: field 'shape': expected an array [n, {len(names)}] (columns "
                         f"{printable(', '.join(names))}), got shape {list(mapped.shape)}")
    if mapped.shape[0] > BATCH_ROW_LIMIT:
        raise InputError(f"{where}: row {BATCH_ROW_LIMIT + 1}: too many rows (at most {BATCH_ROW_LIMIT})")
    matrix = np.array(mapped, dtype=float)
    bad = ~np.isfinite(matrix) | (np.abs(np.where(np.isfinite(matrix), matrix, 0.0)) > COORDINATE_LIMIT)
    if bad.any():
        row, column = (int(index) for index in np.argwhere(bad)[0])
        value = matrix[row, column]
        problem = (f"expected a finite number, got {value}" if not math.isfinite(value) else
                   f"{value:g} is out of range (displacements are at most {COORDINATE_LIMIT:g} in absolute value)")
        raise InputError(f"{where}: row {row + 1}: column {column + 1} ({printable(names[column])}): {problem}")
    return matrix


# ------------------------------------------------------------------------------------------------ survey cache

def model_survey(path, model):
    """The survey of M the classification uses: the model's own (:func:`classify.survey.survey_of`), read from
    the ``--survey`` cache file when it exists and was made for this model, else computed and written there
    (:func:`classify.survey_cache.cached_survey`).

    Raises
    ------
    InputError
        ``--survey: ...`` for a file that cannot be read or written, or was made for another mechanism.
    """
    from ..survey import survey_of
    from ..survey_cache import SurveyCacheError, cached_survey

    if path is None:
        return survey_of(model)
    if not path:
        raise InputError("--survey: an empty path")
    try:
        return cached_survey(path, model)[0]
    except SurveyCacheError as error:
        raise InputError(f"--survey: {printable(str(error))}") from None
