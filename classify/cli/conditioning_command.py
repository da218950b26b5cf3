"""``closedchain conditioning NAME|FILE [--param K=V] [--configuration C] [--at JSON] [--matrix M] [--mode N|all]
[--grid X=a:b:n Y=a:b:n [PHI=a:b:n]] [--length L|auto] [--out FILE] [--format json|text]``: condition numbers
and isoconditioning maps (Chablat, Caro, Wenger & Angeles 2002; Chablat, Wenger & Angeles 1998).

Without ``--grid``: κ of Ā, B, Ā⁻¹B, B⁻¹Ā and Park & Kim's λ₁/λₙ at the one
configuration (``home ⊕ --at``, or the named configuration). The catalogue's
``3-prr`` and ``five-bar`` use the papers' own A and B (2002 eqs. 4a-b; 1998
eqs. 3b-c); any other mechanism the derived relation (rows of [B A]
orthonormal in the weighted coordinates, stated in ``normalisation``). JSON:
``{"source", "mechanism", "relation", "normalisation", "definition", "kappa":
{"A", "B", "A-1B", "B-1A", "lambda"} (null where undefined or infinite),
"characteristic_length": {"value", "method", ...}}``.

With ``--grid`` (``3-prr``: X, Y in mm and optionally PHI, the orientations
searched at each position, default 72 over [−π, π); ``five-bar``: X, Y): per
working mode (``--mode``, default all) the map of 1/κ, and JSON
``{"characteristic_length", "isotropic": [postures], "matrix", "modes": [{"mode",
"global_index", "min_kappa", "max_kappa", "grid_size", "unreachable_share",
"singular_share", "matrices": {...}}], "grid"}``. ``--out`` writes the figure
(``.png``, ``.svg``) or the grid values (``.npz``, ``.json``).

``--length auto``: the 3-PRR's closed form √2 r sin γ at γ = π/2 (2002 §3.4);
for another mechanism with an orientation output, the L minimising κ(J̄) at the
configuration (scipy); not needed (null) without an orientation output.
"""

from __future__ import annotations

import math

from ._common import InputError, displacements, dumps, entry_options, is_entry, source, write_output

__all__ = ["add_parser", "run"]

MATRIX_CHOICES = ("A", "B", "A-1B", "B-1A", "lambda")
#: catalogue entries with the papers' own A and B
PAPER_ENTRIES = ("3-prr", "five-bar")
FIVE_BAR_MODES = ("++", "+-", "-+", "--")
#: default orientations searched at each 3-PRR position
DEFAULT_ORIENTATIONS = 72
#: most grid points (positions × orientations)
GRID_LIMIT = 2_000_000


def add_parser(commands):
    parser = commands.add_parser("conditioning", help="condition numbers and isoconditioning maps (Chablat et al.)")
    parser.add_argument("file", metavar="FILE|NAME", help="mechanism file (YAML or JSON) or catalogue name")
    entry_options(parser)
    parser.add_argument("--at", default=None, metavar="JSON|@FILE", help="joint displacements from home")
    parser.add_argument("--matrix", choices=MATRIX_CHOICES, default="B-1A",
                        help="the matrix of the maps, figure and scalar fields (default B-1A, the papers' K̄)")
    parser.add_argument("--mode", default="all", metavar="N|all", help="working mode of the maps (default all)")
    parser.add_argument("--grid", nargs="+", action="extend", default=None, metavar="X=a:b:n",
                        help="grid axes X=a:b:n Y=a:b:n [PHI=a:b:n] (3-prr, five-bar)")
    parser.add_argument("--length", default="auto", metavar="L|auto", help="characteristic length (default auto)")
    parser.add_argument("--out", default=None, metavar="FILE", help="figure (.png, .svg) or values (.npz, .json)")
    parser.add_argument("--format", choices=("json", "text"), default="json", help="what is printed (default json)")
    return parser


def _length_option(text):
    if text == "auto":
        return None
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"--length: expected a positive number or 'auto', got {text[:40]!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"--length: expected a positive finite number, got {text[:40]}")
    return value


