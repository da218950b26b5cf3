"""``closedchain map FILE|NAME --grid NAME=a:b:n [NAME=a:b:n ...] [--project] [--configuration C] [--param K=V]
[--survey FILE] [--out FILE.npz|csv|json|jsonl] [--format json|text]``: classify every point of a grid of joint
coordinates.

The grid is over joint coordinates given as displacements from the home, as
``--at`` gives them (``A``, ``S1[x]``, ``U1[2]``; :mod:`classify.cli._names`);
the coordinates not on the grid keep the value of the configuration the
command starts from (``--configuration``, else the home; a catalogue entry's
home is its configuration). Each grid point becomes a configuration on M in
one of two ways.

Assembly (the default). The grid coordinates are held at exactly the grid
values, and so are the actuated coordinates off the grid when the grid is
over actuated coordinates only (as ``closedchain classify --assemble``: the
inputs not named stay where they are); an S joint with a grid coordinate is
held whole. The other coordinates close the loops (where the held ones leave
them free to move, the corrections of least length pick the configuration
nearest the previous one), by continuation over the
grid: the grid point nearest the starting configuration is reached from it,
and every other point from an already reached neighbouring grid point (one
step along one axis), so the map follows the starting configuration's
assembly branch (working mode) over the grid. One continuation step, from a
configuration q on M to the held values h' (the predictor–corrector
:func:`mechanisms.assemble` uses from the home): the held coordinates move
from their values at q to h' in sub-steps of at most 0.2 (dimensionless), each
predicted to first order, ``q ⊕ −s·(DΦ_q s)⁺ DΦ_h Δh``, and corrected by
Gauss–Newton in the free coordinates to ‖Φ‖ ≤ 1e-10 with no half-turn loop; a
sub-step whose corrector does not converge, or moves the free coordinates
more than 0.25 (dimensionless: a jump to another branch), is halved, and the
step fails below 1/64 of the way (or 1e-5). A grid point none of whose
reached neighbours leads to it is *unreachable* (outside the inputs' reach on
this branch, or beyond a fold). A part of the grid with no reached neighbour
at all is started like the first point: from the starting configuration,
nearest point first. The held values of a reached point are the grid values
bit for bit. All the grid points of one continuation front are computed at
once (array work): a grid of n₁ × … × n_d points takes about n₁ + … + n_d
fronts, so a long one-dimensional grid is the slowest per point.

Projection (``--project``). Each grid point's configuration (the starting
configuration with the grid coordinates set) is projected onto M
(Gauss–Newton, :func:`manifold.project`, all points at once), which moves
every coordinate, the grid ones included; unreachable where projection
fails. Each point reports its projection distance.

Then one :func:`classify.classify_many` over the reachable points, with the
mechanism's survey of M (``--survey FILE``: a cache file, read when it was
made for this mechanism, else computed and written).

Output: per grid point its index, grid coordinates, whether it was reached,
and, when reached, the row of :meth:`classify.Classifications.rows` (kinds,
singular, dof, ranks, expected ranks, margins, λ's, condition number,
degeneracy) and the displacements of the configuration classified. ``--out``:
``.json`` one document ``{"source", "mechanism", "method": "assemble" |
"project", "held": [coordinate names] | null, "grid": {name: [a, b, n]},
"shape", "survey", "points": [...], "summary": {"total", "reachable",
"unreachable", "regular", "cspace", "actuator", "end_effector"}}``; ``.jsonl`` one point per line;
``.csv`` one point per row; ``.npz`` arrays shaped like the grid
(``reachable``, ``coordinates`` [*shape, d], ``points``, ``displacements``,
and every column of :meth:`classify.Classifications.arrays` — NaN, -1 or
false where unreachable). Without ``--out``: the JSON document
(``--format json``) or a table with the counts and, for one- and
two-dimensional grids, a picture of the kinds (``--format text``).
"""

from __future__ import annotations

from ..progress import progress_bar, show_progress
from ..text import printable
from ._common import InputError, check_length_scale, common_options, entry_options, source, survey_option

__all__ = ["add_parser", "run", "held_columns", "assemble_grid", "grid_neighbours", "PICTURE"]

