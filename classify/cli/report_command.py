"""``closedchain report [PATH|NAME ...] [--closures FILE] [--output FILE] [--html FILE] [--jobs N]
[--format json|text]``: classify the catalogue (every entry at its defaults and at each named configuration), or
every mechanism file under the paths, with the derived Gosselin–Angeles kinds alongside.

A robot file is imported and assembled (:func:`classify.cli._common.import_file`): a URDF given by name with its
``--closures`` file, an MJCF ``.xml`` file, and in a folder every ``.urdf`` with the ``.yaml`` of the same stem
beside it as its closures file (the layout of the example-parallel-robots collection); it is classified at the
closed configuration reached, its ``home``.

The configurations of one design share one survey of M (:func:`classify.survey.survey`), and the designs run in
parallel (``--jobs``); every configuration is classified with its own generator seeded by ``--seed``, so the
report does not depend on the number of jobs.
"""

from __future__ import annotations

import functools
import textwrap
from collections import Counter
from dataclasses import dataclass, replace
from pathlib import Path
from typing import NamedTuple, Optional

from mechanisms import catalogue

from ..text import printable
from ._common import (
    IMPORT_SUFFIXES, MECHANISM_SUFFIXES, InputError, check_length_scale, check_output, closures_option,
    common_options, dumps, import_file, integer, is_entry, path_exists, same_file, write_output,
)

__all__ = ["add_parser", "run", "run_tasks", "report_table", "table_cells", "report_summary", "ReportRow",
           "JOINT_OUTPUTS", "CONFIGURATION_PARAMETERS", "LEGEND", "legend", "OUTPUT_SUFFIXES", "HTML_SUFFIXES"]

#: the suffixes of --output (text, Markdown-friendly text or JSON, as --format says; "": none)
OUTPUT_SUFFIXES = ("", ".txt", ".text", ".md", ".log", ".json")
#: the suffixes of --html
HTML_SUFFIXES = (".html", ".htm")

#: catalogue entry → the joints whose coordinates are the Gosselin–Angeles outputs, where the paper compares with a
#: joint output rather than the end-effector (whose dimension differs from the number of inputs): the first joint
#: of the list that is not actuated. The slider-crank: the slide's displacement x for the crank input θ
#: (Gosselin & Angeles 1990, eq. 9); driven by the slide (Park & Kim Fig. 3d), the crank angle.
JOINT_OUTPUTS = {"slider-crank": ("slide", "crank")}

#: catalogue entry → the parameters that place its mechanism in a configuration (inputs, pose, assembly branch,
#: working mode); the other parameters fix the design. Named configurations whose other parameters are equal are
#: configurations of one design and share one survey of M. Entries not listed share only between identical
#: parameter sets: the Gough–Stewart and 5-SPU builders orient universal joints along the legs at the requested
#: pose, so each pose is a design of its own.
CONFIGURATION_PARAMETERS = {
    "slider-crank": ("theta", "branch"),
    "five-bar": ("theta1", "theta2", "assembly", "theta3"),
    "spherical-six-bar": ("theta1", "theta2", "theta3", "branch"),
    "planar-six-bar": ("theta1", "theta2", "theta3", "branch"),
    "eclipse": ("x", "y", "z", "roll", "pitch", "yaw", "elbow"),
    "watt-six-bar": ("theta", "branch_rocker", "branch_output", "psi"),
    "planar-3rrr": ("x", "y", "phi", "mode1", "mode2", "mode3", "theta1", "theta2", "theta3"),
    "spherical-3rrr": ("rotation_x", "rotation_y", "rotation_z", "working_mode_1", "working_mode_2",
                       "working_mode_3", "theta_folded"),
    "3-prr": ("x", "y", "phi", "working_mode"),
    "3-prr-inputs": ("rho1", "rho2", "rho3", "x", "y", "phi"),
    "hybrid": ("theta1", "theta2", "theta3", "assembly", "theta4"),
}


