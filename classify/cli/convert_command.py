"""``closedchain convert FILE|NAME [--closures C.yaml] [--configuration C] [--param K=V] --write OUT
[--format json|text]``: convert a mechanism between formats.

Inputs: a URDF with its closures file (``--closures``), an MJCF file (``.xml``), a mechanism file or a catalogue
entry. Outputs (by ``--write``'s suffix): a contract-format mechanism file (``.yaml``, ``.yml``, ``.json``), whose
home is the assembled configuration and whose ``description`` records the import's notes; or a URDF (``.urdf``)
with its closures file beside it (same stem, ``.yaml``; :mod:`mechanisms.export`), which the URDF importer and
Pinocchio read.

A mechanism file keeps its home, every named configuration and its description (``--configuration`` is
refused for it); a catalogue entry is written with the description ``closedchain catalog NAME --write`` gives it
(entry, paper, parameters); a file that is an input of the conversion is never written over. Suffixes are read
case-insensitively (``.YAML`` as ``.yaml``).

A URDF and its closures file hold no joint weights, named configurations nor description: what the mechanism
(or its mechanism file) has of them is left out and said, as a note and as a warning line on stderr naming it
(the joints with their weights, the configurations). A name XML 1.0 cannot hold (a control character) is refused
before anything is written.

Prints the import's notes, the export's and one line per file written (``--format text``, the default), or a
JSON object (``--format json``): ``{"mechanism", "written": [paths], "joints", "loops", "notes"}``, with
``"actuated"`` (the closures file's actuated joints) for a URDF.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..text import printable
from ._common import InputError, MECHANISM_SUFFIXES, closures_option, dumps, entry_options, entry_values, is_entry, \
    same_file, source, warn_if_serial

__all__ = ["add_parser", "run"]


def add_parser(commands):
    parser = commands.add_parser("convert", help="convert URDF + closures / MJCF to a mechanism file, and back")
    parser.add_argument("file", metavar="FILE|NAME",
                        help="URDF (with --closures), MJCF (.xml), mechanism file or catalogue name")
    entry_options(parser)
    closures_option(parser)
    parser.add_argument("--write", required=True, metavar="OUT",
                        help="the file to write: .yaml/.yml/.json (a mechanism file) or .urdf (with OUT's stem "
                             ".yaml as its closures file)")
    parser.add_argument("--format", choices=("json", "text"), default="text",
                        help="what is printed: the notes and the files written, as lines or as JSON (default text)")
    return parser


def run(arguments, out):
    from mechanisms import MechanismError
    from mechanisms.io import save

    target = Path(arguments.write)
    suffix = target.suffix.lower()  # as mechanisms.io reads them: .YAML is .yaml
    if suffix not in (*MECHANISM_SUFFIXES, ".urdf"):
        raise InputError(f"--write: expected a .yaml, .yml, .json or .urdf file, got {printable(arguments.write)}")
    entry = is_entry(arguments.file)
    mechanism, named = source(arguments)
    imported = getattr(arguments, "imported", None)
    document = getattr(arguments, "document", None)
    configurations = {"named": named} if named else None
    description = imported.description if imported is not None else None
    if document is not None:  # a mechanism file: its home, named configurations and description, all kept
        configurations, description = dict(document.configurations) or None, document.description
    elif entry:  # as `closedchain catalog NAME --write` describes it: the entry, its paper, its parameters
        from mechanisms import catalogue

        from .catalog_command import entry_description

        item = catalogue.entry(arguments.file)
        description = entry_description(item, arguments.configuration, entry_values(item, arguments))
    source_files = [Path(arguments.file)] + ([Path(arguments.closures)] if getattr(arguments, "closures", None) else [])
    written = [target] + ([target.with_suffix(".yaml")] if suffix == ".urdf" else [])
    for path in written:
        if any(same_file(path, other) for other in source_files):
            raise InputError(f"--write: {printable(str(path))} is an input of this conversion: it would be "
                             f"overwritten (write elsewhere)")
    warn_if_serial(mechanism)  # a URDF with an empty closures file, as `classify` warns of it
    if suffix == ".urdf":
        from mechanisms.export import write_urdf

        closures_path = target.with_suffix(".yaml")
        if named:
            raise InputError("--configuration: a URDF is written at the mechanism's home")
        # what the pair cannot hold is said: a mechanism file's own description (an import's is its notes, printed
        # below; a catalogue entry's is `closedchain catalog NAME`'s, and the entry's name is the robot's)
        kept = description if document is not None else None
        try:
            exported = write_urdf(mechanism, target, closures_path, configurations, kept)
        except MechanismError as error:
            raise InputError(f"--write: {error}") from None
        for note in exported.notes:
            print(f"closedchain: warning: {printable(note)}", file=sys.stderr)
        notes = (list(imported.notes) if imported is not None else []) + list(exported.notes)
        if arguments.format == "json":
            out.write(dumps({"mechanism": mechanism.name, "written": [str(target), str(closures_path)],
                             "joints": len(mechanism.joints), "loops": len(exported.closures.loops),
                             "actuated": len(exported.closures.actuated), "notes": notes}) + "\n")
            return
        for note in imported.notes if imported is not None else ():
            out.write(f"imported: {printable(note)}\n")
        for note in exported.notes:
            out.write(f"note: {printable(note)}\n")
        out.write(f"wrote {printable(str(target))} and its closures {printable(str(closures_path))}: "
                  f"{len(exported.closures.loops)} loop(s), {len(exported.closures.actuated)} actuated joint(s)\n")
        return
    if document is not None and arguments.configuration is not None:
        raise InputError("--configuration: converting a mechanism file keeps its home and every named "
                         "configuration (name one when classifying the file written)")
    try:
        save(mechanism, target, configurations=configurations, description=description)
    except MechanismError as error:
        raise InputError(f"--write: {error}") from None
    notes = list(imported.notes) if imported is not None else []
    if arguments.format == "json":
        out.write(dumps({"mechanism": mechanism.name, "written": [str(target)], "joints": len(mechanism.joints),
                         "loops": mechanism.loop_count, "notes": notes}) + "\n")
        return
    for note in notes:
        out.write(f"imported: {printable(note)}\n")
    out.write(f"wrote {printable(str(target))}: {printable(mechanism.name)}, {len(mechanism.joints)} joints, "
              f"{mechanism.loop_count} loop(s)\n")
