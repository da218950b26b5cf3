"""``closedchain sweep NAME --param K=a:b:n [--param K=V …] [--samples N] [--seed S] [--scheduler ADDRESS]
[--workers W] [--chunk D] [--out sweep.csv|json|parquet] [--format json|text]``: per design of a grid of
catalogue parameters, the share of sampled configurations of each kind and the smallest margins
(:mod:`classify.sweep`), on a Dask cluster or in this process."""

from __future__ import annotations

import csv
import io
import json
import os
import sys
from contextlib import contextmanager
from pathlib import Path

from mechanisms import MechanismError, catalogue

from ..progress import progress_bar
from ..text import printable
from ._common import COUNT_LIMIT, InputError, dumps, finite, integer, seed_type, write_output

__all__ = ["add_parser", "run", "SCHEDULER_TIMEOUT", "WORKER_WAIT", "WORKER_LIMIT", "OUTPUT_SUFFIXES", "read_table"]

#: seconds allowed to reach a --scheduler before giving up
SCHEDULER_TIMEOUT = 5.0
#: seconds to wait for a first worker of a scheduler that has none (an adaptive cluster may be starting one)
WORKER_WAIT = 60.0
#: most local worker processes --workers may ask for
WORKER_LIMIT = 64
#: default number of local worker processes
DEFAULT_WORKERS = 2
#: default configurations per design
DEFAULT_SAMPLES = 32
OUTPUT_SUFFIXES = (".csv", ".json", ".parquet")
#: the --scheduler value that runs the chunks in this process
SERIAL = "serial"
#: most designs the text summary lists one per line (every row goes to --out or --format json)
TABLE_LIMIT = 200
#: designs built, in order, before the sweep starts, until one builds: a sweep none of whose designs can be built
#: is refused before any cluster starts (a larger grid whose first designs all fail is left to the sweep's rows)
BUILD_CHECKS = 1000


def add_parser(commands):
    parser = commands.add_parser(
        "sweep", help="per design of a catalogue parameter grid, the share of sampled configurations of each kind "
                      "and the smallest margins, on a Dask cluster")
    parser.add_argument("name", metavar="NAME", help="catalogue name (see `closedchain catalog`)")
    parser.add_argument("--param", action="append", default=[], metavar="K=a:b:n|K=V",
                        help="a swept parameter (n values from a to b) or a fixed one (repeatable); the first "
                             "swept parameter varies slowest")
    parser.add_argument("--samples", type=integer, default=DEFAULT_SAMPLES, metavar="N",
                        help=f"configurations sampled per design (default {DEFAULT_SAMPLES})")
    parser.add_argument("--seed", type=seed_type, default=0,
                        help="seed of the sampling, an integer ≥ 0 (default 0); design i uses the i-th child of it")
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS",
                        help="address of a running Dask scheduler (e.g. tcp://host:8786), or 'serial' to run in "
                             "this process (default: a local cluster of --workers processes)")
    parser.add_argument("--workers", type=integer, default=None, metavar="W",
                        help=f"worker processes of the local cluster (default {DEFAULT_WORKERS}; 0 runs in this "
                             f"process)")
    parser.add_argument("--chunk", type=integer, default=None, metavar="D",
                        help="designs per task (default: about 32 tasks per worker, at most 16 designs each)")
    parser.add_argument("--out", default=None, metavar="FILE",
                        help="write one row per design: .csv (flat columns), .json (the grid and the rows) or "
                             ".parquet (flat columns; needs pyarrow)")
    parser.add_argument("--format", choices=("json", "text"), default="text", help="of the summary on stdout")
    return parser


# ----------------------------------------------------------------------------- checks


def _check(arguments):
    """Refuse bad options before anything runs."""
    if arguments.name not in catalogue.names():
        raise InputError(f"sweep: {arguments.name[:80]!r} is not a catalogue entry (entries: "
                         f"{', '.join(catalogue.names())})")
    if not 1 <= arguments.samples <= COUNT_LIMIT:
        raise InputError(f"--samples: expected a count ≥ 1 and at most {COUNT_LIMIT}, got {arguments.samples}")
    if arguments.workers is not None and not 0 <= arguments.workers <= WORKER_LIMIT:
        raise InputError(f"--workers: expected a number of processes from 0 to {WORKER_LIMIT}, "
                         f"got {arguments.workers}")
    if arguments.workers is not None and arguments.scheduler is not None:
        raise InputError(f"--workers: sizes the local cluster; it does not apply with --scheduler "
                         f"{printable(arguments.scheduler)[:80]}")
    if arguments.chunk is not None and arguments.chunk < 1:
        raise InputError(f"--chunk: expected at least 1 design per task, got {arguments.chunk}")
    if arguments.scheduler is not None and not arguments.scheduler.strip():
        raise InputError("--scheduler: expected an address such as tcp://host:8786, or 'serial'")
    if arguments.out is not None:
        _check_out(arguments.out)