def _axis(text):
    name, separator, rest = text.partition("=")
    fields = rest.split(":")
    if not separator or len(fields) != 3:
        raise InputError(f"--grid {text[:40]!r}: expected NAME=a:b:n")
    try:
        start, stop, count = float(fields[0]), float(fields[1]), int(fields[2])
    except ValueError:
        raise InputError(f"--grid {text[:40]!r}: a and b must be numbers and n an integer") from None
    if not (math.isfinite(start) and math.isfinite(stop)) or count < 1 or (count == 1 and start != stop):
        raise InputError(f"--grid {text[:40]!r}: expected finite a, b and an integer n ≥ 1 (n = 1 needs a = b)")
    return name.strip().upper(), (start, stop, count)


def _grid(texts, entry):
    axes = dict(_axis(text) for text in texts)
    allowed = {"X", "Y", "PHI"} if entry == "3-prr" else {"X", "Y"}
    unknown = sorted(set(axes) - allowed)
    if unknown or not {"X", "Y"} <= set(axes) or len(axes) != len(texts):
        raise InputError(f"--grid: expected the axes {', '.join(sorted(allowed))} once each (X and Y required), got "
                         f"{', '.join(texts)}")
    return axes


def _source_entry(arguments):
    return arguments.file if is_entry(arguments.file) else None


def _three_prr_design(mechanism):
    import numpy as np

    pivots = np.array([mechanism.joint(f"C{leg}").point for leg in (1, 2, 3)], dtype=float)
    sliders = np.array([mechanism.joint(f"B{leg}").point for leg in (1, 2, 3)], dtype=float)
    radius = float(np.linalg.norm(pivots[0] - pivots.mean(axis=0)))
    leg = float(np.linalg.norm(pivots[0] - sliders[0]))
    return radius, leg


def _modes(text, labels):
    if text == "all":
        return list(labels)
    for label in labels:
        if text == str(label):
            return [label]
    raise InputError(f"--mode: expected one of {', '.join(map(str, labels))} or all, got {text[:40]!r}")


def run(arguments, out):
    import numpy as np

    from mechanisms import configuration

    length = _length_option(arguments.length)
    mechanism, named = source(arguments)
    at = displacements(arguments.at)
    point = configuration(mechanism, {**named, **at}, where="--at").point
    entry = _source_entry(arguments)
    if entry == "3-prr-inputs":
        entry = "3-prr"
    if arguments.grid is not None:
        if entry not in PAPER_ENTRIES:
            raise InputError("--grid: isoconditioning maps are available for the catalogue entries 3-prr and five-bar")
        result, maps = _maps(arguments, mechanism, point, entry, length)
    else:
        result, maps = _single(mechanism, point, entry, length), None
    result = {"source": arguments.file, "mechanism": mechanism.name, **result}
    if arguments.out is not None:
        _write(arguments, result, maps)
    if arguments.format == "json":
        out.write(dumps(result) + "\n")
    else:
        out.write(_text(result) + "\n")


