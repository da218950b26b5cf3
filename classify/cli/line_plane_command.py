"""``closedchain line-plane [FILE|NAME] [--base "x1,y1 x2,y2 …" --platform "z1 … z5"] [--legs l1,…,l5]
[--move-base I:T] [--move-platform I:Z] [--framework] [--rtol R] [--format json|text]``: the invariants of a line-plane
5-SPU (Borràs, Thomas & Torras 2011).

The design comes from ``--base`` and ``--platform`` (five base attachments
(xᵢ, yᵢ) in the plane Π and five coordinates zᵢ along the platform line Λ),
or from a 5-SPU mechanism file or the catalogue entry ``5-spu`` (with
``--param``/``--configuration``; :func:`classify.line_plane_files.design_from_mechanism`),
which also gives the home pose and its singularity reading.

Output (``--format json``): ``design``; ``family`` (quartic, cubic,
quadratic, architecturally singular) with ``family_margins`` and ``rtol``;
``cofactors`` (C₁ … C₆ of (12)-(13) divided by ``cofactor_scale``, their
largest magnitude: they are defined up to a factor); ``B`` (16) or null at
infinity; ``B_inf`` (15) as line coefficients (a, b, c), a² + b² = 1, or
null at infinity; ``Lambda_plus`` (23) or null
(:func:`classify.line_plane_pencil.lambda_plus`: the copy on the side of B∞ of the
base attachments' centroid); ``b_lines`` (the B-line of each leg, (a, b, c)
with a² + b² = 1, signed as ``B_inf``: the centroid on its positive side, so
that a renumbering of the legs or a flip of i leaves each leg's line
unchanged; :func:`classify.line_plane_pencil.oriented_b_line`; null at
infinity). B, ``B_inf``, ``Lambda_plus`` and ``b_lines`` are computed in the
normalised frame and mapped back, so they move with the base frame. For an
architecturally singular design all Cⱼ vanish: ``cofactors``, ``B``,
``B_inf``, ``Lambda_plus`` and ``b_lines`` are null (undefined, whatever
rounding left in ``cofactor_scale``). With a mechanism, ``pose`` (p, i at home, in the frame
of the fitted base plane) and ``singularity`` (the reading of (17) there:
``singular``, ``margin``, ``parallel``, ``intersection`` A, ``z`` μ and
``distance`` from A to B_μ, positive on the side of the base centroid); with
``--legs``, ``legs`` (the five leg lengths as given, in the order of the
legs) and ``assembly_modes`` (the polynomial route, real ones first, each
with its residual and multiplicity: coincident modes, at the leg lengths of a singular
configuration, are listed once), ``real_modes`` (distinct real poses) and,
with ``--framework``, the modes found by the closedchain mechanism route (a
search from random starts that stops once it has found as many as the
polynomial route, or at least one: with no real mode it tries every start)
and whether the two agree;
with ``--move-base I:T`` (leg I moved by T along its B-line) or
``--move-platform I:Z`` (leg I's platform attachment moved to Z, allowed iff
its base attachment is at B), ``rearranged``: the new design and its
invariants. A refused move, a bad design (not five legs, coincident legs,
four collinear base attachments, non-finite numbers) or bad lengths exit
with status 2 and one line naming the option.
"""

from __future__ import annotations

from ._common import InputError, dumps, entry_options, is_entry, number, source

__all__ = ["add_parser", "run", "parse_base", "parse_numbers", "parse_move"]