def _check_out(path):
    suffix = os.path.splitext(path)[1].lower()  # Path("sweep.csv/").suffix would be ".csv"
    if suffix not in OUTPUT_SUFFIXES:
        raise InputError(f"--out: expected a file ending in {', '.join(OUTPUT_SUFFIXES)}, got "
                         f"{printable(path)[:80]}")
    folder = Path(path).parent
    if not folder.is_dir():
        raise InputError(f"--out: {printable(path)[:80]}: no folder {printable(folder)[:80]}")
    # before the sweep, not after it: a folder in the way, or a folder this process cannot write in
    if Path(path).is_dir():
        raise InputError(f"--out: {printable(path)[:80]}: it is a folder")
    if not os.access(folder, os.W_OK):
        raise InputError(f"--out: {printable(path)[:80]}: the folder {printable(folder)[:80]} is not writable")
    if suffix == ".parquet":
        _pyarrow()


def _pyarrow():
    """pyarrow and pyarrow.parquet, or an input error saying how to install them."""
    try:
        import pyarrow
        import pyarrow.parquet
    except ImportError:
        raise InputError("--out: writing .parquet needs pyarrow: pip install pyarrow (or "
                         "pip install 'closedchain[parquet]'), or write .csv or .json") from None
    return pyarrow, pyarrow.parquet


def _check_buildable(entry, grid):
    """Refuse a sweep none of whose designs can be built, before it starts (no cluster, no "sweeping" line).

    The designs are built in order (:func:`classify.sweep.design_mechanism`, as :func:`classify.sweep.sweep_design`
    builds them) until one builds, at most :data:`BUILD_CHECKS` of them.

    Raises
    ------
    InputError
        ``--param: no design of the sweep can be built (design 0: …)``, with a hint for a parameter that is not
        a number given as ``a:b:n`` (fixed at that text, not swept).
    """
    from ..sweep import design_mechanism

    first = None
    for index in range(min(len(grid), BUILD_CHECKS)):
        _, error = design_mechanism(entry, grid.parameters(index))
        if error is None:
            return
        first = error if first is None else first
    if first is None or len(grid) > BUILD_CHECKS:
        return
    hints = [f"; {name}={value} is not swept: a:b:n sweeps number parameters only" for name, value in grid.fixed
             if isinstance(value, str) and len(value.split(":")) == 3]
    raise InputError(f"--param: no design of the sweep can be built (design 0: {first}){''.join(hints[:1])}")


# ----------------------------------------------------------------------------- where the chunks run


async def _probe(address, timeout):
    """Open and close one connection to a Dask scheduler (its handshake included), within `timeout` seconds."""
    import asyncio

    from distributed.comm import connect

    comm = await asyncio.wait_for(connect(address, timeout=timeout), timeout)
    await comm.close()


def _connect(address):
    """A client of the scheduler at `address`; an input error naming --scheduler if it cannot be reached.

    The address is probed first (:func:`_probe`), so that an unreachable one (or another kind of server)
    fails within :data:`SCHEDULER_TIMEOUT` and leaves no half-made client behind; a scheduler that has no
    worker is given :data:`WORKER_WAIT` seconds for one to join (else the sweep would wait for ever).
    """
    import asyncio

    from distributed import Client

    shown = printable(address)[:80]
    try:
        asyncio.run(_probe(address, SCHEDULER_TIMEOUT))
        client = Client(address, timeout=SCHEDULER_TIMEOUT, set_as_default=False)
    except (OSError, ValueError, TypeError) as error:  # TimeoutError is an OSError
        reason = " ".join(str(error).split())
        if isinstance(error, TimeoutError) or reason.startswith("Timed out") or not reason:
            reason = f"no answer within {SCHEDULER_TIMEOUT:g} s"
        raise InputError(f"--scheduler: cannot reach a Dask scheduler at {shown}: {reason}") from None
    except Exception:  # another server's answer read as Dask frames: a MemoryError, a struct.error, …
        raise InputError(f"--scheduler: {shown} answers, but not as a Dask scheduler (another server on that "
                         f"port?)") from None
    try:
        if not client.scheduler_info().get("workers"):
            print(f"closedchain: the scheduler at {shown} has no worker yet: waiting up to {WORKER_WAIT:g} s",
                  file=sys.stderr)
        client.wait_for_workers(1, timeout=WORKER_WAIT)
    except TimeoutError:
        client.close()
        raise InputError(f"--scheduler: the scheduler at {shown} has no worker (none joined within "
                         f"{WORKER_WAIT:g} s); start workers with `dask worker {shown}`") from None
    return client


