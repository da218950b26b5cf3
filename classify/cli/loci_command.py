"""``closedchain loci FILE|NAME [--param K=V] [--configuration C] [--coordinates J1,J5|end-effector]
[--kinds actuator,end_effector,cspace] [--grid NAME=a:b:n NAME=a:b:n] [--section NAME=a:b:n]
[--out FIG.png|svg|pdf] [--format json|text]``: trace the singularity loci of a 1-, 2- or 3-dof mechanism
(:mod:`classify.loci`).

2 dof: the grid (default the actuated coordinates, 24 points over a turn
around the starting configuration, or over ± half a characteristic length
for a slide, :data:`classify.loci_grids.SLIDE_RANGE`) is
assembled by continuation from the starting configuration (``--configuration``,
else the home), and the loci through its seeds are followed on M as
curves. 3 dof: the same in sections at fixed values of a third coordinate
(``--section``, default the first actuated coordinate at 4 values, the
start's among them: −π, −π/2, 0 and π/2 from it for an angle, −½, −¼, 0 and
¼ of a characteristic length for a slide; the grid's default axes are then
the other two actuated coordinates), the grid of every section assembled by
one continuation, so all sections are on the starting configuration's
branch. 1 dof: M's branches are followed from sampled points of M and the
loci are points on them. Every point reported is confirmed singular of its
kind by the classification; C-space singularities (branch points) are
points, also searched for from where σ_r, the r-th singular value of DΦ (r
its rank at regular points), is locally smallest (1 and 2 dof,
:func:`classify.loci_search.search_cspace`).

``--coordinates``: what the loci are shown in — joint coordinates (comma
separated, as ``--at`` names them) or ``end-effector`` (its point). Default
the grid's coordinates (2 dof), the grid's and the section's (3 dof), the
actuated coordinate and the next one (1 dof).

``--format json``: ``{"mechanism", "source", "coordinates": [names],
"pieces": [{"kind", "closed", "configurations": [{joint: displacement}],
"coordinates": [[...]], "residuals": [...], "whole_branch"}], "branches": [...same, 1 dof],
"coverage": {...}}``; 3 dof: each piece also has its ``"section"`` (the
section coordinate's value, a displacement from home), and the coverage
``"section": {name: [a, b, n]}`` and ``"sections": [{"value", "reached",
"seeds", "pieces"}]``. 1 dof: ``"whole_branch": true`` marks a piece that is
a whole branch of M along which the kind's sign function vanishes
identically, and the coverage's ``"whole_branch": [{"kind", "branch",
"points", "largest", "tolerance"}]`` gives the largest magnitude of the sign
function along it (:func:`classify.loci_signs.sign_magnitudes`) against the
tolerance. Each configuration is given as joint displacements
from the mechanism's home exactly as ``--at`` takes them, so
``closedchain classify NAME --at '<one of them>'`` reproduces its verdict.
``--branches N`` (2 dof): the grid assembled on up to N assembly branches
(:func:`classify.grid_continuation.assemble_branches`), the loci traced on
all, the map's points coloured by branch; the coverage's
``"assembly_branches": {"found", "reached", "solutions", "asked"}``.
``--out``: the C-space map with the loci overlaid
(:func:`classify.figures.loci.draw_cspace_map`; 3 dof: the sections stacked
in 3-D, or, when ``--coordinates`` names two coordinates or a planar
end-effector, one panel per section, :func:`classify.figures.loci.draw_sections`);
the text or JSON is printed as well.
"""

from __future__ import annotations

from ..text import drawn, printable
from ._common import (InputError, check_output, common_options, configuration_options, entry_options, file_after_grid,
                      input_files, integer, source)

__all__ = ["add_parser", "run", "DEFAULT_COUNT"]

#: grid points per axis without --grid
DEFAULT_COUNT = 24


