"""Analytic derivatives of the loop constraints and the end-effector map.

Taylor (slope) tests: for a random direction v and steps t,
|Φ(p ⊕ tv) − Φ(p) − t DΦ v| = O(t²) and with ½t² D²Φ(v, v) added, O(t³);
likewise for f in the chart of N at f(p). Points are random configurations of
K (off M as well as on it), including ball joints at the gimbal-lock attitudes
of three-angle parametrisations.
"""

import numpy as np
import pytest

from builders import (bennett, five_bar, five_bar_positions, ladder, rsur, rsur_stack, spatial_mix,
                      spherical_four_bar)
from mechanisms.catalogue import entry
from mechanisms.catalogue.slider_crank import slider_crank
from mechanisms.kinematics import _nearest_point, loop_origin
from manifold import ImplicitManifold, ProjectionError, numerical_rank, project, rotation_exp, tangent_basis
from mechanisms import (
    EndEffector, Mechanism, closes, configuration_space, constraint, constraint_hessian, constraint_jacobian,
    end_effector, end_effector_chart, end_effector_hessian, end_effector_jacobian, home, kinematics_of,
)

MECHANISMS = {
    "slider-crank": lambda: slider_crank(crank=2.0, coupler=1.0, theta=0.3),
    "five-bar": lambda: five_bar(five_bar_positions(1.2, 2.0)),
    "spherical four-bar": spherical_four_bar,
    "bennett": bennett,
    "RSUR pose": rsur,
    "RSUR position": lambda: rsur("position"),
    "mix pose": spatial_mix,
    "mix orientation": lambda: spatial_mix("orientation"),
    "mix position": lambda: spatial_mix("position"),
    "RSUR tool": lambda: with_tool(rsur("position"), (0.3, -0.5, 0.8)),
    "mix tool": lambda: with_tool(spatial_mix("position"), (1.0, 2.0, -0.5)),
}


def with_tool(mechanism, axis):
    """The mechanism with its end-effector made an axisymmetric tool (``output: tool``) along `axis`."""
    tool = EndEffector(mechanism.end_effector.link, mechanism.end_effector.point, "tool", axis)
    return Mechanism(mechanism.name, mechanism.space, mechanism.joints, mechanism.ground, tool)


def slopes(function, jacobian, hessian, point, space, rng, chart=None):
    """Observed orders of the first- and second-order Taylor remainders."""
    direction = rng.standard_normal(space.dim)
    value, first, second = function(point), jacobian(point), hessian(point)
    steps = np.array([1e-2, 5e-3, 2.5e-3])
    errors = []
    for step in steps:
        moved = function(space.retract(point, step * direction))
        change = moved - value if chart is None else chart(value, moved)
        linear = step * first @ direction
        quadratic = 0.5 * step ** 2 * np.einsum("cab,a,b->c", second, direction, direction)
        errors.append((np.linalg.norm(change - linear), np.linalg.norm(change - linear - quadratic)))
    errors = np.array(errors)
    scale = max(np.linalg.norm(first @ direction), 1.0)
    orders = [np.polyfit(np.log(steps), np.log(errors[:, i]), 1)[0] if errors[-1, i] > 1e-13 * scale else np.inf
              for i in range(2)]
    return orders


def random_points(mechanism, rng, count=3):
    space = kinematics_of(mechanism).ambient
    points = list(space.random_point(rng, size=count))
    for joint in mechanism.joints:  # ball joints at gimbal attitudes
        if joint.type == "S":
            point = space.random_point(rng)
            for attitude in ([0, np.pi / 2, 0], [0, 0, 1e-9], [np.pi - 1e-6, 0, 0]):
                (part,) = kinematics_of(mechanism).point_parts[joint.name]
                point = point.copy()
                point[part] = rotation_exp(np.array(attitude, dtype=float)).ravel()
                points.append(point)
    return points


@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_constraint_derivatives_pass_the_taylor_test(name):
    rng = np.random.default_rng(10)
    mechanism = MECHANISMS[name]()
    space = kinematics_of(mechanism).ambient
    for point in random_points(mechanism, rng):
        first, second = slopes(lambda p: constraint(mechanism, p), lambda p: constraint_jacobian(mechanism, p),
                               lambda p: constraint_hessian(mechanism, p), point, space, rng)
        assert first > 1.9 and second > 2.9, (first, second)


