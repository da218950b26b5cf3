"""``closedchain classify FILE|NAME [--configuration C] [--param K=V] [--at JSON|@file] [--project |
--assemble [--branch N]] [--survey FILE] [--format json|text]``: classify ``home ⊕ at`` (docs/design.rst, "CLI"),
or the assembly with the ``--at`` joints held at exactly those values (:func:`mechanisms.assemble`).

``closedchain classify FILE|NAME --batch FILE.{json,jsonl,csv,npy} [--project] [--survey FILE] [--threads T]
[--out FILE.{jsonl,json,csv,npz}] [--format json|text]``: classify many configurations at once, each given as
``--at`` gives one (joint displacements from home; the file formats and their limits in
:mod:`classify.cli._batch_io`), with one :func:`classify.classify_many` call (its chunks in ``--threads`` threads,
every usable core by default). With ``--project`` each is projected onto M first; otherwise a configuration that does not close
the loops is refused, naming its row. Output: JSON
lines (one object per configuration: ``row``, then :meth:`classify.Classifications.rows`, then the
``displacements`` of the configuration classified, and ``projection_distance`` with ``--project``) on stdout, or
a compact table (``--format text``), or ``--out FILE``: ``.jsonl``, ``.json`` (a list of the same objects),
``.csv`` (flattened; a joint's displacements in columns named by its coordinates, ``displacements_S1[x]``,
so that they read back as a batch file) or ``.npz`` (:meth:`classify.Classifications.arrays` with ``row``, ``points``,
``displacements``, ``coordinate_names``), with a one-line summary on stdout.

``--survey FILE``: the survey of M comes from a cache file when the file exists and was made for this mechanism
(:mod:`classify.survey_cache`), else it is computed and written there.
"""

from __future__ import annotations

from ..progress import show_progress
from ..text import printable
from ._common import (
    InputError, check_length_scale, check_output, closures_option, common_options, configuration_options, displacements,
    dumps, entry_options, entry_values, input_files, integer, is_entry, source, survey_option, threads_option,
    warn_if_serial,
)

__all__ = ["add_parser", "run", "describe_source"]


def describe_source(arguments, at=None):
    """Where a command's configuration comes from, as the JSON ``source`` object.

    Parameters
    ----------
    arguments : argparse.Namespace
        With ``file`` (FILE|NAME), ``configuration`` and ``param``.
    at : dict, optional
        The displacements given with ``--at`` (recorded when not empty).

    Returns
    -------
    dict
        ``{"catalogue": NAME, "parameters": {...}, "configuration": C}`` (every
        parameter of the entry, the paper's input values included) or
        ``{"file": PATH, "configuration": C}``; C is None without
        ``--configuration``.
    """
    from mechanisms import catalogue

    if is_entry(arguments.file):
        item = catalogue.entry(arguments.file)
        result = {"catalogue": item.name, "parameters": entry_values(item, arguments),
                  "configuration": arguments.configuration}
    else:
        result = {"file": arguments.file, "configuration": arguments.configuration}
        if getattr(arguments, "closures", None) is not None:
            result["closures"] = arguments.closures
    if at:
        result["at"] = at
    return result


def add_parser(commands):
    parser = commands.add_parser("classify", help="classify one configuration, or a batch of them, of a mechanism "
                                                  "file or catalogue entry")
    parser.add_argument("file", metavar="FILE|NAME", help="mechanism file (YAML or JSON), URDF (with --closures), "
                                                          "MJCF (.xml) or catalogue name")
    entry_options(parser)
    closures_option(parser)
    parser.add_argument("--at", default=None,
                        help="joint displacements from home as a JSON object, or @file.json")
    parser.add_argument("--batch", default=None, metavar="FILE",
                        help="classify every configuration of FILE (.json, .jsonl, .csv or .npy), each given as "
                             "joint displacements from home as --at takes them; JSON lines out")
    parser.add_argument("--project", action="store_true",
                        help="project a configuration that does not close onto the C-space")
    parser.add_argument("--assemble", action="store_true",
                        help="hold the --at joints (and the other actuated joints) at exactly those values and "
                             "solve the loops for the others")
    parser.add_argument("--branch", type=integer, default=None, metavar="N",
                        help="with --assemble: the N-th assembly at those inputs, by distance from home "
                             "(default: the one reached from home)")
    survey_option(parser)
    threads_option(parser)
    parser.add_argument("--out", default=None, metavar="FILE",
                        help="with --batch: write the results to FILE (.jsonl, .json, .csv or .npz) and print a "
                             "summary")
    parser.add_argument("--format", choices=("json", "text"), default=None,
                        help="json or text (default text; with --batch, JSON lines)")
    common_options(parser)
    return parser