def add_parser(commands):
    parser = commands.add_parser("line-plane",
                                 help="line-plane 5-SPU families, rearrangements and assembly modes (Borràs et al.)")
    parser.add_argument("file", nargs="?", default=None, metavar="FILE|NAME",
                        help="a 5-SPU mechanism file or the catalogue entry 5-spu (instead of --base/--platform)")
    entry_options(parser)
    parser.add_argument("--base", default=None, metavar='"x1,y1 x2,y2 …"',
                        help="the five base attachments (x, y) in the base plane, separated by spaces")
    parser.add_argument("--platform", default=None, metavar='"z1 … z5"',
                        help="the five platform attachments z along the platform line")
    parser.add_argument("--legs", default=None, metavar="l1,…,l5",
                        help="five leg lengths: list every assembly mode (forward kinematics)")
    parser.add_argument("--framework", action="store_true",
                        help="with --legs, also find the real modes with the closedchain mechanism (assemble "
                             "from many starts) and say whether the two routes agree")
    parser.add_argument("--move-base", default=None, metavar="I:T",
                        help="move base attachment I (1-5) by T along its B-line (singularity-invariant)")
    parser.add_argument("--move-platform", default=None, metavar="I:Z",
                        help="move platform attachment I (1-5) to Z (allowed iff base attachment I is at B)")
    parser.add_argument("--rtol", type=number, default=None, metavar="R",
                        help="relative cut of the family decisions (default 1e-8): a design read from a file "
                             "rounded to d significant digits needs about 10^(1-d)")
    parser.add_argument("--format", choices=("json", "text"), default="text")
    return parser


def _number(text, option):
    import math

    from mechanisms._numerals import decimal_number
    from mechanisms.joints import COORDINATE_LIMIT

    try:
        value = decimal_number(text)
    except ValueError as error:
        raise InputError(f"{option}: {error}") from None
    if not math.isfinite(value):
        raise InputError(f"{option}: expected finite numbers, got {text[:40]}")
    if abs(value) > COORDINATE_LIMIT:
        raise InputError(f"{option}: expected numbers at most {COORDINATE_LIMIT:g} in absolute value (as in a "
                         f"mechanism file), got {text[:40]}")
    return value


def parse_numbers(text, option, count=5):
    """``count`` numbers separated by commas or spaces."""
    items = text.replace(",", " ").split()
    if len(items) != count:
        raise InputError(f"{option}: expected {count} numbers (a line-plane 5-SPU has five legs), got {len(items)}")
    return [_number(item, option) for item in items]


def parse_base(text):
    """``--base "x1,y1 x2,y2 …"``: five pairs."""
    pairs = text.replace(";", " ").split()
    if len(pairs) != 5:
        raise InputError(f"--base: expected five pairs x,y separated by spaces (a line-plane 5-SPU has five legs), "
                         f"got {len(pairs)}")
    result = []
    for pair in pairs:
        parts = pair.split(",")
        if len(parts) != 2:
            raise InputError(f"--base: expected a pair x,y, got {pair[:40]!r}")
        result.append([_number(part, "--base") for part in parts])
    return result


def parse_move(text, option):
    """``I:T``: a leg number 1-5 and a number."""
    parts = text.split(":")
    if len(parts) != 2:
        raise InputError(f"{option}: expected I:T (a leg 1-5 and a number), got {text[:40]!r}")
    try:
        index = int(parts[0])
    except ValueError:
        raise InputError(f"{option}: expected a leg number 1-5 before ':', got {parts[0][:40]!r}") from None
    if not 1 <= index <= 5:
        raise InputError(f"{option}: expected a leg number 1-5, got {index}")
    return index - 1, _number(parts[1], option)


def _design(arguments):
    """(design, pose or None) from the options or the mechanism."""
    from ..line_plane import DesignError, design_from_mechanism, line_plane_design

    if arguments.file is not None:
        if arguments.base is not None or arguments.platform is not None:
            raise InputError("--base, --platform: give a design either by FILE|NAME or by --base/--platform")
        if is_entry(arguments.file) and arguments.file != "5-spu":
            raise InputError(f"{arguments.file}: not a line-plane 5-SPU (the catalogue entry is 5-spu)")
        mechanism, named = source(arguments)
        if named:
            raise InputError("--configuration: a file's named configurations are not supported here; use its home")
        try:
            design, position, direction = design_from_mechanism(mechanism)
        except DesignError as error:
            raise InputError(f"{arguments.file}: {error}") from None
        return design, (position, direction)
    if arguments.param or arguments.configuration:
        raise InputError("--param, --configuration: apply to a catalogue entry or file, not to --base/--platform")
    if arguments.base is None or arguments.platform is None:
        raise InputError("--base, --platform: give both (or a 5-SPU FILE|NAME)")
    base = parse_base(arguments.base)
    platform = parse_numbers(arguments.platform, "--platform")
    try:
        return line_plane_design(base, platform, rtol=arguments.rtol), None
    except DesignError as error:
        raise InputError(f"--{error.field}: {str(error).split(': ', 1)[-1]}") from None


