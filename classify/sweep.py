"""Design sweeps: a grid of catalogue parameters, and per design the share of each kind of singularity.

A *design* is one point of a grid over the parameters of a catalogue entry
(:mod:`mechanisms.catalogue`): each swept parameter takes the values of a
linspace ``a:b:n``, the others a fixed value or the entry's default. For
each design, :func:`sweep_design` builds the mechanism, draws configurations
of its C-space M spread over the assembly branches, classifies them with one
:func:`classify.classify_many` call and records what fraction of them is of
each kind, and how close the regular ones came to the rank cut.

A design is built as the catalogue builds it (``Entry.assemble``): at its
parameters, the entry's inputs included (the five-bar's ``theta1``,
``theta2``, ``assembly``) at their fixed value or default, which must close
the loops. A design whose C-space is not empty but whose loops do not close
at those inputs is a row with the error "cannot be built", not a design
without configurations: the five-bar with ``distal=3`` (base 6, proximal 8)
at the default θ1 = 1.8, θ2 = 1.3, whose elbows are 9.96 apart, farther than
the two distal links reach (6), though at θ1 = 1, θ2 = 2 it assembles. Fix
inputs at which every design of the sweep assembles (``--param theta1=1.0
--param theta2=2.0``; ``"theta1=1.0"`` among the specs of
:func:`design_grid`), or sweep them with the rest.

The designs are independent, so :func:`sweep` cuts them into chunks and runs
each chunk as one task, in this process or on a Dask cluster
(``dask.distributed.Client``). Nothing in a design's row depends on the
chunking or the scheduling: its random configurations come from a generator
seeded with ``SeedSequence(seed, spawn_key=(design,))`` (the `design`-th child
of ``SeedSequence(seed)``), and the survey of M from the model's own seed
(:func:`classify.survey.survey_of`). Dask is imported only when it is used:
by :func:`local_cluster`, and by :func:`sweep` when it is given a client.

Examples
--------
>>> from classify.sweep import design_grid
>>> from mechanisms.catalogue import entry
>>> grid = design_grid(entry("slider-crank"), ["crank=1:3:3", "coupler=2"])
>>> len(grid), grid.parameters(2)
(3, {'crank': 3.0, 'coupler': 2.0})
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from manifold import ManifoldError
from mechanisms import ConfigurationError, MechanismError, catalogue
from mechanisms._numerals import decimal_integer
from mechanisms.joints import is_number

from .batch import classify_many
from .model import model_of
from .report import KINDS

__all__ = [
    "DESIGN_LIMIT", "DesignGrid", "Sweep", "design_grid", "design_rng", "design_mechanism", "sweep_design",
    "sweep_chunk", "sweep", "chunk_size", "flat_row", "local_cluster", "COLUMN_GROUPS", "QUIET_WORKER_SETTINGS",
]

#: most designs one sweep may hold (the product of the axis lengths)
DESIGN_LIMIT = 100_000
#: chunks per worker thread aimed at by the automatic chunk size (load balance vs. per-task overhead)
CHUNKS_PER_THREAD = 32
#: largest automatic chunk, in designs
AUTOMATIC_CHUNK_LIMIT = 16
#: the nested groups of a row, flattened as ``group.key`` columns by :func:`flat_row`
COLUMN_GROUPS = ("parameters", "share", "smallest_margin")


@dataclass(frozen=True)
class DesignGrid:
    """A grid of designs over the parameters of a catalogue entry.

    Designs are numbered in C order of the axes: the first axis varies
    slowest, the last fastest (as :func:`itertools.product`).

    Attributes
    ----------
    mechanism : str
        The catalogue name.
    axes : tuple of (str, tuple)
        Swept parameters, in the order given, each with its values.
    fixed : tuple of (str, object)
        Parameters set to one value, in the order given.
    defaults : tuple of (str, object)
        Every parameter of the entry with its default (what the others take).
    """

    mechanism: str
    axes: tuple
    fixed: tuple
    defaults: tuple

    @property
    def shape(self):
        """The number of values of each axis, tuple of int."""
        return tuple(len(values) for _, values in self.axes)

    def __len__(self):
        return math.prod(self.shape)

    def parameters(self, index):
        """The parameters set by the grid at design `index` (swept and fixed), in the entry's order.

        Parameters
        ----------
        index : int
            From 0 to ``len(self) - 1``.

        Returns
        -------
        dict of str to value
        """
        index = int(index)
        if not 0 <= index < len(self):
            raise IndexError(f"design {index} is out of range (the grid has {len(self)})")
        position = np.unravel_index(index, self.shape) if self.axes else ()
        given = {**dict(self.fixed), **{name: values[int(at)] for (name, values), at in zip(self.axes, position)}}
        return {name: given[name] for name in self.order}

    @property
    def order(self):
        """The names of the parameters the grid sets (swept and fixed), in the entry's order."""
        given = {name for name, _ in self.axes} | {name for name, _ in self.fixed}
        return tuple(name for name, _ in self.defaults if name in given)

    def to_dict(self):
        """The grid as JSON-ready data: ``mechanism``, ``designs``, ``axes`` {name: values}, ``fixed``,
        ``defaults`` and ``order`` (a sentence saying how designs are numbered)."""
        return {"mechanism": self.mechanism, "designs": len(self),
                "axes": {name: list(values) for name, values in self.axes},
                "fixed": dict(self.fixed), "defaults": dict(self.defaults),
                "order": "C order of the axes: the first axis varies slowest"}


