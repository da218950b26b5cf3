"""The end-effector rank decision's reference scale does not depend on the order of the joints in the file
(docs/conventions.rst, "Rank tolerance policy").

Df is nonzero only on the spanning tree's path from the ground to the end-effector's link, and the tree is grown
in file order: listing the 3-PRR's joints in another order put rail3, C3, B3 on the path instead of rail1, B1,
C1, moved σ₁(H½ Df·diag(s)) by 37 %, and a configuration near the cut (found by an audit) read end-effector
singular in one file and regular in the other, in ``classify``, ``classify --batch``, ``map`` and ``compare``.
"""

import dataclasses

import numpy as np
import pytest

from classify import classify, classify_many, model_of
from mechanisms import Mechanism, assemble, catalogue, home
from mechanisms.kinematics import end_effector_jacobian, end_effector_reference, kinematics_of

ORDER = ["B2", "C2", "C1", "rail3", "rail2", "C3", "B3", "rail1", "B1"]


def reordered(mechanism, names):
    by_name = {joint.name: joint for joint in mechanism.joints}
    return Mechanism(mechanism.name, mechanism.space, [by_name[name] for name in names], mechanism.ground,
                     mechanism.end_effector)


def reversed_joint(mechanism, name):
    """`name` written from its second link to its first (an R or P joint: same point, axis reversed, so the
    displacement keeps its sign convention up to the axis)."""
    joints = []
    for joint in mechanism.joints:
        if joint.name == name:
            axis = None if joint.axis is None else tuple(-value for value in joint.axis)
            joint = dataclasses.replace(joint, links=joint.links[::-1], axis=axis)
        joints.append(joint)
    return Mechanism(mechanism.name, mechanism.space, joints, mechanism.ground, mechanism.end_effector)


def test_the_audits_three_prr_reads_alike_in_either_order():
    mechanism = catalogue.entry("3-prr").mechanism("fig3_serial_leg1")
    other = reordered(mechanism, ORDER)
    assert kinematics_of(other).link_chains[other.end_effector.link].elements != \
        kinematics_of(mechanism).link_chains[mechanism.end_effector.link].elements  # another path to the platform
    reports = []
    for each in (mechanism, other):
        point = assemble(each, {"rail2": 3.3e-4}).point
        reports.append(classify(each, point))
    first, second = (report.end_effector.decision for report in reports)
    assert reports[0].kinds == reports[1].kinds == ("end_effector",)
    assert first.tolerance == pytest.approx(second.tolerance, rel=1e-12)
    np.testing.assert_allclose(first.singular_values, second.singular_values, rtol=1e-9)


def reference_values(mechanism, point):
    """The singular values of the reference rows (``R·diag(s)``, before H½)."""
    return np.linalg.svd(end_effector_reference(mechanism, point), compute_uv=False)


@pytest.mark.parametrize("name", [item.name for item in catalogue.entries()
                                  if item.mechanism().end_effector is not None])
def test_the_reference_rows_have_the_same_singular_values_in_any_order_and_direction(name):
    """Another order of the joints, reversed (another spanning tree, another path to the end-effector's link), and
    one R or P joint written the other way round: the same σ's of R·diag(s), at home and at points of M."""
    mechanism = catalogue.entry(name).mechanism()
    other = reordered(mechanism, [joint.name for joint in mechanism.joints][::-1])
    flippable = next((joint.name for joint in mechanism.joints if joint.type in ("R", "P")), None)
    if flippable is not None:
        other = reversed_joint(other, flippable)
    values = reference_values(mechanism, home(mechanism))
    np.testing.assert_allclose(values, reference_values(other, home(other)), rtol=1e-12, atol=1e-12 * values[0])