def first_order_slope(function, jacobian, point, space, rng):
    """Observed order of the first-order Taylor remainder of `function` (∞ when it is rounding)."""
    direction = rng.standard_normal(space.dim)
    value, first = function(point), jacobian(point)
    steps = np.array([1e-3, 5e-4, 2.5e-4])
    errors = [np.linalg.norm(function(space.retract(point, step * direction)) - value - step * first @ direction)
              for step in steps]
    return np.polyfit(np.log(steps), np.log(errors), 1)[0] if errors[-1] > 1e-13 else np.inf


@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_the_closing_map_vanishes_on_m_with_dphi_as_its_jacobian_there(name):
    """closing_space (mechanisms.kinematics): zero on M, where its Jacobian is DΦ; its Jacobian is its derivative
    everywhere (Taylor test at random points of K, ball joints at gimbal attitudes included: the rotation
    vector's through the inverse left Jacobian of SO(3))."""
    rng = np.random.default_rng(14)
    mechanism = MECHANISMS[name]()
    closing = configuration_space(mechanism).closing
    space = kinematics_of(mechanism).ambient
    on_m = [project(configuration_space(mechanism), home(mechanism))]
    on_m.append(project(configuration_space(mechanism), space.retract(on_m[0], 0.1 * rng.standard_normal(space.dim))))
    for point in on_m:
        assert np.linalg.norm(closing.constraint(point)) < 1e-11
        np.testing.assert_allclose(closing.constraint_jacobian(point), constraint_jacobian(mechanism, point),
                                   atol=1e-10)
    rotation, loop = {"planar": (1, 3), "spherical": (3, 3), "spatial": (3, 6)}[mechanism.space]
    for point in on_m + random_points(mechanism, rng):
        angles = np.linalg.norm(closing.constraint(point).reshape(-1, loop)[:, :rotation], axis=-1)
        if np.any(angles > np.pi - 1e-2):
            continue  # the rotation vector jumps from πn to −πn across a half-turn: no derivative there
        slope = first_order_slope(closing.constraint, closing.constraint_jacobian, point, space, rng)
        assert slope > 1.9, slope


def test_the_closing_maps_last_point_is_kept_but_its_arrays_are_the_callers():
    """Gauss-Newton asks the rows, then the Jacobian, at one point: the closing map computes both once and keeps
    them for the next call at the same point, handing out copies (a caller writing into them changes nothing)."""
    mechanism = MECHANISMS["RSUR pose"]()
    closing = configuration_space(mechanism).closing
    point = kinematics_of(mechanism).ambient.random_point(np.random.default_rng(16))
    rows, jacobian = closing.constraint(point), closing.constraint_jacobian(point)
    expected = rows.copy(), jacobian.copy()
    rows[:] = 7.0
    np.testing.assert_array_equal(closing.constraint(point), expected[0])
    closing.constraint_jacobian(point)[:] = 7.0
    np.testing.assert_array_equal(closing.constraint_jacobian(point), expected[1])
    other = closing.constraint(point + 0.1)
    assert not np.allclose(other, expected[0])


@pytest.mark.parametrize("name", ["five-bar", "spherical four-bar", "RSUR pose"])
def test_a_point_that_is_not_finite_gives_nan_closing_rows_and_leaves_the_others(name):
    """As Φ: scipy's Rotation.from_matrix raised LinAlgError on a NaN matrix, failing the whole stack."""
    mechanism = MECHANISMS[name]()
    closing = configuration_space(mechanism).closing
    points = np.stack([home(mechanism)] * 3)
    points[1, 0] = np.nan
    points[2, 0] = np.inf
    with np.errstate(invalid="ignore"):
        rows, phi = closing.constraint(points), constraint(mechanism, points)
    assert np.all(np.isnan(rows[1:, :1])) and np.linalg.norm(rows[0]) < 1e-12
    np.testing.assert_array_equal(np.isnan(rows), np.isnan(phi))