def _spec_error(name, message):
    where = f"--param {name}" if name else "--param"
    return MechanismError(f"{where}: {message}")


def _axis(entry, name, value):
    """The values of a swept parameter ``a:b:n`` (a linspace), typed as the parameter's default."""
    parts = value.split(":")
    if len(parts) != 3:
        raise _spec_error(name, f"expected a:b:n (n values from a to b) or one value, got {value[:40]!r}")
    low = catalogue.parse_parameter(entry, f"{name}={parts[0]}")[1]
    high = catalogue.parse_parameter(entry, f"{name}={parts[1]}")[1]
    try:
        count = decimal_integer(parts[2])
    except ValueError:
        raise _spec_error(name, f"expected a whole number of values n in a:b:n, got {parts[2][:40]!r}") from None
    if count < 1:
        raise _spec_error(name, f"expected at least 1 value in a:b:n, got n = {count}")
    if count == 1 and low != high:
        raise _spec_error(name, f"n = 1 gives one value: a and b must be equal (got {low:g} and {high:g})")
    if count > DESIGN_LIMIT:
        raise _spec_error(name, f"{count} values exceed the limit of {DESIGN_LIMIT} designs per sweep")
    values = np.linspace(low, high, count)
    if isinstance(entry.parameters[name], int):
        if not np.all(values == np.round(values)):
            raise _spec_error(name, f"an integer parameter needs whole steps; {low}:{high}:{count} gives "
                                    f"{values[1] - values[0]:g}")
        return tuple(int(item) for item in np.round(values))
    return tuple(float(item) for item in values)


