"""``closedchain map FILE|NAME --grid NAME=a:b:n [NAME=a:b:n ...] [--project] [--configuration C] [--param K=V]
[--closures FILE] [--survey FILE] [--threads T] [--out FILE.npz|csv|json|jsonl | --format json|text]``: classify
every point of a grid of joint coordinates.

The grid is over joint coordinates given as displacements from the home, as
``--at`` gives them (``A``, ``S1[x]``, ``U1[2]``; :mod:`classify.cli._names`);
the coordinates not on the grid keep the value of the configuration the
command starts from (``--configuration``, else the home; a catalogue entry's
home is its configuration). Each grid point becomes a configuration on M in
one of two ways.

Assembly (the default): by continuation over the grid from the starting
configuration, on its assembly branch (working mode)
(:mod:`classify.grid_continuation`). The grid coordinates are held at
exactly the grid values, and so are the actuated coordinates off the grid
when the grid is over actuated coordinates only (as ``closedchain classify
--assemble``: the inputs not named stay where they are); an S joint with a
grid coordinate is held whole. A grid point that no continuation from a
reached neighbour leads to is *unreachable* (outside the inputs' reach on
this branch, or beyond a fold). From a starting configuration singular
for the held coordinates (e.g. an actuator singularity of a grid over the
inputs), or at a C-space singularity (DΦ of a lower rank than the survey's),
continuation can reach nothing: the grid points it leaves are then
started from a regular neighbour on M
(:func:`classify.grid_continuation.regular_start`), said in the output
(JSON ``"start": {"singular", "cspace", "moved", "margin", "tolerance", "tied"}``, null
with ``--project``; ``tied`` > 1 where other neighbours were as well
conditioned, as the two mirror-image assembly modes next to a dead centre:
which one the map follows is then a convention of the coordinates).

Projection (``--project``). Each grid point's configuration (the starting
configuration with the grid coordinates set) is projected onto M
(Gauss–Newton, :func:`manifold.project`, all points at once but each on its
own), which moves every coordinate, the grid ones included; unreachable
where projection fails. Each point reports its projection distance, and its
``displacements`` are those of the projected configuration, the one
classified (not the grid values: ``coordinates`` gives those). Projection
does not keep neighbouring grid points on one assembly branch (working
mode): a point may land on another branch than its neighbours (the
five-bar over its two inputs has isolated points of the other branch inside
the start's); the default assembly gives a map of one branch.

A grid axis over a whole turn of an angle (both ends given) is closed on
itself: the two ends are one configuration, continuation walks across them,
and the map does not depend on which end is called which
(:mod:`classify.grid_continuation`).

Then one :func:`classify.classify_many` over the reachable points (its chunks
in ``--threads`` threads, every usable core by default), with the mechanism's
survey of M (``--survey FILE``: a cache file, read when it was made for this
mechanism, else computed and written).

Output: per grid point its index, grid coordinates, whether it was reached,
and, when reached, the row of :meth:`classify.Classifications.rows` (kinds,
singular, dof, ranks, expected ranks, margins, λ's, condition number,
degeneracy) and the displacements of the configuration classified. ``--out``:
``.json`` one document ``{"source", "mechanism", "method": "assemble" |
"project", "held": [coordinate names] | null, "start", "grid": {name: [a, b, n]},
"shape", "survey", "points": [...], "summary": {"total", "reachable",
"unreachable", "regular", "cspace", "actuator", "end_effector"}}``; ``.jsonl`` one point per line;
``.csv`` one point per row; ``.npz`` arrays shaped like the grid
(``reachable``, ``coordinates`` ``[*shape, d]``, ``points``, ``displacements``,
and every column of :meth:`classify.Classifications.arrays` — NaN, -1 or
false where unreachable). Without ``--out``: the JSON document
(``--format json``) or a table with the counts and, for one- and
two-dimensional grids, a picture of the kinds (``--format text``).
"""

from __future__ import annotations

from ..progress import progress_bar, show_progress
from ..text import printable
from ._common import (InputError, check_length_scale, check_output, closures_option, common_options,
                      configuration_options, entry_options, file_after_grid, input_files, source, survey_option,
                      threads_option, warn_if_serial)

__all__ = ["add_parser", "run", "PICTURE"]

#: the text picture's character per grid point: kinds (several: "+"), regular, unreachable
PICTURE = {"regular": ".", "actuator": "A", "end_effector": "E", "cspace": "C", "several": "+", "unreachable": "x"}