def _single(mechanism, point, entry, length):
    import numpy as np

    from ..characteristic_length import CharacteristicLength, best_length_at
    from ..conditioning import condition_numbers, mechanism_condition_numbers, mechanism_jacobians
    from ..conditioning_matrices import five_bar_matrices, three_prr_matrices, three_prr_pose_of

    if entry == "3-prr":
        radius, leg = _three_prr_design(mechanism)
        found = _three_prr_length(radius, length)
        pose, signs = three_prr_pose_of(mechanism, point)
        direct, inverse, _ = three_prr_matrices(pose, signs, radius, _base_radius(mechanism), leg)
        numbers = condition_numbers(direct, inverse, found.value, (2,), scales=(leg, leg),
                                    normalisation="Chablat, Caro, Wenger & Angeles 2002 eqs. 4a-b, 7")
        relation = "paper"
        extra = {"pose": pose.tolist(), "working_mode_signs": signs.astype(int).tolist()}
    elif entry == "five-bar":
        joints = {name: np.array(mechanism.joint(name).point) for name in "ACPDB"}
        from mechanisms import link_pose

        moved = {name: (link_pose(mechanism, link, point) @ np.append(joints[name], 1.0))[:2]
                 for name, link in (("C", "proximal_left"), ("P", "distal_left"), ("D", "proximal_right"))}
        c, p, d, b = moved["C"], moved["P"], moved["D"], joints["B"]
        proximal, distal = float(np.linalg.norm(c - joints["A"])), float(np.linalg.norm(p - c))
        angles = np.array([math.atan2(c[1], c[0]), math.atan2(*(d - b)[::-1]), math.atan2(*(p - c)[::-1]),
                           math.atan2(*(p - d)[::-1])])
        direct, inverse = five_bar_matrices(angles, proximal, distal, float(np.linalg.norm(d - b)),
                                            float(np.linalg.norm(p - d)))
        numbers = condition_numbers(direct, inverse, scales=(distal, proximal * distal),
                                    normalisation="Chablat, Wenger & Angeles 1998 eqs. 3b-c")
        found = CharacteristicLength(None, "not_needed", reference="no orientation output")
        relation = "paper"
        extra = {"angles": angles.tolist()}
    else:
        from ..metrics import end_effector_metric

        try:
            rotations = end_effector_metric(mechanism, 1.0) != end_effector_metric(mechanism, 2.0)
            has_orientation = bool(np.any(rotations))
            if length is not None:
                found = CharacteristicLength(length, "given")
            elif has_orientation:
                base = mechanism.characteristic_length
                found = best_length_at(lambda value: mechanism_jacobians(mechanism, point[None], value)[0][0],
                                       (base * 1e-3, base * 1e3))
            else:
                found = CharacteristicLength(None, "not_needed", reference="no orientation output")
            numbers = mechanism_condition_numbers(mechanism, point[None], found.value)
        except ValueError as error:
            raise InputError(str(error)) from None
        relation = "derived"
        extra = {}
    kappa = numbers.at(0) if np.ndim(numbers.values["A"]) else {key: _number(value) for key, value in
                                                                 numbers.values.items()}
    return {"relation": relation, "normalisation": numbers.normalisation, "definition": numbers.definition,
            "kappa": kappa, "characteristic_length": found.to_dict(), **extra}


def _number(value):
    value = float(value)
    return value if math.isfinite(value) else None


def _base_radius(mechanism):
    """R of a catalogue 3-PRR: the rail lines are the sides of the base triangle, at distance R/2 from O."""
    import numpy as np

    from mechanisms.catalogue import three_prr as layout

    slider = np.array(mechanism.joint("B1").point, dtype=float)
    normal = layout.rail_directions()[0] @ np.array([[0.0, 1.0], [-1.0, 0.0]])
    return float(2 * abs(np.dot(slider, normal)))


def _three_prr_length(radius, length):
    from ..characteristic_length import CharacteristicLength, three_prr_length

    if length is not None:
        return CharacteristicLength(length, "given")
    return CharacteristicLength(float(three_prr_length(radius, math.pi / 2)), "closed_form", None, None,
                                "Chablat, Caro, Wenger & Angeles 2002 §3.4: L = √2 r sin γ at γ = π/2 (Fig. 4a)")