def design_grid(entry, specs):
    """The grid of designs described by ``K=a:b:n`` (swept) and ``K=V`` (fixed) texts.

    Parameters
    ----------
    entry : mechanisms.catalogue.Entry or str
        The catalogue entry or its name.
    specs : sequence of str
        ``K=a:b:n``: parameter K takes the n values ``numpy.linspace(a, b, n)``
        (a number parameter, or an integer one whose steps are whole); n = 1
        needs a = b (as ``--grid``). ``K=V``: K is fixed at V (any parameter, typed as its
        default, :func:`mechanisms.catalogue.parse_parameter`). Text is never
        evaluated.

    Returns
    -------
    DesignGrid

    Raises
    ------
    MechanismError
        One line starting with ``--param`` for an unknown parameter, a
        parameter given twice, a value of the wrong type, non-finite or out of
        range, an axis with n < 1, or more than :data:`DESIGN_LIMIT` designs;
        one naming the entries for an unknown entry name.

    Examples
    --------
    >>> from classify.sweep import design_grid
    >>> grid = design_grid("five-bar", ["assembly=-1:1:2", "theta1=0:1:3"])
    >>> grid.shape, grid.parameters(4)
    ((2, 3), {'theta1': 0.5, 'assembly': 1})
    """
    if isinstance(entry, str):
        entry = catalogue.entry(entry)
    defaults = entry.parameters
    axes, fixed, seen = [], [], set()
    for text in specs:
        name, separator, value = text.partition("=")
        name, value = name.strip(), value.strip()
        if not separator or not name:
            raise _spec_error("", f"expected K=V or K=a:b:n, got {text[:40]!r}")
        if name in seen:
            raise _spec_error(name, "given twice")
        default = defaults.get(name)
        if name in defaults and ":" in value and is_number(default):
            axes.append((name, _axis(entry, name, value)))
        else:
            fixed.append(catalogue.parse_parameter(entry, text))
        seen.add(name)
    designs = math.prod(len(values) for _, values in axes)
    if designs > DESIGN_LIMIT:
        sizes = " × ".join(str(len(values)) for _, values in axes)
        raise _spec_error("", f"{sizes} = {designs} designs exceed the limit of {DESIGN_LIMIT} per sweep; "
                              f"use fewer values or split the sweep")
    return DesignGrid(entry.name, tuple(axes), tuple(fixed), tuple(defaults.items()))


def design_rng(seed, index):
    """The random generator of design `index`: ``SeedSequence(seed).spawn(…)[index]``, made directly.

    Parameters
    ----------
    seed : int
        The sweep's seed, ≥ 0.
    index : int
        The design's number in its grid.

    Returns
    -------
    numpy.random.Generator
    """
    return np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=(int(index),)))


def _share(count, total):
    return float(count) / total if total else None


def _smallest_margin(result, kind):
    """The smallest ``smallest_kept / tolerance`` over the configurations where `kind` does not hold."""
    regular = ~result.kind(kind)
    ratios = result.margins[kind][regular, 0] / result.tolerances[kind][regular]
    ratios = ratios[np.isfinite(ratios)]
    return float(ratios.min()) if len(ratios) else None


def _row(index, parameters, samples=0, share=None, margins=None, architecture_singular=None, error=None):
    return {"design": int(index), "parameters": dict(parameters), "samples": int(samples),
            "share": share or {kind: None for kind in (*KINDS, "regular")},
            "smallest_margin": margins or {kind: None for kind in KINDS},
            "architecture_singular": architecture_singular, "error": error}


def _one_line(error):
    return " ".join((str(error).strip() or type(error).__name__).split())


def design_mechanism(entry, parameters):
    """One design's mechanism, built as :func:`sweep_design` builds it, or why it cannot be.

    Parameters
    ----------
    entry : mechanisms.catalogue.Entry
    parameters : dict
        The design's parameters (:meth:`DesignGrid.parameters`).

    Returns
    -------
    mechanism : Mechanism or None
    error : str or None
        One line starting ``cannot be built`` where the design cannot be built, else None.
    """
    try:
        return entry.assemble(entry.values(**parameters)), None
    except (ValueError, ArithmeticError, np.linalg.LinAlgError) as error:  # MechanismError included
        text = _one_line(error)  # Entry.assemble names the parameters and says "cannot be built"
        return None, text if "cannot be built" in text else f"cannot be built: {text}"