@pytest.mark.parametrize("name", ["3-prr", "planar-3rrr", "spherical-3rrr", "gough-stewart", "5-spu", "eclipse"])
def test_the_reference_gram_is_that_of_every_coordinates_df_column(name):
    """R's column of a coordinate is the rate of f its screw gives: Df's column of an order of the joints that puts
    the coordinate on Df's path (up to sign). Where some order reaches every coordinate, R·diag(s)·(R·diag(s))ᵀ is
    the sum of those columns' squares; elsewhere the Gram of the columns reached is below it."""
    mechanism = catalogue.entry(name).mechanism()
    scales = model_of(mechanism).manifold.ambient.tangent_scales
    names = [joint.name for joint in mechanism.joints]
    columns = {}
    for shift in range(len(names)):
        other = reordered(mechanism, names[shift:] + names[:shift])
        jacobian = end_effector_jacobian(other, home(other))
        for index, coordinate in enumerate(other.coordinate_names):
            if np.any(jacobian[:, index]) and coordinate[-3:-1] not in ("[x", "[y", "[z"):  # balls: a rotation
                columns.setdefault(coordinate, jacobian[:, index] * scales[mechanism.coordinate_names.index(
                    coordinate)])
    reference = end_effector_reference(mechanism, home(mechanism))
    gram = reference @ reference.T
    reached = sum(np.outer(column, column) for column in columns.values())
    balls = [coordinate for coordinate in mechanism.coordinate_names if coordinate[-3:-1] in ("[x", "[y", "[z")]
    if len(columns) + len(balls) == len(mechanism.coordinate_names) and not balls:
        np.testing.assert_allclose(gram, reached, atol=1e-12 * np.abs(gram).max())
    else:  # the Gram of the columns reached is below R's (positive semidefinite difference)
        assert np.linalg.eigvalsh(gram - reached).min() >= -1e-12 * np.abs(gram).max()
    assert len(columns) > len(set(np.flatnonzero(np.any(end_effector_jacobian(mechanism, home(mechanism)), axis=0))))


def test_a_stack_uses_the_same_reference_as_single_calls():
    mechanism = catalogue.entry("3-prr").mechanism("fig3_serial_leg1")
    other = reordered(mechanism, ORDER)
    for each in (mechanism, other):
        model = model_of(each)
        points = np.stack([assemble(each, {"rail2": value}).point for value in (3.3e-4, 1e-2, -2e-2)])
        result = classify_many(model, points)
        for index, point in enumerate(points):
            report = classify(model, point)
            assert result.kinds(index) == report.kinds
            np.testing.assert_allclose(result.tolerances["end_effector"][index], report.end_effector.decision.tolerance,
                                       rtol=1e-12)


@pytest.mark.parametrize("name", [item.name for item in catalogue.entries()
                                  if item.mechanism().end_effector is not None])
def test_the_rates_a_twist_gives_are_the_chart_of_df(name):
    """A(p) in closed form (position, orientation, pose, tool; planar, spherical, spatial) equals the rates
    Df's own formulas give the motion ∂F = ξ̂ F of the end-effector's link, at random poses, for every unit twist."""
    from scipy.spatial.transform import Rotation

    from mechanisms import _groups as groups
    from mechanisms.kinematics import _end_effector_columns, _skew, _twist_rates

    mechanism = catalogue.entry(name).mechanism()
    compiled = kinematics_of(mechanism)
    rng = np.random.default_rng(7)
    size = groups.MATRIX_SIZE[compiled.space]
    poses = np.zeros((6, size, size))
    poses[..., -1, -1] = 1.0
    if compiled.space == "planar":
        angles = rng.uniform(-np.pi, np.pi, 6)
        poses[:, :2, :2] = np.stack([[np.cos(angles), -np.sin(angles)], [np.sin(angles), np.cos(angles)]]).transpose(
            2, 0, 1)
        poses[:, :2, 2] = rng.normal(size=(6, 2))
        units = np.zeros((3, 3, 3))
        units[0, 1, 0], units[0, 0, 1], units[1, 0, 2], units[2, 1, 2] = 1.0, -1.0, 1.0, 1.0
    else:
        poses[:, :3, :3] = Rotation.random(6, random_state=7).as_matrix()
        units = np.zeros((3 if compiled.space == "spherical" else 6, size, size))
        units[:3, :3, :3] = _skew(np.eye(3))
        if compiled.space == "spatial":
            poses[:, :3, 3] = rng.normal(size=(6, 3))
            units[3:, :3, 3] = np.eye(3)
    expected = np.swapaxes(_end_effector_columns(compiled, poses, units @ poses[:, None]), -1, -2)
    np.testing.assert_allclose(_twist_rates(compiled, poses), expected, atol=1e-14)