@functools.cache
def legend():
    """What the report's table means (:data:`LEGEND`); the text report starts with it."""
    from ..comparison import REASONS  # imported when used: SymPy

    reason_lines = "\n".join(textwrap.fill(f"{reason}: {text}", width=114, initial_indent=" " * 6,
                                            subsequent_indent=" " * 8) for reason, text in REASONS.items())
    return _LEGEND.format(reasons=reason_lines)


def __getattr__(name):
    """:data:`LEGEND`, made on first use (it lists :data:`classify.comparison.REASONS`, whose module imports
    SymPy)."""
    if name == "LEGEND":
        return legend()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


#: :data:`LEGEND` with ``{reasons}`` for the lines of :data:`classify.comparison.REASONS`
_LEGEND = """\
closedchain report: the Park–Kim classification of each configuration, Gosselin–Angeles alongside.

Legend
  source, configuration  the catalogue entry (at its defaults: `default`) or the file (at its home: `home`) and
                         the named configuration; each row's account, below the table, gives the parameters and
                         the joint values.
  dof                    m, the dimension of the C-space M at the configuration.
  kinds                  the singularities found (cspace, actuator, end_effector), or `regular`.
  C-space, actuator,     r/e: the rank found here / the rank expected of it — DΦ: its rank on M nearby;
  end-effector           G: m − the idle freedoms; J: min(dim N, m, the largest rank of J on M). r < e is a
                         singularity of that kind. `-`: no end-effector.
    degenerate           an actuator singularity with a self-motion: locked, the actuators do not hold the
                         mechanism (a motion followed to a finite distance certifies it).
    nondegenerate        an actuator singularity where, locked, the mechanism is a structure.
    undetermined         the second-order test is inconclusive (or not run, at a C-space singularity): the
                         report does not guess.
    +i idle              i idle freedoms: motions that move neither an actuator nor the end-effector (a leg
                         spinning between two ball joints); not counted as singular.
    (architecture)       an architecture singularity: with the actuators locked, a freedom still moves the
                         end-effector at every configuration of M (Gosselin & Angeles 1990, eq. 87; the free
                         spin of the 5-SPU's tool seen by a pose end-effector), so every configuration is a
                         degenerate actuator singularity.
  κ                      the condition number λ₁/λₙ of the manipulability proper values; `∞` at an end-effector
                         singularity (λₙ = 0); `-` where they are not defined (no end-effector, an actuator or
                         a C-space singularity); with idle freedoms, of the motions that move something.
  G–A (derived)          Gosselin & Angeles's kinds from the matrices A, B derived from the mechanism: I (det B
                         = 0) ↔ end-effector, II (det A = 0) ↔ actuator, III (both) ↔ both or C-space;
                         `regular`; `undefined` where A and B are not n × n. The outputs are the end-effector's
                         coordinates, or `[outputs …]` the joint coordinates the paper uses (Park–Kim then
                         classified with the same outputs). A reason in brackets when the two do not
                         correspond:
{reasons}
"""


class ReportRow(NamedTuple):
    """One configuration of the report.

    Attributes
    ----------
    source : str
        The catalogue name or the file.
    name : str
        The configuration's name (``default``, ``home`` or a named configuration).
    report : Report
        Park–Kim, with the mechanism's own end-effector.
    comparison : ComparisonRow
        Gosselin–Angeles from the derived matrices, and how it corresponds.
    outputs : tuple of str or None
        The output coordinates of the comparison when they are joint coordinates (:data:`JOINT_OUTPUTS`);
        None: the end-effector's.
    """

    source: str
    name: str
    report: object
    comparison: object
    outputs: Optional[tuple] = None


@dataclass(frozen=True)
class _Task:
    """A unit of work: configurations of one source, in report order, that share their surveys.

    `closures` is the closures file of a URDF source (None: none, or not a URDF).
    """

    source: str
    names: tuple
    is_file: bool = False
    closures: Optional[str] = None


class _Configuration(NamedTuple):
    """One configuration of a task, as the report classifies and draws it: the mechanism built for it, the point,
    and the report's ``source`` account."""

    name: str
    mechanism: object
    point: object
    source: dict


