"""``closedchain classify FILE|NAME [--configuration C] [--param K=V] [--at JSON|@file] [--project]
[--format json|text]``: classify ``home ⊕ at`` (docs/design.rst, "CLI")."""

from __future__ import annotations


import numpy as np

from mechanisms import configuration

from ..classification import classify
from ._common import check_length_scale, common_options, displacements, dumps, entry_options, source

__all__ = ["add_parser", "run"]


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
    given = {**named, **displacements(arguments.at)}
    projected = configuration(mechanism, given, project_onto=arguments.project, where="--at")
    rng = np.random.default_rng(arguments.seed)
    report = classify(mechanism, projected.point, rng=rng, length_scale=arguments.length_scale)
    if arguments.format == "json":
        result = report.to_dict()
        if arguments.project:
            result["projection_distance"] = projected.distance
        out.write(dumps(result) + "\n")
    else:
        if projected.distance:
            out.write(f"projected onto the C-space: moved by {projected.distance:.3g}\n")
        out.write(report.to_text() + "\n")