def _maps(arguments, mechanism, point, entry, length):
    import numpy as np

    from ..characteristic_length import isotropic_postures, three_prr_kappa
    from ..conditioning_matrices import three_prr_pose_of
    from ..isoconditioning import five_bar_cartesian_map, three_prr_map

    axes = _grid(arguments.grid, entry)
    xs, ys = (np.linspace(*axes[name]) for name in ("X", "Y"))
    if entry == "3-prr":
        from mechanisms.catalogue.three_prr import WORKING_MODES

        orientations = (np.linspace(*axes["PHI"]) if "PHI" in axes
                        else np.linspace(-math.pi, math.pi, DEFAULT_ORIENTATIONS, endpoint=False))
        if len(xs) * len(ys) * len(orientations) > GRID_LIMIT:
            raise InputError(f"--grid: at most {GRID_LIMIT} points (X × Y × PHI)")
        radius, leg = _three_prr_design(mechanism)
        base = _base_radius(mechanism)
        found = _three_prr_length(radius, length)
        modes = _modes(arguments.mode, sorted(WORKING_MODES))
        maps = [three_prr_map(xs, ys, WORKING_MODES[mode], found.value, orientations, mode=str(mode),
                              platform_radius=radius, base_radius=base, leg_length=leg) for mode in modes]
        pose, signs = three_prr_pose_of(mechanism, point)
        starts = [pose, np.array([0.0, 0.0, math.pi / 3]), np.array([0.0, 0.0, -math.pi / 3])]
        isotropic = [{"posture": posture.tolist(), "kappa_minus_one": margin, "signs": signs.astype(int).tolist()}
                     for posture, margin in isotropic_postures(
                         lambda posture: three_prr_kappa(found.value, posture, signs, "B-1A", radius, base, leg),
                         starts)]
        grid = {"x": list(axes["X"]), "y": list(axes["Y"]),
                "phi": [float(orientations[0]), float(orientations[-1]), int(len(orientations))]}
    else:
        from ..characteristic_length import CharacteristicLength

        if len(xs) * len(ys) > GRID_LIMIT:
            raise InputError(f"--grid: at most {GRID_LIMIT} points (X × Y)")
        item = mechanism.joint("B").point
        joints = {name: np.array(mechanism.joint(name).point) for name in "ACP"}
        proximal = float(np.linalg.norm(joints["C"] - joints["A"]))
        distal = float(np.linalg.norm(joints["P"] - joints["C"]))
        modes = _modes(arguments.mode, FIVE_BAR_MODES)
        maps = [five_bar_cartesian_map(xs, ys, tuple(1 if sign == "+" else -1 for sign in mode), mode=mode,
                                       base=float(item[0]), proximal=proximal, distal=distal) for mode in modes]
        found = CharacteristicLength(None, "not_needed", reference="no orientation output")
        isotropic = []
        grid = {"x": list(axes["X"]), "y": list(axes["Y"])}
    entries = []
    for conditioning_map in maps:
        summary = conditioning_map.summary()
        chosen = summary["matrices"][arguments.matrix]
        entries.append({"mode": conditioning_map.mode, "global_index": chosen["global_index"],
                        "min_kappa": chosen["min_kappa"], "max_kappa": chosen["max_kappa"],
                        "grid_size": summary["grid_size"], "unreachable_share": summary["unreachable_share"],
                        "singular_share": chosen["singular_share"], "matrices": summary["matrices"]})
    return ({"relation": "paper", "matrix": arguments.matrix, "characteristic_length": found.to_dict(),
             "isotropic": isotropic, "modes": entries, "grid": grid}, maps)


def _write(arguments, result, maps):
    import numpy as np

    path = arguments.out
    suffix = path.rsplit(".", 1)[-1].lower() if "." in path else ""
    if suffix in ("png", "svg"):
        if maps is None:
            raise InputError("--out: a figure needs --grid")
        from ..figures.conditioning import isoconditioning_figure

        figure = isoconditioning_figure(maps, arguments.matrix, units="mm" if result["mechanism"] == "3-prr" else "")
        try:
            figure.savefig(path, format=suffix)
        except OSError as error:
            raise InputError(f"--out: {path}: cannot write the file: {error.strerror or error}") from None
    elif suffix == "npz":
        if maps is None:
            raise InputError("--out: grid values need --grid")
        arrays = {"x": maps[0].axes[0], "y": maps[0].axes[1]}
        for conditioning_map in maps:
            arrays[f"reachable_{conditioning_map.mode}"] = conditioning_map.reachable
            for matrix, values in conditioning_map.inverse.items():
                arrays[f"inverse_kappa_{matrix}_{conditioning_map.mode}"] = values
        try:
            np.savez_compressed(path, **arrays)
        except OSError as error:
            raise InputError(f"--out: {path}: cannot write the file: {error.strerror or error}") from None
    elif suffix == "json":
        document = dict(result)
        if maps is not None:
            document["values"] = {conditioning_map.mode: {matrix: values.tolist() for matrix, values
                                                          in conditioning_map.inverse.items()}
                                  for conditioning_map in maps}
        write_output(path, dumps(document), "--out")
    else:
        raise InputError(f"--out: expected a .png, .svg, .npz or .json file, got {path[:60]!r}")


def _text(result):
    lines = [f"{result['mechanism']} ({result['relation']} relation)"]
    length = result["characteristic_length"]
    lines.append(f"characteristic length: {length['value']} ({length['method']})")
    if "kappa" in result:
        for matrix, value in result["kappa"].items():
            lines.append(f"  κ({matrix}) = {'∞ or undefined' if value is None else f'{value:.6g}'}")
    for entry in result.get("modes", []):
        index = entry["global_index"]
        lines.append(f"  mode {entry['mode']}: global index of 1/κ({result['matrix']}) = "
                     f"{'n/a' if index is None else f'{index:.4f}'}, unreachable {entry['unreachable_share']:.1%}")
    return "\n".join(lines)