def add_parser(commands):
    parser = commands.add_parser("report", help="classify the catalogue, or every mechanism file under the paths")
    parser.add_argument("paths", nargs="*", default=[], metavar="PATH|NAME",
                        help="mechanism files, robot files (URDF with --closures, MJCF .xml), folders or catalogue "
                             "names (default: every catalogue entry, at its defaults and at each named "
                             "configuration); in a folder, a URDF's closures file is the .yaml of its stem")
    parser.add_argument("--output", default=None,
                        help="write the report to this file and print only a summary")
    parser.add_argument("--html", default=None, metavar="FILE",
                        help="also write the report as one self-contained HTML page, with each configuration drawn "
                             "and the singularity loci of each design of one to three dof")
    parser.add_argument("--jobs", type=integer, default=None, metavar="N",
                        help="processes to run in parallel (default: the available cores; 1: none)")
    parser.add_argument("--format", choices=("json", "text"), default="text")
    closures_option(parser)
    common_options(parser)
    return parser


def _folder_files(folder):
    """(path, closures) of the files under a folder: mechanism files, and each URDF with the ``.yaml`` of its stem
    beside it as its closures file (that YAML is not read as a mechanism file)."""
    found = sorted(path for path in folder.rglob("*") if path.suffix in (*MECHANISM_SUFFIXES, ".urdf"))
    closures = {path.with_suffix(".yaml"): path for path in found if path.suffix == ".urdf"}
    files = []
    for path in found:
        if path.suffix == ".urdf":
            beside = path.with_suffix(".yaml")
            files.append((path, str(beside) if beside.is_file() else None))
        elif path not in closures:
            files.append((path, None))
    return files


def _looks_like_urdf(path):
    from mechanisms.urdf import looks_like_urdf  # imported when used: NumPy

    return looks_like_urdf(path)


def _mechanism_files(paths, closures=None):
    """(path, closures file or None) of every file to report: the files named, and those under the folders
    (:func:`_folder_files`); `closures` (``--closures``) goes with the one URDF named."""
    files, named = [], []
    for path in map(Path, paths):
        if not path_exists(path):
            raise InputError(f"{printable(path)}: no such file or folder")
        if path.is_dir():
            files += _folder_files(path)
            continue
        if path.suffix == ".urdf" or (path.suffix == ".xml" and _looks_like_urdf(path)):
            named.append(len(files))
        files.append((path, None))
    if closures is not None:
        if len(named) != 1:
            raise InputError(f"--closures: applies to one URDF file named on the command line, got {len(named)}")
        files[named[0]] = (files[named[0]][0], closures)
    if not files:
        raise InputError(f"no mechanism files (.yaml, .yml, .json, .urdf) under {', '.join(map(printable, paths))}")
    return files


# ------------------------------------------------------------------------------------------------ the table

def _rank(result):
    return "-" if result is None else f"{result.rank}/{result.expected_rank}"


def _actuator_cell(report):
    cell = _rank(report.actuator) + (f" {report.degeneracy}" if report.degeneracy else "")
    cell += f" +{report.idle_freedoms} idle" if report.idle_freedoms else ""
    return cell + (" (architecture)" if report.architecture_singular else "")


def _condition_cell(report):
    if report.manipulability is None:
        return "-"
    value = report.manipulability.condition_number
    return "∞" if value is None else f"{value:.3g}"


def _gosselin_angeles_cell(comparison, outputs):
    cell = comparison.gosselin_angeles.label + ("" if comparison.agree else f" ({comparison.reason})")
    return cell + (f" [outputs {', '.join(map(printable, outputs))}]" if outputs else "")


def table_cells(rows):
    """The header and the cells of the report's table, one tuple of str per :class:`ReportRow` (or
    ``(source, name, report, comparison)`` tuple); names are escaped (:func:`classify.report.printable`).

    The last column is Gosselin–Angeles's kinds from the derived matrices.
    """
    header = ("source", "configuration", "dof", "kinds", "C-space", "actuator", "end-effector", "κ",
              "G–A (derived)")
    lines = []
    for row in (ReportRow(*row) for row in rows):
        report = row.report
        lines.append((printable(row.source), printable(row.name), str(report.dof),
                      report.label, _rank(report.cspace), _actuator_cell(report),
                      _rank(report.end_effector), _condition_cell(report),
                      _gosselin_angeles_cell(row.comparison, row.outputs)))
    return header, lines