def sweep_design(entry, parameters, samples, seed, index=0):
    """Build one design, sample its C-space and classify the samples: one row of a sweep.

    Parameters
    ----------
    entry : mechanisms.catalogue.Entry or str
    parameters : mapping of str to value
        The parameters set by the grid (the others take their defaults).
    samples : int
        How many configurations to draw, ≥ 0.
    seed : int
        The sweep's seed; the design's generator is :func:`design_rng` (seed, index).
    index : int
        The design's number in its grid.

    Returns
    -------
    dict
        JSON-ready: ``design`` (the index), ``parameters``, ``samples`` (the
        configurations drawn; fewer than asked where projections onto M fail),
        ``share`` {kind: fraction of the samples where the kind holds, and
        ``regular``: where none does; None without samples or, for
        ``end_effector``, without an end-effector}, ``smallest_margin`` {kind:
        the smallest ratio σ_kept / tolerance over the samples where the kind
        does *not* hold (σ_kept the smallest singular value kept by the rank
        decision, so the ratio is > 1 and 1 is the cut: how close a regular
        configuration came to being called singular); None where no regular
        sample has a kept value}, ``architecture_singular`` (a locked-actuator
        freedom moves the end-effector at some sample; None without samples)
        and ``error`` (None, or one line saying why the design could not be
        built or analysed; the other fields are then empty).

    Notes
    -----
    The design is built at the entry's inputs (fixed in `parameters`, else their defaults): where they do not
    close the loops, the row's ``error`` says it cannot be built, even if its C-space is not empty (module
    notes). The configurations come from :func:`classify.sample_configurations`
    (Gauss–Newton projections of random points of the ambient space, which
    reach the other assembly branches, and a random walk on M from the
    design's home, then `samples` of them chosen at random), so the home
    itself, often a special configuration of the paper, is not counted.
    """
    from .comparison import sample_configurations  # here: classify.comparison imports SymPy

    if isinstance(entry, str):
        entry = catalogue.entry(entry)
    mechanism, error = design_mechanism(entry, parameters)
    if error is not None:
        return _row(index, parameters, error=error)
    try:
        model = model_of(mechanism)
        points = sample_configurations(model, int(samples), design_rng(seed, index))
        if not len(points):
            return _row(index, parameters)
        result = classify_many(model, points)
    except (MechanismError, ConfigurationError, ManifoldError, ArithmeticError, np.linalg.LinAlgError) as error:
        return _row(index, parameters, error=f"cannot be analysed: {_one_line(error)}")
    count = len(result)
    has_end_effector = model.end_effector_dimension > 0
    share = {kind: _share(np.count_nonzero(result.kind(kind)), count)
             if kind != "end_effector" or has_end_effector else None for kind in KINDS}
    share["regular"] = _share(np.count_nonzero(~result.singular.any(axis=1)), count)
    margins = {kind: _smallest_margin(result, kind) for kind in KINDS}
    return _row(index, parameters, count, share, margins, bool(result.architecture_singular))


def sweep_chunk(mechanism, designs, samples, seed):
    """The rows of a chunk of designs (one Dask task).

    Parameters
    ----------
    mechanism : str
        The catalogue name.
    designs : sequence of (int, dict)
        (index, parameters) of each design.
    samples, seed : int
        As in :func:`sweep_design`.

    Returns
    -------
    list of dict
    """
    entry = catalogue.entry(mechanism)
    return [sweep_design(entry, parameters, samples, seed, index) for index, parameters in designs]


def chunk_size(designs, threads):
    """The automatic chunk size: about :data:`CHUNKS_PER_THREAD` chunks per thread, at most
    :data:`AUTOMATIC_CHUNK_LIMIT` designs each (1 when running in this process)."""
    if threads <= 1:
        return 1
    return max(1, min(AUTOMATIC_CHUNK_LIMIT, math.ceil(designs / (CHUNKS_PER_THREAD * threads))))