@pytest.mark.parametrize("name", ["five-bar", "spherical four-bar", "RSUR pose"])
def test_a_half_turn_is_a_zero_of_phi_but_not_of_the_closing_map(name):
    """Gauss-Newton from random points of K ends at half-turns, zeros of Φ that `closes` rejects; the closing
    map's rotation rows (one loop here) are a rotation vector of length π there (so manifold.sample_manifold
    projects onto it first)."""
    rng = np.random.default_rng(15)
    mechanism = MECHANISMS[name]()
    manifold = configuration_space(mechanism)
    space = manifold.ambient
    found = []
    for guess in space.random_point(rng, size=40):
        try:
            point = project(ImplicitManifold(space, manifold.constraint, manifold.constraint_jacobian), guess)
        except ProjectionError:
            continue
        if not closes(mechanism, point):
            found.append(point)
    assert found, "no half-turn reached"
    for point in found:
        assert np.linalg.norm(constraint(mechanism, point)) < 1e-11
        rotation = manifold.closing.constraint(point)[:1 if mechanism.space == "planar" else 3]
        assert np.linalg.norm(rotation) == pytest.approx(np.pi, abs=1e-9)


@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_end_effector_derivatives_pass_the_taylor_test(name):
    rng = np.random.default_rng(11)
    mechanism = MECHANISMS[name]()
    space = kinematics_of(mechanism).ambient
    for point in random_points(mechanism, rng):
        first, second = slopes(
            lambda p: end_effector(mechanism, p), lambda p: end_effector_jacobian(mechanism, p),
            lambda p: end_effector_hessian(mechanism, p), point, space, rng,
            chart=lambda a, b: end_effector_chart(mechanism, a, b))
        assert first > 1.9 and second > 2.9, (first, second)


@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_batched_calls_equal_repeated_single_calls(name):
    rng = np.random.default_rng(12)
    mechanism = MECHANISMS[name]()
    space = kinematics_of(mechanism).ambient
    points = space.random_point(rng, size=6).reshape(2, 3, -1)
    for function in (constraint, constraint_jacobian, constraint_hessian,
                     end_effector, end_effector_jacobian, end_effector_hessian):
        batched = function(mechanism, points)
        for i in range(2):
            for j in range(3):
                np.testing.assert_allclose(batched[i, j], function(mechanism, points[i, j]), atol=1e-13)


def test_jacobian_columns_are_the_joint_twists_at_home():
    """At a closed configuration the columns of DΦ are the joint screws (Park & Kim eq. 8) about the loop
    origin c (the centroid of the ground's joint points): planar revolute at (x, y): rotation row 1,
    translation rows (y − c_y, −(x − c_x))/L."""
    points = five_bar_positions(1.2, 2.0)
    mechanism = five_bar(points)
    length = mechanism.characteristic_length
    origin = loop_origin(mechanism)
    assert np.linalg.norm(origin) > 0.1  # the base pivots are not centred on the base frame's origin
    expected = np.array([[1.0, (y - origin[1]) / length, -(x - origin[0]) / length] for x, y in points]).T
    jacobian = constraint_jacobian(mechanism, home(mechanism))
    # J5 is traversed from proximal2 to the ground in the loop only if it is the chord; compare up to sign
    for column in range(5):
        assert min(np.linalg.norm(jacobian[:, column] - expected[:, column]),
                   np.linalg.norm(jacobian[:, column] + expected[:, column])) < 1e-12


@pytest.mark.parametrize("dimension", [2, 3])
def test_the_nearest_point_of_crossing_lines_is_their_crossing_wherever_their_points_slide(dimension):
    """Lines through one point c (well crossed): c, for any points on them and either axis sign; lines close to
    parallel along a direction: the centroid's coordinate along it (mechanisms.kinematics.loop_origin)."""
    rng = np.random.default_rng(5)
    crossing = rng.normal(size=dimension)
    axes = np.linalg.qr(rng.normal(size=(dimension, dimension)))[0].T[:, :dimension]
    axes = np.vstack([axes, (axes[0] + axes[1]) / np.sqrt(2)])
    for _ in range(3):
        slides = rng.normal(scale=5.0, size=len(axes))
        signs = rng.choice([-1.0, 1.0], size=len(axes))
        found = _nearest_point(crossing + slides[:, None] * axes, signs[:, None] * axes)
        np.testing.assert_allclose(found, crossing, atol=1e-12 * np.abs(slides).max())
    if dimension == 2:  # two rails 1e-4 apart in angle: their crossing is about 1e4 away, the point is not
        points = rng.normal(size=(2, 2))
        found = _nearest_point(points, np.array([[1.0, 0.0], [np.cos(1e-4), np.sin(1e-4)]]))
        assert np.linalg.norm(found - points.mean(axis=0)) <= np.linalg.norm(points[0] - points[1])