def add_parser(commands):
    parser = commands.add_parser("loci", help="trace the singularity loci of a 1-, 2- or 3-dof mechanism (3 dof: "
                                              "in sections), and its C-space map")
    parser.add_argument("file", nargs="?", metavar="FILE|NAME",  # optional to argparse: file_after_grid
                        help="mechanism file (YAML or JSON) or catalogue name")
    entry_options(parser)
    parser.add_argument("--coordinates", default=None, metavar="J1,J5|end-effector",
                        help="the coordinates the loci are shown in: joint coordinates or end-effector")
    parser.add_argument("--kinds", default="actuator,end_effector,cspace", metavar="K,...",
                        help="which loci: actuator, end_effector, cspace (default all)")
    parser.add_argument("--grid", nargs="+", action="extend", default=None, metavar="NAME=a:b:n",
                        help="2 and 3 dof: the two grid axes the seeds are searched on (default the actuated "
                             f"coordinates, {DEFAULT_COUNT} points over a turn, or over ± half a "
                             "characteristic length for a slide)")
    parser.add_argument("--section", default=None, metavar="NAME=a:b:n",
                        help="3 dof: the coordinate held in each section and its values (default the first "
                             "actuated coordinate at 4 values around the start's, the start's among them)")
    parser.add_argument("--branches", type=integer, default=1, metavar="N",
                        help="2 dof: assemble the grid on up to N assembly branches (the start's, then others found "
                             "by solving the loops from random values at a few grid points; default 1)")
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


def _grid(arguments, mechanism, dof):
    """(columns, ranges, counts) of --grid and --section for :func:`classify.loci.trace_loci` (Nones where
    defaulted)."""
    from ..loci import SECTION_COUNT, default_columns
    from ._grid import parse_grid

    if arguments.grid is not None and dof == 1:
        raise InputError("--grid: applies to 2- and 3-dof mechanisms (a 1-dof C-space is followed from sampled "
                         "points)")
    if arguments.section is not None and dof != 3:
        raise InputError(f"--section: applies to 3-dof mechanisms (this one has {dof} dof)")
    if arguments.grid is None and arguments.section is None:
        return None, None, (DEFAULT_COUNT, DEFAULT_COUNT)
    columns, ranges, counts = [], [], []
    if arguments.grid is not None:
        grid = parse_grid(arguments.grid, mechanism)
        if len(grid.names) != 2 or min(grid.counts) < 2:
            raise InputError(f"--grid: expected two axes NAME=a:b:n with n ≥ 2 (a {dof}-dof locus grid)")
        columns, ranges, counts = list(grid.columns), list(zip(grid.starts, grid.stops)), list(grid.counts)
    if dof == 2:
        return columns, ranges, counts
    section = None
    if arguments.section is not None:
        section = parse_grid([arguments.section], mechanism, "--section")
        section = (section.columns[0], (section.starts[0], section.stops[0]), section.counts[0])
        if section[0] in columns:
            raise InputError("--section: its coordinate is a --grid axis too")
    defaults = default_columns(mechanism, 3)
    if not columns:  # the grid's default axes: the default ones without the section's coordinate
        others = [column for column in defaults if section is None or column != section[0]]
        columns = others[:2]
        ranges, counts = [None, None], [DEFAULT_COUNT, DEFAULT_COUNT]
    if section is None:
        column = next(column for column in defaults[2:] + defaults[:2] + list(range(mechanism.ambient_dimension))
                      if column not in columns)
        section = (column, None, SECTION_COUNT)
    return columns + [section[0]], ranges + [section[1]], counts + [section[2]]


def _piece(mechanism, piece, coordinates):
    from ..loci import locus_coordinates
    from ._configurations import displacements_of, joint_displacements

    values, _ = locus_coordinates(mechanism, piece.points, coordinates)
    entry = {"kind": piece.kind, "closed": piece.closed,
             "configurations": joint_displacements(mechanism, displacements_of(mechanism, piece.points)),
             "coordinates": values.tolist(), "residuals": piece.residuals.tolist(),
             "whole_branch": piece.whole_branch}
    if piece.section is not None:
        entry["section"] = piece.section
    return entry