def _assembled(mechanism, named, at, arguments):
    """(point, the assembly's JSON) with the --at joints held and the loops solved (`mechanisms.assemble`)."""
    import numpy as np

    from mechanisms import assemble

    if arguments.project:
        raise InputError("--assemble: give either --assemble or --project, not both")
    if not at:
        raise InputError("--assemble: name the joints to hold with --at, e.g. --at '{\"J1\": 0.3}'")
    reached = assemble(mechanism, at, branch=arguments.branch, guess=named or None,
                       rng=np.random.default_rng(arguments.seed), where="--at")
    return reached.point, reached.to_dict()


def run(arguments, out):
    check_length_scale(arguments.length_scale)
    if arguments.batch is not None:
        _run_batch(arguments, out)
        return
    for option, given in (("--out", arguments.out is not None), ("--threads", arguments.threads is not None)):
        if given:
            raise InputError(f"{option}: applies with --batch")
    _run_single(arguments, out)


def _run_single(arguments, out):
    from dataclasses import replace

    import numpy as np

    from mechanisms import configuration

    from ..classification import classify
    from ..model import model_of
    from ._batch_io import model_survey

    mechanism, named = source(arguments)
    at = displacements(arguments.at)
    if arguments.branch is not None and not arguments.assemble:
        raise InputError("--branch: applies with --assemble")
    assembly, distance = None, 0.0
    if arguments.assemble:
        point, assembly = _assembled(mechanism, named, at, arguments)
    else:
        projected = configuration(mechanism, {**named, **at}, project_onto=arguments.project,
                                  where=configuration_options(arguments, at),
                                  remedy="give closing values, or use --assemble to hold the values given and solve "
                                         "the loops for the other joints, or --project to move the configuration onto "
                                         "the C-space (the values given move too)")
        point, distance = projected.point, projected.distance
    warn_if_serial(mechanism)
    survey = None if arguments.survey is None else model_survey(arguments.survey,
                                                                 model_of(mechanism, arguments.length_scale))
    rng = np.random.default_rng(arguments.seed)
    report = classify(mechanism, point, survey=survey, rng=rng, length_scale=arguments.length_scale)
    report = replace(report, source=describe_source(arguments, at))
    imported = getattr(arguments, "imported", None)
    if arguments.format == "json":
        result = report.to_dict()
        if imported is not None:
            result["import"] = imported.to_dict()
        if arguments.project:
            result["projection_distance"] = distance
        if assembly is not None:
            result["assembly"] = assembly
        out.write(dumps(result) + "\n")
    else:
        if imported is not None:
            out.write("".join(f"imported: {printable(note)}\n" for note in imported.notes))
        if distance:
            out.write(f"projected onto the C-space: moved by {distance:.3g}\n")
        if assembly is not None:
            found = ("not an isolated assembly (the held joints leave it free to move), so not numbered"
                     if assembly["branch"] is None else f"branch {assembly['branch']} of {assembly['branches']} found")
            out.write(f"assembled with {', '.join(printable(name) for name in assembly['held'])} held: {found}, "
                      f"residual {assembly['residual']:.1e}\n")
        out.write(report.to_text() + "\n")


def _check_batch_options(arguments):
    for option, given in (("--at", arguments.at is not None), ("--assemble", arguments.assemble),
                          ("--branch", arguments.branch is not None)):
        if given:
            raise InputError(f"{option}: does not apply with --batch (the batch file gives the configurations; "
                             f"`closedchain map` assembles grids of inputs)")
    if arguments.seed:
        raise InputError("--seed: does not apply with --batch (the batch classification is deterministic)")
    if arguments.out is not None and arguments.format is not None:
        raise InputError("--format: applies to what is printed; with --out the file's suffix gives the format")