#: ‖Φ‖ of an assembled grid point (the default of :func:`mechanisms.assemble`)
_TOLERANCE = 1e-10
#: largest dimensionless corrector move a continuation sub-step accepts (as :mod:`mechanisms.assembly`)
_JUMP = 0.25
#: largest dimensionless move of the held coordinates in one sub-step
_SUBSTEP = 0.2
#: continuation gives up when a sub-step falls below this fraction of the way to the target, or below 1e-5
#: (dimensionless): a grid map needs the points on the branch, not where exactly it ends between two of them
_SMALLEST_FRACTION = 1 / 64
_SMALLEST_STEP = 1e-5
#: Gauss–Newton iterations of one corrector
_CORRECTOR_ITERATIONS = 8
#: sub-steps one continuation may take
_STEP_LIMIT = 2000
#: grid points tried at once when a part of the grid is started from the configuration: first, and at most
_SEED_CHUNK = 16
_SEED_CHUNK_LIMIT = 4096

#: the text picture's character per grid point: kinds (several: "+"), regular, unreachable
PICTURE = {"regular": ".", "actuator": "A", "end_effector": "E", "cspace": "C", "several": "+", "unreachable": "x"}


def add_parser(commands):
    parser = commands.add_parser(
        "map", help="classify every point of a grid of joint coordinates (assembled, or projected onto M)")
    parser.add_argument("file", metavar="FILE|NAME", help="mechanism file (YAML or JSON) or catalogue name")
    entry_options(parser)
    parser.add_argument("--grid", nargs="+", action="extend", required=True, metavar="NAME=a:b:n",
                        help="a grid axis: coordinate NAME (joint displacement from home, as --at) from a to b in n "
                             "points; repeat for more axes (at most 1e6 points in all)")
    parser.add_argument("--project", action="store_true",
                        help="project each grid point's configuration onto the C-space (moves every coordinate) "
                             "instead of holding the grid coordinates and solving the loops for the others")
    survey_option(parser)
    parser.add_argument("--out", default=None, metavar="FILE",
                        help="write the map to FILE (.npz, .csv, .json or .jsonl) and print a summary")
    parser.add_argument("--format", choices=("json", "text"), default="text",
                        help="what is printed without --out (default text)")
    common_options(parser)
    return parser


# ------------------------------------------------------------------------------------------------ held coordinates

def held_columns(mechanism, grid):
    """The tangent coordinates held at each grid point (sorted column indices).

    The grid's coordinates (an S joint's three when one of them is on the
    grid), and the actuated coordinates off the grid when every grid
    coordinate is actuated.
    """
    from ._names import coordinate_columns

    held = set(grid.columns)
    for name, columns in coordinate_columns(mechanism).items():
        if mechanism.joint(name).type == "S" and held & set(columns):
            held |= set(columns)
    actuated = set(mechanism.actuated_coordinates)
    if set(grid.columns) <= actuated:
        held |= actuated
    return tuple(sorted(held))


def _held_entries(ambient, held):
    """The point entries of the factors whose tangent coordinates are held, shape=[h]."""
    import numpy as np

    held = set(held)
    entries = []
    for point_part, tangent_part in zip(ambient.point_slices, ambient.tangent_slices):
        if held & set(range(ambient.dim)[tangent_part]):
            entries += list(range(ambient.point_size)[point_part])
    return np.array(entries, dtype=int)


# ------------------------------------------------------------------------------------------------ continuation