@pytest.mark.parametrize("name", ["bennett", "RSUR pose", "mix pose", "spherical four-bar"])
def test_second_derivative_on_tangent_vectors_is_the_lie_bracket_form(name):
    """On M, for a tangent vector v, D²Φ(v, v) = Σ_{a before b} [Z_a v_a, Z_b v_b]: the bracket
    form of the twists carried to the configuration (twice the second-order term of the
    Baker-Campbell-Hausdorff expansion of log of the loop product)."""
    from mechanisms import _groups as groups
    from mechanisms._chains import expand as _expand

    rng = np.random.default_rng(13)
    mechanism = MECHANISMS[name]()
    compiled = kinematics_of(mechanism)
    manifold = configuration_space(mechanism)
    start = compiled.ambient.retract(home(mechanism), 0.05 * rng.standard_normal(compiled.ambient.dim))
    point = project(manifold, start)
    basis, _ = tangent_basis(manifold, point)
    vector = basis @ rng.standard_normal(basis.shape[1])
    rows = groups.LOOP_ROWS[compiled.space]
    rotation_rows = groups.ROTATION_ROWS[compiled.space]
    hessian = constraint_hessian(mechanism, point)
    for loop, chain in enumerate(compiled.loops):
        product, coordinates, first, _ = _expand(compiled.space, chain, point, 1)
        carried = [first[c] @ np.linalg.inv(product) * vector[index]
                   for c, (index, _, _, _) in enumerate(coordinates)]
        bracket = sum(carried[i] @ carried[j] - carried[j] @ carried[i]
                      for i in range(len(carried)) for j in range(i + 1, len(carried))
                      if coordinates[i][3] != coordinates[j][3])
        expected = groups.vee(compiled.space, bracket)
        expected[rotation_rows:] /= compiled.length
        observed = np.einsum("cab,a,b->c", hessian[loop * rows:(loop + 1) * rows], vector, vector)
        np.testing.assert_allclose(observed, expected, atol=1e-9)


def test_bennett_is_overconstrained_but_mobile():
    mechanism = bennett()
    jacobian = constraint_jacobian(mechanism, home(mechanism))
    assert jacobian.shape == (6, 4)
    assert numerical_rank(jacobian).rank == 3


def with_output(mechanism, output):
    """The mechanism with its end-effector's output replaced (same link and point)."""
    frame = EndEffector(mechanism.end_effector.link,
                        None if output == "orientation" else mechanism.end_effector.point, output)
    return Mechanism(mechanism.name, mechanism.space, mechanism.joints, mechanism.ground, frame)


FAST_PATHS = {
    **MECHANISMS,
    "five-bar pose": lambda: with_output(five_bar(five_bar_positions(1.2, 2.0)), "pose"),
    "five-bar orientation": lambda: with_output(five_bar(five_bar_positions(1.2, 2.0)), "orientation"),
    "slider-crank pose": lambda: with_output(slider_crank(crank=2.0, coupler=1.0, theta=0.3), "pose"),
}