@dataclass(frozen=True, eq=False)
class Sweep:
    """The result of a sweep: one row per design, in design order.

    Attributes
    ----------
    grid : DesignGrid
    samples : int
        The configurations asked per design.
    seed : int
    rows : tuple of dict
        :func:`sweep_design`'s rows.
    """

    grid: DesignGrid
    samples: int
    seed: int
    rows: tuple

    @property
    def mechanism(self):
        return self.grid.mechanism

    def table(self):
        """The rows with flat columns (:func:`flat_row`), for CSV and Parquet."""
        return [flat_row(row) for row in self.rows]

    def columns(self):
        """The flat column names, in order: ``design``, ``parameters.K`` …, ``samples``, ``share.KIND`` …
        (and ``share.regular``), ``smallest_margin.KIND`` …, ``architecture_singular``, ``error``."""
        return (["design"] + [f"parameters.{name}" for name in self.grid.order] + ["samples"]
                + [f"share.{kind}" for kind in (*KINDS, "regular")]
                + [f"smallest_margin.{kind}" for kind in KINDS] + ["architecture_singular", "error"])

    def summary(self):
        """Totals over the designs: ``designs``, ``errors``, ``configurations``, ``share`` (over every
        configuration sampled, None where nothing was sampled), ``smallest_margin`` {kind: {``value``,
        ``design``} or None}, ``architecture_singular`` (the number of such designs)."""
        done = [row for row in self.rows if row["error"] is None and row["samples"]]
        total = sum(row["samples"] for row in done)
        share = {}
        for kind in (*KINDS, "regular"):
            counted = [row for row in done if row["share"][kind] is not None]
            weight = sum(row["samples"] for row in counted)
            share[kind] = (sum(row["share"][kind] * row["samples"] for row in counted) / weight
                           if weight else None)
        smallest = {}
        for kind in KINDS:
            margins = [(row["smallest_margin"][kind], row["design"]) for row in done
                       if row["smallest_margin"][kind] is not None]
            value, design = min(margins) if margins else (None, None)
            smallest[kind] = None if value is None else {"value": value, "design": design}
        return {"designs": len(self.rows), "errors": sum(row["error"] is not None for row in self.rows),
                "configurations": total, "share": share, "smallest_margin": smallest,
                "architecture_singular": sum(bool(row["architecture_singular"]) for row in self.rows)}

    def to_dict(self):
        """JSON-ready: ``mechanism``, ``samples``, ``seed``, ``grid`` (:meth:`DesignGrid.to_dict`), ``rows``."""
        return {"mechanism": self.mechanism, "samples": self.samples, "seed": self.seed,
                "grid": self.grid.to_dict(), "rows": [dict(row) for row in self.rows]}


def flat_row(row):
    """A row with its nested groups (:data:`COLUMN_GROUPS`) as ``group.key`` columns.

    Examples
    --------
    >>> from classify.sweep import flat_row
    >>> flat_row({"design": 0, "parameters": {"crank": 1.0}, "share": {"actuator": 0.5}})
    {'design': 0, 'parameters.crank': 1.0, 'share.actuator': 0.5}
    """
    result = {}
    for name, value in row.items():
        if name in COLUMN_GROUPS:
            result.update({f"{name}.{key}": item for key, item in value.items()})
        else:
            result[name] = value
    return result


def local_cluster(workers=2):
    """A Dask LocalCluster for sweeps on this machine: `workers` processes of one thread each.

    No dashboard (its HTTP server on a free local port, so a cluster already on
    port 8787 causes no warning), Dask's log silenced, the workers' profiler and
    monitors slowed down (:data:`QUIET_WORKER_SETTINGS`). On Linux the worker
    processes are forked from this one, so they start in a fraction of a second
    with NumPy, SciPy and this package already imported; a spawned worker starts
    a new interpreter and imports them again (seconds on two cores, eating the
    gain of a sweep of a minute). Elsewhere (macOS, Windows), or when
    ``DASK_DISTRIBUTED__WORKER__MULTIPROCESSING_METHOD`` is set, Dask's own
    choice is kept.

    Parameters
    ----------
    workers : int
        Number of worker processes, ≥ 1.

    Returns
    -------
    distributed.LocalCluster
        Close it (or use it as a context manager) when done; connect with
        ``distributed.Client(cluster)``.
    """
    import logging

    import dask
    from distributed import LocalCluster

    with dask.config.set(_local_settings()):
        return LocalCluster(n_workers=int(workers), threads_per_worker=1, processes=True, dashboard_address=None,
                            scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}, silence_logs=logging.CRITICAL)