def add_parser(commands):
    parser = commands.add_parser(
        "map", help="classify every point of a grid of joint coordinates (assembled, or projected onto M)")
    parser.add_argument("file", nargs="?", metavar="FILE|NAME",  # optional to argparse: file_after_grid
                        help="mechanism file (YAML or JSON), URDF (with --closures), MJCF (.xml) or catalogue name")
    entry_options(parser)
    closures_option(parser)
    parser.add_argument("--grid", nargs="+", action="extend", required=True, metavar="NAME=a:b:n",
                        help="a grid axis: coordinate NAME (joint displacement from home, as --at) from a to b in n "
                             "points; repeat for more axes (at most 1e6 points in all)")
    parser.add_argument("--project", action="store_true",
                        help="project each grid point's configuration onto the C-space on its own (moves every "
                             "coordinate; neighbouring points may land on different assembly branches; the "
                             "displacements are those classified) instead of holding the grid coordinates and "
                             "solving the loops for the others by continuation on one branch")
    survey_option(parser)
    threads_option(parser)
    parser.add_argument("--out", default=None, metavar="FILE",
                        help="write the map to FILE (.npz, .csv, .json or .jsonl) and print a summary")
    parser.add_argument("--format", choices=("json", "text"), default=None,
                        help="what is printed without --out (default text)")
    common_options(parser)
    return parser


# ------------------------------------------------------------------------------------------------ output

def _per_point_arrays(result, reachable, shape):
    """The columns of :meth:`classify.Classifications.arrays` spread over the grid (NaN, -1, false where
    unreachable)."""
    import numpy as np

    arrays = {}
    for name, column in result.arrays().items():
        column = np.asarray(column)
        if name == "kinds":  # the names of the columns of `singular`, not a column
            arrays[name] = column
            continue
        if column.dtype == bool:
            fill = False
        elif np.issubdtype(column.dtype, np.integer):
            fill = -1
        else:
            fill = np.nan
        spread = np.full((reachable.size,) + column.shape[1:], fill, dtype=column.dtype)
        spread[reachable] = column
        arrays[name] = spread.reshape(tuple(shape) + column.shape[1:])
    return arrays


def _picture(kinds, reachable, shape):
    """One character per grid point (:data:`PICTURE`): one line for a 1-D grid, one line per value of the first
    axis for a 2-D grid."""
    characters = []
    for index in range(len(reachable)):
        if not reachable[index]:
            characters.append(PICTURE["unreachable"])
        elif not kinds[index]:
            characters.append(PICTURE["regular"])
        else:
            characters.append(PICTURE[kinds[index][0]] if len(kinds[index]) == 1 else PICTURE["several"])
    width = shape[-1]
    return "\n".join("".join(characters[row:row + width]) for row in range(0, len(characters), width))


def _legend():
    return ", ".join(f"{character} {name.replace('_', '-')}" for name, character in PICTURE.items())


def _configurations(arguments, mechanism, named, grid, constraint_rank):
    """The grid's configurations: (points [n, point_size], reachable [n], projection distances [n] or None,
    StartingPoint or None); `constraint_rank` the survey's rank of DΦ·s on M (a start at a C-space singularity
    is singular)."""
    import numpy as np

    from mechanisms import CLOSURE_TOLERANCE, configuration, validate_displacements

    from ..grid_continuation import assemble_grid, held_columns
    from . import _configurations as configurations

    validate_displacements(mechanism, named, "--configuration")
    base = configurations.displacement_vector(mechanism, named)
    requested = np.array(np.broadcast_to(base, (grid.size, base.size)))
    requested[:, list(grid.columns)] = grid.values().reshape(grid.size, len(grid.columns))
    targets = configurations.points_of(mechanism, requested)
    if arguments.project:  # every grid point is projected: the start need not close the loops
        return configurations.project_configurations(mechanism, targets, CLOSURE_TOLERANCE) + (None,)
    starting = configuration(mechanism, named, where=configuration_options(arguments, {}))
    bar = progress_bar(grid.size, "assembling", unit="point")
    try:
        points, reachable, starting = assemble_grid(mechanism, starting.point, targets, grid.shape,
                                                    held_columns(mechanism, grid), bar, with_start=True,
                                                    constraint_rank=constraint_rank)
    finally:
        bar.close()
    return points, reachable, None, starting


def _entries(mechanism, grid, reachable, result, displacements, distance):
    """One JSON-ready entry per grid point, in C order (see the module notes)."""
    import numpy as np

    from ._configurations import joint_displacements

    rows = iter(result.rows())
    given = iter(joint_displacements(mechanism, displacements))
    coordinates = grid.values().reshape(grid.size, len(grid.names)).tolist()
    indices = np.array(np.unravel_index(np.arange(grid.size), grid.shape)).T.tolist()
    entries = []
    for flat in range(grid.size):
        entry = {"index": indices[flat], "coordinates": dict(zip(grid.names, coordinates[flat])),
                 "reachable": bool(reachable[flat])}
        if reachable[flat]:
            entry.update(next(rows))
            entry["displacements"] = next(given)
            if distance is not None:
                entry["projection_distance"] = float(distance[flat])
        entries.append(entry)
    return entries


