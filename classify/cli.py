"""The ``closedchain`` command.

``closedchain classify FILE|NAME [--configuration C] [--param k=v ...] [--at JSON|@file]
[--project] [--format json|text]`` classifies ``home ⊕ at`` (DESIGN.md, "CLI") of a
mechanism file or of a catalogue entry; ``closedchain report [PATH ...]``
classifies every mechanism file under the paths (default: every catalogue
entry) at its home and at each of its named configurations and prints a table;
``closedchain catalog [NAME] [--write FILE]`` lists the catalogue, describes an
entry, or writes it as a mechanism file; ``closedchain compare FILE|NAME [--at …]
[--inputs J1,J5] [--outputs …] [--samples N] [--path N]`` classifies configurations
both the Park–Kim and the Gosselin–Angeles way and explains every difference.

Exit status: 0 done (singular or not), 2 bad input (one line on stderr), 1 an
internal error.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import traceback
from dataclasses import replace
from pathlib import Path

import numpy as np

from mechanisms import ConfigurationError, MechanismError, actuate, configuration, home
from mechanisms import catalogue
from mechanisms.io import read, save
from mechanisms.joints import joint_coordinate_names

from .classification import classify
from .comparison import compare, comparison_row, sample_configurations
from .gosselin_angeles_examples import RELATIONS
from .paths import path_configurations, singular_crossings
from .model import joint_output_model, model_of
from .survey import survey as survey_mechanism

__all__ = ["main", "report_table"]

MECHANISM_SUFFIXES = (".yaml", ".yml", ".json")


class InputError(Exception):
    """Bad input from the command line: exit status 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise InputError(message)


def _parser():
    parser = _Parser(prog="closedchain", description="Singularity analysis of closed kinematic chains.")
    commands = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    one = commands.add_parser("classify", help="classify one configuration of a mechanism file or catalogue entry")
    one.add_argument("file", metavar="FILE|NAME", help="mechanism file (YAML or JSON) or catalogue name")
    _entry_options(one)
    one.add_argument("--at", default=None,
                     help="joint displacements from home as a JSON object, or @file.json")
    one.add_argument("--project", action="store_true",
                     help="project a configuration that does not close onto the C-space")
    one.add_argument("--format", choices=("json", "text"), default="text")
    _common_options(one)
    many = commands.add_parser("report", help="classify the catalogue, or every mechanism file under the paths")
    many.add_argument("paths", nargs="*", default=[], metavar="PATH|NAME",
                      help="files, folders or catalogue names (default: every catalogue entry, "
                           "at its defaults and at each named configuration)")
    many.add_argument("--output", default=None, help="also write the report to this file")
    many.add_argument("--format", choices=("json", "text"), default="text")
    _common_options(many)
    both = commands.add_parser("compare", help="Park–Kim and Gosselin–Angeles side by side, with the reason "
                                                "for every difference")
    both.add_argument("file", metavar="FILE|NAME", help="mechanism file (YAML or JSON) or catalogue name")
    _entry_options(both)
    both.add_argument("--at", action="append", default=[], metavar="JSON",
                      help="a configuration: joint displacements from home as JSON or @file.json (repeatable)")
    both.add_argument("--project", action="store_true",
                      help="project configurations that do not close onto the C-space")
    both.add_argument("--inputs", default=None, metavar="J1,J2",
                      help="the driven joints, comma-separated (default: the mechanism's actuated joints)")
    both.add_argument("--outputs", default=None, metavar="J3,J4",
                      help="output joints, comma-separated: their coordinates are the outputs "
                           "(default: the end-effector's coordinates)")
    both.add_argument("--relation", default=None, metavar="NAME",
                      help="use the paper's F of a catalogue entry (e.g. eq9 for slider-crank) instead of the "
                           "matrices derived from the mechanism")
    both.add_argument("--samples", type=int, default=8, metavar="N",
                      help="also compare N configurations sampled over the assembly branches (default 8)")
    both.add_argument("--path", type=int, default=0, metavar="N",
                      help="also compare up to N configurations each way along a curve of M through the home, "
                           "and the actuator and end-effector singularities the curve crosses")
    both.add_argument("--path-step", type=float, default=0.05, metavar="H",
                      help="distance between configurations along the path (joint-coordinate units, default 0.05)")
    both.add_argument("--format", choices=("json", "text"), default="text")
    _common_options(both)
    listing = commands.add_parser("catalog", help="list the catalogue, describe an entry or write it to a file")
    listing.add_argument("name", nargs="?", default=None, help="catalogue name (default: list them all)")
    _entry_options(listing)
    listing.add_argument("--write", default=None, metavar="FILE",
                         help="write the entry as a mechanism file (.yaml, .yml or .json)")
    listing.add_argument("--format", choices=("json", "text"), default="text")
    return parser


