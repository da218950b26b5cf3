"""``closedchain loci FILE|NAME [--param K=V] [--configuration C] [--coordinates J1,J5|end-effector]
[--kinds actuator,end_effector,cspace] [--grid NAME=a:b:n NAME=a:b:n] [--out FIG.png|svg|pdf]
[--format json|text]``: trace the singularity loci of a 1- or 2-dof mechanism (:mod:`classify.loci`).

2 dof: the grid (default the actuated coordinates, 24 points over a turn
around the starting configuration, or ±2 characteristic lengths) is
assembled by continuation from the starting configuration (``--configuration``,
else the home), and the loci through its seeds are followed on M as
curves. 1 dof: M's branches are followed from sampled points of M and the
loci are points on them. Every point reported is confirmed singular of its
kind by the classification; C-space singularities (branch points) are
points.

``--coordinates``: what the loci are shown in — joint coordinates (comma
separated, as ``--at`` names them) or ``end-effector`` (its point). Default
the grid's coordinates (2 dof), the actuated coordinate and the next one
(1 dof).

``--format json``: ``{"mechanism", "source", "coordinates": [names],
"pieces": [{"kind", "closed", "configurations": [{joint: displacement}],
"coordinates": [[...]], "residuals": [...]}], "branches": [...same, 1 dof],
"coverage": {...}}``. Each configuration is given as joint displacements
from the mechanism's home exactly as ``--at`` takes them, so
``closedchain classify NAME --at '<one of them>'`` reproduces its verdict.
``--out``: the C-space map with the loci overlaid
(:func:`classify.figures.loci.draw_cspace_map`); the text or JSON is printed
as well.
"""

from __future__ import annotations

from ..text import printable
from ._common import InputError, common_options, entry_options, source

__all__ = ["add_parser", "run", "DEFAULT_COUNT"]

#: grid points per axis without --grid
DEFAULT_COUNT = 24


def add_parser(commands):
    parser = commands.add_parser("loci", help="trace the singularity loci of a 1- or 2-dof mechanism, and its "
                                              "C-space map")
    parser.add_argument("file", metavar="FILE|NAME", help="mechanism file (YAML or JSON) or catalogue name")
    entry_options(parser)
    parser.add_argument("--coordinates", default=None, metavar="J1,J5|end-effector",
                        help="the coordinates the loci are shown in: joint coordinates or end-effector")
    parser.add_argument("--kinds", default="actuator,end_effector,cspace", metavar="K,...",
                        help="which loci: actuator, end_effector, cspace (default all)")
    parser.add_argument("--grid", nargs="+", action="extend", default=None, metavar="NAME=a:b:n",
                        help="2 dof: the two grid axes the seeds are searched on (default the actuated "
                             f"coordinates, {DEFAULT_COUNT} points over a turn)")
    parser.add_argument("--out", default=None, metavar="FIG", help="write the C-space map with the loci (.png, "
                                                                   ".svg or .pdf)")
    parser.add_argument("--format", choices=("json", "text"), default="text", help="what is printed (default text)")
    common_options(parser)
    return parser


def _coordinates(text, mechanism, default):
    """The columns named by --coordinates, or "end-effector"."""
    from ._names import coordinate_column

    if text is None:
        return default
    if text.strip() == "end-effector":
        if mechanism.end_effector is None:
            raise InputError("--coordinates: the mechanism has no end-effector")
        if mechanism.space == "spherical" or mechanism.end_effector.point is None:
            raise InputError("--coordinates: end-effector coordinates need an end-effector point")
        return "end-effector"
    names = [name.strip() for name in text.split(",")]
    if not all(names) or not 1 <= len(names) <= 3:
        raise InputError(f"--coordinates: expected one to three comma-separated coordinate names or end-effector, "
                         f"got {printable(repr(text))}")
    columns = [coordinate_column(mechanism, name, "--coordinates") for name in names]
    if len(set(columns)) != len(columns):
        raise InputError("--coordinates: a coordinate is named twice")
    return columns


def _grid(arguments, mechanism):
    """(columns, ranges, counts) of --grid, or Nones."""
    from ._grid import parse_grid

    if arguments.grid is None:
        return None, None, (DEFAULT_COUNT, DEFAULT_COUNT)
    grid = parse_grid(arguments.grid, mechanism)
    if len(grid.names) != 2 or min(grid.counts) < 2:
        raise InputError("--grid: expected two axes NAME=a:b:n with n ≥ 2 (a 2-dof locus grid)")
    return list(grid.columns), list(zip(grid.starts, grid.stops)), list(grid.counts)