@pytest.mark.parametrize("name", sorted(FAST_PATHS))
def test_first_order_closed_forms_equal_the_matrix_products(name):
    """DΦ and Df from prefix products only (planar: complex numbers, no 3×3 products; spherical and
    spatial: twists carried by the prefixes, ``∂T = Ŵ T``) equal the prefix·twist·suffix products of
    :func:`mechanisms._chains.expand_group`, on and off M, balls at gimbal attitudes included."""
    from mechanisms import _chains as chains
    from mechanisms import _groups as groups
    from mechanisms import closure_and_jacobian
    from mechanisms.kinematics import _end_effector_columns, _link_group

    rng = np.random.default_rng(14)
    mechanism = FAST_PATHS[name]()
    compiled = kinematics_of(mechanism)
    points = np.array(random_points(mechanism, rng, count=4))
    batch = points.shape[:-1]
    pattern = compiled.pattern
    jacobian = np.zeros(batch + pattern.shape)
    products = np.zeros(batch + (len(compiled.loops),) + (groups.MATRIX_SIZE[compiled.space],) * 2)
    entries = []
    for group in compiled.loop_groups:
        product, first, _ = chains.expand_group(compiled.space, group, points, 1)
        products[..., group.chains, :, :] = product
        entries.append(groups.loop_rows(compiled.space, first, compiled.length).reshape(batch + (-1,)))
    jacobian[..., pattern.rows, pattern.columns] = np.concatenate(entries, axis=-1)
    rows = groups.loop_rows(compiled.space, products, compiled.length).reshape(batch + (-1,))
    turns = np.all(groups.is_identity_rotation(compiled.space, products), axis=-1)
    fast_rows, fast_turns, fast_jacobian = closure_and_jacobian(mechanism, points)
    np.testing.assert_allclose(fast_jacobian, jacobian, rtol=0, atol=1e-13)
    np.testing.assert_allclose(fast_rows, rows, rtol=0, atol=1e-13)
    np.testing.assert_allclose(constraint(mechanism, points), rows, rtol=0, atol=1e-13)
    np.testing.assert_allclose(constraint_jacobian(mechanism, points), jacobian, rtol=0, atol=1e-13)
    assert np.array_equal(fast_turns, turns)
    group = _link_group(compiled, compiled.end_effector_link)
    product, first, _ = chains.expand_group(compiled.space, group, points, 1)
    columns = _end_effector_columns(compiled, product[..., 0, :, :], first[..., 0, :, :, :])
    expected = np.zeros(batch + (columns.shape[-1], compiled.ambient.dim))
    expected[..., :, group.columns[0]] = np.swapaxes(columns, -1, -2)
    np.testing.assert_allclose(end_effector_jacobian(mechanism, points), expected, rtol=0, atol=1e-13)


@pytest.mark.parametrize("output", ["position", "pose"])
def test_an_end_effector_on_the_ground_never_moves(output):
    """Its chain has no coordinate: the spatial carried twists stacked an empty list (an internal error of
    ``closedchain classify``), where the planar ones gave J = 0. Now J and its derivative are 0 in every space."""
    from mechanisms import Joint

    joints = [Joint("a", "R", ("g", "l1"), point=(0, 0, 0), axis=(0, 0, 1), actuated=True),
              Joint("b", "R", ("l1", "l2"), point=(1, 0, 0), axis=(0, 0, 1)),
              Joint("c", "R", ("l2", "l3"), point=(1, 1, 0), axis=(0, 0, 1)),
              Joint("d", "R", ("l3", "g"), point=(0, 1, 0), axis=(0, 0, 1))]
    mechanism = Mechanism("four-bar", "spatial", joints, "g", EndEffector("g", (0.5, 0.5, 0.0), output))
    point = home(mechanism)
    assert not np.any(end_effector_jacobian(mechanism, point))
    assert not np.any(end_effector_hessian(mechanism, point))
    from classify import classify

    report = classify(mechanism, point)
    assert report.kinds == () and (report.end_effector.rank, report.end_effector.expected_rank) == (0, 0)


PREFIX_TREE_MECHANISMS = {
    "ladder of 1": lambda: ladder(1, tail=2),
    "ladder of 3": lambda: ladder(3, tail=2),
    "ladder of 40": lambda: ladder(40, tail=2),
    "3-PRR": lambda: entry("3-prr").mechanism(),
    "slider-crank": lambda: entry("slider-crank").mechanism(),
}