def _correct(mechanism, points, free, iterations=_CORRECTOR_ITERATIONS):
    """Gauss–Newton corrector in the free coordinates from a stack of configurations (held ones fixed bit for bit).

    ``q ← q ⊕ −s·(DΦ_q(q)·s)⁺ Φ(q)``, the step of least dimensionless length,
    until ‖Φ‖ ≤ 1e-3 × the assembly tolerance, `iterations` steps, or a step
    that does not decrease ‖Φ‖ (then the iteration stops there): the
    corrector of a continuation step, whose predictor is close, so neither
    damped nor line-searched (a step that does not converge is halved by the
    caller instead).

    Parameters
    ----------
    mechanism : Mechanism
    points : ndarray, shape=[m, point_size]
    free : ndarray of int, shape=[f]
        The free tangent coordinates.

    Returns
    -------
    points : ndarray, shape=[m, point_size]
    residuals : ndarray, shape=[m]
        ‖Φ‖ at each (NaN where the iteration diverged).
    """
    import numpy as np

    from mechanisms.kinematics import constraint, constraint_jacobian, kinematics_of

    ambient = kinematics_of(mechanism).ambient
    scales = ambient.tangent_scales[free]
    points = np.array(points, dtype=float)
    values = constraint(mechanism, points)
    norms = np.linalg.norm(values, axis=-1)
    if not len(free):
        return points, norms
    active = np.isfinite(norms)
    for _ in range(iterations):
        rows = np.flatnonzero(active & (norms > 1e-3 * _TOLERANCE))
        if not rows.size:
            break
        jacobian = constraint_jacobian(mechanism, points[rows])[..., free] * scales
        tangent = np.zeros((rows.size, ambient.dim))
        tangent[:, free] = -scales * np.einsum("arc,ac->ar", np.linalg.pinv(jacobian, rcond=1e-12), values[rows])
        points[rows] = ambient.retract(points[rows], tangent)
        values[rows] = constraint(mechanism, points[rows])
        previous, norms[rows] = norms[rows], np.linalg.norm(values[rows], axis=-1)
        active[rows] = norms[rows] < previous  # not converging (above the tolerance): the caller halves the step
    return points, norms


def _continue(mechanism, sources, targets, held, entries):
    """Continuation from configurations on M to the held values of target points, all at once.

    Parameters
    ----------
    mechanism : Mechanism
    sources : ndarray, shape=[m, point_size]
        Configurations on M.
    targets : ndarray, shape=[m, point_size]
        Points whose held entries are the values to reach.
    held : ndarray of int
        The held tangent coordinates.
    entries : ndarray of int
        The point entries of the held factors (:func:`_held_entries`).

    Returns
    -------
    reached : ndarray, shape=[m, point_size]
        The configurations (held entries those of `targets`; NaN rows where not reached).
    ok : ndarray of bool, shape=[m]
    """
    import numpy as np

    from mechanisms.kinematics import closes, constraint_jacobian, kinematics_of

    ambient = kinematics_of(mechanism).ambient
    scales = ambient.tangent_scales
    free = np.setdiff1d(np.arange(ambient.dim), held)
    count = len(sources)
    delta = np.zeros((count, ambient.dim))
    delta[:, held] = ambient.inverse_retract(sources, targets)[:, held]
    size = np.linalg.norm(delta / scales, axis=-1)
    largest = np.minimum(1.0, _SUBSTEP / np.maximum(size, 1e-300))
    step, done = largest.copy(), np.zeros(count)
    current = np.array(sources, dtype=float)
    status = np.zeros(count, dtype=np.int8)  # 0 walking, 1 reached, -1 failed
    for _ in range(_STEP_LIMIT):
        rows = np.flatnonzero(status == 0)
        if not rows.size:
            break
        goal = np.minimum(1.0, done[rows] + step[rows])
        base = ambient.retract(sources[rows], goal[:, None] * delta[rows])
        final = goal == 1.0
        base[final] = targets[rows[final]]  # the grid values bit for bit
        start = current[rows].copy()
        start[:, entries] = base[:, entries]
        tangent = np.zeros((rows.size, ambient.dim))
        if free.size:
            jacobian = constraint_jacobian(mechanism, current[rows])
            motion = np.einsum("mch,mh->mc", jacobian[..., held], (goal - done[rows])[:, None] * delta[rows][:, held])
            inverse = np.linalg.pinv(jacobian[..., free] * scales[free], rcond=1e-12)
            tangent[:, free] = -scales[free] * np.einsum("mfc,mc->mf", inverse, motion)
        predicted = ambient.retract(start, tangent)
        corrected, residuals = _correct(mechanism, predicted, free)
        move = np.linalg.norm(ambient.inverse_retract(predicted, corrected)[:, free] / scales[free], axis=-1)
        good = ((residuals <= _TOLERANCE) & np.asarray(closes(mechanism, corrected, _TOLERANCE), dtype=bool)
                & (move <= _JUMP))
        accepted, refused = rows[good], rows[~good]
        current[accepted], done[accepted] = corrected[good], goal[good]
        step[accepted] = np.minimum(2.0 * step[accepted], largest[accepted])
        status[accepted[goal[good] == 1.0]] = 1
        step[refused] /= 2.0
        status[refused[(step[refused] < _SMALLEST_FRACTION) | (step[refused] * size[refused] < _SMALLEST_STEP)]] = -1
    ok = status == 1
    current[~ok] = np.nan
    return current, ok


