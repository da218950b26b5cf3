"""``closedchain conditioning NAME|FILE [--param K=V] [--configuration C] [--at JSON] [--matrix M] [--mode N|all]
[--grid X=a:b:n Y=a:b:n [PHI=a:b:n | Z=a:b:n] | NAME=a:b:n ...] [--length L|auto] [--out FILE]
[--format json|text]``: condition numbers and isoconditioning maps (Chablat, Caro, Wenger & Angeles 2002;
Chablat, Wenger & Angeles 1998).

Without ``--grid``: κ of Ā, B, Ā⁻¹B, B⁻¹Ā and Park & Kim's λ₁/λₙ at the one
configuration (``home ⊕ --at``, or the named configuration). The catalogue's
``3-prr`` and ``five-bar`` use the papers' own A and B (2002 eqs. 4a-b; 1998
eqs. 3b-c, with the five-bar's own L3, L4); any other mechanism the derived
relation (rows of [B A] orthonormal in coordinates of one unit, the length,
stated in ``normalisation``). JSON:
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

``--length auto``: the 3-PRR's √2 r sin γ at its isotropic posture with γ closest to π/2, the largest L
at which an isotropic posture exists (√2 r where γ = π/2 is reachable; 2002 §3.4);
for another mechanism with an orientation output, the L minimising κ(J̄) over L
and the posture (scipy; :func:`classify.characteristic_length.mechanism_optimal_length`; where κ = 1 is
reached along a family, its largest L),
reported with the optimal posture (joint displacements) and the isotropic
postures found (κ = 1); not needed (null) without an orientation output.

Any mechanism with n inputs = n outputs = n dof (and a catalogue entry with
axes other than its paper's X, Y[, PHI | Z]) maps per working mode (its
inverse-kinematics branches at the configuration's pose,
:func:`classify.inverse_kinematics_branches.mechanism_working_modes`; ``--mode N|all``) over
a Cartesian grid ``--grid X=a:b:n Y=a:b:n [Z=a:b:n | PHI=a:b:n]`` (a position
output, or a planar pose; ``grid_kind`` "cartesian": the mode followed over the
grid up to its serial singularities,
:func:`classify.inverse_kinematics_branches.follow_working_mode`) or over a grid of joint
coordinates ``--grid NAME=a:b:n ...`` as ``closedchain map`` (``grid_kind``
"joint": assembled by continuation from the mode's configuration, on its
branch; ``held`` names the coordinates held); 1/κ(J̄) and Park & Kim's
λₙ/λ₁ are computed by the batched engine (κ(A), κ(B) of the derived relation
only with ``--matrix A|B``); unreachable points are NaN, the batched
classification's singular points counted (``classified_singular_share``) and
marked on the figure. The hybrid (``hybrid``) maps over X, Y, Z (AB the Y
axis); its figure shows the isoconditioning surfaces (the in-plane curves
turned about AB).
"""

from __future__ import annotations

import math

from ..text import printable
from ._common import (InputError, check_length_scale, check_output, configuration_options, displacements, dumps,
                      entry_options, file_after_grid, input_files, is_entry, source, write_output)

__all__ = ["add_parser", "run"]

MATRIX_CHOICES = ("A", "B", "A-1B", "B-1A", "lambda")
#: catalogue entries with the papers' own A and B
PAPER_ENTRIES = ("3-prr", "five-bar")
#: the Cartesian grid axes of the papers' maps, per catalogue entry (any other --grid is over joint coordinates)
PAPER_AXES = {"3-prr": {"X", "Y", "PHI"}, "five-bar": {"X", "Y"}, "hybrid": {"X", "Y", "Z"}}
#: most grid points of a general mechanism's map (per working mode: continuation and a classification each)
GENERAL_GRID_LIMIT = 40_000
FIVE_BAR_MODES = ("++", "+-", "-+", "--")
#: default orientations searched at each 3-PRR position
DEFAULT_ORIENTATIONS = 72
#: most grid points (positions × orientations)
GRID_LIMIT = 2_000_000


