"""``closedchain compare FILE|NAME [--at …] [--inputs J1,J5] [--outputs …] [--relation R] [--samples N]
[--path N] [--format json|text]``: Park–Kim and Gosselin–Angeles side by side, with the reason for every
difference."""

from __future__ import annotations

import sys
from dataclasses import replace

from ..text import printable
from ._common import (
    InputError, check_count, check_length_scale, check_path_step, closures_option, common_options,
    configuration_options, displacements, dumps, entry_options, integer, is_entry, joint_list, number, source,
)

__all__ = ["add_parser", "run"]

#: distance between configurations along a --path by default (dimensionless joint coordinates)
DEFAULT_PATH_STEP = 0.05


def add_parser(commands):
    parser = commands.add_parser("compare", help="Park–Kim and Gosselin–Angeles side by side, with the reason "
                                                 "for every difference")
    parser.add_argument("file", metavar="FILE|NAME", help="mechanism file (YAML or JSON), URDF (with --closures), "
                                                          "MJCF (.xml) or catalogue name")
    entry_options(parser)
    closures_option(parser)
    parser.add_argument("--at", action="append", default=[], metavar="JSON",
                        help="a configuration: joint displacements from home as JSON or @file.json (repeatable)")
    parser.add_argument("--project", action="store_true",
                        help="project configurations that do not close onto the C-space")
    parser.add_argument("--inputs", default=None, metavar="J1,J2",
                        help="the driven joints, comma-separated (default: the mechanism's actuated joints)")
    parser.add_argument("--outputs", default=None, metavar="J3,J4",
                        help="output joints, comma-separated: their coordinates are the outputs "
                             "(default: the end-effector's coordinates)")
    parser.add_argument("--relation", default=None, metavar="NAME",
                        help="use the paper's F of a catalogue entry (e.g. eq9 for slider-crank) instead of the "
                             "matrices derived from the mechanism")
    parser.add_argument("--samples", type=integer, default=0, metavar="N",
                        help="also compare N configurations sampled over the assembly branches (default 0)")
    parser.add_argument("--path", type=integer, default=0, metavar="N",
                        help="also compare up to N configurations each way along a curve of M through the home "
                             "(not continued from a C-space singularity; stopped where a loop closes), and the "
                             "actuator, end-effector and C-space singularities the curve crosses or touches "
                             "(from sign changes and dips of the smallest singular value at the configurations "
                             "and midpoints: a dip narrower than half a step that shows at none can be missed)")
    parser.add_argument("--path-step", type=number, default=None, metavar="H",
                        help="distance between configurations along the --path (joint-coordinate units, "
                             f"default {DEFAULT_PATH_STEP})")
    parser.add_argument("--format", choices=("json", "text"), default="text")
    common_options(parser)
    return parser


def _paper_relation(arguments, mechanism, point):
    """The (relation, coordinates) named by --relation for a catalogue entry."""
    from ..gosselin_angeles_examples import RELATIONS  # imported when used: SymPy

    known = RELATIONS.get(arguments.file, {}) if is_entry(arguments.file) else {}
    if arguments.relation not in known:
        entries = "; ".join(f"{name}: {', '.join(relations)}" for name, relations in RELATIONS.items())
        raise InputError(f"--relation: no relation {arguments.relation!r} for {arguments.file!r} "
                         f"(the paper's relations are: {entries})")
    try:
        return known[arguments.relation](mechanism, point)
    except ValueError as error:
        raise InputError(f"--relation: {arguments.relation} does not apply here: {error}") from None


def _check_relation_outputs(arguments, outputs):
    """Refuse ``--outputs`` other than the paper's with a ``--relation``: the relation's x is the paper's output
    (:data:`classify.gosselin_angeles_examples.PAPER_OUTPUTS`, else the entry's end-effector), and with other
    outputs Park–Kim and Gosselin–Angeles would compare two problems (velocities alone cannot always tell: on
    a mechanism of one degree of freedom any two outputs move together wherever both move)."""
    from ..gosselin_angeles_examples import PAPER_OUTPUTS

    if outputs is None or not is_entry(arguments.file):
        return
    paper = PAPER_OUTPUTS.get(arguments.file)
    if tuple(outputs) != paper:
        expected = f"--outputs {','.join(paper)}" if paper else "no --outputs (the end-effector)"
        raise InputError(f"--outputs: {arguments.relation}'s outputs are the paper's: give {expected}")


def _check_relation_variables(arguments, mechanism, model, start, coordinates):
    """Refuse a paper's relation whose inputs θ are not the mechanism's actuated coordinates, or whose outputs x
    are not the compared outputs, near the start (:func:`classify.comparison.relation_variables_mismatch`):
    every row would compare two different input-output problems."""
    from ..comparison import relation_variables_mismatch

    mismatch = relation_variables_mismatch(model, start, coordinates)
    if mismatch == "inputs":
        actuated = ", ".join(printable(mechanism.coordinate_names[index]) for index in mechanism.actuated_coordinates)
        raise InputError(f"--relation: {arguments.relation}'s inputs are the paper's, not the actuated coordinates "
                         f"here ({actuated}); compare without --relation (the derived Gosselin–Angeles matrices "
                         f"follow the actuation)")
    if mismatch == "outputs":
        raise InputError(f"--outputs: {arguments.relation}'s outputs are the paper's, not the outputs compared "
                         f"here; name the paper's outputs or compare without --relation")