@contextmanager
def _quiet_distributed():
    """Dask's own log lines (connections, worker start and stop) silenced while the sweep runs."""
    import logging

    logger = logging.getLogger("distributed")
    level = logger.level
    logger.setLevel(logging.ERROR)
    try:
        yield
    finally:
        logger.setLevel(level)


@contextmanager
def _client(arguments):
    """The Dask client the chunks run on (None: in this process), and a phrase saying where that is."""
    workers = DEFAULT_WORKERS if arguments.workers is None else arguments.workers
    if arguments.scheduler == SERIAL or (arguments.scheduler is None and workers == 0):
        yield None, "in this process"
        return
    with _quiet_distributed():
        if arguments.scheduler is not None:
            client = _connect(arguments.scheduler)
            try:
                yield client, f"on the scheduler at {printable(arguments.scheduler)[:80]}"
            finally:
                client.close()
            return
        from distributed import Client

        from ..sweep import local_cluster

        with local_cluster(workers) as cluster, Client(cluster, set_as_default=False) as client:
            yield client, f"on a local cluster of {workers} worker process{'es' if workers > 1 else ''}"


# ----------------------------------------------------------------------------- outputs


def _schema_types(result):
    """Column name -> one of "int", "float", "bool", "str": the type of every flat column."""
    defaults = dict(result.grid.defaults)
    types = {"design": "int", "samples": "int", "architecture_singular": "bool", "error": "str"}
    for name in result.grid.order:
        default = defaults[name]
        types[f"parameters.{name}"] = ("bool" if isinstance(default, bool) else "int" if isinstance(default, int)
                                       else "float" if isinstance(default, (int, float)) else "str")
    for column in result.columns():
        types.setdefault(column, "float")
    return types