def _piece(mechanism, piece, coordinates):
    from ..loci import locus_coordinates
    from ._configurations import displacements_of, joint_displacements

    values, _ = locus_coordinates(mechanism, piece.points, coordinates)
    return {"kind": piece.kind, "closed": piece.closed,
            "configurations": joint_displacements(mechanism, displacements_of(mechanism, piece.points)),
            "coordinates": values.tolist(), "residuals": piece.residuals.tolist()}


def _text(document):
    coverage = document["coverage"]
    lines = [f"loci of {printable(document['mechanism'])} ({coverage['dof']} dof), shown in "
             f"{', '.join(printable(name) for name in document['coordinates'])}"]
    if "grid" in coverage:
        grid = ", ".join(f"{printable(name)} from {low:.4g} to {high:.4g} in {count}"
                         for name, (low, high, count) in coverage["grid"].items())
        lines.append(f"  grid: {grid}; {coverage['reached']} of {coverage['grid_points']} points reached")
    if "branches" in coverage:
        closed = sum(coverage["branches_closed"])
        lines.append(f"  branches of M: {coverage['branches']} ({closed} closed), from {coverage['samples']} "
                     f"sampled points")
    for kind, count in coverage["pieces"].items():
        pieces = [piece for piece in document["pieces"] if piece["kind"] == kind]
        closed = sum(piece["closed"] for piece in pieces)
        points = sum(len(piece["configurations"]) for piece in pieces)
        lines.append(f"  {kind.replace('_', '-')}: {count} piece(s), {closed} closed, {points} point(s)"
                     + (f"; not traced: {coverage['not_traced'][kind]}" if kind in coverage["not_traced"] else ""))
    dropped = {kind: count for kind, count in coverage["unconfirmed"].items() if count}
    if dropped:
        lines.append("  dropped (not confirmed by the classification): "
                     + ", ".join(f"{kind.replace('_', '-')} {count}" for kind, count in dropped.items()))
    return "\n".join(lines) + "\n"


def run(arguments, out):
    from mechanisms import configuration

    from ..loci import default_columns, trace_loci
    from ..model import model_of
    from ..survey import survey_of
    from . import _outputs as outputs
    from .classify_command import describe_source
    from .draw_command import figure_path, parse_kinds, write_figure

    import numpy as np

    if arguments.out is not None:
        figure_path(arguments.out)
    kinds = parse_kinds(arguments.kinds)
    mechanism, named = source(arguments)
    start = configuration(mechanism, named, where="--configuration").point
    model = model_of(mechanism, arguments.length_scale)
    survey = survey_of(model)
    dof = mechanism.ambient_dimension - survey.constraint_rank
    if dof not in (1, 2):
        raise InputError(f"loci: traced for 1- and 2-dof mechanisms; {printable(mechanism.name)} has {dof} dof")
    columns, ranges, counts = _grid(arguments, mechanism)
    if dof == 1 and arguments.grid is not None:
        raise InputError("--grid: applies to 2-dof mechanisms (a 1-dof C-space is followed from sampled points)")
    coordinates = _coordinates(arguments.coordinates, mechanism,
                               columns if columns is not None else default_columns(mechanism, dof))
    loci = trace_loci(mechanism, start, columns=columns, ranges=ranges, counts=counts, kinds=kinds,
                      rng=np.random.default_rng(arguments.seed), survey=survey)
    from ..loci import locus_coordinates

    _, names = locus_coordinates(mechanism, start[None], coordinates)
    document = {"mechanism": mechanism.name, "source": describe_source(arguments), "coordinates": list(names),
                "pieces": [_piece(mechanism, piece, coordinates) for piece in loci.pieces],
                "branches": [_piece(mechanism, branch, coordinates) for branch in loci.branches],
                "coverage": loci.coverage}
    if arguments.out is not None:
        from ..figures.loci import draw_cspace_map

        write_figure(draw_cspace_map(mechanism, loci, coordinates, title=f"{mechanism.name}: singularity loci"),
                     arguments.out)
    if arguments.format == "json":
        out.write(outputs.json_text(document) + "\n")
    else:
        out.write(_text(document))
    if arguments.out is not None and arguments.format == "text":
        out.write(f"map written to {printable(arguments.out)}\n")