def report_table(rows):
    """A fixed-width table of :func:`table_cells`, one line per :class:`ReportRow`."""
    header, lines = table_cells(rows)
    widths = [max(len(line[i]) for line in lines + [header]) for i in range(len(header))]
    text = ["  ".join(cell.ljust(width) for cell, width in zip(line, widths)).rstrip() for line in [header] + lines]
    text.insert(1, "  ".join("-" * width for width in widths))
    return "\n".join(text)


def _comparison_text(row):
    comparison = row.comparison
    verdict = "corresponds" if comparison.agree else f"differs: {comparison.reason}"
    outputs = f", outputs {', '.join(map(printable, row.outputs))}" if row.outputs else ""
    return (f"Gosselin–Angeles (derived{outputs}): {comparison.gosselin_angeles.label} "
            f"({verdict}; {printable(comparison.note)})")


def _import_lines(row):
    """The lines that say how an imported robot was read and assembled (none for other sources)."""
    origin = row.report.source or {}
    lines = [f"  closures: {printable(origin['closures'])}"] if "closures" in origin else []
    return "".join(f"{line}\n" for line in lines + [f"  imported: {printable(note)}"
                                                    for note in origin.get("import", {}).get("notes", ())])


def _text(rows):
    details = "\n\n".join(f"== {printable(row.source)} [{printable(row.name)}]\n{_import_lines(row)}"
                          f"{row.report.to_text()}\n  {_comparison_text(row)}" for row in rows)
    return legend() + "\n" + report_table(rows) + "\n\n" + details


def _json(rows):
    result = []
    for row in rows:
        classified = row.report.to_dict()
        origin = classified.pop("source", None) or {}
        comparison = row.comparison.to_dict(park_kim=False)
        comparison["outputs"] = None if row.outputs is None else list(row.outputs)
        if row.outputs is not None:
            comparison["park_kim_kinds"] = list(row.comparison.park_kim.kinds)
        result.append({"source": row.source, "configuration_name": row.name,
                       **{key: origin[key] for key in ("parameters", "closures", "import") if key in origin},
                       **classified, "comparison": comparison})
    return dumps(result)


def report_summary(rows, output, json=False):
    """Three lines for the terminal: the counts by kind, the Gosselin–Angeles agreement and where the report is.

    Parameters
    ----------
    rows : sequence of ReportRow
    output : str
        Where the report was written.
    json : bool
        Whether it was written as JSON (one object per configuration, no legend or table).

    Returns
    -------
    str
    """
    kinds = Counter(kind for row in rows for kind in row.report.kinds)
    degeneracy = Counter(row.report.degeneracy for row in rows if row.report.degeneracy)
    regular = sum(not row.report.kinds for row in rows)
    sources = len(dict.fromkeys(row.source for row in rows))
    agree = sum(row.comparison.agree for row in rows)
    undefined = sum(not row.comparison.gosselin_angeles.defined for row in rows)
    by_kind = ", ".join(f"{count} {kind.replace('_', '-')}" for kind, count in sorted(kinds.items()))
    split = ", ".join(f"{degeneracy[name]} {name}" for name in ("degenerate", "nondegenerate", "undetermined")
                      if degeneracy[name])
    lines = [f"classified {len(rows)} configurations of {sources} mechanism(s): {regular} regular; "
             f"singular: {by_kind or 'none'}" + (f" (actuator: {split})" if split else ""),
             f"Gosselin–Angeles (derived): {agree} correspond, {len(rows) - agree - undefined} differ, "
             f"{undefined} undefined",
             (f"the whole report (one JSON object per configuration) is in {printable(output)}" if json else
              f"the whole report (legend, table, one account per configuration) is in {printable(output)}")]
    return "\n".join(lines)


# ------------------------------------------------------------------------------------------------ the work

def _design(item, name):
    """The key of the design a named configuration of a catalogue entry belongs to."""
    placing = set(CONFIGURATION_PARAMETERS.get(item.name, ()))
    values = item.values(None if name == "default" else name)
    return tuple((key, repr(value)) for key, value in values.items() if key not in placing)