def _arrays(mechanism, grid, points, reachable, result, displacements, distance):
    """The NPZ arrays of a map, shaped like the grid."""
    import numpy as np

    arrays = _per_point_arrays(result, reachable, grid.shape)
    spread = np.full((grid.size, displacements.shape[-1]), np.nan)
    spread[reachable] = displacements
    arrays.update({
        "grid_names": np.array(grid.names), "grid_start": np.array(grid.starts),
        "grid_stop": np.array(grid.stops), "grid_count": np.array(grid.counts),
        "coordinates": grid.values(), "reachable": reachable.reshape(grid.shape),
        "points": np.where(reachable[:, None], points, np.nan).reshape(grid.shape + (points.shape[-1],)),
        "displacements": spread.reshape(grid.shape + (displacements.shape[-1],)),
        "coordinate_names": np.array(mechanism.coordinate_names)})
    if distance is not None:
        arrays["projection_distance"] = distance.reshape(grid.shape)
    return arrays


def _text(grid, entries, reachable, summary_text):
    """The table, the counts and, for one- and two-dimensional grids, the picture."""
    from ._outputs import result_table

    table = result_table(
        tuple(printable(name) for name in grid.names),
        [(tuple(f"{entry['coordinates'][name]:.6g}" for name in grid.names),
          entry if entry["reachable"] else None) for entry in entries])
    lines = [table, "", summary_text]
    if len(grid.shape) <= 2:
        kinds = [tuple(entry.get("kinds", ())) for entry in entries]
        axes = " × ".join(printable(name) for name in grid.names)
        lines += ["", f"kinds over the grid ({axes}; {_legend()}):", _picture(kinds, reachable, grid.shape)]
    return "\n".join(lines) + "\n"


def run(arguments, out):
    from ..batch import classify_many
    from ..grid_continuation import held_columns
    from ..model import model_of
    from . import _outputs as outputs
    from ._batch_io import model_survey
    from ._configurations import displacements_of
    from ._grid import parse_grid
    from .classify_command import describe_source

    file_after_grid(arguments)
    check_length_scale(arguments.length_scale)
    if arguments.seed:
        raise InputError("--seed: does not apply to `closedchain map` (the map is deterministic)")
    file_format = outputs.output_format(arguments.out) if arguments.out is not None else None
    if file_format is not None and arguments.format is not None:
        raise InputError("--format: applies to what is printed; with --out the file's suffix gives the format")
    check_output(arguments.out, "--out", input_files(arguments))  # before the survey cache is written
    mechanism, named = source(arguments)
    warn_if_serial(mechanism)
    grid = parse_grid(arguments.grid, mechanism)
    model = model_of(mechanism, arguments.length_scale)
    survey = model_survey(arguments.survey, model)
    points, reachable, distance, starting = _configurations(arguments, mechanism, named, grid,
                                                            survey.constraint_rank)
    result = classify_many(model, points[reachable], survey=survey, progress=show_progress(),
                          workers=-1 if arguments.threads is None else arguments.threads)
    displacements = displacements_of(mechanism, result.points)
    reached = int(reachable.sum())
    summary = {"total": grid.size, "reachable": reached, "unreachable": grid.size - reached,
               **outputs.kind_counts(result)}
    summary_text = "map of " + outputs.summary_line(summary, grid.size, "grid points")
    if starting is not None and starting.singular:
        summary_text += (" (the start is a C-space singularity" if starting.cspace
                         else " (the start is singular for the held coordinates") + (
            f"; the points it leaves continued from a regular neighbour on M {starting.moved:.3g} away"
            + (f", one of {starting.tied} as well conditioned)" if starting.tied > 1 else ")")
            if starting.moved else ")")
    if file_format == "npz":
        outputs.write_npz(arguments.out, _arrays(mechanism, grid, points, reachable, result, displacements,
                                                 distance))
        out.write(f"{summary_text}; written to {printable(arguments.out)}\n")
        return
    entries = _entries(mechanism, grid, reachable, result, displacements, distance)
    if file_format is None and arguments.format != "json":
        out.write(_text(grid, entries, reachable, summary_text))
        return
    held = None if arguments.project else [mechanism.coordinate_names[column]
                                           for column in held_columns(mechanism, grid)]
    document = {"source": describe_source(arguments), "mechanism": mechanism.name,
                "method": "project" if arguments.project else "assemble", "held": held,
                "start": None if starting is None else starting.to_dict(),
                "grid": grid.to_dict(), "shape": list(grid.shape), "survey": result.survey.to_dict(),
                "points": entries, "summary": summary}
    if file_format is None:
        out.write(outputs.json_text(document) + "\n")
        return
    outputs.write_rows(arguments.out, entries, document, mechanism=mechanism)
    out.write(f"{summary_text}; written to {printable(arguments.out)}\n")