#: Dask settings of :func:`local_cluster`'s workers: no statistical profiler (it samples the task's stack every
#: 10 ms) and event-loop health checks and resource monitors every second or two rather than every 20-500 ms;
#: together they cost a worker about 10 % of its time on the sweeps of a design per tenth of a second.
QUIET_WORKER_SETTINGS = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.worker.memory.monitor-interval": "1s",
}


def _local_settings():
    """Dask settings of :func:`local_cluster`: :data:`QUIET_WORKER_SETTINGS`, and fork on Linux unless the
    environment chooses the start method."""
    import os
    import sys

    settings = dict(QUIET_WORKER_SETTINGS)
    if sys.platform.startswith("linux") and "DASK_DISTRIBUTED__WORKER__MULTIPROCESSING_METHOD" not in os.environ:
        settings["distributed.worker.multiprocessing-method"] = "fork"
    return settings


def _chunks(grid, size):
    """The designs of `grid` as (index, parameters) lists of `size` designs."""
    designs = [(index, grid.parameters(index)) for index in range(len(grid))]
    return [designs[start:start + size] for start in range(0, len(designs), size)]


def _threads(client):
    """The number of worker threads of a Dask client's cluster (1 when unknown)."""
    try:
        return max(1, sum(client.nthreads().values()))
    except (AttributeError, TypeError, ValueError):
        return 1


def sweep(mechanism, specs, samples, seed=0, client=None, chunk=None, progress=None):
    """Run every design of a grid and gather their rows in design order.

    Parameters
    ----------
    mechanism : str or mechanisms.catalogue.Entry
        The catalogue entry.
    specs : sequence of str or DesignGrid
        The grid (:func:`design_grid`'s texts, or the grid itself).
    samples : int
        Configurations drawn per design.
    seed : int
        Seed of the sweep; design i draws from :func:`design_rng` (seed, i).
    client : dask.distributed.Client, optional
        Run each chunk as one task on its cluster; default: in this process,
        one chunk after the other.
    chunk : int, optional
        Designs per chunk (task); default :func:`chunk_size`. The rows do not
        depend on it.
    progress : callable, optional
        ``progress(count)``, called with the number of designs of each chunk as
        it completes (in completion order).

    Returns
    -------
    Sweep

    Raises
    ------
    MechanismError
        For a bad grid (:func:`design_grid`). A design that cannot be built or
        analysed is a row with an ``error``, not an exception; an exception
        raised by a task (a bug) propagates.
    """
    entry = catalogue.entry(mechanism) if isinstance(mechanism, str) else mechanism
    grid = specs if isinstance(specs, DesignGrid) else design_grid(entry, specs)
    if grid.mechanism != entry.name:
        raise ValueError(f"the grid is of {grid.mechanism!r}, not of {entry.name!r}")
    samples, seed = int(samples), int(seed)
    if samples < 0 or seed < 0:
        raise ValueError(f"expected samples ≥ 0 and seed ≥ 0, got {samples} and {seed}")
    size = int(chunk) if chunk is not None else chunk_size(len(grid), 1 if client is None else _threads(client))
    if size < 1:
        raise ValueError(f"expected a chunk of at least 1 design, got {size}")
    chunks = _chunks(grid, size)
    report = progress or (lambda count: None)
    if client is None:
        results = []
        for designs in chunks:
            results.append(sweep_chunk(entry.name, designs, samples, seed))
            report(len(designs))
    else:
        results = _on_cluster(client, entry.name, chunks, samples, seed, report)
    rows = tuple(row for rows in results for row in rows)
    return Sweep(grid, samples, seed, rows)


def _on_cluster(client, name, chunks, samples, seed, report):
    """Each chunk as one task on the client's cluster; the chunks' rows in chunk order."""
    from distributed import as_completed

    futures = [client.submit(sweep_chunk, name, designs, samples, seed, pure=False) for designs in chunks]
    sizes = {future.key: len(designs) for future, designs in zip(futures, chunks)}
    try:
        for future in as_completed(futures, loop=client.loop):
            if future.status == "error":
                break
            report(sizes[future.key])
        return client.gather(futures)
    finally:
        client.cancel(futures)