def add_parser(commands):
    parser = commands.add_parser("conditioning", help="condition numbers and isoconditioning maps (Chablat et al.)")
    parser.add_argument("file", nargs="?", metavar="FILE|NAME",  # optional to argparse: file_after_grid
                        help="mechanism file (YAML or JSON) or catalogue name")
    entry_options(parser)
    parser.add_argument("--at", default=None, metavar="JSON|@FILE", help="joint displacements from home")
    parser.add_argument("--matrix", choices=MATRIX_CHOICES, default="B-1A",
                        help="the matrix of the maps, figure and scalar fields (default B-1A, the papers' K̄)")
    parser.add_argument("--mode", default="all", metavar="N|all", help="working mode of the maps (default all)")
    parser.add_argument("--grid", nargs="+", action="extend", default=None, metavar="X=a:b:n",
                        help="grid axes: the papers' X=a:b:n Y=a:b:n [PHI=a:b:n] (3-prr), X Y (five-bar), X Y Z "
                             "(hybrid); any mechanism: its end-effector's X Y [Z | PHI], or joint coordinates "
                             "NAME=a:b:n (as closedchain map)")
    parser.add_argument("--length", default="auto", metavar="L|auto", help="characteristic length (default auto)")
    parser.add_argument("--out", default=None, metavar="FILE", help="figure (.png, .svg) or values (.npz, .json)")
    parser.add_argument("--format", choices=("json", "text"), default="json", help="what is printed (default json)")
    return parser