def _path_rows(model, start, count, step, start_label="home"):
    """Labels and points along a path of M through `start` (labelled `start_label`), with the singularities it
    crosses or touches in place (:func:`classify.paths.follow_path`, :func:`classify.paths.singular_crossings`)."""
    from manifold import jacobian_rank

    from ..paths import NoPathError, follow_path, singular_crossings
    from ..survey import survey_of

    try:
        path = follow_path(model, start, count, step=step)
    except NoPathError:
        raise InputError(f"--path: no curve of M through {printable(start_label)}: 0 degrees of freedom there "
                         f"(nothing to follow)") from None
    if path.reason == "cspace":
        rank, expected = jacobian_rank(model.manifold, start).rank, survey_of(model).constraint_rank
        print(f"--path: M could not be continued from {printable(start_label)}: a C-space singularity (rank DΦ "
              f"{rank} < {expected}), where more than one curve of M may meet and none is singled out; the path is "
              f"the start alone (start near it, on the branch wanted, e.g. with --at … --project)", file=sys.stderr)
    elif path.reason is not None:
        print(f"--path: M could not be continued from {printable(start_label)} (no curve of M leaves it within "
              f"the step): the path is the start alone", file=sys.stderr)
    if path.closed:
        print(f"--path: the path closed on itself (a loop of M) between path{path.steps[-1]:+d} and "
              f"path{path.steps[0]:+d}; each configuration of the loop is on it once", file=sys.stderr)
    crossings = {}
    for crossing in singular_crossings(model, path.points, closed=path.closed):
        crossings.setdefault(crossing.index, []).append(crossing)
    labels, points = [], []
    steps = path.steps
    for index, (point, step) in enumerate(zip(path.points, steps)):
        labels.append(start_label if step == 0 else f"path{step:+d}")
        points.append(point)
        for crossing in crossings.get(index, []):  # between this point and the next, named by their steps
            name = "touching" if crossing.touching else "crossing"
            labels.append(f"{name} {step:+d}…{steps[(index + 1) % len(steps)]:+d} "
                          f"({crossing.kind.replace('_', '-')})")
            points.append(crossing.point)
    return labels, points


def run(arguments, out):
    import numpy as np

    from mechanisms import actuate, configuration
    from mechanisms.joints import joint_coordinate_names

    from ..comparison import compare, sample_configurations
    from ..model import joint_output_model, model_of
    from .classify_command import describe_source

    check_length_scale(arguments.length_scale)
    check_count(arguments.samples, "--samples")
    check_count(arguments.path, "--path")
    step_given = arguments.path_step is not None
    path_step = arguments.path_step if step_given else DEFAULT_PATH_STEP
    check_path_step(path_step)
    if step_given and not arguments.path:
        raise InputError("--path-step: applies to a --path (none is asked)")
    if arguments.relation is not None and arguments.inputs is not None:
        raise InputError("--inputs: a --relation has the paper's inputs (the entry's actuated joints): other "
                         "inputs are compared without --relation, with the derived Gosselin–Angeles matrices")
    mechanism, named = source(arguments)
    if arguments.inputs is not None:
        mechanism = actuate(mechanism, joint_list(arguments.inputs, "--inputs"), where="--inputs")
    output_names = outputs = None
    if arguments.outputs is not None:
        outputs = joint_list(arguments.outputs, "--outputs")
        model = joint_output_model(mechanism, outputs, where="--outputs")
        output_names = tuple(name for joint in outputs for name in joint_coordinate_names(mechanism.joint(joint)))
    elif mechanism.end_effector is None:
        raise InputError(f"--outputs: {mechanism.name!r} has no end-effector; name the output joints")
    else:
        model = model_of(mechanism, arguments.length_scale)
    if not len(model.actuators):
        raise InputError(f"--inputs: {mechanism.name!r} has no actuated joint; name the input joints")
    start = configuration(mechanism, named, where=configuration_options(arguments, {}),
                          remedy="give closing values (--project moves the --at configurations only)").point
    given = [configuration(mechanism, {**named, **at}, project_onto=arguments.project,
                           where=configuration_options(arguments, at)).point
             for at in map(displacements, arguments.at)]
    rng = np.random.default_rng(arguments.seed)
    model = replace(model, starts=np.stack([start, *given]))
    start_label = "home" if arguments.configuration is None else arguments.configuration
    labels, points = [start_label], [start]
    if arguments.path:
        labels, points = _path_rows(model, start, arguments.path, path_step, start_label)
    labels += [f"at{index}" for index in range(1, len(given) + 1)]
    points += given
    samples = sample_configurations(model, arguments.samples, rng)
    labels += [f"sample{index}" for index in range(1, len(samples) + 1)]
    points += list(samples)
    relation = coordinates = None
    if arguments.relation is not None:
        _check_relation_outputs(arguments, outputs)
        relation, coordinates = _paper_relation(arguments, mechanism, start)  # the branch sign of the start
        _check_relation_variables(arguments, mechanism, model, start, coordinates)
    print(f"comparing {len(points)} configurations of {printable(mechanism.name)}", file=sys.stderr)
    result = compare(model, np.stack(points), labels, relation=relation, coordinates=coordinates, rng=rng,
                     output_names=output_names)
    origin = describe_source(arguments)
    if arguments.format == "json":
        out.write(dumps({"mechanism": result.mechanism, "source": origin, **result.to_dict()}) + "\n")
    else:
        out.write(result.to_text(source=origin) + "\n")