def _entry_options(parser):
    parser.add_argument("--configuration", default=None, metavar="C",
                        help="a named configuration (of the catalogue entry, or of the file)")
    parser.add_argument("--param", action="append", default=[], metavar="K=V",
                        help="a catalogue parameter (repeatable); see `closedchain catalog NAME`")


def _common_options(parser):
    parser.add_argument("--seed", type=int, default=0, help="seed of the random sampling (default 0)")
    parser.add_argument("--length-scale", type=float, default=None,
                        help="length scale of the SE(2)/SE(3) end-effector metric")


def _displacements(text):
    if text is None:
        return {}
    if text.startswith("@"):
        try:
            text = Path(text[1:]).read_text()
        except OSError as error:
            raise InputError(f"--at: cannot read {text[1:]!r}: {error.strerror}") from None
    try:
        value = json.loads(text)
    except json.JSONDecodeError as error:
        raise InputError(f"--at: invalid JSON: {error.msg} (line {error.lineno}, column {error.colno})") from None
    if not isinstance(value, dict):
        raise InputError(f"--at: expected a JSON object mapping joint names to displacements, "
                         f"got {type(value).__name__}")
    return value


def _check_length_scale(value):
    if value is not None and (not np.isfinite(value) or value <= 0):
        raise InputError(f"--length-scale: expected a positive finite number, got {value}")


def _is_entry(text):
    """Whether a FILE|NAME argument names a catalogue entry (an existing path always wins)."""
    return text in catalogue.names() and not Path(text).exists()


def _entry_values(item, arguments):
    """The entry's parameters: defaults, then the --configuration presets, then the --param texts."""
    return item.values(arguments.configuration,
                       **dict(catalogue.parse_parameter(item, text) for text in arguments.param))


def _source(arguments):
    """(mechanism, displacements of the named configuration) for FILE or catalogue NAME."""
    if _is_entry(arguments.file):
        item = catalogue.entry(arguments.file)
        return item.build(**_entry_values(item, arguments)), {}
    path = Path(arguments.file)
    if not path.exists() and path.suffix not in MECHANISM_SUFFIXES:
        raise InputError(f"{arguments.file}: no such file or catalogue entry (see `closedchain catalog`)")
    if arguments.param:
        raise InputError(f"--param: applies to catalogue entries, not to the file {arguments.file}")
    document = read(path)
    if arguments.configuration is None:
        return document.mechanism, {}
    if arguments.configuration not in document.configurations:
        known = ", ".join(document.configurations) or "none"
        raise InputError(f"--configuration: {path} has no configuration {arguments.configuration!r} "
                         f"(known: {known})")
    return document.mechanism, document.configurations[arguments.configuration]


def _run_classify(arguments, out):
    _check_length_scale(arguments.length_scale)
    mechanism, named = _source(arguments)
    displacements = {**named, **_displacements(arguments.at)}
    projected = configuration(mechanism, displacements, project_onto=arguments.project, where="--at")
    rng = np.random.default_rng(arguments.seed)
    report = classify(mechanism, projected.point, rng=rng, length_scale=arguments.length_scale)
    if arguments.format == "json":
        result = report.to_dict()
        if arguments.project:
            result["projection_distance"] = projected.distance
        out.write(json.dumps(result, indent=2, ensure_ascii=False) + "\n")
    else:
        if projected.distance:
            out.write(f"projected onto the C-space: moved by {projected.distance:.3g}\n")
        out.write(report.to_text() + "\n")


