"""Results of a batch or a map as files and text: JSON lines, JSON, CSV, NPZ, a fixed-width table, a summary.

The output format comes from the suffix of ``--out``: JSON lines
(``.jsonl``), one JSON document (``.json``), CSV with nested fields flattened
(``margins_actuator_smallest_kept``) and lists numbered (``eigenvalues[0]``)
(``.csv``), or NumPy arrays (``.npz``). Every failure to write is one line
naming the option and the file.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os

import numpy as np

from mechanisms import MechanismError
from mechanisms.io import write_text_file

from ..text import printable
from ._common import InputError
from ._names import shown

__all__ = [
    "OUTPUT_SUFFIXES", "output_format", "flat_row", "csv_text", "json_text", "write_npz", "write_rows",
    "result_table", "kind_counts", "summary_line",
]

OUTPUT_SUFFIXES = (".jsonl", ".json", ".csv", ".npz")


def output_format(path, option="--out"):
    """The output format of a file name: ``jsonl``, ``json``, ``csv`` or ``npz`` (from its suffix)."""
    suffix = os.path.splitext(path)[1].lower()
    if suffix not in OUTPUT_SUFFIXES:
        raise InputError(f"{option}: {printable(path)}: expected a file ending in {', '.join(OUTPUT_SUFFIXES)}, "
                         f"got {shown(suffix or 'no extension')}")
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
    a missing or null value is an empty cell.

    A group or a list of numbers that is null (or an empty list) in some rows is the empty cells of the columns
    it has in the others (``eigenvalues[0]``, …), which take its place in the order, not a column of its own."""
    flat = [flat_row(row) for row in rows]
    header = list(dict.fromkeys(name for row in flat for name in row))
    containers = set().union(*(_containers(row) for row in rows)) - {  # a cell of its own somewhere: kept
        name for row in flat for name, value in row.items() if value is not None and value != ""}
    spread = {name: [column for column in header if column.startswith((f"{name}[", f"{name}_"))]
              for name in header if name in containers}
    header = list(dict.fromkeys(column for name in header for column in spread.get(name, [name])))
    stream = io.StringIO()
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(header)
    for row in flat:
        writer.writerow(["" if row.get(name) is None else _cell(row[name]) for name in header])
    return stream.getvalue()


def _containers(row, prefix=""):
    """The flat names of a row's groups and lists of numbers (the fields :func:`flat_row` spreads over several
    columns)."""
    names = set()
    for key, value in row.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            names |= {name} | _containers(value, f"{name}_")
        elif isinstance(value, (list, tuple)) and value and not all(isinstance(item, str) for item in value):
            names.add(name)
    return names


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


def write_rows(path, rows, document=None, option="--out", mechanism=None):
    """Write JSON-ready rows to a ``.jsonl``, ``.json`` or ``.csv`` file (``.json``: `document`, default the list
    of rows). In CSV, with `mechanism`, the ``displacements`` of a joint of several coordinates are columns named
    by its coordinates (``displacements_S1[x]``, as a batch file names them), not by their index."""
    kind = output_format(path, option)
    if kind == "jsonl":
        text = "".join(json.dumps(row, ensure_ascii=False, allow_nan=False) + "\n" for row in rows)
    elif kind == "json":
        text = json_text(rows if document is None else document) + "\n"
    elif kind == "csv":
        text = csv_text(rows if mechanism is None else [_coordinate_displacements(row, mechanism) for row in rows])
    else:
        raise ValueError(f"rows are written as JSON lines, JSON or CSV, not {kind}")
    try:
        write_text_file(path, text)
    except MechanismError as error:
        raise InputError(f"{option}: {error}") from None


def _coordinate_displacements(row, mechanism):
    """`row` with its ``displacements`` keyed by coordinate names (a joint of several coordinates spread)."""
    from mechanisms.joints import joint_coordinate_names

    displacements = row.get("displacements")
    if not isinstance(displacements, dict):
        return row
    named = {}
    for joint, value in displacements.items():
        if isinstance(value, list):
            named.update(zip(joint_coordinate_names(mechanism.joint(joint)), value))
        else:
            named[joint] = value
    return dict(row, displacements=named)


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