def _catalogue_tasks(item):
    """One task per design of a catalogue entry, in order of first appearance."""
    groups = {}
    for name in ("default", *item.configurations):
        groups.setdefault(_design(item, name), []).append(name)
    return [_Task(item.name, tuple(names)) for names in groups.values()]


def _layout(mechanism):
    """What a shared survey needs to be identical: the coordinates, actuators and end-effector."""
    joints = tuple((joint.name, joint.type, joint.links, joint.actuated) for joint in mechanism.joints)
    end_effector = mechanism.end_effector
    return (mechanism.space, mechanism.coordinate_names, joints,
            None if end_effector is None else (end_effector.link, end_effector.output))


def _joint_outputs(entry_name, mechanism):
    """The output joints of the comparison (:data:`JOINT_OUTPUTS`), or None for the end-effector."""
    for joint in JOINT_OUTPUTS.get(entry_name, ()):
        if not mechanism.joint(joint).actuated:
            return (joint,)
    return None


class _Surveys:
    """Surveys of M shared by the configurations of one task, keyed by layout and outputs."""

    def __init__(self, seed):
        self.seed = seed
        self.known = {}

    def of(self, key, model):
        import numpy as np

        from ..survey import survey as survey_mechanism

        if key not in self.known:
            self.known[key] = survey_mechanism(model, np.random.default_rng(self.seed), starts=model.starts)
        return self.known[key]


def _configurations(task):
    """The configurations of a task, in its order: the one place that builds each configuration's mechanism and
    point for the rows and the pictures.

    A catalogue entry's configuration is its mechanism built at it (:meth:`mechanisms.catalogue.Entry.mechanism`)
    at its home; a mechanism file's are its home and named configurations, on the file's one mechanism; an
    imported robot (URDF + closures, MJCF) has one, ``home``, the closed configuration its import reached.

    Returns
    -------
    list of _Configuration
    """
    from mechanisms import configuration, home
    from mechanisms.io import read

    if not task.is_file:
        item = catalogue.entry(task.source)
        result = []
        for name in task.names:
            chosen = None if name == "default" else name
            mechanism = item.mechanism(chosen)
            result.append(_Configuration(name, mechanism, home(mechanism),
                                         {"catalogue": item.name, "parameters": item.values(chosen),
                                          "configuration": chosen}))
        return result
    path = Path(task.source)
    if path.suffix.lower() in IMPORT_SUFFIXES:
        imported = import_file(path, task.closures)
        origin = {"file": task.source, "configuration": None,
                  **({"closures": task.closures} if task.closures is not None else {}), "import": imported.to_dict()}
        return [_Configuration("home", imported.mechanism, home(imported.mechanism), origin)]
    document = read(path)
    named = {"home": {}, **document.configurations}
    return [_Configuration(name, document.mechanism,
                           configuration(document.mechanism, named[name],
                                         where=f"{printable(path)}: configurations[{name!r}]").point,
                           {"file": task.source, "configuration": None if name == "home" else name})
            for name in task.names]


def _catalogue_rows(task, seed, length_scale):
    """The rows of a catalogue task: each configuration classified on its own mechanism (built at it), with the
    design's shared surveys."""
    import numpy as np

    from mechanisms.joints import joint_coordinate_names

    from ..classification import classify
    from ..comparison import comparison_row
    from ..model import joint_output_model, model_of

    surveys = _Surveys(seed)
    rows = []
    for name, mechanism, point, origin in _configurations(task):
        check_length_scale(length_scale, mechanism)
        model, layout = model_of(mechanism, length_scale), _layout(mechanism)
        report = classify(model, point, survey=surveys.of(layout, model), rng=np.random.default_rng(seed))
        report = replace(report, source=origin)
        outputs = _joint_outputs(task.source, mechanism)
        compared_model, compared = model, report
        if outputs is not None:
            compared_model = joint_output_model(mechanism, outputs)
            compared = classify(compared_model, point, survey=surveys.of((layout, outputs), compared_model),
                                rng=np.random.default_rng(seed))
            outputs = tuple(name for joint in outputs for name in joint_coordinate_names(mechanism.joint(joint)))
        rows.append(ReportRow(task.source, name, report, comparison_row(compared_model, point, compared, name),
                              outputs))
    return rows