def _entry_description(item, configuration_name, values):
    settings = ", ".join(f"{name}={value!r}" for name, value in values.items())
    at = f" at {configuration_name}" if configuration_name else ""
    return (f"closedchain catalogue entry {item.name}{at}: {item.summary} "
            f"From {item.reference}. Parameters: {settings}.")


def _joint_list(text, where):
    names = [name.strip() for name in text.split(",")]
    if not all(names):
        raise InputError(f"{where}: expected comma-separated joint names, got {text!r}")
    return names


def _paper_relation(arguments, mechanism, point):
    """The (relation, coordinates) named by --relation for a catalogue entry."""
    known = RELATIONS.get(arguments.file, {}) if _is_entry(arguments.file) else {}
    if arguments.relation not in known:
        entries = "; ".join(f"{name}: {', '.join(relations)}" for name, relations in RELATIONS.items())
        raise InputError(f"--relation: no relation {arguments.relation!r} for {arguments.file!r} "
                         f"(the paper's relations are: {entries})")
    try:
        return known[arguments.relation](mechanism, point)
    except ValueError as error:
        raise InputError(f"--relation: {arguments.relation} does not apply here: {error}") from None


def _path_rows(model, start, count, step):
    """Labels and points along a path of M through `start`, with the singularities it crosses in place."""
    path, steps = path_configurations(model, start, count, step=step)
    crossings = {}
    for index, point, kind in singular_crossings(model, path):
        crossings.setdefault(index, []).append((point, kind))
    labels, points = [], []
    for index, (point, step) in enumerate(zip(path, steps)):
        labels.append("home" if step == 0 else f"path{step:+d}")
        points.append(point)
        for crossing, kind in crossings.get(index, []):
            labels.append(f"crossing ({kind.replace('_', '-')})")
            points.append(crossing)
    return labels, points


def _run_compare(arguments, out):
    _check_length_scale(arguments.length_scale)
    for option in ("samples", "path"):
        if getattr(arguments, option) < 0:
            raise InputError(f"--{option}: expected a count ≥ 0, got {getattr(arguments, option)}")
    if not (np.isfinite(arguments.path_step) and arguments.path_step > 0):
        raise InputError(f"--path-step: expected a positive number, got {arguments.path_step}")
    mechanism, named = _source(arguments)
    if arguments.inputs is not None:
        mechanism = actuate(mechanism, _joint_list(arguments.inputs, "--inputs"), where="--inputs")
    output_names = None
    if arguments.outputs is not None:
        outputs = _joint_list(arguments.outputs, "--outputs")
        model = joint_output_model(mechanism, outputs, where="--outputs")
        output_names = tuple(name for joint in outputs for name in joint_coordinate_names(mechanism.joint(joint)))
    elif mechanism.end_effector is None:
        raise InputError(f"--outputs: {mechanism.name!r} has no end-effector; name the output joints")
    else:
        model = model_of(mechanism, arguments.length_scale)
    if not len(model.actuators):
        raise InputError(f"--inputs: {mechanism.name!r} has no actuated joint; name the input joints")
    start = configuration(mechanism, named, where="--configuration").point
    given = [configuration(mechanism, {**named, **_displacements(text)}, project_onto=arguments.project,
                           where="--at").point for text in arguments.at]
    rng = np.random.default_rng(arguments.seed)
    model = replace(model, starts=np.stack([start, *given]))
    labels, points = ["home"], [start]
    if arguments.path:
        labels, points = _path_rows(model, start, arguments.path, arguments.path_step)
    labels += [f"at{index}" for index in range(1, len(given) + 1)]
    points += given
    samples = sample_configurations(model, arguments.samples, rng)
    labels += [f"sample{index}" for index in range(1, len(samples) + 1)]
    points += list(samples)
    relation = coordinates = None
    if arguments.relation is not None:
        relation, coordinates = _paper_relation(arguments, mechanism, points[0])
    print(f"comparing {len(points)} configurations of {mechanism.name}", file=sys.stderr)
    result = compare(model, np.stack(points), labels, relation=relation, coordinates=coordinates, rng=rng,
                     output_names=output_names)
    if arguments.format == "json":
        out.write(json.dumps(result.to_dict(), indent=2, ensure_ascii=False) + "\n")
    else:
        out.write(result.to_text() + "\n")


