"""``closedchain classify FILE|NAME [--configuration C] [--param K=V] [--at JSON|@file] [--project]
[--format json|text]``: classify ``home ⊕ at`` (docs/design.rst, "CLI")."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mechanisms import catalogue, configuration

from ..classification import classify
from ._common import (
    check_length_scale, common_options, displacements, dumps, entry_options, entry_values, is_entry, source,
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
    parser.add_argument("--format", choices=("json", "text"), default="text")
    common_options(parser)
    return parser


def run(arguments, out):
    check_length_scale(arguments.length_scale)
    mechanism, named = source(arguments)
    at = displacements(arguments.at)
    given = {**named, **at}
    projected = configuration(mechanism, given, project_onto=arguments.project, where="--at")
    rng = np.random.default_rng(arguments.seed)
    report = classify(mechanism, projected.point, rng=rng, length_scale=arguments.length_scale)
    report = replace(report, source=describe_source(arguments, at))
    if arguments.format == "json":
        result = report.to_dict()
        if arguments.project:
            result["projection_distance"] = projected.distance
        out.write(dumps(result) + "\n")
    else:
        if projected.distance:
            out.write(f"projected onto the C-space: moved by {projected.distance:.3g}\n")
        out.write(report.to_text() + "\n")
