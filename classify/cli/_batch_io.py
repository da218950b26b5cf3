"""Batches of configurations for the command line: reading them, grid specifications, writing the results.

``closedchain classify --batch FILE`` and ``closedchain map --grid`` take
configurations as *joint displacements from the mechanism's home*, exactly
as ``--at`` does (:func:`mechanisms.from_displacements`): a number for R and
P joints, a pair for U and C, a rotation vector for S. Inside, a batch is a
displacement matrix, shape=[n, k], one column per tangent coordinate in the
order of ``mechanism.coordinate_names`` (``A``, ``S1[x]``, ``S1[y]``,
``S1[z]``, ``U1[1]``, …; an S joint's three columns are its rotation vector).

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

Grid specifications (``--grid NAME=a:b:n``): NAME a coordinate name, a and b
finite numbers, n an integer ≥ 1 (``numpy.linspace(a, b, n)``; n = 1 needs
a = b); at most :data:`GRID_POINT_LIMIT` points in all.

Outputs (the format from the suffix of ``--out``): JSON lines (``.jsonl``),
one JSON document (``.json``), CSV with nested fields flattened
(``margins_actuator_smallest_kept``) and lists numbered
(``eigenvalues[0]``) (``.csv``), or NumPy arrays (``.npz``).

This module imports NumPy and the kinematics: the commands import it when
they run, not at start-up.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import stat
from dataclasses import dataclass

import numpy as np

from manifold import rotation_exp, rotation_log
from mechanisms import MechanismError
from mechanisms.io import DIGITS_LIMIT, check_displacement, read_text_file, write_text_file
from mechanisms.joints import COORDINATE_LIMIT, joint_coordinate_names
from mechanisms.kinematics import closes, constraint, constraint_jacobian, kinematics_of

from ..text import printable
from ._common import InputError

__all__ = [
    "BATCH_SUFFIXES", "OUTPUT_SUFFIXES", "BATCH_ROW_LIMIT", "BATCH_FILE_LIMIT", "GRID_POINT_LIMIT",
    "PROJECTION_TOLERANCE", "Grid", "coordinate_columns", "displacement_vector", "points_of", "displacements_of",
    "joint_displacements", "read_batch", "off_manifold_row", "project_many", "parse_grid", "output_format",
    "flat_row", "csv_text", "json_text", "write_npz", "write_rows", "result_table", "kind_counts", "summary_line",
    "model_survey",
]

BATCH_SUFFIXES = (".json", ".jsonl", ".csv", ".npy")
OUTPUT_SUFFIXES = (".jsonl", ".json", ".csv", ".npz")
#: most configurations in one batch file
BATCH_ROW_LIMIT = 1_000_000
#: largest batch file read, in bytes (256 MiB)
BATCH_FILE_LIMIT = 2 ** 28
#: most points of a --grid (the product of the counts)
GRID_POINT_LIMIT = 1_000_000
#: ‖Φ‖ a projected configuration reaches (as :func:`manifold.project`)
PROJECTION_TOLERANCE = 1e-12


# ------------------------------------------------------------------------------------------------ coordinates

def coordinate_columns(mechanism):
    """Joint name → the indices of its tangent coordinates (columns of a displacement matrix), in order.

    Parameters
    ----------
    mechanism : Mechanism

    Returns
    -------
    dict of str to tuple of int
    """
    columns, start = {}, 0
    for joint in mechanism.joints:
        count = len(joint_coordinate_names(joint))
        columns[joint.name] = tuple(range(start, start + count))
        start += count
    return columns


def displacement_vector(mechanism, displacements):
    """The displacement row, shape=[k], of a mapping joint name → displacement (checked before).

    Joints not named are at home (0).
    """
    vector = np.zeros(len(mechanism.coordinate_names))
    columns = coordinate_columns(mechanism)
    for name, value in displacements.items():
        vector[list(columns[name])] = np.atleast_1d(np.asarray(value, dtype=float))
    return vector


def points_of(mechanism, matrix):
    """The configurations ``home ⊕ displacements`` of a displacement matrix.

    Row by row what :func:`mechanisms.from_displacements` builds: each joint's
    entries set to its values, an S joint's rotation matrix the exponential of
    its rotation vector.

    Parameters
    ----------
    mechanism : Mechanism
    matrix : ndarray, shape=[n, k]

    Returns
    -------
    points : ndarray, shape=[n, point_size]
    """
    compiled = kinematics_of(mechanism)
    matrix = np.asarray(matrix, dtype=float).reshape(-1, len(mechanism.coordinate_names))
    points = np.array(np.broadcast_to(compiled.ambient.neutral(), (len(matrix), compiled.ambient.point_size)))
    columns = coordinate_columns(mechanism)
    for joint in mechanism.joints:
        parts, indices = compiled.point_parts[joint.name], columns[joint.name]
        if joint.type == "S":
            points[:, parts[0]] = rotation_exp(matrix[:, list(indices)]).reshape(len(matrix), 9)
        else:
            for part, index in zip(parts, indices):
                points[:, part] = matrix[:, index:index + 1]
    return points


def displacements_of(mechanism, points):
    """The displacement matrix of configurations (the inverse of :func:`points_of`).

    Row by row :func:`mechanisms.to_displacements`: joint values as they are,
    an S joint's rotation vector the principal logarithm of its rotation.

    Parameters
    ----------
    mechanism : Mechanism
    points : ndarray, shape=[n, point_size]

    Returns
    -------
    matrix : ndarray, shape=[n, k]
    """
    compiled = kinematics_of(mechanism)
    points = np.asarray(points, dtype=float).reshape(-1, compiled.ambient.point_size)
    matrix = np.zeros((len(points), len(mechanism.coordinate_names)))
    columns = coordinate_columns(mechanism)
    for joint in mechanism.joints:
        parts, indices = compiled.point_parts[joint.name], columns[joint.name]
        if joint.type == "S":
            matrix[:, list(indices)] = rotation_log(points[:, parts[0]].reshape(-1, 3, 3))
        else:
            for part, index in zip(parts, indices):
                matrix[:, index] = points[:, part][:, 0]
    return matrix


def joint_displacements(mechanism, matrix):
    """The mappings joint name → displacement (a float for R and P, a list for S, U and C) of displacement rows.

    Parameters
    ----------
    mechanism : Mechanism
    matrix : ndarray, shape=[n, k] or [k]

    Returns
    -------
    list of dict (n of them), or one dict for a single row
    """
    matrix = np.asarray(matrix, dtype=float)
    layout = [(name, indices[0] if mechanism.joint(name).type in ("R", "P") else list(indices))
              for name, indices in coordinate_columns(mechanism).items()]
    rows = [{name: (values[where] if isinstance(where, int) else [values[index] for index in where])
             for name, where in layout} for values in np.atleast_2d(matrix).tolist()]
    return rows[0] if matrix.ndim == 1 else rows


def _coordinate_index(mechanism):
    """Coordinate name → column, and joint name → column for joints of one coordinate (R, P)."""
    index = {name: column for column, name in enumerate(mechanism.coordinate_names)}
    for joint, indices in coordinate_columns(mechanism).items():
        if len(indices) == 1:
            index.setdefault(joint, indices[0])
    return index


def _coordinate(mechanism, name, where):
    """The column of a coordinate named in a file or an option; InputError for an unknown name."""
    index = _coordinate_index(mechanism)
    if name in index:
        return index[name]
    joints = {joint.name: joint for joint in mechanism.joints}
    if name in joints:
        names = joint_coordinate_names(joints[name])
        raise InputError(f"{where}: joint {_shown(name)} ({joints[name].type}) has {len(names)} coordinates: name "
                         f"one of {_known(names)}")
    raise InputError(f"{where}: unknown coordinate {_shown(name)} (known: {_known(mechanism.coordinate_names)})")


def _shown(text, limit=40):
    """A name or a cell from a file, quoted, escaped and cut for a one-line message."""
    text = str(text)
    return printable(repr(text if len(text) <= limit else text[:limit - 3] + "..."))


def _known(names, limit=20):
    """Names for a message: the first `limit`, then how many in all."""
    names = list(names)
    shown = ", ".join(names[:limit]) + (f", … ({len(names)} in all)" if len(names) > limit else "")
    return printable(shown)


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
        raise InputError(f"{where}: unknown batch format {_shown(suffix or 'no extension')} "
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


class _DuplicateKey(Exception):
    pass


class _LongInteger(Exception):
    pass


def _unique_object(pairs):
    result = {}
    for key, value in pairs:
        if key in result:
            raise _DuplicateKey(key)
        result[key] = value
    return result


def _bounded_integer(text):
    if len(text.lstrip("-")) > DIGITS_LIMIT:
        raise _LongInteger(len(text.lstrip("-")))
    return int(text)


#: decodes one JSON value: duplicate keys and integers of more than DIGITS_LIMIT digits refused
_DECODER = json.JSONDecoder(object_pairs_hook=_unique_object, parse_int=_bounded_integer)
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
        return _DECODER.raw_decode(text, index)
    except json.JSONDecodeError as error:
        raise InputError(f"{where}: cannot parse JSON: {error.msg} at {_position(text, error.pos)}") from None
    except _DuplicateKey as error:
        raise InputError(f"{where}: cannot parse JSON: duplicate key {_shown(error.args[0])}") from None
    except _LongInteger as error:
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
                raise InputError(f"{where}: joint {_shown(name)}: unknown joint (known: {_known(self.joints)})")
            columns = self.columns[name]
            if type(item) is float and len(columns) == 1 and abs(item) <= COORDINATE_LIMIT:  # the common case
                vector[columns[0]] = item
                continue
            try:
                checked = check_displacement(item, joint, f"{where}: joint {_shown(name)}")
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
        found = "nothing" if index >= len(text) else _shown(text[index])
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


def _number(cell, where):
    """A finite number within the coordinate limit from a CSV cell."""
    text = cell.strip()
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"{where}: expected a number, got {_shown(cell) if text else 'an empty cell'}") from None
    if not math.isfinite(value):
        raise InputError(f"{where}: expected a finite number, got {_shown(text)}")
    if abs(value) > COORDINATE_LIMIT:
        raise InputError(f"{where}: {value:g} is out of range (displacements are at most {COORDINATE_LIMIT:g} in "
                         f"absolute value)")
    return value


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
            column = _coordinate(mechanism, name, f"{where}: header (line {reader.line_num}), column {position}")
            if column in columns:
                raise InputError(f"{where}: header (line {reader.line_num}), column {position}: coordinate "
                                 f"{_shown(name)} is given twice")
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
                vector[column] = _number(cell, f"{here}: column {_shown(name)}")
            rows.append(vector)
    except csv.Error as error:
        raise InputError(f"{where}: line {reader.line_num}: cannot parse CSV: {printable(str(error))}") from None
    return np.array(rows, dtype=float).reshape(len(rows), len(base))


def _read_npy(path, mechanism, where):
    """An array [n, k] of displacements in coordinate order; its header is checked before it is read."""
    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except (OSError, ValueError) as error:
        raise InputError(f"{where}: cannot read the file: {printable(getattr(error, 'strerror', None) or error)}") \
            from None
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
        raise InputError(f"{where}: expected an array of real numbers, got dtype {_shown(kind)}")
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


# ------------------------------------------------------------------------------------------------ points on M

def off_manifold_row(mechanism, points, tolerance):
    """The index of the first configuration that does not close the loops (None if all close), and its ‖Φ‖."""
    closed = np.asarray(closes(mechanism, points, tolerance), dtype=bool).reshape(-1)
    if closed.all():
        return None, 0.0
    index = int(np.flatnonzero(~closed)[0])
    return index, float(np.linalg.norm(constraint(mechanism, points[index])))


def project_many(mechanism, points, closed_tolerance, max_iterations=60):
    """Gauss–Newton projection of a stack of configurations onto M, as :func:`manifold.project` one at a time.

    The configurations that already close (‖Φ‖ ≤ `closed_tolerance`, no
    half-turn) are kept as they are (as :func:`mechanisms.configuration`
    does); the others iterate ``p ← p ⊕ (−s·(DΦ(p)·s)⁺ Φ(p))`` until
    ‖Φ‖ ≤ :data:`PROJECTION_TOLERANCE`, all at once.

    Parameters
    ----------
    mechanism : Mechanism
    points : ndarray, shape=[n, point_size]
    closed_tolerance : float
        ``mechanisms.CLOSURE_TOLERANCE``.
    max_iterations : int

    Returns
    -------
    projected : ndarray, shape=[n, point_size]
    reached : ndarray of bool, shape=[n]
        Whether the projection converged to a configuration that closes every loop.
    distance : ndarray, shape=[n]
        Norm of the chart step from each point to its projection (0 where it closed; NaN where not reached).
    """
    ambient = kinematics_of(mechanism).ambient
    scales = ambient.tangent_scales
    requested = np.asarray(points, dtype=float).reshape(-1, ambient.point_size)
    projected = requested.copy()
    moving = np.flatnonzero(~np.asarray(closes(mechanism, requested, closed_tolerance), dtype=bool).reshape(-1))
    values = constraint(mechanism, projected[moving])
    active = moving.copy()
    for _ in range(max_iterations):
        norms = np.linalg.norm(values, axis=-1)
        keep = ~(norms <= PROJECTION_TOLERANCE) & np.isfinite(norms)
        active, values = active[keep], values[keep]
        if not len(active):
            break
        jacobian = constraint_jacobian(mechanism, projected[active]) * scales
        steps = -scales * np.einsum("akc,ac->ak", np.linalg.pinv(jacobian, rcond=1e-12), values)
        projected[active] = ambient.retract(projected[active], steps)
        values = constraint(mechanism, projected[active])
    reached = np.ones(len(projected), dtype=bool)
    distance = np.zeros(len(projected))
    if len(moving):
        norms = np.linalg.norm(constraint(mechanism, projected[moving]), axis=-1)
        reached[moving] = (norms <= PROJECTION_TOLERANCE) & np.asarray(
            closes(mechanism, projected[moving], np.inf), dtype=bool).reshape(-1)
        distance[moving] = np.linalg.norm(ambient.inverse_retract(requested[moving], projected[moving]), axis=-1)
    distance[~reached] = np.nan
    return projected, reached, distance


# ------------------------------------------------------------------------------------------------ grids

@dataclass(frozen=True)
class Grid:
    """A rectangular grid of coordinate values (``--grid NAME=a:b:n ...``).

    Attributes
    ----------
    names : tuple of str
        The coordinate names, one per grid axis.
    columns : tuple of int
        Their columns in a displacement matrix (indices into ``mechanism.coordinate_names``).
    starts, stops : tuple of float
    counts : tuple of int
    """

    names: tuple
    columns: tuple
    starts: tuple
    stops: tuple
    counts: tuple

    @property
    def shape(self):
        return tuple(self.counts)

    @property
    def size(self):
        return math.prod(self.counts)

    def axes(self):
        """The values along each axis, a list of arrays of shape=[n_i]."""
        return [np.linspace(start, stop, count) for start, stop, count in zip(self.starts, self.stops, self.counts)]

    def values(self):
        """The coordinates of every grid point, shape=[*shape, d] (C order: the last axis varies fastest)."""
        return np.stack(np.meshgrid(*self.axes(), indexing="ij"), axis=-1)

    def to_dict(self):
        """``{name: [a, b, n]}``."""
        return {name: [start, stop, count]
                for name, start, stop, count in zip(self.names, self.starts, self.stops, self.counts)}


def _grid_number(text, what, where):
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"{where}: {what}: expected a number, got {_shown(text) if text.strip() else 'nothing'}") \
            from None
    if not math.isfinite(value):
        raise InputError(f"{where}: {what}: expected a finite number, got {_shown(text)}")
    if abs(value) > COORDINATE_LIMIT:
        raise InputError(f"{where}: {what}: {value:g} is out of range (at most {COORDINATE_LIMIT:g} in absolute "
                         f"value)")
    return value


def parse_grid(texts, mechanism):
    """The :class:`Grid` of ``--grid`` texts ``NAME=a:b:n``.

    Raises
    ------
    InputError
        ``--grid 'TEXT': ...`` (one line): no ``=``, not three fields, a
        non-finite bound, a count that is not an integer ≥ 1 (or 1 with
        a ≠ b), an unknown or repeated coordinate, or more than
        :data:`GRID_POINT_LIMIT` points in all.
    """
    names, columns, starts, stops, counts = [], [], [], [], []
    size = 1
    for text in texts:
        where = f"--grid {_shown(text, 60)}"
        name, equals, spec = text.rpartition("=")
        if not equals or not name.strip():
            raise InputError(f"{where}: expected NAME=a:b:n (a coordinate name, the first and last values and "
                             f"the number of points)")
        name = name.strip()
        fields = spec.split(":")
        if len(fields) != 3:
            raise InputError(f"{where}: expected NAME=a:b:n with three fields after '=', got {len(fields)}")
        start = _grid_number(fields[0], "a", where)
        stop = _grid_number(fields[1], "b", where)
        count_text = fields[2].strip()
        if not count_text.isdecimal() or len(count_text) > 12 or int(count_text) < 1:
            raise InputError(f"{where}: n: expected an integer ≥ 1, got {_shown(fields[2]) if count_text else 'nothing'}")
        count = int(count_text)
        if count == 1 and start != stop:
            raise InputError(f"{where}: n = 1 gives one point: a and b must be equal (got {start:g} and {stop:g})")
        column = _coordinate(mechanism, name, where)
        if column in columns:
            raise InputError(f"{where}: coordinate {_shown(mechanism.coordinate_names[column])} is on the grid twice")
        size *= count
        if size > GRID_POINT_LIMIT:
            raise InputError(f"{where}: the grid has more than {GRID_POINT_LIMIT} points (the product of the counts)")
        names.append(mechanism.coordinate_names[column])
        columns.append(column)
        starts.append(start)
        stops.append(stop)
        counts.append(count)
    if not names:
        raise InputError("--grid: expected at least one NAME=a:b:n")
    return Grid(tuple(names), tuple(columns), tuple(starts), tuple(stops), tuple(counts))


# ------------------------------------------------------------------------------------------------ writing

def output_format(path, option="--out"):
    """The output format of a file name: ``jsonl``, ``json``, ``csv`` or ``npz`` (from its suffix)."""
    suffix = os.path.splitext(path)[1].lower()
    if suffix not in OUTPUT_SUFFIXES:
        raise InputError(f"{option}: {printable(path)}: expected a file ending in {', '.join(OUTPUT_SUFFIXES)}, "
                         f"got {_shown(suffix or 'no extension')}")
    return suffix[1:]


def flat_row(row, prefix=""):
    """A JSON-ready row as one level of columns: nested keys joined by ``_``, list items as ``name[i]``, a list of
    names (``kinds``) as one cell joined by ``;``."""
    result = {}
    for key, value in row.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            result.update(flat_row(value, f"{name}_"))
        elif isinstance(value, (list, tuple)) and all(isinstance(item, str) for item in value):
            result[name] = ";".join(value)
        elif isinstance(value, (list, tuple)):
            result.update({f"{name}[{index}]": item for index, item in enumerate(value)})
        else:
            result[name] = value
    return result


def csv_text(rows):
    """CSV text of JSON-ready rows (:func:`flat_row`): the union of their columns in order of first appearance;
    a missing or null value is an empty cell."""
    flat = [flat_row(row) for row in rows]
    header = list(dict.fromkeys(name for row in flat for name in row))
    stream = io.StringIO()
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(header)
    for row in flat:
        writer.writerow(["" if row.get(name) is None else _cell(row[name]) for name in header])
    return stream.getvalue()


def _cell(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "" if not math.isfinite(value) else repr(value)
    return value


def write_npz(path, arrays, option="--out"):
    """Write NumPy arrays to a ``.npz`` file (``numpy.load`` reads them back); every failure is an InputError."""
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    try:
        descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | getattr(os, "O_NONBLOCK", 0), 0o666)
    except (OSError, ValueError) as error:
        raise InputError(f"{option}: {printable(path)}: cannot write the file: "
                         f"{printable(getattr(error, 'strerror', None) or error)}") from None
    try:
        if hasattr(os, "set_blocking"):
            os.set_blocking(descriptor, True)
        with os.fdopen(descriptor, "wb") as handle:
            descriptor = None
            handle.write(buffer.getvalue())
    except OSError as error:
        raise InputError(f"{option}: {printable(path)}: cannot write the file: "
                         f"{printable(error.strerror or error)}") from None
    finally:
        if descriptor is not None:
            os.close(descriptor)


def json_text(value):
    """Indented JSON of JSON-ready data (rows of :meth:`classify.Classifications.rows` hold no NaN: a NaN here is
    an error, not written)."""
    return json.dumps(value, indent=2, ensure_ascii=False, allow_nan=False)


def write_rows(path, rows, document=None, option="--out"):
    """Write JSON-ready rows to a ``.jsonl``, ``.json`` or ``.csv`` file (``.json``: `document`, default the list
    of rows)."""
    kind = output_format(path, option)
    if kind == "jsonl":
        text = "".join(json.dumps(row, ensure_ascii=False, allow_nan=False) + "\n" for row in rows)
    elif kind == "json":
        text = json_text(rows if document is None else document) + "\n"
    elif kind == "csv":
        text = csv_text(rows)
    else:
        raise ValueError(f"rows are written as JSON lines, JSON or CSV, not {kind}")
    try:
        write_text_file(path, text)
    except MechanismError as error:
        raise InputError(f"{option}: {error}") from None


def _rank_cell(row, kind):
    """``r/e (kept|dropped)`` of one kind of a row, ``-`` where the model has none (no end-effector)."""
    if kind not in row["ranks"]:
        return "-"
    margins = row["margins"][kind]
    kept, dropped = (("-" if value is None else f"{value:.2g}")
                     for value in (margins["smallest_kept"], margins["largest_dropped"]))
    return f"{row['ranks'][kind]}/{row['expected_ranks'][kind]} ({kept}|{dropped})"


def result_table(header, entries):
    """A fixed-width table: the leading cells of each entry, then its kinds, ranks with margins, and κ.

    Parameters
    ----------
    header : tuple of str
        The leading columns' titles (``("row",)``, or the grid's coordinate names).
    entries : sequence of (tuple of str, dict or None)
        The leading cells and the row (:meth:`classify.Classifications.rows`), None for an unreachable
        grid point.

    Returns
    -------
    str
        A rank cell reads ``r/e (σ kept|σ dropped)``: the rank found, the rank expected, and the margins of the
        decision (``-`` where none).
    """
    titles = (*header, "kinds", "C-space", "actuator", "end-effector", "κ")
    lines = []
    for cells, row in entries:
        if row is None:
            lines.append((*cells, "unreachable", "", "", "", ""))
            continue
        condition = row["condition_number"]
        lines.append((*cells, ", ".join(row["kinds"]) or "regular", _rank_cell(row, "cspace"),
                      _rank_cell(row, "actuator"), _rank_cell(row, "end_effector"),
                      "-" if condition is None else f"{condition:.3g}"))
    widths = [max(len(line[column]) for line in [titles] + lines) for column in range(len(titles))]
    text = ["  ".join(cell.ljust(width) for cell, width in zip(line, widths)).rstrip() for line in [titles] + lines]
    text.insert(1, "  ".join("-" * width for width in widths))
    return "\n".join(text)


def kind_counts(result):
    """``{"regular": n, "cspace": n, "actuator": n, "end_effector": n}`` of a :class:`classify.Classifications`
    (a configuration singular in two kinds counts in both)."""
    from ..report import KINDS

    counts = {"regular": int(np.count_nonzero(~result.singular.any(axis=1)))}
    counts.update({kind: int(np.count_nonzero(result.kind(kind))) for kind in KINDS})
    return counts


def summary_line(counts, total, what="configurations"):
    """``N configurations: R regular; singular: a actuator, …`` from :func:`kind_counts`."""
    singular = ", ".join(f"{count} {kind.replace('_', '-')}" for kind, count in counts.items()
                         if kind not in ("regular", "unreachable", "reachable", "total") and count)
    text = f"{total} {what}: {counts['regular']} regular; singular: {singular or 'none'}"
    if counts.get("unreachable"):
        text += f"; {counts['unreachable']} unreachable"
    return text


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
    try:
        return cached_survey(path, model)[0]
    except SurveyCacheError as error:
        raise InputError(f"--survey: {printable(str(error))}") from None
