"""``closedchain catalog [NAME] [--param K=V] [--configuration C] [--write FILE] [--format json|text]``: list
the catalogue, describe an entry, or write it as a mechanism file."""

from __future__ import annotations

import sys

from mechanisms import MechanismError, catalogue

from ._common import InputError, dumps, entry_options, entry_values

__all__ = ["add_parser", "run", "entry_description"]


def add_parser(commands):
    parser = commands.add_parser("catalog", help="list the catalogue, describe an entry or write it to a file")
    parser.add_argument("name", nargs="?", default=None, help="catalogue name (default: list them all)")
    entry_options(parser)
    parser.add_argument("--write", default=None, metavar="FILE",
                        help="write the entry as a mechanism file (.yaml, .yml or .json)")
    parser.add_argument("--format", choices=("json", "text"), default="text")
    return parser


def entry_description(item, configuration_name, values):
    """The description written into a mechanism file made from a catalogue entry."""
    settings = ", ".join(f"{name}={value!r}" for name, value in values.items())
    at = f" at {configuration_name}" if configuration_name else ""
    return (f"closedchain catalogue entry {item.name}{at}: {item.summary} "
            f"From {item.reference}. Parameters: {settings}.")


def _entry_dict(item):
    return {"name": item.name, "summary": item.summary, "reference": item.reference,
            "parameters": item.parameters,
            "configurations": {name: dict(presets) for name, presets in item.configurations.items()}}


def _write(mechanism, path, description):
    """Save the mechanism file; a path that cannot be written is an input error naming --write."""
    from mechanisms.io import save  # imported when used: YAML

    try:
        save(mechanism, path, description=description)
    except MechanismError as error:
        raise InputError(f"--write: {error}") from None


def run(arguments, out):
    if arguments.name is None:
        if arguments.write or arguments.param or arguments.configuration:
            raise InputError("catalog: --write, --param and --configuration need a catalogue NAME")
        if arguments.format == "json":
            out.write(dumps([_entry_dict(item) for item in catalogue.entries()]) + "\n")
            return
        items = catalogue.listing()  # names, summaries, references, configurations: no entry imported
        width = max(len(item.name) for item in items)
        for item in items:
            out.write(f"{item.name.ljust(width)}  {item.summary}\n")
            out.write(f"{'':{width}}  {item.reference}\n")
            if item.configurations:
                out.write(f"{'':{width}}  configurations: {', '.join(item.configurations)}\n")
        return
    item = catalogue.entry(arguments.name)
    values = entry_values(item, arguments)
    mechanism = item.assemble(values)
    if arguments.write:
        _write(mechanism, arguments.write, entry_description(item, arguments.configuration, values))
        print(f"{item.name} written to {arguments.write}", file=sys.stderr)
        return
    if arguments.format == "json":
        out.write(dumps({**_entry_dict(item), "values": values}) + "\n")
        return
    lines = [f"{item.name}: {item.summary}", f"from {item.reference}", "", "parameters (value, default):"]
    lines += [f"  {name} = {value!r}  (default {item.parameters[name]!r})" for name, value in values.items()]
    lines += ["", "configurations:"]
    lines += [f"  {name}: " + ", ".join(f"{key}={value!r}" for key, value in presets.items())
              for name, presets in item.configurations.items()] or ["  none"]
    lines += ["", f"{mechanism.space} mechanism, {len(mechanism.joints)} joints, {mechanism.loop_count} loop(s), "
              f"actuated: {', '.join(joint.name for joint in mechanism.joints if joint.actuated) or 'none'}"]
    out.write("\n".join(lines) + "\n")