def _invariants(design, rtol):
    """The JSON-ready invariants of a design, its family decided with `rtol`."""
    import numpy as np

    from ..line_plane import b_infinity, b_point, cofactors, family, lambda_plus
    from ..line_plane_pencil import oriented_b_line

    kind = family(design, rtol)
    values = cofactors(design)
    scale = float(np.max(np.abs(values)))
    point = b_point(design, rtol)
    line = b_infinity(design, rtol)
    plus = lambda_plus(design, rtol)
    undefined = kind.name == "architecturally singular"
    lines = None if undefined else []
    for row in () if undefined else oriented_b_line(design, design.platform, kind.rtol):
        lines.append(None if np.isnan(row[0]) else row.tolist())
    return {
        "design": design.to_dict(),
        "family": kind.name,
        "family_margins": kind.to_dict()["margins"],
        "rtol": kind.rtol,
        "cofactors": None if undefined else (values / scale).tolist(),
        "cofactor_scale": scale,
        "B": None if point is None else point.tolist(),
        "B_inf": None if line is None else line.tolist(),
        "Lambda_plus": None if plus is None else plus[0].tolist(),
        "b_lines": lines,
    }


def _rearranged(design, arguments):
    from ..line_plane import RearrangementError, move_base, move_platform

    try:
        if arguments.move_base is not None:
            index, distance = parse_move(arguments.move_base, "--move-base")
            moved = move_base(design, index, distance, rtol=arguments.rtol)
            return moved, {"move": {"rule": "base along its B-line", "leg": index + 1, "distance": distance}}
        index, z = parse_move(arguments.move_platform, "--move-platform")
        moved = move_platform(design, index, z, rtol=arguments.rtol)
        return moved, {"move": {"rule": "platform attachment of a leg at B", "leg": index + 1, "z": z}}
    except RearrangementError as error:
        option = "--move-base" if arguments.move_base is not None else "--move-platform"
        raise InputError(f"{option}: {error}") from None


def _modes(design, arguments, result):
    from ..line_plane import DesignError
    from ..line_plane_kinematics import assembly_modes, framework_assembly_modes, same_modes

    lengths = parse_numbers(arguments.legs, "--legs")
    try:
        modes = assembly_modes(design, lengths, rtol=arguments.rtol)
    except DesignError as error:
        if error.field == "legs":
            raise InputError(f"--legs: {str(error).split(': ', 1)[-1]}") from None
        source = arguments.file if arguments.file is not None else "--base, --platform"
        raise InputError(f"{source}: {str(error).split(': ', 1)[-1]}") from None
    result["legs"] = lengths
    result["assembly_modes"] = [mode.to_dict() for mode in modes]
    result["real_modes"] = sum(mode.real for mode in modes)
    if arguments.framework:
        # the search stops once it has found as many modes as the polynomial route; with none, it searches every
        # start (it must look for one to confirm there is none)
        found = framework_assembly_modes(design, lengths, expected=max(1, result["real_modes"]))
        result["framework_modes"] = [mode.to_dict() for mode in found]
        result["routes_agree"] = same_modes(modes, found, design.characteristic_length)