@pytest.mark.parametrize("name", sorted(PREFIX_TREE_MECHANISMS))
def test_the_prefix_tree_of_planar_chains_gives_their_products(name):
    """mechanisms._chains.planar_tree_products (doubling over the tree of the chains' prefixes, ⌈log₂ L⌉
    steps) equals planar_prefixes chain by chain to rounding, for every link of planar mechanisms (the
    end-effector reference's carriers: a ladder 40 loops deep has one chain shape per rung; the 3-PRR and the
    slider-crank have P joints), at random points of K and on a stack; the tree has a node per distinct
    prefix, at most one per joint."""
    from mechanisms import _chains as chains

    rng = np.random.default_rng(43)
    mechanism = PREFIX_TREE_MECHANISMS[name]()
    compiled = kinematics_of(mechanism)
    links = [link for link in compiled.link_chains if link != mechanism.ground]
    groups = chains.groups_of("planar", [compiled.link_chains[link] for link in links])
    tree = chains.planar_tree(compiled.link_chains, links)
    assert len(tree.parents) <= 1 + len(mechanism.joints)
    assert name.startswith("ladder") or not all(group.rotation.all() for group in groups)  # P joints
    points = compiled.ambient.retract(np.broadcast_to(home(mechanism), (3, compiled.ambient.point_size)),
                                      rng.standard_normal((3, compiled.ambient.dim)) * compiled.ambient.tangent_scales)
    rotations, translations = chains.planar_tree_products(tree, points)
    size = np.max(np.abs(translations))
    for group in groups:
        expected_rotations, expected_translations = chains.planar_prefixes(group, points)
        np.testing.assert_allclose(rotations[:, group.chains], expected_rotations[..., -1], rtol=0, atol=1e-13)
        np.testing.assert_allclose(translations[:, group.chains], expected_translations[..., -1], rtol=0,
                                   atol=1e-13 * size)
    single = chains.planar_tree_products(tree, points[1])
    np.testing.assert_array_equal(single[0], rotations[1])


MATRIX_TREE_MECHANISMS = {
    "RSUR stack of 12": lambda: rsur_stack(12),
    "mix": spatial_mix,
    "bennett": bennett,
    "spherical four-bar": spherical_four_bar,
    "spherical 3-RRR": lambda: entry("spherical-3rrr").mechanism(),
    "Gough-Stewart": lambda: entry("gough-stewart").mechanism(),
}


@pytest.mark.parametrize("name", sorted(MATRIX_TREE_MECHANISMS))
def test_the_prefix_tree_of_matrix_chains_gives_their_products(name):
    """mechanisms._chains.matrix_tree_products (doubling over the tree of the chains' prefixes, ⌈log₂ L⌉ steps)
    equals expand_group's products chain by chain to rounding, for every link of spatial and spherical mechanisms
    (the end-effector reference's carriers: it took one expand_group call per chain shape, one per stage of a
    stack: 0.15 s of a 0.2 s classify of a stack of 100 RSUR loops), with balls, U, C and P joints, at random
    points of K and on a stack; the tree has a node per distinct prefix."""
    from mechanisms import _chains as chains

    rng = np.random.default_rng(44)
    mechanism = MATRIX_TREE_MECHANISMS[name]()
    compiled = kinematics_of(mechanism)
    links = [link for link in compiled.link_chains if link != mechanism.ground]
    link_chains = [compiled.link_chains[link] for link in links]
    tree = chains.matrix_tree(compiled.space, compiled.link_chains, links)
    assert len(tree.parents) <= 1 + sum(len(chain.elements) for chain in link_chains)
    assert len(tree.parents) < 1 + sum(len(chain.elements) for chain in link_chains) or len(links) == 1
    points = compiled.ambient.retract(np.broadcast_to(home(mechanism), (3, compiled.ambient.point_size)),
                                      rng.standard_normal((3, compiled.ambient.dim)) * compiled.ambient.tangent_scales)
    products = chains.matrix_tree_products(compiled.space, tree, points)
    size = max(1.0, np.max(np.abs(products)))
    for group in chains.groups_of(compiled.space, link_chains):
        expected = chains.expand_group(compiled.space, group, points, 0)[0]
        np.testing.assert_allclose(products[:, group.chains], expected, rtol=0, atol=1e-13 * size)
    np.testing.assert_allclose(chains.matrix_tree_products(compiled.space, tree, points[1]), products[1], rtol=0,
                               atol=1e-13 * size)