def grid_neighbours(shape):
    """The neighbours of every grid point, shape=[n, 2d]: column 2a the point one step back along axis a,
    2a + 1 one step forward (flat C-order indices, -1 off the grid)."""
    import numpy as np

    flat = np.arange(int(np.prod(shape, dtype=np.int64))).reshape(shape)
    result = np.full((flat.size, 2 * len(shape)), -1, dtype=np.int64)
    for axis in range(len(shape)):
        for column, (target, origin) in enumerate(((slice(1, None), slice(None, -1)),
                                                   (slice(None, -1), slice(1, None)))):
            neighbour = np.full(shape, -1, dtype=np.int64)
            into, out_of = [slice(None)] * len(shape), [slice(None)] * len(shape)
            into[axis], out_of[axis] = target, origin
            neighbour[tuple(into)] = flat[tuple(out_of)]
            result[:, 2 * axis + column] = neighbour.reshape(-1)
    return result


def assemble_grid(mechanism, start, targets, shape, held, bar=None):
    """Every grid point assembled by continuation over the grid from a configuration (see the module notes).

    Parameters
    ----------
    mechanism : Mechanism
    start : ndarray, shape=[point_size]
        The starting configuration, on M.
    targets : ndarray, shape=[n, point_size]
        The grid points in C order: the held entries are the values to hold.
    shape : tuple of int
        The grid's shape (n = its product).
    held : sequence of int
        The held tangent coordinates (:func:`held_columns`).
    bar : progress bar, optional
        Updated by the number of points reached.

    Returns
    -------
    points : ndarray, shape=[n, point_size]
        NaN rows where unreachable.
    reached : ndarray of bool, shape=[n]
    """
    import numpy as np

    from mechanisms.kinematics import kinematics_of

    ambient = kinematics_of(mechanism).ambient
    held = np.asarray(held, dtype=int)
    entries = _held_entries(ambient, held)
    targets = np.asarray(targets, dtype=float)
    count = len(targets)
    neighbours = grid_neighbours(shape)
    points = np.full(targets.shape, np.nan)
    reached = np.zeros(count, dtype=bool)
    tried = np.zeros(neighbours.shape, dtype=bool)
    started = np.zeros(count, dtype=bool)
    distance = np.linalg.norm(ambient.inverse_retract(start, targets)[:, held] / ambient.tangent_scales[held],
                              axis=-1)
    candidates = np.zeros(0, dtype=np.int64)
    while True:
        if candidates.size:  # a continuation front: each from one reached neighbour not tried yet
            around = neighbours[candidates]
            usable = (around >= 0) & reached[np.maximum(around, 0)] & ~tried[candidates]
            keep = usable.any(axis=1)
            candidates, around, usable = candidates[keep], around[keep], usable[keep]
        if candidates.size:
            direction = np.argmax(usable, axis=1)
            origins = around[np.arange(candidates.size), direction]
            tried[candidates, direction] = True
            found, ok = _continue(mechanism, points[origins], targets[candidates], held, entries)
            won = candidates[ok]
            points[won], reached[won] = found[ok], True
            if bar is not None:
                bar.update(int(won.size))
            following = neighbours[won].reshape(-1)
            following = following[following >= 0]
            candidates = np.unique(np.concatenate([candidates[~ok], following[~reached[following]]]))
            continue
        seed = _seed(mechanism, start, targets, held, entries, distance,
                     np.flatnonzero(~reached & ~started & ~tried.any(axis=1)), started)
        if seed is None:
            break
        index, point = seed
        points[index], reached[index] = point, True
        if bar is not None:
            bar.update(1)
        candidates = neighbours[index][neighbours[index] >= 0]
        candidates = candidates[~reached[candidates]]
    return points, reached