def _run_catalog(arguments, out):
    if arguments.name is None:
        if arguments.write or arguments.param or arguments.configuration:
            raise InputError("catalog: --write, --param and --configuration need a catalogue NAME")
        items = catalogue.entries()
        if arguments.format == "json":
            out.write(json.dumps([_entry_dict(item) for item in items], indent=2, ensure_ascii=False) + "\n")
            return
        width = max(len(item.name) for item in items)
        for item in items:
            out.write(f"{item.name.ljust(width)}  {item.summary}\n")
            out.write(f"{'':{width}}  {item.reference}\n")
            if item.configurations:
                out.write(f"{'':{width}}  configurations: {', '.join(item.configurations)}\n")
        return
    item = catalogue.entry(arguments.name)
    values = _entry_values(item, arguments)
    mechanism = item.build(**values)
    if arguments.write:
        save(mechanism, arguments.write, description=_entry_description(item, arguments.configuration, values))
        print(f"{item.name} written to {arguments.write}", file=sys.stderr)
        return
    if arguments.format == "json":
        out.write(json.dumps({**_entry_dict(item), "values": values}, indent=2, ensure_ascii=False) + "\n")
        return
    lines = [f"{item.name}: {item.summary}", f"from {item.reference}", "", "parameters (value, default):"]
    lines += [f"  {name} = {value!r}  (default {item.parameters[name]!r})" for name, value in values.items()]
    lines += ["", "configurations:"]
    lines += [f"  {name}: " + ", ".join(f"{key}={value!r}" for key, value in presets.items())
              for name, presets in item.configurations.items()] or ["  none"]
    lines += ["", f"{mechanism.space} mechanism, {len(mechanism.joints)} joints, {mechanism.loop_count} loop(s), "
              f"actuated: {', '.join(joint.name for joint in mechanism.joints if joint.actuated) or 'none'}"]
    out.write("\n".join(lines) + "\n")


def _entry_dict(item):
    return {"name": item.name, "summary": item.summary, "reference": item.reference,
            "parameters": item.parameters,
            "configurations": {name: dict(presets) for name, presets in item.configurations.items()}}


def _mechanism_files(paths):
    files = []
    for path in map(Path, paths):
        if path.is_dir():
            files += sorted(p for p in path.rglob("*") if p.suffix in MECHANISM_SUFFIXES)
        elif path.exists():
            files.append(path)
        else:
            raise InputError(f"{path}: no such file or folder")
    if not files:
        raise InputError(f"no mechanism files (.yaml, .yml, .json) under {', '.join(map(str, paths))}")
    return files


def report_table(reports):
    """A fixed-width table of (source, configuration name, Report, ComparisonRow) rows; the source is a
    catalogue name or a file, the last column Gosselin–Angeles's kinds from the derived matrices."""
    header = ("source", "configuration", "dof", "kinds", "C-space", "actuator", "end-effector", "κ",
              "G–A (derived)")
    rows = []
    for source, name, report, comparison in reports:
        def rank(result):
            return "-" if result is None else f"{result.rank}/{result.expected_rank}"
        actuator = rank(report.actuator) + (f" {report.degeneracy}" if report.degeneracy else "")
        condition = "-"
        if report.manipulability is not None:
            value = report.manipulability.condition_number
            condition = "∞" if value is None else f"{value:.3g}"
        rows.append((source, name, str(report.dof), ", ".join(report.kinds) or "regular",
                     rank(report.cspace), actuator, rank(report.end_effector), condition,
                     comparison.gosselin_angeles.label + ("" if comparison.agree else f" ({comparison.reason})")))
    widths = [max(len(row[i]) for row in rows + [header]) for i in range(len(header))]
    lines = ["  ".join(cell.ljust(width) for cell, width in zip(row, widths)).rstrip()
             for row in [header] + rows]
    lines.insert(1, "  ".join("-" * width for width in widths))
    return "\n".join(lines)