def run(arguments, out):
    if arguments.move_base is not None and arguments.move_platform is not None:
        raise InputError("--move-base, --move-platform: give one move at a time")
    if arguments.framework and arguments.legs is None:
        raise InputError("--framework: needs --legs")
    if arguments.rtol is None:
        from ..line_plane import FAMILY_RTOL

        arguments.rtol = FAMILY_RTOL
    if not 0 < arguments.rtol < 1:
        raise InputError(f"--rtol: expected a number between 0 and 1, got {arguments.rtol:g}")
    design, pose = _design(arguments)
    result = _invariants(design, arguments.rtol)
    if pose is not None:
        from ..line_plane import singularity_reading

        position, direction = pose
        reading = singularity_reading(design, position, direction)
        result["pose"] = {"p": position.tolist(), "i": direction.tolist()}
        intersection = None if reading.intersection is None else reading.intersection.tolist()
        result["singularity"] = {"singular": reading.singular, "margin": reading.margin,
                                 "parallel": reading.parallel, "intersection": intersection,
                                 "z": reading.z, "distance": reading.distance}
    if arguments.legs is not None:
        _modes(design, arguments, result)
    if arguments.move_base is not None or arguments.move_platform is not None:
        moved, move = _rearranged(design, arguments)
        result["rearranged"] = {**move, **_invariants(moved, arguments.rtol)}
    out.write((dumps(result) if arguments.format == "json" else _text(result)) + "\n")
    return 0


def _vector(values):
    if values is None:
        return "at infinity"
    return "(" + ", ".join(f"{value + 0.0:.6g}" for value in values) + ")"


def _design_text(result, indent=""):
    margins = result["family_margins"]
    lines = [f"{indent}base      " + " ".join(f"({x:g}, {y:g})" for x, y in result["design"]["base"]),
             f"{indent}platform  " + " ".join(f"{z:g}" for z in result["design"]["platform"]),
             f"{indent}family    {result['family']}  [margins: architecture {margins['architecture']:.2e}, "
             f"B {margins['B']:.2e}, B_inf {margins['B_inf']:.2e}; cut {result['rtol']:g}]"]
    if result["cofactors"] is None:
        return lines + [f"{indent}cofactors all vanish: C1..C6, B, B_inf, Lambda+ and the B-lines are undefined"]
    return lines + [
        f"{indent}cofactors C1..C6 ∝ {_vector(result['cofactors'])}",
        f"{indent}B         {_vector(result['B'])}",
        f"{indent}B_inf     {'at infinity' if result['B_inf'] is None else _line(result['B_inf'])}",
        f"{indent}Lambda+   {'undefined' if result['Lambda_plus'] is None else _line(result['Lambda_plus'])}"]


def _line(coefficients):
    a, b, c = coefficients
    return f"{a:.6g} x + {b:.6g} y + {c:.6g} = 0"


def _text(result):
    lines = ["line-plane 5-SPU (Borràs, Thomas & Torras 2011)"] + _design_text(result, "  ")
    if "singularity" in result:
        reading = result["singularity"]
        lines.append(f"  home pose p = {_vector(result['pose']['p'])}, i = {_vector(result['pose']['i'])}: "
                     f"{'singular' if reading['singular'] else 'regular'} (margin {reading['margin']:.2e})")
    if "assembly_modes" in result:
        modes = result["assembly_modes"]
        counted = sum(mode["multiplicity"] for mode in modes)
        repeated = (f", {len(modes)} distinct: the lengths are at a singular configuration"
                    if counted > len(modes) else "")
        lines.append(f"  assembly modes: {counted} ({result['real_modes']} real{repeated})")
        for mode in modes:
            if mode["real"]:
                double = f"  (multiplicity {mode['multiplicity']})" if mode["multiplicity"] > 1 else ""
                lines.append(f"    real     p = {_vector(mode['p'])}  i = {_vector(mode['i'])}  "
                             f"residual {mode['residual']:.1e}{double}")
            else:
                lines.append(f"    complex  p = {_vector(mode['p']['real'])} + i·{_vector(mode['p']['imag'])}")
        if "routes_agree" in result:
            lines.append(f"  closedchain mechanism route: {len(result['framework_modes'])} real modes; "
                         f"{'agrees' if result['routes_agree'] else 'DISAGREES'} with the polynomial route")
    if "rearranged" in result:
        move = result["rearranged"]["move"]
        lines.append(f"  rearranged ({move['rule']}, leg {move['leg']}):")
        lines += _design_text(result["rearranged"], "    ")
    return "\n".join(lines)