def _batch_points(arguments, mechanism, named):
    """The batch's configurations on M, and their projection distances (None without --project)."""
    from mechanisms import CLOSURE_TOLERANCE, validate_displacements

    from . import _configurations as configurations
    from ._batch_io import read_batch

    validate_displacements(mechanism, named, "--configuration")
    base = configurations.displacement_vector(mechanism, named)
    matrix = read_batch(arguments.batch, mechanism, base)
    points = configurations.points_of(mechanism, matrix)
    where = f"--batch: {printable(arguments.batch)}"
    if arguments.project:
        points, reached, distance = configurations.project_configurations(mechanism, points, CLOSURE_TOLERANCE)
        if not reached.all():
            row = int(reached.argmin())
            raise InputError(f"{where}: row {row + 1}: projection onto the configuration space failed (no "
                             f"configuration closing the loops near it)")
        return points, distance
    row, residual = configurations.off_manifold_row(mechanism, points, CLOSURE_TOLERANCE)
    if row is not None:
        problem = (f"|Φ| = {residual:.3g} > {CLOSURE_TOLERANCE:g}" if residual > CLOSURE_TOLERANCE
                   else "a loop closes with a half-turn")
        raise InputError(f"{where}: row {row + 1}: the configuration does not close the loops ({problem}); give "
                         f"closing values or use --project")
    return points, None


def _run_batch(arguments, out):
    import numpy as np

    from ..batch import classify_many
    from ..model import model_of
    from . import _outputs as outputs
    from ._batch_io import model_survey
    from ._configurations import displacements_of, joint_displacements

    _check_batch_options(arguments)
    file_format = outputs.output_format(arguments.out) if arguments.out is not None else None
    check_output(arguments.out, "--out", input_files(arguments))  # before the survey cache is written
    mechanism, named = source(arguments)
    points, distance = _batch_points(arguments, mechanism, named)
    warn_if_serial(mechanism)
    model = model_of(mechanism, arguments.length_scale)
    survey = model_survey(arguments.survey, model)
    result = classify_many(model, points, survey=survey, progress=show_progress(),
                          workers=-1 if arguments.threads is None else arguments.threads)
    displacements_matrix = displacements_of(mechanism, result.points)
    summary = "classified " + outputs.summary_line(outputs.kind_counts(result), len(result))
    if file_format == "npz":
        arrays = dict(result.arrays())
        arrays.update({"row": np.arange(1, len(result) + 1), "points": result.points,
                       "displacements": displacements_matrix,
                       "coordinate_names": np.array(mechanism.coordinate_names)})
        if distance is not None:
            arrays["projection_distance"] = distance
        outputs.write_npz(arguments.out, arrays)
        out.write(f"{summary}; written to {printable(arguments.out)}\n")
        return
    rows = _rows(result, joint_displacements(mechanism, displacements_matrix), distance)
    if file_format is not None:
        outputs.write_rows(arguments.out, rows, mechanism=mechanism)
        out.write(f"{summary}; written to {printable(arguments.out)}\n")
    elif arguments.format == "text":
        table = outputs.result_table(("row",), [((str(row["row"]),), row) for row in rows])
        out.write(f"{table}\n\n{summary}\n")
    else:
        import json

        out.write("".join(json.dumps(row, ensure_ascii=False, allow_nan=False) + "\n" for row in rows))


def _rows(result, displacements, distance):
    """The JSON-ready row of each configuration: ``row`` (from 1), :meth:`classify.Classifications.rows`, the
    ``displacements`` classified, and ``projection_distance`` with --project."""
    rows = []
    for index, (row, given) in enumerate(zip(result.rows(), displacements)):
        entry = {"row": index + 1, **row, "displacements": given}
        if distance is not None:
            entry["projection_distance"] = float(distance[index])
        rows.append(entry)
    return rows
