"""``closedchain draw FILE|NAME [--param K=V] [--configuration C] [--at JSON] [--project] [--kinds K,...]
--out FIG.png|svg|pdf [--format json|text]``: draw a mechanism at a configuration.

The configuration is ``home ⊕ at`` as for ``closedchain classify`` (a
configuration that does not close is refused unless ``--project``). The
drawing (:func:`classify.figures.drawing.draw_mechanism`): links, joints
(actuated ones filled squares), the end-effector; the configuration is
classified and, at a singularity, the lost directions of the singular kinds
(``--kinds``, default all) are drawn as arrows at the joints they move.
Planar mechanisms in the plane, spherical ones on the unit sphere, spatial
ones on 3-D axes. Prints one line, the file written and the kinds found
(``--format text``, the default), or a JSON object (``--format json``):
``{"mechanism", "written": [path], "kinds", "classification"}``, the last the
``closedchain classify`` object of the configuration drawn.
"""

from __future__ import annotations

from ..text import drawn, printable
from ._common import (InputError, check_output, closures_option, common_options, configuration_options, displacements,
                      dumps, entry_options, input_files, source)

__all__ = ["add_parser", "run", "FIGURE_SUFFIXES", "KIND_NAMES", "TITLE_LIMIT"]

#: the file types a figure may be written as
FIGURE_SUFFIXES = (".png", ".svg", ".pdf")
#: longest --title, in characters (a title of 10⁵ characters took a minute and gigabytes to typeset)
TITLE_LIMIT = 200
#: --kinds names → the kinds of :data:`classify.KINDS`
KIND_NAMES = {"actuator": "actuator", "end_effector": "end_effector", "end-effector": "end_effector",
              "cspace": "cspace", "c-space": "cspace"}


def add_parser(commands):
    parser = commands.add_parser("draw", help="draw a mechanism at a configuration (links, joints, lost directions)")
    parser.add_argument("file", metavar="FILE|NAME", help="mechanism file (YAML or JSON), URDF (with --closures), "
                                                          "MJCF (.xml) or catalogue name")
    entry_options(parser)
    closures_option(parser)
    parser.add_argument("--at", default=None, metavar="JSON",
                        help="joint displacements from home, as a JSON object or @file.json (as `classify --at`)")
    parser.add_argument("--project", action="store_true",
                        help="project a configuration that does not close onto the C-space")
    parser.add_argument("--kinds", default=None, metavar="K,...",
                        help="whose lost directions to draw: actuator, end_effector, cspace (default every kind "
                             "that holds)")
    parser.add_argument("--title", default=None, help="the figure's title (default the mechanism and the kinds)")
    parser.add_argument("--out", required=True, metavar="FIG",
                        help="the figure file: .png, .svg or .pdf")
    parser.add_argument("--format", choices=("json", "text"), default="text",
                        help="what is printed: one line, or the file and the classification as JSON (default text)")
    common_options(parser)
    return parser


def figure_path(text, option="--out"):
    """Refuse a figure file name whose suffix is not one of :data:`FIGURE_SUFFIXES`."""
    from pathlib import Path

    if Path(text).suffix.lower() not in FIGURE_SUFFIXES:
        raise InputError(f"{option}: {printable(text)}: expected a file name ending in "
                         f"{', '.join(FIGURE_SUFFIXES)}")
    return text


def parse_kinds(text, option="--kinds"):
    """The kinds of a comma-separated list (None for None)."""
    if text is None:
        return None
    kinds = []
    for name in (part.strip() for part in text.split(",")):
        if name not in KIND_NAMES:
            raise InputError(f"{option}: unknown kind {printable(repr(name))} (known: actuator, end_effector, "
                             f"cspace)")
        kinds.append(KIND_NAMES[name])
    return tuple(dict.fromkeys(kinds))


def write_figure(figure, path, option="--out"):
    """Write a figure, every failure an :class:`InputError` naming the option."""
    from ..figures.drawing import save_figure

    try:
        save_figure(figure, path)
    except OSError as error:
        raise InputError(f"{option}: {printable(path)}: cannot write the figure: {error.strerror or error}") from None


def check_title(text):
    """Refuse a ``--title`` matplotlib cannot draw: longer than :data:`TITLE_LIMIT` characters, control
    characters other than newline (a glyph it lacks, a tab included), or mathtext (between dollar signs) it cannot
    parse, checked on an empty figure before any work."""
    import unicodedata
    import warnings

    if len(text) > TITLE_LIMIT:
        raise InputError(f"--title: at most {TITLE_LIMIT} characters, got {len(text)}")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    if any(unicodedata.category(character) == "Cc" and character != "\n" for character in text):
        raise InputError(f"--title: control characters are not drawn; got {printable(text[:40])}")
    figure = Figure()
    FigureCanvasAgg(figure)
    figure.suptitle(text)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a missing glyph is said by savefig, if at all, not twice
            figure.canvas.draw()
    except ValueError as error:
        reason = " ".join(str(error).split())[:120]
        raise InputError(f"--title: matplotlib cannot typeset the mathtext between its dollar signs ({reason}); "
                         "write \\$ for a dollar sign") from None


def run(arguments, out):
    import numpy as np

    from mechanisms import configuration

    from ..classification import classify
    from ..figures.drawing import draw_mechanism

    path = figure_path(arguments.out)
    check_output(path, "--out", input_files(arguments))
    kinds = parse_kinds(arguments.kinds)
    if arguments.title is not None:
        check_title(arguments.title)
    mechanism, named = source(arguments)
    at = displacements(arguments.at)
    point = configuration(mechanism, {**named, **at}, project_onto=arguments.project,
                          where=configuration_options(arguments, at)).point
    report = classify(mechanism, point, rng=np.random.default_rng(arguments.seed),
                      length_scale=arguments.length_scale)
    found = ", ".join(kind.replace("_", "-") for kind in report.kinds) or "regular"
    title = arguments.title if arguments.title is not None else f"{drawn(mechanism.name)}: {found}"
    figure = draw_mechanism(mechanism, point, report=report, kinds=kinds, title=title)
    write_figure(figure, path)
    if arguments.format == "json":
        out.write(dumps({"mechanism": mechanism.name, "written": [path], "kinds": list(report.kinds),
                         "classification": report.to_dict()}) + "\n")
        return
    out.write(f"drawing of {printable(mechanism.name)} ({found}) written to {printable(path)}\n")
