"""``closedchain report [PATH|NAME ...] [--output FILE] [--format json|text]``: classify the catalogue (every
entry at its defaults and at each named configuration), or every mechanism file under the paths, with the
derived Gosselin–Angeles kinds alongside."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from mechanisms import catalogue, configuration, home
from mechanisms.io import read

from ..classification import classify
from ..comparison import comparison_row
from ..model import model_of
from ..survey import survey as survey_mechanism
from ._common import MECHANISM_SUFFIXES, InputError, check_length_scale, common_options, dumps, is_entry

__all__ = ["add_parser", "run", "report_table"]


def add_parser(commands):
    parser = commands.add_parser("report", help="classify the catalogue, or every mechanism file under the paths")
    parser.add_argument("paths", nargs="*", default=[], metavar="PATH|NAME",
                        help="files, folders or catalogue names (default: every catalogue entry, "
                             "at its defaults and at each named configuration)")
    parser.add_argument("--output", default=None, help="also write the report to this file")
    parser.add_argument("--format", choices=("json", "text"), default="text")
    common_options(parser)
    return parser


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


def run(arguments, out):
    check_length_scale(arguments.length_scale)
    names = [text for text in arguments.paths if is_entry(text)] if arguments.paths else catalogue.names()
    paths = [text for text in arguments.paths if not is_entry(text)]
    reports = list(_catalogue_reports(map(catalogue.entry, names), arguments))
    if paths:
        reports += list(_file_reports(paths, arguments))
    if arguments.format == "json":
        text = dumps([{"source": source, "configuration_name": name, **report.to_dict(),
                            "comparison": comparison.to_dict(park_kim=False)}
                           for source, name, report, comparison in reports])
    else:
        details = "\n\n".join(f"== {path} [{name}]\n{report.to_text()}\n  Gosselin–Angeles (derived): "
                               f"{_comparison_text(comparison)}"
                               for path, name, report, comparison in reports)
        text = report_table(reports) + "\n\n" + details
    out.write(text + "\n")
    if arguments.output:
        Path(arguments.output).write_text(text + "\n", encoding="utf-8")
        print(f"report written to {arguments.output}", file=sys.stderr)