def _file_rows(task, seed, length_scale):
    """The rows of a mechanism file at its home and named configurations (or of an imported robot at its
    assembled home), with one survey from all of them."""
    import numpy as np

    from ..classification import classify
    from ..comparison import comparison_row
    from ..model import model_of
    from ..survey import survey as survey_mechanism

    configurations = _configurations(task)
    mechanism = configurations[0].mechanism
    check_length_scale(length_scale, mechanism)
    model = model_of(mechanism, length_scale)
    shared = survey_mechanism(model, np.random.default_rng(seed),
                              starts=np.stack([entry.point for entry in configurations]))
    rows = []
    for name, _, point, origin in configurations:
        report = classify(model, point, survey=shared, rng=np.random.default_rng(seed))
        report = replace(report, source=origin)
        rows.append(ReportRow(task.source, name, report, comparison_row(model, point, report, name)))
    return rows


def _rows(task, seed, length_scale):
    """The report rows of one task (run in a worker process)."""
    return (_file_rows if task.is_file else _catalogue_rows)(task, seed, length_scale)


def run_tasks(tasks, seed=0, length_scale=None, jobs=None):
    """Every task's rows, in task order, with a progress bar; in `jobs` processes (1: in this one).

    The rows do not depend on `jobs`: each configuration is classified with
    ``numpy.random.default_rng(seed)`` and each shared survey too.
    """
    work = functools.partial(_rows, seed=seed, length_scale=length_scale)
    return [row for rows in _map_tasks(work, tasks, jobs, "classifying") for row in rows]


def _map_tasks(work, tasks, jobs, description):
    """``[work(task) for task in tasks]``, in `jobs` processes (default the available cores; 1: in this one),
    with a progress bar counting configurations; the first error stops the rest."""
    from concurrent.futures import ProcessPoolExecutor, as_completed

    from ..progress import progress_bar
    from ..threads import available_cores

    jobs = min(available_cores() if jobs is None else jobs, len(tasks))
    with progress_bar(sum(len(task.names) for task in tasks), description) as progress:
        if jobs <= 1:
            results = []
            for task in tasks:
                results.append(work(task))
                progress.update(len(task.names))
            return results
        with ProcessPoolExecutor(max_workers=jobs) as executor:
            futures = {executor.submit(work, task): task for task in tasks}
            try:
                for future in as_completed(futures):
                    future.result()  # a worker's error stops the report at once
                    progress.update(len(futures[future].names))
            except BaseException:
                executor.shutdown(wait=False, cancel_futures=True)
                raise
            return [future.result() for future in futures]


# ------------------------------------------------------------------------------------------------ the HTML page

def _task_pictures(task, reports, seed=0):
    """The pictures of one task (run in a worker process): ``(source, name) → [Picture]`` for each configuration
    drawn (`reports`: ``(source, name) → Report``), and ``(source, None) → [Picture]`` for the loci of the task's
    design when it has one to three dof. The captions name the source and configuration as the table does
    (:func:`classify.text.printable`)."""
    from ..model import model_of
    from ..report_pictures import configuration_picture, loci_picture
    from ..survey import survey_of

    pictures, configurations = {}, _configurations(task)
    source = printable(task.source)
    for name, mechanism, point, _ in configurations:
        pictures[task.source, name] = [configuration_picture(mechanism, point, reports[task.source, name],
                                                             f"{source}: {printable(name)}")]
    # the loci from the task's first configuration (from a singular one, the grid starts at a regular neighbour)
    name, mechanism, point, _ = configurations[0]
    loci = loci_picture(mechanism, point, survey_of(model_of(mechanism)),
                        f"{source} at {printable(name)}: C-space and singularity loci", seed=seed)
    if loci is not None:
        pictures[task.source, None] = [loci]
    return pictures