def _reported(model, name, point, survey, rng):
    """(Report, ComparisonRow) of one configuration: Park–Kim, then the derived Gosselin–Angeles side."""
    report = classify(model, point, survey=survey, rng=rng)
    return report, comparison_row(model, point, report, name)


def _file_reports(paths, arguments):
    """(file, configuration name, Report, ComparisonRow) for every mechanism file under the paths."""
    for path in _mechanism_files(paths):
        document = read(path)
        mechanism = document.mechanism
        named = {"home": {}}
        named.update(document.configurations)
        points = {name: configuration(mechanism, values, where=f"{path}: configurations[{name!r}]").point
                  for name, values in named.items()}
        rng = np.random.default_rng(arguments.seed)
        model = model_of(mechanism, arguments.length_scale)
        shared = survey_mechanism(model, rng, starts=np.stack(list(points.values())))
        for name, point in points.items():
            print(f"classifying {path} [{name}]", file=sys.stderr)
            yield (str(path), name, *_reported(model, name, point, shared, rng))


def _catalogue_reports(items, arguments):
    """(entry name, configuration name, Report, ComparisonRow) for catalogue entries at each named
    configuration."""
    for item in items:
        for name in ("default", *item.configurations):
            print(f"classifying {item.name} [{name}]", file=sys.stderr)
            mechanism = item.mechanism(None if name == "default" else name)
            rng = np.random.default_rng(arguments.seed)
            yield (item.name, name, *_reported(model_of(mechanism, arguments.length_scale), name, home(mechanism),
                                                None, rng))


def _comparison_text(comparison):
    verdict = "corresponds" if comparison.agree else f"differs: {comparison.reason}"
    return f"{comparison.gosselin_angeles.label} ({verdict}; {comparison.note})"


def _run_report(arguments, out):
    _check_length_scale(arguments.length_scale)
    names = [text for text in arguments.paths if _is_entry(text)] if arguments.paths else catalogue.names()
    paths = [text for text in arguments.paths if not _is_entry(text)]
    reports = list(_catalogue_reports(map(catalogue.entry, names), arguments))
    if paths:
        reports += list(_file_reports(paths, arguments))
    if arguments.format == "json":
        text = json.dumps([{"source": source, "configuration_name": name, **report.to_dict(),
                            "comparison": comparison.to_dict(park_kim=False)}
                           for source, name, report, comparison in reports], indent=2, ensure_ascii=False)
    else:
        details = "\n\n".join(f"== {path} [{name}]\n{report.to_text()}\n  Gosselin–Angeles (derived): "
                               f"{_comparison_text(comparison)}"
                               for path, name, report, comparison in reports)
        text = report_table(reports) + "\n\n" + details
    out.write(text + "\n")
    if arguments.output:
        Path(arguments.output).write_text(text + "\n", encoding="utf-8")
        print(f"report written to {arguments.output}", file=sys.stderr)


def main(argv=None, out=None):
    """Entry point of the ``closedchain`` command; returns the exit status."""
    out = sys.stdout if out is None else out
    try:
        arguments = _parser().parse_args(argv)
        {"classify": _run_classify, "report": _run_report, "catalog": _run_catalog,
         "compare": _run_compare}[arguments.command](
            arguments, out)
        return 0
    except (InputError, MechanismError, ConfigurationError) as error:
        message = " ".join(str(error).split())
        print(f"closedchain: error: {message}", file=sys.stderr)
        return 2
    except Exception as error:  # noqa: BLE001 - the CLI must never show a traceback by default
        if os.environ.get("CLOSEDCHAIN_DEBUG"):
            traceback.print_exc()
        message = " ".join(f"{type(error).__name__}: {error}".split())
        print(f"closedchain: internal error: {message} (set CLOSEDCHAIN_DEBUG=1 for details)", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