def serial_chain(u_links, output):
    """A spatial serial chain U–R–C–S–P (the C and P written from their second link), every joint on Df's path."""
    from mechanisms import EndEffector, Joint

    axes = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0))
    joints = [Joint("U", "U", u_links, point=(0.0, 0.0, 0.3), axes=axes if u_links[0] == "ground" else axes[::-1]),
              Joint("R", "R", ("l1", "l2"), point=(0.2, 0.1, 0.8), axis=(0.0, 0.0, 1.0)),
              Joint("C", "C", ("l3", "l2"), point=(0.5, -0.2, 1.0), axis=(0.6, 0.0, 0.8)),
              Joint("S", "S", ("l3", "l4"), point=(0.7, 0.3, 1.4)),
              Joint("P", "P", ("l5", "l4"), axis=(0.0, 0.6, 0.8), actuated=True)]
    end_effector = EndEffector("l5", point=None if output == "orientation" else (0.9, 0.4, 1.9), output=output,
                               axis=(0.0, 0.0, 1.0) if output == "tool" else None)
    return Mechanism("serial", "spatial", joints, "ground", end_effector)


@pytest.mark.parametrize("output", ["pose", "position", "orientation", "tool"])
@pytest.mark.parametrize("u_links", [("ground", "l1"), ("l1", "ground")])
def test_on_a_serial_chain_the_reference_gram_is_dfs_away_from_home(u_links, output):
    """Every joint of a serial chain is on Df's path, so R·diag(s) and Df·diag(s) have one Gram at any
    configuration, whichever way the joints are written: a U joint's first axis is fixed in its first link only
    (the reference took the ground's pose for it when the U was written from its second link, 39 % off away
    from home; a review found it)."""
    import warnings

    from mechanisms import from_displacements

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a serial chain: no loop
        mechanism = serial_chain(u_links, output)
    rng = np.random.default_rng(3)
    scales = model_of(mechanism).manifold.ambient.tangent_scales
    for _ in range(3):
        point = from_displacements(mechanism, {"U": tuple(rng.uniform(-1, 1, 2)), "R": rng.uniform(-1, 1),
                                               "C": tuple(rng.uniform(-1, 1, 2)), "S": tuple(rng.uniform(-1, 1, 3)),
                                               "P": rng.uniform(-1, 1)})
        jacobian = end_effector_jacobian(mechanism, point) * scales
        reference = end_effector_reference(mechanism, point)
        np.testing.assert_allclose(reference @ reference.T, jacobian @ jacobian.T,
                                   atol=1e-14 * np.abs(jacobian @ jacobian.T).max())


def test_a_u_joint_written_the_other_way_round_keeps_the_reference_away_from_home():
    """The Gough–Stewart with U1 written from its cylinder to the ground (axes swapped), at a configuration off
    home: the same platform pose and the same σ's of R·diag(s) (the review's case: 4.6240 against 4.6254)."""
    from mechanisms.kinematics import end_effector as end_effector_value

    mechanism = catalogue.entry("gough-stewart").mechanism()
    joints = [dataclasses.replace(joint, links=joint.links[::-1], axes=joint.axes[::-1]) if joint.name == "U1"
              else joint for joint in mechanism.joints]
    other = Mechanism(mechanism.name, mechanism.space, joints, mechanism.ground, mechanism.end_effector)
    actuated = [joint.name for joint in mechanism.joints if joint.actuated]
    values = {actuated[0]: 0.07, actuated[1]: -0.05}
    point, other_point = assemble(mechanism, values).point, assemble(other, values).point
    np.testing.assert_allclose(end_effector_value(mechanism, point), end_effector_value(other, other_point),
                               atol=1e-12)
    values = reference_values(mechanism, point)
    np.testing.assert_allclose(reference_values(other, other_point), values, rtol=1e-12, atol=1e-12 * values[0])