def _seed(mechanism, start, targets, held, entries, distance, fresh, started):
    """The grid point nearest the starting configuration (among `fresh`) that continuation from it reaches;
    (index, configuration) or None. The points are tried nearest first, in chunks that double in size (the first
    is usually the one), and marked in `started`."""
    import numpy as np

    order = fresh[np.argsort(distance[fresh], kind="stable")]
    begin, size = 0, _SEED_CHUNK
    while begin < order.size:
        chunk = order[begin:begin + size]
        started[chunk] = True
        found, ok = _continue(mechanism, np.broadcast_to(start, targets[chunk].shape), targets[chunk], held,
                              entries)
        if ok.any():
            first = int(np.argmax(ok))
            return int(chunk[first]), found[first]
        begin, size = begin + size, min(2 * size, _SEED_CHUNK_LIMIT)
    return None


# ------------------------------------------------------------------------------------------------ output

def _per_point_arrays(result, reachable, shape):
    """The columns of :meth:`classify.Classifications.arrays` spread over the grid (NaN, -1, false where
    unreachable)."""
    import numpy as np

    arrays = {}
    for name, column in result.arrays().items():
        column = np.asarray(column)
        if name == "kinds":  # the names of the columns of `singular`, not a column
            arrays[name] = column
            continue
        if column.dtype == bool:
            fill = False
        elif np.issubdtype(column.dtype, np.integer):
            fill = -1
        else:
            fill = np.nan
        spread = np.full((reachable.size,) + column.shape[1:], fill, dtype=column.dtype)
        spread[reachable] = column
        arrays[name] = spread.reshape(tuple(shape) + column.shape[1:])
    return arrays


def _picture(kinds, reachable, shape):
    """One character per grid point (:data:`PICTURE`): one line for a 1-D grid, one line per value of the first
    axis for a 2-D grid."""
    characters = []
    for index in range(len(reachable)):
        if not reachable[index]:
            characters.append(PICTURE["unreachable"])
        elif not kinds[index]:
            characters.append(PICTURE["regular"])
        else:
            characters.append(PICTURE[kinds[index][0]] if len(kinds[index]) == 1 else PICTURE["several"])
    width = shape[-1]
    return "\n".join("".join(characters[row:row + width]) for row in range(0, len(characters), width))


def _legend():
    return ", ".join(f"{character} {name.replace('_', '-')}" for name, character in PICTURE.items())


def _configurations(arguments, mechanism, named, grid):
    """The grid's configurations: (points [n, point_size], reachable [n], projection distances [n] or None)."""
    import numpy as np

    from mechanisms import CLOSURE_TOLERANCE, configuration

    from . import _configurations as configurations

    starting = configuration(mechanism, named, where="--configuration")
    base = configurations.displacement_vector(mechanism, named)
    requested = np.array(np.broadcast_to(base, (grid.size, base.size)))
    requested[:, list(grid.columns)] = grid.values().reshape(grid.size, len(grid.columns))
    targets = configurations.points_of(mechanism, requested)
    if arguments.project:
        return configurations.project_configurations(mechanism, targets, CLOSURE_TOLERANCE)
    bar = progress_bar(grid.size, "assembling", unit="point")
    try:
        points, reachable = assemble_grid(mechanism, starting.point, targets, grid.shape,
                                          held_columns(mechanism, grid), bar)
    finally:
        bar.close()
    return points, reachable, None


def _entries(mechanism, grid, reachable, result, displacements, distance):
    """One JSON-ready entry per grid point, in C order (see the module notes)."""
    import numpy as np

    from ._configurations import joint_displacements

    rows = iter(result.rows())
    given = iter(joint_displacements(mechanism, displacements))
    coordinates = grid.values().reshape(grid.size, len(grid.names)).tolist()
    indices = np.array(np.unravel_index(np.arange(grid.size), grid.shape)).T.tolist()
    entries = []
    for flat in range(grid.size):
        entry = {"index": indices[flat], "coordinates": dict(zip(grid.names, coordinates[flat])),
                 "reachable": bool(reachable[flat])}
        if reachable[flat]:
            entry.update(next(rows))
            entry["displacements"] = next(given)
            if distance is not None:
                entry["projection_distance"] = float(distance[flat])
        entries.append(entry)
    return entries