def _html(tasks, rows, arguments):
    """The HTML page of the report (:func:`classify.html_report.html_report`)."""
    from ..html_report import html_report

    reports = {(row.source, row.name): row.report for row in rows}
    work = functools.partial(_task_pictures, reports=reports, seed=arguments.seed)
    pictures = {}
    for found in _map_tasks(work, tasks, arguments.jobs, "drawing"):
        for key, value in found.items():
            pictures.setdefault(key, []).extend(value)
    return html_report(rows, pictures, summary=report_summary(rows, arguments.html), legend=legend())


def _tasks(arguments):
    """The tasks of the report, and every (source, configuration name) in report order."""
    from mechanisms.io import read

    names = [text for text in arguments.paths if is_entry(text)] if arguments.paths else catalogue.names()
    paths = [text for text in arguments.paths if not is_entry(text)]
    tasks, order = [], []
    for item in map(catalogue.entry, dict.fromkeys(names)):
        tasks += _catalogue_tasks(item)
        order += [(item.name, name) for name in ("default", *item.configurations)]
    if paths:
        for path, closures in dict.fromkeys((str(path), closures) for path, closures in
                                            _mechanism_files(paths, arguments.closures)):
            if Path(path).suffix.lower() in IMPORT_SUFFIXES:
                import_file(path, closures)  # a robot that cannot be imported stops the report before the work
                tasks.append(_Task(path, ("home",), is_file=True, closures=closures))
            else:
                tasks.append(_Task(path, ("home", *read(path).configurations), is_file=True))
            order += [(path, name) for name in tasks[-1].names]
    elif arguments.closures is not None:
        raise InputError("--closures: applies to a URDF file named on the command line, got none")
    return tasks, order


def run(arguments, out):
    check_length_scale(arguments.length_scale)
    if arguments.jobs is not None and arguments.jobs < 1:
        raise InputError(f"--jobs: expected a count ≥ 1, got {arguments.jobs}")
    for text in arguments.paths:
        if not text:
            raise InputError("PATH: an empty path (it would be read as the current folder)")
    for option, path in (("--output", arguments.output), ("--html", arguments.html)):
        if path == "":
            raise InputError(f"{option}: an empty path")
        if path and (Path(path).is_dir() or not Path(path).resolve().parent.is_dir()):
            raise InputError(f"{option}: cannot write {printable(path)}: "
                             + ("it is a folder" if Path(path).is_dir() else "its folder does not exist"))
    if arguments.output and arguments.html and same_file(arguments.output, arguments.html):
        raise InputError(f"--output, --html: one file for both ({printable(arguments.output)}): the page would "
                         "overwrite the text")
    for option, path, suffixes in (("--output", arguments.output, OUTPUT_SUFFIXES),
                                   ("--html", arguments.html, HTML_SUFFIXES)):
        if path and Path(path).suffix.lower() not in suffixes:
            shown = ", ".join(suffix for suffix in suffixes if suffix) + (" or none" if "" in suffixes else "")
            raise InputError(f"{option}: {printable(path)}: expected a file name ending in {shown}")
    tasks, order = _tasks(arguments)
    inputs = [(f"the input file {printable(task.source)}", task.source) for task in tasks if task.is_file]
    inputs += [(f"the closures file {printable(task.closures)}", task.closures) for task in tasks if task.closures]
    for option, path in (("--output", arguments.output), ("--html", arguments.html)):
        check_output(path, option, inputs)  # a file named, or one found under a folder named
    position = {key: index for index, key in enumerate(order)}
    rows = sorted(run_tasks(tasks, arguments.seed, arguments.length_scale, arguments.jobs),
                  key=lambda row: position[row.source, row.name])
    text = _json(rows) if arguments.format == "json" else _text(rows)
    if arguments.html:
        write_output(arguments.html, _html(tasks, rows, arguments), "--html")
    if not arguments.output:
        out.write(text + "\n")
        return
    write_output(arguments.output, text + "\n", "--output")
    out.write(report_summary(rows, arguments.output, json=arguments.format == "json") + "\n")
    if arguments.html:
        out.write(f"the same report as a page with pictures (drawings, loci) is in {printable(arguments.html)}\n")