def screw_reference(mechanism, points):
    """The end-effector reference of a planar mechanism in matrix form (``_screw_reference``: the carriers' poses
    from the matrix tree of their chains' prefixes, the planar plan's tree being the complex one)."""
    import dataclasses

    from mechanisms import _chains as chains
    from mechanisms.kinematics import _reference_plan, _screw_reference

    compiled = kinematics_of(mechanism)
    plan = _reference_plan(mechanism)
    tree = chains.matrix_tree(compiled.space, compiled.link_chains, plan.carriers[plan.chained:])
    return _screw_reference(mechanism, compiled, dataclasses.replace(plan, tree=tree), points)


@pytest.mark.parametrize("name", ["five-bar", "slider-crank", "planar-six-bar", "watt-six-bar", "planar-3rrr",
                                  "3-prr"])
def test_the_planar_complex_form_is_the_screw_columns_in_dfs_chart(name):
    """A planar mechanism's reference in complex form (a point: Re z, Im z, z the complex rates; an orientation:
    the rates ω; a pose: ω and the body rates r̄_F z) is the matrix form's ``A Ad_g Ξ⁰ diag(s)`` in Df's chart: the
    same singular values under any weighting of the rows (H^½ = diag(1, 10, ...), a model's own metric; a review
    found a closed form that rotated the rows 0.68 off under diag(1, 100)), at points of M walked from home."""
    from manifold import sample_manifold

    mechanism = catalogue.entry(name).mechanism()
    model = model_of(mechanism)
    points = sample_manifold(model.manifold, np.random.default_rng(1), model.starts, random_count=2, walk_count=6)
    closed = end_effector_reference(mechanism, points)
    columns = screw_reference(mechanism, points)
    for weights in (np.ones(model.end_effector_dimension), 10.0 ** np.arange(model.end_effector_dimension)):
        expected = np.linalg.svd(weights[:, None] * columns, compute_uv=False)
        np.testing.assert_allclose(np.linalg.svd(weights[:, None] * closed, compute_uv=False), expected, rtol=1e-12,
                                   atol=1e-12 * expected.max())


def test_a_planar_point_far_from_its_joints_keeps_its_small_singular_value():
    """An end-effector point 1e6 lengths from the joints: σ₂ of the reference rows keeps its digits (a closed form
    (Σ|z|² − |Σz²|)/2 lost 3e-5 of it; a review found it)."""
    from mechanisms import EndEffector

    mechanism = catalogue.entry("slider-crank").mechanism()
    far = Mechanism(mechanism.name, mechanism.space, mechanism.joints, mechanism.ground,
                    EndEffector(mechanism.end_effector.link, (1e6, 3e5), "position"))
    point = home(far)
    expected = np.linalg.svd(screw_reference(far, point), compute_uv=False)
    np.testing.assert_allclose(np.linalg.svd(end_effector_reference(far, point), compute_uv=False), expected,
                               rtol=1e-9)


@pytest.mark.parametrize("name", ["five-bar", "planar-3rrr", "gough-stewart", "spherical-3rrr"])
def test_an_empty_stack_has_an_empty_reference(name):
    mechanism = catalogue.entry(name).mechanism()
    empty = np.zeros((0, home(mechanism).size))
    reference = end_effector_reference(mechanism, empty)
    assert reference.shape[:2] == (0, end_effector_jacobian(mechanism, empty).shape[1])