def _csv_cell(value):
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def _csv_text(result):
    """One row per design with flat columns; floats written to round-trip exactly, None as an empty cell."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    columns = result.columns()
    writer.writerow(columns)
    for row in result.table():
        writer.writerow([_csv_cell(row[column]) for column in columns])
    return buffer.getvalue()


def _write_parquet(result, path):
    pyarrow, parquet = _pyarrow()
    kinds = {"int": pyarrow.int64(), "float": pyarrow.float64(), "bool": pyarrow.bool_(), "str": pyarrow.string()}
    types = _schema_types(result)
    columns = result.columns()
    schema = pyarrow.schema([(column, kinds[types[column]]) for column in columns],
                            metadata={"closedchain.sweep": json.dumps(finite(_header(result)))})
    table = pyarrow.Table.from_pylist(result.table(), schema=schema)
    try:
        parquet.write_table(table, path)
    except OSError as error:
        raise InputError(f"--out: {printable(path)[:80]}: cannot write the file: {error}") from None


def _header(result):
    """What the JSON and Parquet files hold besides the rows: mechanism, samples, seed, grid."""
    return {key: value for key, value in result.to_dict().items() if key != "rows"}


def _write(result, path):
    suffix = Path(path).suffix.lower()
    if suffix == ".parquet":
        _write_parquet(result, path)
    elif suffix == ".csv":
        write_output(path, _csv_text(result), "--out")
    else:
        write_output(path, dumps(result.to_dict()) + "\n", "--out")


def _typed(text, kind):
    if text == "":
        return None
    if kind == "int":
        return int(text)
    if kind == "float":
        return float(text)
    if kind == "bool":
        return text == "true"
    return text


def read_table(path, result=None):
    """Read back the flat rows of a ``--out`` file (for checks and notebooks).

    Parameters
    ----------
    path : str
        A ``.csv``, ``.json`` or ``.parquet`` file written by ``closedchain sweep``.
    result : Sweep, optional
        Gives the column types of a CSV file (default: every cell read as a
        number where it parses as one, ``true``/``false`` as booleans).

    Returns
    -------
    list of dict
        One flat row (:func:`classify.sweep.flat_row`) per design.
    """
    from ..sweep import flat_row

    suffix = Path(path).suffix.lower()
    if suffix == ".json":
        with open(path, encoding="utf-8") as handle:
            return [flat_row(row) for row in json.load(handle)["rows"]]
    if suffix == ".parquet":
        _, parquet = _pyarrow()
        return parquet.read_table(path).to_pylist()
    with open(path, encoding="utf-8", newline="") as handle:
        rows = list(csv.DictReader(handle))
    types = _schema_types(result) if result is not None else {}
    return [{column: _typed(text, types.get(column) or _guess(text)) for column, text in row.items()}
            for row in rows]


def _guess(text):
    if text in ("true", "false"):
        return "bool"
    for kind, convert in (("int", int), ("float", float)):
        try:
            convert(text)
            return kind
        except ValueError:
            continue
    return "str"


# ----------------------------------------------------------------------------- summary


def _number(value, digits=4):
    return "-" if value is None else f"{value:.{digits}g}"


def _grid_phrase(grid):
    parts = [f"{printable(name)} {_number(values[0])} … {_number(values[-1])} in {len(values)}"
             for name, values in grid.axes]
    parts += [f"{printable(name)} = {printable(value)}" for name, value in grid.fixed]
    return "; ".join(parts) or "the defaults"


def _summary_text(result, out_path):
    from ..report import KINDS  # here: classify.report imports NumPy

    summary = result.summary()
    lines = [f"{printable(result.mechanism)}: {summary['designs']} design{'s' if summary['designs'] != 1 else ''} "
             f"({_grid_phrase(result.grid)}), {result.samples} configurations sampled per design, seed {result.seed}"]
    if out_path is None:
        lines += _table_lines(result)
    share = summary["share"]
    lines.append(f"share of the {summary['configurations']} configurations: "
                 + ", ".join(f"{kind.replace('_', '-')} {_number(share[kind])}" for kind in (*KINDS, "regular")))
    margins = summary["smallest_margin"]
    lines.append("smallest margin (σ kept / cut, over regular configurations): " + ", ".join(
        f"{kind.replace('_', '-')} " + ("-" if margins[kind] is None else
                                         f"{margins[kind]['value']:.3g} (design {margins[kind]['design']})")
        for kind in KINDS))
    lines.append(f"architecture-singular designs: {summary['architecture_singular']}; "
                 f"designs in error: {summary['errors']}")
    if out_path is not None:
        lines.append(f"rows written to {printable(out_path)}")
    return "\n".join(lines) + "\n"


def _table_lines(result):
    from ..report import KINDS  # here: classify.report imports NumPy

    names = result.grid.order
    header = (["design"] + [printable(name) for name in names] + ["samples"]
              + [f"{kind.replace('_', '-')}" for kind in (*KINDS, "regular")]
              + [f"margin {kind.replace('_', '-')}" for kind in KINDS])
    table = [header]
    errors = []
    for row in result.rows[:TABLE_LIMIT]:
        if row["error"] is not None:
            errors.append(f"  design {row['design']}: {printable(row['error'])}")
        table.append([str(row["design"])] + [printable(_number(row["parameters"][name])
                                                       if isinstance(row["parameters"][name], float)
                                                       else row["parameters"][name]) for name in names]
                     + [str(row["samples"])] + [_number(row["share"][kind]) for kind in (*KINDS, "regular")]
                     + [_number(row["smallest_margin"][kind], 3) for kind in KINDS])
    widths = [max(len(line[column]) for line in table) for column in range(len(header))]
    lines = ["  " + "  ".join(cell.rjust(width) for cell, width in zip(line, widths)) for line in table]
    if len(result.rows) > TABLE_LIMIT:
        more = len(result.rows) - TABLE_LIMIT
        lines.append(f"  … {more} more design{'s' if more != 1 else ''}: every row is in --out FILE or "
                     f"--format json")
    if errors:
        lines += ["errors:"] + errors
    return lines


def _summary_json(result, out_path):
    document = {"mechanism": result.mechanism, "samples": result.samples, "seed": result.seed,
                "grid": result.grid.to_dict(), "summary": result.summary(), "out": out_path}
    if out_path is None:
        document["rows"] = list(result.rows)
    return dumps(document) + "\n"


# ----------------------------------------------------------------------------- the command


def run(arguments, out):
    from ..sweep import design_grid, sweep

    _check(arguments)
    entry = catalogue.entry(arguments.name)
    try:
        grid = design_grid(entry, arguments.param)
    except MechanismError as error:
        raise InputError(str(error)) from None
    _check_buildable(entry, grid)
    with _client(arguments) as (client, where):
        print(f"sweeping {len(grid)} design{'s' if len(grid) != 1 else ''} of {printable(entry.name)} "
              f"({arguments.samples} configurations each) {where}", file=sys.stderr)
        bar = progress_bar(len(grid), "designs", unit="design")
        try:
            result = sweep(entry, grid, arguments.samples, arguments.seed, client=client, chunk=arguments.chunk,
                           progress=bar.update)
        except ModuleNotFoundError as error:
            raise InputError(f"--scheduler: the cluster's workers cannot import {error.name!r}: install "
                             f"closedchain on every worker") from None
        finally:
            bar.close()
    errors = [row["error"] or "" for row in result.rows]
    if all("cannot be built" in error and not error.startswith("cannot be analysed") for error in errors):
        # a fixed value that no design can have (classify refuses it too), not a sweep that found nothing
        raise InputError(f"--param: no design of the sweep can be built (design 0: {errors[0]})")
    if arguments.out is not None:
        _write(result, arguments.out)
    text = _summary_json if arguments.format == "json" else _summary_text
    out.write(text(result, arguments.out))