#: below this share of the grid reached on the start's assembly branch, the text suggests a finer grid or more
#: branches (a degenerate five-bar's 5 × 3 grid over a turn of each actuator reaches 1 point, its 10 × 10 one 39),
#: and, when a grid or section coordinate is a slide, a narrower range (a 3-RPR's grid over ±8.6, twice its
#: characteristic length, reached 1 point of 2304: its legs are 1.9 long)
SPARSE_GRID = 0.1


def _sparse_hint(coverage, slides):
    """The text's line for a grid whose share of points reached is below :data:`SPARSE_GRID`: `slides` are the
    grid's and section's slide coordinates (whose range can be wider than the mechanism reaches; an angle's
    default is a turn)."""
    finer = "a finer --grid" + (" or --branches 2" if coverage["dof"] == 2 else "")
    if not slides:
        return (f"  few grid points are on the start's assembly branch and connected to it at this spacing: {finer} "
                f"may seed more loci")
    options = "--grid or --section" if "section" in coverage else "--grid"
    return (f"  few grid points are on the start's assembly branch and connected to it: the range of "
            f"{', '.join(printable(name) for name in slides)} may be wider than the mechanism reaches (a narrower "
            f"{options} range), or at this spacing {finer} may seed more loci")


def _text(document, slides=()):
    coverage = document["coverage"]
    lines = [f"loci of {printable(document['mechanism'])} ({coverage['dof']} dof), shown in "
             f"{', '.join(printable(name) for name in document['coordinates'])}"]
    if "grid" in coverage:
        grid = ", ".join(f"{printable(name)} from {low:.4g} to {high:.4g} in {count}"
                         for name, (low, high, count) in coverage["grid"].items())
        sections = ""
        if "section" in coverage:
            (name, (low, high, count)), = coverage["section"].items()
            sections = f" in {count} section(s) {printable(name)} from {low:.4g} to {high:.4g}"
        lines.append(f"  grid: {grid}{sections}; {coverage['reached']} of {coverage['grid_points']} points "
                     f"reached")
        if "assembly_branches" not in coverage and coverage["reached"] < SPARSE_GRID * coverage["grid_points"]:
            lines.append(_sparse_hint(coverage, slides))
    if "branches" in coverage:
        closed = sum(coverage["branches_closed"])
        lines.append(f"  branches of M: {coverage['branches']} ({closed} closed), from {coverage['samples']} "
                     f"sampled points")
    for kind, count in coverage["pieces"].items():
        pieces = [piece for piece in document["pieces"] if piece["kind"] == kind]
        closed = sum(piece["closed"] for piece in pieces)
        points = sum(len(piece["configurations"]) for piece in pieces)
        whole = sum(piece.get("whole_branch", False) for piece in pieces)
        lines.append(f"  {kind.replace('_', '-')}: {count} piece(s), {closed} closed, {points} point(s)"
                     + (f", {whole} a whole branch of M" if whole else "")
                     + (f"; not traced: {coverage['not_traced'][kind]}" if kind in coverage["not_traced"] else ""))
    start = coverage.get("start")
    if start is not None and start["singular"]:
        lines.append("  the start is singular for the grid's coordinates" + (
            f": the grid points it leaves were continued from a regular neighbour on M {start['moved']:.3g} away "
            f"(margin {start['margin']:.2g} > {start['tolerance']:g})" if start["moved"] else ""))
    if "assembly_branches" in coverage:
        found = coverage["assembly_branches"]
        lines.append(f"  assembly branches of the grid: {found['found']} (of at most {found['asked']}), reaching "
                     + ", ".join(str(count) for count in found["reached"]) + " grid point(s)")
    for record in coverage.get("whole_branch", ()):
        lines.append(f"  {record['kind'].replace('_', '-')} singular along the whole branch {record['branch'] + 1} "
                     f"(the JSON's branches[{record['branch']}], counted from 0): "
                     f"the sign function's magnitude at most {record['largest']:.2g} at its {record['points']} "
                     f"points (tolerance {record['tolerance']:g})")
    if "cspace_search" in coverage:
        search = coverage["cspace_search"]
        lines.append(f"  C-space singularities searched for from {search['seeds']} point(s) where σ_r(DΦ) is "
                     f"locally smallest: {search['found']} found, {search['confirmed']} confirmed")
    if "actuator_search" in coverage:
        search = coverage["actuator_search"]
        lines.append(f"  actuator singularities (redundant actuation) searched for from {search['seeds']} point(s) "
                     f"where σ_k([DΦ; Dπ]) is locally smallest: {search['found']} found, {search['confirmed']} "
                     f"confirmed")
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

    file_after_grid(arguments)
    if arguments.out is not None:
        figure_path(arguments.out)
        check_output(arguments.out, "--out", input_files(arguments))
    kinds = parse_kinds(arguments.kinds)
    if arguments.branches < 1:
        raise InputError(f"--branches: at least 1, got {arguments.branches}")
    mechanism, named = source(arguments)
    start = configuration(mechanism, named, where=configuration_options(arguments, {}),
                          remedy="give closing values").point
    model = model_of(mechanism, arguments.length_scale)
    survey = survey_of(model)
    dof = mechanism.ambient_dimension - survey.constraint_rank
    if dof not in (1, 2, 3):
        raise InputError(f"loci: traced for 1-, 2- and 3-dof mechanisms; {printable(mechanism.name)} has {dof} "
                         f"dof")
    if arguments.branches != 1 and dof != 2:
        raise InputError(f"--branches: applies to a 2-dof mechanism's grid; {printable(mechanism.name)} has {dof} "
                         f"dof")
    columns, ranges, counts = _grid(arguments, mechanism, dof)
    coordinates = _coordinates(arguments.coordinates, mechanism,
                               columns if columns is not None else default_columns(mechanism, dof, start))
    loci = trace_loci(mechanism, start, columns=columns, ranges=ranges, counts=counts, kinds=kinds,
                      rng=np.random.default_rng(arguments.seed), survey=survey, assembly_branches=arguments.branches)
    from ..loci import locus_coordinates

    _, names = locus_coordinates(mechanism, start[None], coordinates)
    document = {"mechanism": mechanism.name, "source": describe_source(arguments), "coordinates": list(names),
                "pieces": [_piece(mechanism, piece, coordinates) for piece in loci.pieces],
                "branches": [_piece(mechanism, branch, coordinates) for branch in loci.branches],
                "coverage": loci.coverage}
    if arguments.out is not None:
        from ..figures.loci import draw_cspace_map, draw_sections

        title = f"{drawn(mechanism.name)}: singularity loci"
        flat = len(names) <= 2  # a 3-dof mechanism's sections as panels, else stacked in 3-D
        figure = (draw_sections(mechanism, loci, coordinates, title=title, units=True) if dof == 3 and flat
                  else draw_cspace_map(mechanism, loci, coordinates, title=title, units=True))
        write_figure(figure, arguments.out)
    if arguments.format == "json":
        out.write(outputs.json_text(document) + "\n")
    else:
        from ..loci_coordinates import _is_angle

        names = [*loci.coverage.get("grid", ()), *(name for name, (low, high, _) in loci.coverage.get("section", {})
                                                   .items() if high > low)]  # a single section has no range
        out.write(_text(document, [name for name in names
                                   if not _is_angle(mechanism, mechanism.coordinate_names.index(name))]))
    if arguments.out is not None and arguments.format == "text":
        out.write(f"map written to {printable(arguments.out)}\n")
