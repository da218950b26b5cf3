"""The ``closedchain`` command: one module per subcommand.

* ``closedchain classify FILE|NAME`` (:mod:`classify.cli.classify_command`)
  classifies ``home ⊕ at`` of a mechanism file or of a catalogue entry
  (docs/design.rst, "CLI");
* ``closedchain report [PATH|NAME ...]`` (:mod:`classify.cli.report_command`)
  classifies the catalogue, or every mechanism file under the paths, at each
  named configuration, and prints a table;
* ``closedchain compare FILE|NAME`` (:mod:`classify.cli.compare_command`)
  puts Park–Kim and Gosselin–Angeles side by side;
* ``closedchain map FILE|NAME --grid …`` (:mod:`classify.cli.map_command`)
  classifies every point of a grid of joint coordinates;
* ``closedchain sweep NAME --param K=a:b:n …`` (:mod:`classify.cli.sweep_command`)
  sweeps a catalogue parameter grid, one Dask task per chunk of designs;
* ``closedchain draw FILE|NAME --out FIG`` (:mod:`classify.cli.draw_command`) draws
  the mechanism at a configuration, with its lost directions at a singularity;
* ``closedchain loci FILE|NAME`` (:mod:`classify.cli.loci_command`) traces the
  singularity loci of a 1-, 2- or 3-dof mechanism (3: in sections) and draws its C-space map;
* ``closedchain conditioning FILE|NAME`` (:mod:`classify.cli.conditioning_command`)
  condition numbers, characteristic length, working modes and isoconditioning
  maps (Chablat, Wenger & Angeles 1998; Chablat, Caro, Wenger & Angeles 2002);
* ``closedchain line-plane`` (:mod:`classify.cli.line_plane_command`) the
  line-plane 5-SPU's family, B-lines, rearrangements and assembly modes
  (Borràs, Thomas & Torras 2011);
* ``closedchain convert FILE`` (:mod:`classify.cli.convert_command`) writes a
  URDF (+ closures) or MJCF robot as a mechanism file, or a mechanism as
  URDF + closures;
* ``closedchain catalog [NAME]`` (:mod:`classify.cli.catalog_command`) lists the
  catalogue, describes an entry or writes it as a mechanism file.

Exit status: 0 done (singular or not), 2 bad input (one line on stderr), 1 an
internal error.

Start-up is instant (``closedchain --help``, ``closedchain catalog``): the
subcommand modules import only the standard library and the light parts of
the package at module level; SymPy, SciPy, Matplotlib, Dask and the like are
imported inside the functions that use them.
"""

from __future__ import annotations

import os
import sys
import traceback

from mechanisms import ConfigurationError, MechanismError

from ..text import printable
from . import (catalog_command, classify_command, compare_command, conditioning_command, convert_command, draw_command,
               line_plane_command, loci_command, map_command, report_command, sweep_command)
from ._common import InputError, Parser
from .report_command import report_table

__all__ = ["main", "report_table", "InputError"]

#: subcommand name → its module (each has ``add_parser(commands)`` and ``run(arguments, out)``)
COMMANDS = {
    "classify": classify_command,
    "report": report_command,
    "compare": compare_command,
    "catalog": catalog_command,
    "map": map_command,
    "sweep": sweep_command,
    "conditioning": conditioning_command,
    "line-plane": line_plane_command,
    "convert": convert_command,
    "draw": draw_command,
    "loci": loci_command,
}


def parser():
    """The argument parser of the whole command."""
    result = Parser(prog="closedchain", description="Singularity analysis of closed kinematic chains.")
    commands = result.add_subparsers(dest="command", required=True, parser_class=Parser)
    for module in COMMANDS.values():
        module.add_parser(commands)
    return result


def _one_line(text):
    """`text` on one line, safe for a terminal (:func:`classify.text.printable`: control and format
    characters, and lone surrogates from undecodable file names, written as backslash escapes)."""
    return printable(" ".join(str(text).split()))


def _standard_output():
    """``sys.stdout``, set to escape rather than fail on text it cannot encode (a file name that is not
    valid UTF-8 echoed in a report)."""
    if hasattr(sys.stdout, "reconfigure"):
        try:
            sys.stdout.reconfigure(errors="backslashreplace")
        except (ValueError, OSError):  # a stream that cannot be reconfigured any more
            pass
    return sys.stdout


def _silence_standard_output():
    """Point the standard output at the null device, so that Python's flush at exit does not fail on the
    closed pipe again (the way the Python documentation advises for SIGPIPE)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):  # no file descriptor (a test's stream)
        pass


def main(argv=None, out=None):
    """Entry point of the ``closedchain`` command; returns the exit status."""
    out = _standard_output() if out is None else out
    try:
        arguments = parser().parse_args(argv)
        COMMANDS[arguments.command].run(arguments, out)
        return 0
    except (InputError, MechanismError, ConfigurationError) as error:
        print(f"closedchain: error: {_one_line(error)}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader stopped reading (`closedchain report | head`): nothing is wrong
        _silence_standard_output()
        return 0
    except Exception as error:  # noqa: BLE001 - the CLI must never show a traceback by default
        if os.environ.get("CLOSEDCHAIN_DEBUG"):
            traceback.print_exc()
        message = _one_line(f"{type(error).__name__}: {error}")
        print(f"closedchain: internal error: {message} (set CLOSEDCHAIN_DEBUG=1 for details)", file=sys.stderr)
        return 1