def _length_option(text):
    if text == "auto":
        return None
    from mechanisms._numerals import decimal_number

    try:
        value = decimal_number(text)
    except ValueError:
        raise InputError(f"--length: expected a positive number or 'auto', got {text[:40]!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"--length: expected a positive finite number, got {text[:40]}")
    return value


def _axis(text):
    """``(NAME, (a, b, n))`` of a --grid axis, the name upper-cased (:func:`classify.cli._grid.parse_axis`)."""
    from ._grid import parse_axis

    name, start, stop, count = parse_axis(text)
    return name.upper(), (start, stop, count)


def _paper_grid(texts, entry):
    """Whether every --grid axis is one of the paper's Cartesian axes of `entry` (else: joint coordinates)."""
    return all(text.partition("=")[0].strip().upper() in PAPER_AXES[entry] for text in texts)


def _grid(texts, entry):
    axes = dict(_axis(text) for text in texts)
    allowed = PAPER_AXES[entry]
    required = {"X", "Y", "Z"} if entry == "hybrid" else {"X", "Y"}
    unknown = sorted(set(axes) - allowed)
    if unknown or not required <= set(axes) or len(axes) != len(texts):
        raise InputError(f"--grid: expected the axes {', '.join(sorted(allowed))} once each "
                         f"({', '.join(sorted(required))} required), got {', '.join(texts)}")
    return axes


#: catalogue parameters outside the papers' relations: with any of them given, the relation is derived instead
#: (the papers' matrices are for the entries' own actuation and end-effector, and the five-bar's equal legs)
NOT_PAPER_PARAMETERS = ("actuated", "end_effector", "proximal_right", "distal_right")


def _source_entry(arguments):
    """The catalogue entry whose paper relation applies, or None (a file, or a --param outside the relation)."""
    if not is_entry(arguments.file):
        return None
    given = {text.partition("=")[0].strip() for text in arguments.param}
    return None if given & set(NOT_PAPER_PARAMETERS) else arguments.file


def _not_needed(length, why):
    """The characteristic length of outputs without mixed units; --length refused there (it would be ignored)."""
    from ..characteristic_length import CharacteristicLength

    if length is not None:
        raise InputError(f"--length: {why}: no characteristic length applies")
    return CharacteristicLength(None, "not_needed", reference="no orientation output")


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
    from mechanisms import configuration

    file_after_grid(arguments)
    check_output(arguments.out, "--out", input_files(arguments))
    length = _length_option(arguments.length)
    mechanism, named = source(arguments)
    check_length_scale(length, mechanism, "--length")
    if arguments.grid is None and arguments.mode != "all":
        raise InputError("--mode: applies to the maps of --grid")
    at = displacements(arguments.at)
    point = configuration(mechanism, {**named, **at}, where=configuration_options(arguments, at),
                          remedy="give closing values").point
    entry = _source_entry(arguments)
    if entry == "3-prr-inputs":
        entry = "3-prr"
    if arguments.grid is not None:
        if entry in PAPER_AXES and _paper_grid(arguments.grid, entry):
            result, maps = (_hybrid_maps(arguments, mechanism, length) if entry == "hybrid"
                            else _maps(arguments, mechanism, point, entry, length))
        else:
            result, maps = _general_maps(arguments, mechanism, point, length)
    else:
        result, maps = _single(mechanism, point, entry, length), None
    result = {"source": arguments.file, "mechanism": mechanism.name, **result}
    if arguments.out is not None:
        _write(arguments, result, maps, mechanism)
    if arguments.format == "json":
        out.write(dumps(result) + "\n")
    else:
        out.write(_text(result) + "\n")


def _single(mechanism, point, entry, length):
    import numpy as np

    from ..conditioning import condition_numbers, mechanism_condition_numbers, mechanism_jacobians
    from ..conditioning_matrices import five_bar_matrices, three_prr_matrices, three_prr_pose_of

    if entry == "3-prr":
        radius, leg = _three_prr_design(mechanism)
        found = _three_prr_length(mechanism, point, length)
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
        found = _not_needed(length, "the five-bar's outputs are positions")
        relation = "paper"
        extra = {"angles": angles.tolist()}
    else:
        try:
            mechanism_jacobians(mechanism, point[None])   # n actuators = n outputs = n dof, before any search
            found, isotropic = _general_length(mechanism, point, length)
            numbers = mechanism_condition_numbers(mechanism, point[None], found.value)
        except ValueError as error:
            raise InputError(str(error)) from None
        relation = "derived"
        extra = {"isotropic": isotropic}
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


def _three_prr_length(mechanism, point, length):
    """L of a catalogue 3-PRR: given, or the largest L with an isotropic posture (2002 §3.4,
    :func:`classify.characteristic_length.three_prr_characteristic_length`: √2 r where γ = π/2 is reachable);
    where no posture is isotropic, κ(K̄) minimised over L and the posture from the configuration's pose."""
    import numpy as np

    from ..characteristic_length import (CharacteristicLength, optimal_characteristic_length,
                                         three_prr_characteristic_length, three_prr_kappa)
    from ..conditioning_matrices import three_prr_pose_of

    if length is not None:
        return CharacteristicLength(length, "given")
    radius, leg = _three_prr_design(mechanism)
    base = _base_radius(mechanism)
    found = three_prr_characteristic_length(radius, base, leg)
    if found is not None:
        return found
    pose, signs = three_prr_pose_of(mechanism, point)
    optimised = optimal_characteristic_length(
        lambda trial, posture: three_prr_kappa(trial, posture, signs, "B-1A", radius, base, leg),
        math.sqrt(2.0) * radius, pose, rng=np.random.default_rng(0), scales=(leg, leg, 1.0))
    return CharacteristicLength(optimised.value, optimised.method, optimised.posture, optimised.kappa,
                                optimised.reference + "; no isotropic posture exists (eqs. 9a-f): κ > 1")


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
        found = _three_prr_length(mechanism, point, length)
        modes = _modes(arguments.mode, sorted(WORKING_MODES))
        maps = [three_prr_map(xs, ys, WORKING_MODES[mode], found.value, orientations, mode=str(mode),
                              platform_radius=radius, base_radius=base, leg_length=leg) for mode in modes]
        pose, signs = three_prr_pose_of(mechanism, point)
        starts = [pose, np.array([0.0, 0.0, math.pi / 3]), np.array([0.0, 0.0, -math.pi / 3])]
        if found.posture is not None:   # the isotropic posture the length came from
            starts.append(np.array(found.posture, dtype=float))
        isotropic = [{"posture": posture.tolist(), "kappa_minus_one": margin, "signs": signs.astype(int).tolist()}
                     for posture, margin in isotropic_postures(
                         lambda posture: three_prr_kappa(found.value, posture, signs, "B-1A", radius, base, leg),
                         starts, scales=(leg, leg, 1.0))]
        grid = {"x": list(axes["X"]), "y": list(axes["Y"]),
                "phi": [float(orientations[0]), float(orientations[-1]), int(len(orientations))]}
    else:
        if len(xs) * len(ys) > GRID_LIMIT:
            raise InputError(f"--grid: at most {GRID_LIMIT} points (X × Y)")
        design = _five_bar_design(mechanism)
        modes = _modes(arguments.mode, FIVE_BAR_MODES)
        maps = [five_bar_cartesian_map(xs, ys, tuple(1 if sign == "+" else -1 for sign in mode), mode=mode,
                                       **design) for mode in modes]
        found = _not_needed(length, "the five-bar's outputs are positions")
        isotropic = []
        grid = {"x": list(axes["X"]), "y": list(axes["Y"])}
    return ({"relation": "paper", "matrix": arguments.matrix, "characteristic_length": found.to_dict(),
             "isotropic": isotropic, "modes": _mode_entries(maps, arguments.matrix), "grid": grid}, maps)


def _five_bar_design(mechanism):
    """L0 and both legs' lengths L1, L2 (left) and L3, L4 (right) of a catalogue five-bar, read from its home
    geometry (joints A, C, P, D, B: Chablat, Wenger & Angeles 1998 Fig. 1), as keyword arguments of
    :func:`classify.isoconditioning.five_bar_cartesian_map`. A named configuration or ``--param`` with unequal
    legs (e.g. ``fig13_combined``: L3 = 2 L1) is mapped with its own right leg, as ``_single`` does."""
    import numpy as np

    joints = {name: np.array(mechanism.joint(name).point, dtype=float) for name in "ACPDB"}

    def distance(first, second):
        return float(np.linalg.norm(joints[first] - joints[second]))

    return {"base": float(joints["B"][0]), "proximal": distance("C", "A"), "distal": distance("P", "C"),
            "proximal_right": distance("D", "B"), "distal_right": distance("P", "D")}


def _mode_entries(maps, matrix):
    """The JSON entry of each map: its mode, the chosen matrix's index and extremes, the grid's shares."""
    entries = []
    for conditioning_map in maps:
        summary = conditioning_map.summary()
        chosen = summary["matrices"][matrix]
        entry = {"mode": conditioning_map.mode, "global_index": chosen["global_index"],
                 "min_kappa": chosen["min_kappa"], "max_kappa": chosen["max_kappa"],
                 "grid_size": summary["grid_size"], "unreachable_share": summary["unreachable_share"],
                 "singular_share": chosen["singular_share"], "matrices": summary["matrices"]}
        if "classified_singular_share" in summary:
            entry["classified_singular_share"] = summary["classified_singular_share"]
        entries.append(entry)
    return entries


def _hybrid_maps(arguments, mechanism, length):
    """The hybrid's 3-D Cartesian maps (Chablat, Wenger & Angeles 1998 §5): --grid X=… Y=… Z=…, AB the Y axis."""
    import numpy as np

    from ..characteristic_length import CharacteristicLength
    from ..isoconditioning import hybrid_map

    if length is not None:
        raise InputError("--length: the hybrid's outputs are positions: no characteristic length applies")
    axes = _grid(arguments.grid, "hybrid")
    xs, ys, zs = (np.linspace(*axes[name]) for name in ("X", "Y", "Z"))
    if len(xs) * len(ys) * len(zs) > GRID_LIMIT:
        raise InputError(f"--grid: at most {GRID_LIMIT} points (X × Y × Z)")
    joints = {name: np.array(mechanism.joint(name).point, dtype=float) for name in "ABCP"}
    base = float(np.linalg.norm(joints["B"] - joints["A"]))
    proximal = float(np.linalg.norm(joints["C"] - joints["A"]))
    distal = float(np.linalg.norm(joints["P"] - joints["C"]))
    modes = _modes(arguments.mode, FIVE_BAR_MODES)
    maps = [hybrid_map(xs, ys, zs, tuple(1 if sign == "+" else -1 for sign in mode), mode=mode, base=base,
                       proximal=proximal, distal=distal) for mode in modes]
    found = CharacteristicLength(None, "not_needed", reference="no orientation output")
    grid = {"x": list(axes["X"]), "y": list(axes["Y"]), "z": list(axes["Z"])}
    return ({"relation": "paper", "normalisation": "Chablat, Wenger & Angeles 1998 eqs. 22a-b (the five-bar's "
                                                   "plane frame; θ1 enters neither A nor B)",
             "matrix": arguments.matrix, "characteristic_length": found.to_dict(), "isotropic": [],
             "modes": _mode_entries(maps, arguments.matrix), "grid": grid}, maps)


def _general_maps(arguments, mechanism, point, length):
    """Maps of any mechanism over a joint grid (--grid NAME=a:b:n …) or a Cartesian one (--grid X=… Y=…), one
    per working mode (IK branch): :func:`classify.isoconditioning.joint_grid_maps` and
    :func:`~classify.isoconditioning.cartesian_grid_maps`."""
    from ..grid_continuation import held_columns
    from ..inverse_kinematics_branches import cartesian_outputs, mechanism_working_modes
    from ..isoconditioning import cartesian_grid_maps, joint_grid_maps
    from ._grid import parse_grid

    cartesian = _cartesian_grid(arguments.grid, mechanism)
    grid = None if cartesian is not None else parse_grid(arguments.grid, mechanism)
    if cartesian is not None:
        try:
            cartesian_outputs(mechanism, point, *cartesian[:2])  # the axes fit the output, before any work
        except ValueError as error:
            raise InputError(f"--grid: {error}") from None
    try:
        found, isotropic = _general_length(mechanism, point, length)
        modes = mechanism_working_modes(mechanism, point)
        size = grid.size if grid is not None else math.prod(len(values) for values in cartesian[1])
        if size * (len(modes) if arguments.mode == "all" else 1) > GENERAL_GRID_LIMIT:
            raise InputError(f"--grid: at most {GENERAL_GRID_LIMIT} points over all the working modes mapped "
                             f"(a general mechanism's map assembles and classifies every point)")
        chosen = _modes(arguments.mode, [mode.label for mode in modes])
        mapped = [mode for mode in modes if mode.label in chosen]
        derived = arguments.matrix in ("A", "B")
        if cartesian is not None:
            names, axes, values = cartesian
            held, description = None, {name: list(value) for name, value in zip(names, values)}
            maps = cartesian_grid_maps(mechanism, mapped, names, axes, point, found.value, derived=derived)
        else:
            held, description = held_columns(mechanism, grid), grid.to_dict()
            maps = joint_grid_maps(mechanism, mapped, grid, found.value, derived=derived)
    except ValueError as error:
        raise InputError(str(error)) from None
    return ({"relation": "derived", "normalisation": _DERIVED_NORMALISATION, "matrix": arguments.matrix,
             "characteristic_length": found.to_dict(), "isotropic": isotropic,
             "working_modes": [mode.to_dict() for mode in modes],
             "grid_kind": "joint" if cartesian is None else "cartesian",
             "held": None if held is None else [mechanism.coordinate_names[column] for column in held],
             "modes": _mode_entries(maps, arguments.matrix), "grid": description}, maps)


#: the axes of a general mechanism's Cartesian grid: position outputs (x, y[, z]), planar poses (x, y[, φ])
CARTESIAN_AXES = ("X", "Y", "Z", "PHI")


def _cartesian_grid(texts, mechanism):
    """(names, axes, [a, b, n] per axis) of a Cartesian --grid (every axis one of X, Y, Z, PHI and none a
    coordinate name of the mechanism), in the order X, Y, Z, PHI; None for a grid of joint coordinates."""
    import numpy as np

    names = [text.partition("=")[0].strip() for text in texts]
    if not all(name.upper() in CARTESIAN_AXES and name not in mechanism.coordinate_names for name in names):
        return None
    axes = dict(_axis(text) for text in texts)
    if len(axes) != len(texts) or not {"X", "Y"} <= set(axes):
        raise InputError(f"--grid: a Cartesian grid needs X and Y once each (and Z or PHI), got {', '.join(texts)}")
    order = [name for name in CARTESIAN_AXES if name in axes]
    return (tuple(name.lower() if name != "PHI" else "φ" for name in order),
            tuple(np.linspace(*axes[name]) for name in order), tuple(axes[name] for name in order))


_DERIVED_NORMALISATION = ("A-1B, B-1A: J̄ = H^½ Df T (Λ E^½ Dπ T)⁻¹ (batched; Λ = L on angular actuated rates, "
                          "1 on prismatic ones); lambda: Park & Kim's λ₁/λₙ = κ(J̄)² on the same rates (undefined "
                          "where the batched classification says so); A, B (only with --matrix A|B): the derived "
                          "relation, rows of [B A] orthonormal in coordinates of one unit, the length (angular "
                          "actuated rates and output rotations multiplied by L)")


def _general_length(mechanism, point, length):
    """(CharacteristicLength, isotropic postures) of a general mechanism: given, not needed, or optimised."""
    from ..characteristic_length import CharacteristicLength, mechanism_optimal_length

    if not _has_orientation(mechanism):
        return _not_needed(length, "the end-effector's outputs are not positions and orientations together"), []
    if length is not None:
        return CharacteristicLength(length, "given"), []
    found, isotropic = mechanism_optimal_length(mechanism, point)
    return found, [{"displacements": displacements, "kappa_minus_one": margin}
                   for displacements, margin in isotropic]


def _has_orientation(mechanism):
    """Whether L weighs some output (the end-effector metric changes with it), tried at the mechanism's own size
    (any fixed length, e.g. 1, is refused by a mechanism far larger or smaller in its unit)."""
    import numpy as np

    from ..metrics import end_effector_metric

    size = float(mechanism.characteristic_length)
    return bool(np.any(end_effector_metric(mechanism, size) != end_effector_metric(mechanism, 2.0 * size)))


def _write(arguments, result, maps, mechanism=None):
    import numpy as np

    path = arguments.out
    suffix = path.rsplit(".", 1)[-1].lower() if "." in path else ""
    if suffix in ("png", "svg"):
        if maps is None:
            raise InputError("--out: a figure needs --grid")
        figure = _figure(maps, arguments.matrix, result, mechanism)
        try:
            figure.savefig(path, format=suffix)
        except OSError as error:
            raise InputError(f"--out: {path}: cannot write the file: {error.strerror or error}") from None
    elif suffix == "npz":
        if maps is None:
            raise InputError("--out: grid values need --grid")
        arrays = {f"axis_{index}": values for index, values in enumerate(maps[0].axes)}
        arrays["axis_names"] = np.array(maps[0].axis_names)
        arrays.update({"x": maps[0].axes[0], "y": maps[0].axes[1]})
        for conditioning_map in maps:
            arrays[f"reachable_{conditioning_map.mode}"] = conditioning_map.reachable
            if "singular" in conditioning_map.extra:
                arrays[f"singular_{conditioning_map.mode}"] = conditioning_map.extra["singular"]
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


def _figure(maps, matrix, result, mechanism=None):
    """The figure of --out .png/.svg: 2-D maps with their curves; the hybrid's surfaces of revolution. A grid of
    joint coordinates (`mechanism` given) has its axes labelled as displacements from home with their unit
    (:func:`_joint_axis_names`)."""
    import numpy as np

    from ..figures.conditioning import isoconditioning_figure, isoconditioning_surface_figure

    if maps[0].axis_names == ("x", "y", "z"):  # the hybrid: its in-plane maps turned about AB
        from ..isoconditioning import hybrid_plane_map

        xs, ys, zs = maps[0].axes
        radius = float(np.max(np.hypot(*np.meshgrid(xs, zs, indexing="ij"))))
        distances = np.linspace(0.0, radius, max(len(xs), len(zs), 2))
        design = maps[0].extra["design"]
        plane_maps = [hybrid_plane_map(distances, ys, conditioning_map.extra["signs"], conditioning_map.mode,
                                       base=design["L0"], proximal=design["L1"], distal=design["L2"])
                      for conditioning_map in maps]
        return isoconditioning_surface_figure(plane_maps, matrix)
    if len(maps[0].axes) != 2:
        raise InputError(f"--out: a figure needs a grid of two axes, got {len(maps[0].axes)} (write .npz or .json)")
    if result["relation"] == "derived":
        if (result.get("grid_kind") == "joint" and mechanism is not None
                and set(maps[0].axis_names) <= set(mechanism.coordinate_names)):
            from dataclasses import replace

            names = _joint_axis_names(mechanism, maps[0].axis_names)
            maps = [replace(conditioning_map, axis_names=names) for conditioning_map in maps]
        return isoconditioning_figure(maps, matrix, equal_aspect=result.get("grid_kind") == "cartesian")
    return isoconditioning_figure(maps, matrix, units="mm" if result["mechanism"] == "3-prr" else "")


def _joint_axis_names(mechanism, names):
    """The axis labels of a map over joint coordinates `names`: each a displacement from home with its unit,
    ``"A − A₀ (rad)"`` for an angle, the mechanism's unit of length for a slide
    (:func:`classify.figures.loci.axis_labels`).

    Parameters
    ----------
    mechanism : Mechanism
    names : sequence of str
        Coordinate names of the grid's axes.

    Returns
    -------
    tuple of str
        As the figure's labels are escaped again (:func:`classify.text.drawn`), their dollar signs are not.
    """
    from ..figures.loci import axis_labels

    columns = [mechanism.coordinate_names.index(name) for name in names]
    return tuple(label.replace("\\$", "$") for label in axis_labels(mechanism, columns, units=True))


def _text(result):
    lines = [f"{printable(result['mechanism'])} ({result['relation']} relation)"]
    length = result["characteristic_length"]
    lines.append(f"characteristic length: {length['value']} ({length['method']})")
    if "kappa" in result:
        for matrix, value in result["kappa"].items():
            lines.append(f"  κ({matrix}) = {'∞ or undefined' if value is None else f'{value:.6g}'}")
    if result.get("working_modes"):
        lines.append(f"working modes (inverse-kinematics branches at the pose): {len(result['working_modes'])}")
    if result.get("isotropic"):
        lines.append(f"isotropic postures found: {len(result['isotropic'])}")
    for entry in result.get("modes", []):
        index = entry["global_index"]
        lines.append(f"  mode {printable(entry['mode'])}: global index of 1/κ({result['matrix']}) = "
                     f"{'n/a' if index is None else f'{index:.4f}'}, unreachable {entry['unreachable_share']:.1%}")
    return "\n".join(lines)
