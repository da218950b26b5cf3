"""``closedchain classify FILE|NAME [--configuration C] [--param K=V] [--at JSON|@file] [--project |
--assemble [--branch N]] [--format json|text]``: classify ``home ⊕ at`` (docs/design.rst, "CLI"), or
the assembly with the ``--at`` joints held at exactly those values (:func:`mechanisms.assemble`)."""

from __future__ import annotations

import sys
from dataclasses import replace

import numpy as np

from mechanisms import assemble, catalogue, configuration

from ..classification import classify
from ..report import printable
from ._common import (
    InputError, check_length_scale, common_options, displacements, dumps, entry_options, entry_values, is_entry,
    source,
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
    if is_entry(arguments.file):
        item = catalogue.entry(arguments.file)
        result = {"catalogue": item.name, "parameters": entry_values(item, arguments),
                  "configuration": arguments.configuration}
    else:
        result = {"file": arguments.file, "configuration": arguments.configuration}
    if at:
        result["at"] = at
    return result


def add_parser(commands):
    parser = commands.add_parser("classify", help="classify one configuration of a mechanism file or catalogue entry")
    parser.add_argument("file", metavar="FILE|NAME", help="mechanism file (YAML or JSON) or catalogue name")
    entry_options(parser)
    parser.add_argument("--at", default=None,
                        help="joint displacements from home as a JSON object, or @file.json")
    parser.add_argument("--project", action="store_true",
                        help="project a configuration that does not close onto the C-space")
    parser.add_argument("--assemble", action="store_true",
                        help="hold the --at joints (and the other actuated joints) at exactly those values and "
                             "solve the loops for the others")
    parser.add_argument("--branch", type=int, default=None, metavar="N",
                        help="with --assemble: the N-th assembly at those inputs, by distance from home "
                             "(default: the one reached from home)")
    parser.add_argument("--format", choices=("json", "text"), default="text")
    common_options(parser)
    return parser


def _assembled(mechanism, named, at, arguments):
    """(point, the assembly's JSON) with the --at joints held and the loops solved (`mechanisms.assemble`)."""
    if arguments.project:
        raise InputError("--assemble: give either --assemble or --project, not both")
    if not at:
        raise InputError("--assemble: name the joints to hold with --at, e.g. --at '{\"J1\": 0.3}'")
    reached = assemble(mechanism, at, branch=arguments.branch, guess=named or None,
                       rng=np.random.default_rng(arguments.seed), where="--at")
    return reached.point, reached.to_dict()


def run(arguments, out):
    check_length_scale(arguments.length_scale)
    mechanism, named = source(arguments)
    at = displacements(arguments.at)
    if arguments.branch is not None and not arguments.assemble:
        raise InputError("--branch: applies with --assemble")
    assembly, distance = None, 0.0
    if arguments.assemble:
        point, assembly = _assembled(mechanism, named, at, arguments)
    else:
        projected = configuration(mechanism, {**named, **at}, project_onto=arguments.project, where="--at")
        point, distance = projected.point, projected.distance
    if mechanism.loop_count == 0:
        print(f"closedchain: warning: {printable(mechanism.name)} has no loop (a serial chain)", file=sys.stderr)
    rng = np.random.default_rng(arguments.seed)
    report = classify(mechanism, point, rng=rng, length_scale=arguments.length_scale)
    report = replace(report, source=describe_source(arguments, at))
    if arguments.format == "json":
        result = report.to_dict()
        if arguments.project:
            result["projection_distance"] = distance
        if assembly is not None:
            result["assembly"] = assembly
        out.write(dumps(result) + "\n")
    else:
        if distance:
            out.write(f"projected onto the C-space: moved by {distance:.3g}\n")
        if assembly is not None:
            out.write(f"assembled with {', '.join(printable(name) for name in assembly['held'])} held: "
                      f"branch {assembly['branch']} of {assembly['branches']} found, residual "
                      f"{assembly['residual']:.1e}\n")
        out.write(report.to_text() + "\n")
