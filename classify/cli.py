"""The ``closedchain`` command.

``closedchain classify FILE [--at JSON|@file] [--project] [--format json|text]``
classifies ``home ⊕ at`` (DESIGN.md, "CLI"); ``closedchain report [PATH ...]``
classifies every mechanism file under the paths at its home and at each of
its named configurations and prints a table.

Exit status: 0 done (singular or not), 2 bad input (one line on stderr), 1 an
internal error.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import traceback
from pathlib import Path

import numpy as np

from mechanisms import ConfigurationError, MechanismError, configuration
from mechanisms.io import read

from .classification import classify
from .model import model_of
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
    one = commands.add_parser("classify", help="classify one configuration of a mechanism file")
    one.add_argument("file", help="mechanism file (YAML or JSON)")
    one.add_argument("--at", default=None,
                     help="joint displacements from home as a JSON object, or @file.json")
    one.add_argument("--project", action="store_true",
                     help="project a configuration that does not close onto the C-space")
    one.add_argument("--format", choices=("json", "text"), default="text")
    _common_options(one)
    many = commands.add_parser("report", help="classify every mechanism file under the paths")
    many.add_argument("paths", nargs="*", default=["examples"], help="files or folders (default: examples)")
    many.add_argument("--output", default=None, help="also write the report to this file")
    many.add_argument("--format", choices=("json", "text"), default="text")
    _common_options(many)
    return parser


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


def _run_classify(arguments, out):
    _check_length_scale(arguments.length_scale)
    document = read(arguments.file)
    mechanism = document.mechanism
    projected = configuration(mechanism, _displacements(arguments.at), project_onto=arguments.project,
                              where="--at")
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
    """A fixed-width table of (file, configuration name, Report) rows."""
    header = ("mechanism", "configuration", "dof", "kinds", "C-space", "actuator", "end-effector", "κ")
    rows = []
    for _, name, report in reports:
        def rank(result):
            return "-" if result is None else f"{result.rank}/{result.expected_rank}"
        actuator = rank(report.actuator) + (f" {report.degeneracy}" if report.degeneracy else "")
        condition = "-"
        if report.manipulability is not None:
            value = report.manipulability.condition_number
            condition = "∞" if value is None else f"{value:.3g}"
        rows.append((report.mechanism, name, str(report.dof), ", ".join(report.kinds) or "regular",
                     rank(report.cspace), actuator, rank(report.end_effector), condition))
    widths = [max(len(row[i]) for row in rows + [header]) for i in range(len(header))]
    lines = ["  ".join(cell.ljust(width) for cell, width in zip(row, widths)).rstrip()
             for row in [header] + rows]
    lines.insert(1, "  ".join("-" * width for width in widths))
    return "\n".join(lines)


def _run_report(arguments, out):
    _check_length_scale(arguments.length_scale)
    reports = []
    for path in _mechanism_files(arguments.paths):
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
            report = classify(model, point, survey=shared, rng=rng)
            reports.append((str(path), name, report))
    if arguments.format == "json":
        text = json.dumps([{"file": path, "configuration_name": name, **report.to_dict()}
                           for path, name, report in reports], indent=2, ensure_ascii=False)
    else:
        details = "\n\n".join(f"== {path} [{name}]\n{report.to_text()}" for path, name, report in reports)
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
        if arguments.command == "classify":
            _run_classify(arguments, out)
        else:
            _run_report(arguments, out)
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