def _arrays(mechanism, grid, points, reachable, result, displacements, distance):
    """The NPZ arrays of a map, shaped like the grid."""
    import numpy as np

    arrays = _per_point_arrays(result, reachable, grid.shape)
    spread = np.full((grid.size, displacements.shape[-1]), np.nan)
    spread[reachable] = displacements
    arrays.update({
        "grid_names": np.array(grid.names), "grid_start": np.array(grid.starts),
        "grid_stop": np.array(grid.stops), "grid_count": np.array(grid.counts),
        "coordinates": grid.values(), "reachable": reachable.reshape(grid.shape),
        "points": np.where(reachable[:, None], points, np.nan).reshape(grid.shape + (points.shape[-1],)),
        "displacements": spread.reshape(grid.shape + (displacements.shape[-1],)),
        "coordinate_names": np.array(mechanism.coordinate_names)})
    if distance is not None:
        arrays["projection_distance"] = distance.reshape(grid.shape)
    return arrays


def _text(grid, entries, reachable, summary_text):
    """The table, the counts and, for one- and two-dimensional grids, the picture."""
    from ._outputs import result_table

    table = result_table(
        tuple(printable(name) for name in grid.names),
        [(tuple(f"{entry['coordinates'][name]:.6g}" for name in grid.names),
          entry if entry["reachable"] else None) for entry in entries])
    lines = [table, "", summary_text]
    if len(grid.shape) <= 2:
        kinds = [tuple(entry.get("kinds", ())) for entry in entries]
        axes = " × ".join(printable(name) for name in grid.names)
        lines += ["", f"kinds over the grid ({axes}; {_legend()}):", _picture(kinds, reachable, grid.shape)]
    return "\n".join(lines) + "\n"


def run(arguments, out):
    from ..batch import classify_many
    from ..model import model_of
    from . import _outputs as outputs
    from ._batch_io import model_survey
    from ._configurations import displacements_of
    from ._grid import parse_grid
    from .classify_command import describe_source

    check_length_scale(arguments.length_scale)
    if arguments.seed:
        raise InputError("--seed: does not apply to `closedchain map` (the map is deterministic)")
    file_format = outputs.output_format(arguments.out) if arguments.out is not None else None
    mechanism, named = source(arguments)
    grid = parse_grid(arguments.grid, mechanism)
    points, reachable, distance = _configurations(arguments, mechanism, named, grid)
    model = model_of(mechanism, arguments.length_scale)
    survey = model_survey(arguments.survey, model)
    result = classify_many(model, points[reachable], survey=survey, progress=show_progress())
    displacements = displacements_of(mechanism, result.points)
    reached = int(reachable.sum())
    summary = {"total": grid.size, "reachable": reached, "unreachable": grid.size - reached,
               **outputs.kind_counts(result)}
    summary_text = "map of " + outputs.summary_line(summary, grid.size, "grid points")
    if file_format == "npz":
        outputs.write_npz(arguments.out, _arrays(mechanism, grid, points, reachable, result, displacements,
                                                 distance))
        out.write(f"{summary_text}; written to {printable(arguments.out)}\n")
        return
    entries = _entries(mechanism, grid, reachable, result, displacements, distance)
    if file_format is None and arguments.format == "text":
        out.write(_text(grid, entries, reachable, summary_text))
        return
    held = None if arguments.project else [mechanism.coordinate_names[column]
                                           for column in held_columns(mechanism, grid)]
    document = {"source": describe_source(arguments), "mechanism": mechanism.name,
                "method": "project" if arguments.project else "assemble", "held": held,
                "grid": grid.to_dict(), "shape": list(grid.shape), "survey": result.survey.to_dict(),
                "points": entries, "summary": summary}
    if file_format is None:
        out.write(outputs.json_text(document) + "\n")
        return
    outputs.write_rows(arguments.out, entries, document)
    out.write(f"{summary_text}; written to {printable(arguments.out)}\n")
