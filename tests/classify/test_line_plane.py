"""Line-plane 5-SPU invariants (Borràs, Thomas & Torras 2011): cofactors (12)-(13), B (16), B∞ (15), Λ⁺ (23),
the families of Section IV, the singularity polynomial (17) and its reading (18)-(20), the rearrangements of
Section III-B — checked against an independent Jacobian determinant and the Park–Kim classifier."""

import numpy as np
import pytest

from classify import classify, model_of, survey_of
from classify.line_plane import (
    DesignError, RearrangementError, b_infinity, b_line, b_line_direction, b_point, cofactors, design_from_mechanism,
    family, jacobian_determinant, lambda_plus, line_plane_design, move_base, move_platform, singularity_margin,
    singularity_polynomial, singularity_reading)
from mechanisms import home
from mechanisms.catalogue import entry
from mechanisms.catalogue.five_spu import five_spu
from mechanisms.catalogue.five_spu import singularity_polynomial as catalogue_polynomial

#: the catalogue's quadratically solvable design: zᵢ = δxᵢ, δ = 1/2, x₁ = y₁ = 0 (eq. 26)
DELTA = 0.5
QUADRATIC_BASE = [(0.0, 0.0), (2.0, 1.0), (-1.0, 2.0), (1.5, -1.5), (-2.0, -1.0)]


def cross(first, second):
    """The z component of the cross product of two plane vectors."""
    return first[0] * second[1] - first[1] * second[0]


def quartic_design(seed=0):
    rng = np.random.default_rng(seed)
    return line_plane_design(rng.normal(size=(5, 2)), rng.normal(size=5))


def cubic_design(seed=0, angle=0.7):
    """B at infinity (24): B-lines parallel, x = −(C₁z + C₆)/(C₄z + C₂) across them, then turned by `angle`."""
    rng = np.random.default_rng(seed)
    z = rng.normal(size=5)
    c1, c2, c4, c6 = rng.normal(size=4)
    across = -(c1 * z + c6) / (c4 * z + c2)
    along = rng.normal(size=5)
    turn = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    return line_plane_design(np.column_stack([across, along]) @ turn.T, z)


def quadratic_design():
    return line_plane_design(QUADRATIC_BASE, [DELTA * x for x, _ in QUADRATIC_BASE])


DESIGNS = {"quartic": quartic_design, "cubic": cubic_design, "quadratic": quadratic_design}


def random_poses(rng, count):
    positions = np.column_stack([rng.normal(size=(count, 2)), rng.uniform(0.5, 3.0, size=count)])
    directions = rng.normal(size=(count, 3))
    return positions, directions / np.linalg.norm(directions, axis=1, keepdims=True)


def singular_poses(design, rng, count):
    """Poses on the zero set of (17): pₓ solved from it (it is linear in pₓ, coefficient w(C₂w − p_zC₄))."""
    positions, directions = random_poses(rng, count)
    positions[:, 0] = 0.0
    constant = singularity_polynomial(design, positions, directions)
    positions[:, 0] = 1.0
    slope = singularity_polynomial(design, positions, directions) - constant
    positions[:, 0] = -constant / slope
    return positions, directions


# ------------------------------------------------------------------------------------------------ paper's numbers

def test_cofactors_of_the_quadratic_family_are_eq27():
    """Eq. (27): C₁ = δ²F, C₂ = −δ³F, C₃ … C₆ = 0, with F the determinant (28) (F = 225 for this design)."""
    design = quadratic_design()
    rows = [(x * x, x * y, x, y) for x, y in QUADRATIC_BASE[1:]]
    F = np.linalg.det(np.array(rows))
    assert F == pytest.approx(225.0)
    expected = [DELTA ** 2 * F, -DELTA ** 3 * F, 0, 0, 0, 0]
    assert np.allclose(cofactors(design), expected, atol=1e-12 * F)


def test_singularity_polynomial_is_the_determinant_of_the_legs_line_coordinates():
    """(17) — the vector form of the lost (2) — equals −det of the legs' line-coordinate matrix, for any design."""
    rng = np.random.default_rng(1)
    for make in DESIGNS.values():
        design = make()
        positions, directions = random_poses(rng, 6)
        polynomial = singularity_polynomial(design, positions, directions)
        determinant = jacobian_determinant(design, positions, directions, normalise=False)
        assert np.allclose(determinant, -polynomial, rtol=1e-9, atol=1e-12 * np.max(np.abs(polynomial)))
        single = [singularity_polynomial(design, p, i) for p, i in zip(positions, directions)]
        assert np.allclose(single, polynomial, rtol=1e-14, atol=0)


def test_singularity_polynomial_equals_the_catalogue_function():
    design = quadratic_design()
    values = entry("5-spu").values("eq33_second_factor")
    position = [values["p_x"], values["p_y"], values["p_z"]]
    direction = [values["u"], values["v"], values["w"]]
    assert singularity_polynomial(design, position, direction) == pytest.approx(catalogue_polynomial(**values),
                                                                                abs=1e-12)


def test_quadratic_singularities_are_eq33_and_eq35():
    """(33): (17) = −δ²wF[δwpₓ − (δu − 1)p_z]; (35): with the tool vertical, δpₓ + p_z = 0 is singular."""
    design = quadratic_design()
    F = 225.0
    positions, directions = random_poses(np.random.default_rng(2), 8)
    u, w = directions[:, 0], directions[:, 2]
    p_x, p_z = positions[:, 0], positions[:, 2]
    eq33 = DELTA ** 2 * w * F * (DELTA * w * p_x - (u * DELTA - 1) * p_z)
    assert np.allclose(singularity_polynomial(design, positions, directions), -eq33, rtol=1e-10)
    vertical = np.array([0.0, 0.0, 1.0])
    on_plane = singularity_reading(design, [-3.0 / DELTA, 0.4, 3.0], vertical)
    off_plane = singularity_reading(design, [-3.0 / DELTA + 0.5, 0.4, 3.0], vertical)
    assert on_plane.singular and on_plane.margin < 1e-14
    assert not off_plane.singular and off_plane.margin > 1e-3


def test_b_point_is_the_vertex_of_the_pencil_and_attachments_lie_on_their_b_lines():
    """(13)-(16): every base attachment is on its B-line; B is on every B-line; B∞ is the line of z = ∞."""
    design = quartic_design(3)
    point = b_point(design)
    lines = b_line(design, np.append(design.platform, [-7.0, 0.3, 11.0]))
    scale = np.linalg.norm(lines[:, :2], axis=1)
    assert np.all(np.abs(lines[:, :2] @ point + lines[:, 2]) <= 1e-10 * scale)
    own = b_line(design, design.platform)
    assert np.all(np.abs(np.sum(own[:, :2] * design.base, axis=1) + own[:, 2]) <= 1e-10 * scale[:5])
    infinity = b_infinity(design)
    assert abs(infinity[:2] @ point + infinity[2]) < 1e-10
    direction_far = b_line(design, 1e9)
    assert np.allclose(direction_far / np.linalg.norm(direction_far), np.sign(direction_far[0] / infinity[0])
                       * infinity / np.linalg.norm(infinity), atol=1e-6)


def test_lambda_plus_carries_the_platform_attachments_onto_their_b_lines():
    """(23), Fig. 8: b⁺ᵢ on Λ⁺ and on B_{zᵢ}, spaced as the zᵢ on Λ; Λ⁺ parallel to B∞."""
    design = quartic_design(4)
    line, copies = lambda_plus(design)
    own = b_line(design, design.platform)
    assert np.all(np.abs(copies @ line[:2] + line[2]) < 1e-10)
    assert np.all(np.abs(np.sum(own[:, :2] * copies, axis=1) + own[:, 2]) < 1e-9 * np.linalg.norm(own[:, :2], axis=1))
    gaps = np.linalg.norm(copies - copies[0], axis=1)
    assert np.allclose(gaps, np.abs(design.platform - design.platform[0]), atol=1e-10)
    assert abs(cross(line[:2], b_infinity(design)[:2])) < 1e-12


def test_two_coincident_base_attachments_mark_b():
    """Section III-D, remarks 1-2: two coincident base attachments (distinct zᵢ) lie at B."""
    rng = np.random.default_rng(5)
    base = rng.normal(size=(5, 2))
    base[1] = base[0]
    design = line_plane_design(base, rng.normal(size=5))
    assert family(design).name == "quartic"
    assert np.allclose(b_point(design), base[0], atol=1e-10)


def test_parallel_platform_is_singular_iff_it_is_parallel_to_b_infinity():
    """(20): for w = 0, singular iff i = ±(C₅, −C₄, 0)/‖(C₄, C₅)‖ (or Λ in Π)."""
    design = quartic_design(6)
    c4, c5 = cofactors(design)[3:5]
    along = np.array([c5, -c4, 0.0]) / np.hypot(c4, c5)
    across = np.array([c4, c5, 0.0]) / np.hypot(c4, c5)
    position = np.array([0.3, -0.8, 1.7])
    assert singularity_reading(design, position, along).singular
    assert singularity_reading(design, position, along).parallel
    assert not singularity_reading(design, position, across).singular
    assert singularity_reading(design, position * [1, 1, 0], across).singular  # Λ in Π


def test_singularity_reading_is_the_point_where_the_line_meets_the_base_on_its_b_line():
    """(18)-(19): singular iff A = Λ ∩ Π lies on B_μ, μ = −p_z/w."""
    design = quartic_design(7)
    rng = np.random.default_rng(8)
    positions, directions = singular_poses(design, rng, 4)
    for position, direction in zip(positions, directions):
        reading = singularity_reading(design, position, direction)
        assert reading.singular and abs(reading.distance) < 1e-9
        assert np.allclose(position + reading.z * direction, [*reading.intersection, 0.0], atol=1e-12)
        moved = singularity_reading(design, position + [0.3, 0.2, 0.0], direction)
        assert not moved.singular and abs(moved.distance) > 1e-3


# ------------------------------------------------------------------------------------------------ families

def test_each_family_is_recognised_with_its_margins():
    """Section IV-B: quartic (B finite), cubic (B at ∞, B∞ finite), quadratic (both at ∞)."""
    for name, make in DESIGNS.items():
        result = family(make())
        assert result.name == name
        assert result.architecture_margin > 1e-3
        assert result.degree == {"quartic": 4, "cubic": 3, "quadratic": 2}[name]
    cubic = family(cubic_design())
    assert cubic.b_margin < 1e-12 and cubic.b_infinity_margin > 1e-3
    quadratic = family(quadratic_design())
    assert quadratic.b_infinity_margin < 1e-12
    assert b_point(cubic_design()) is None and b_infinity(cubic_design()) is not None
    assert b_point(quadratic_design()) is None and b_infinity(quadratic_design()) is None


def test_architecturally_singular_designs_are_detected_with_their_margin():
    """F = 0 in (28) (Section V-B), and three legs on one B-line (Section III-B): all Cᵢ vanish."""
    on_conic = [(0.0, 0.0), (2.0, 2.0), (3.0, 1.5), (-1.0, 0.5), (0.5, -1.0)]  # xy − x − y = 0: F = 0
    conic = line_plane_design(on_conic, [DELTA * x for x, _ in on_conic])
    result = family(conic)
    assert result.name == "architecturally singular" and result.margin < 1e-14
    three = line_plane_design([(0, 0), (1, 0.5), (2, 1), (0.3, 2), (-1, 1.2)], [0.4, 0.4, 0.4, -1.0, 1.3])
    assert family(three).name == "architecturally singular" and family(three).margin < 1e-14
    assert np.allclose(cofactors(three), 0, atol=1e-12)


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_family_and_margins_do_not_depend_on_the_frame_or_the_unit(name):
    """A rotation and translation of the base frame, a shift of Λ's origin, a flip of i and a scaling."""
    design = DESIGNS[name]()
    reference = family(design)
    angle, shift = 1.1, np.array([3.0, -2.0])
    turn = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    variants = [line_plane_design(design.base @ turn.T + shift, design.platform),
                line_plane_design(design.base, design.platform + 2.5),
                line_plane_design(design.base, -design.platform),
                line_plane_design(7.5 * design.base, 7.5 * design.platform)]
    for variant in variants:
        result = family(variant)
        assert result.name == reference.name
        if reference.name == "quartic" or name == "cubic":
            assert result.architecture_margin == pytest.approx(reference.architecture_margin, rel=1e-8)
        assert (result.b_margin < 1e-10) == (reference.b_margin < 1e-10)
    # B follows the frame
    if reference.name == "quartic":
        assert np.allclose(b_point(variants[0]), turn @ b_point(design) + shift, atol=1e-9)
        assert np.allclose(b_point(variants[3]), 7.5 * b_point(design), atol=1e-9)


def test_bad_designs_are_refused_naming_the_field():
    good = np.random.default_rng(0).normal(size=(5, 2))
    with pytest.raises(DesignError, match="five legs") as error:
        line_plane_design(good[:4], [1, 2, 3, 4])
    assert error.value.field == "base"
    with pytest.raises(DesignError, match="platform") as error:
        line_plane_design(good, [1, 2, 3, 4])
    assert error.value.field == "platform"
    with pytest.raises(DesignError, match="finite"):
        line_plane_design(good, [1, 2, np.nan, 4, 5])
    twin = good.copy()
    twin[3] = twin[1]
    with pytest.raises(DesignError, match="legs 2 and 4 coincide"):
        line_plane_design(twin, [1, 2, 3, 2, 5])
    with pytest.raises(DesignError, match="collinear"):
        line_plane_design([(0, 0), (1, 1), (2, 2), (3, 3), (0, 1)], [1, 2, 3, 4, 5])


# ------------------------------------------------------------------------------------------------ rearrangements

def _singular_set(design, positions, directions, cut=1e-9):
    return np.abs(jacobian_determinant(design, positions, directions)) <= cut


def _poses_for(design, rng):
    """Half on the locus (17), half random: the singular set and its complement."""
    on = singular_poses(design, rng, 6)
    off = random_poses(rng, 6)
    return np.concatenate([on[0], off[0]]), np.concatenate([on[1], off[1]])


def _to_b(design, index):
    """Rule 1: slide base attachment `index` along its B-line to B."""
    gap = (b_point(design) - design.base[index]) @ b_line_direction(design, index)
    return move_base(design, index, gap)


def test_allowed_rearrangements_keep_the_singular_set():
    """Section III-B rules 1 and 2: cofactors proportional, the same poses singular / regular (independent det)."""
    rng = np.random.default_rng(10)
    design = quartic_design(11)
    positions, directions = _poses_for(design, rng)
    before = _singular_set(design, positions, directions)
    assert before.sum() == 6
    moved = move_base(move_base(design, 2, 0.8), 4, -1.3)           # rule 1 twice
    at_b = _to_b(moved, 0)                                           # rule 1: leg 1 to B
    assert np.allclose(at_b.base[0], b_point(design), atol=1e-9)
    lifted = move_platform(at_b, 0, at_b.platform[0] + 2.0)          # rule 2: leg 1 at B
    for after in (moved, at_b, lifted):
        ratio = cofactors(after) / cofactors(design)
        assert np.allclose(ratio, ratio[0], rtol=1e-8)
        assert np.array_equal(_singular_set(after, positions, directions), before)
        assert np.all(np.abs(jacobian_determinant(after, positions[~before], directions[~before])) > 1e-6)
    for make in (cubic_design, quadratic_design):
        other = make()
        poses = _poses_for(other, rng)
        moved = move_base(move_base(other, 1, 0.6), 3, -0.9)
        assert np.array_equal(_singular_set(moved, *poses), _singular_set(other, *poses))


def test_a_forbidden_move_changes_the_singular_set():
    """Rule 2's converse: moving a platform attachment whose base attachment is not at B changes the locus."""
    rng = np.random.default_rng(12)
    design = quartic_design(11)
    positions, directions = _poses_for(design, rng)
    before = _singular_set(design, positions, directions)
    platform = design.platform.copy()
    platform[2] += 0.7
    changed = line_plane_design(design.base, platform)
    after = _singular_set(changed, positions, directions)
    assert before[:6].all() and not after[:6].any()
    with pytest.raises(RearrangementError, match="not at B"):
        move_platform(design, 2, platform[2])


def test_a_move_into_an_architecturally_singular_design_is_refused():
    """Section III-B: the cofactors scale by a factor affine along the B-line; where it vanishes, refuse."""
    design = quartic_design(13)
    index = 3
    first = cofactors(move_base(design, index, 1.0))
    ratio = float(first @ cofactors(design) / (cofactors(design) @ cofactors(design)))
    zero = -1.0 / (ratio - 1.0)   # λ(T) = 1 + (ratio − 1)T vanishes here
    with pytest.raises(RearrangementError, match="architecturally singular"):
        move_base(design, index, zero)
    move_base(design, index, zero + 0.5)   # away from the root the move is fine
    with pytest.raises(RearrangementError, match="B is at infinity"):
        move_platform(quadratic_design(), 1, 0.2)


# ------------------------------------------------------------------------------------------------ Park–Kim classifier

@pytest.fixture(scope="module")
def survey():
    """The survey of M (largest ranks: Φ 24, G 5) of a non-architecturally-singular locked 5-SPU; the same for
    every such design, computed once."""
    return survey_of(model_of(five_spu(spin="locked", end_effector="none")))


def _five_spu(design, position, direction, spin="locked", end_effector="none"):
    parameters = {}
    for index in range(5):
        parameters[f"x{index + 1}"], parameters[f"y{index + 1}"] = (float(value) for value in design.base[index])
        parameters[f"z{index + 1}"] = float(design.platform[index])
    return five_spu(**parameters, p_x=position[0], p_y=position[1], p_z=position[2], u=direction[0],
                    v=direction[1], w=direction[2], spin=spin, end_effector=end_effector)


def _classifier_singular(design, position, direction, survey):
    mechanism = _five_spu(design, position, direction)
    return classify(mechanism, home(mechanism), survey=survey).actuator.singular


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_the_classifier_finds_actuator_singularities_exactly_on_eq17(name, survey):
    design = DESIGNS[name]()
    rng = np.random.default_rng(20)
    on = singular_poses(design, rng, 2)
    off = random_poses(rng, 2)
    for position, direction in zip(*on):
        assert _classifier_singular(design, position, direction, survey)
        assert singularity_margin(design, position, direction) < 1e-12
    for position, direction in zip(*off):
        assert not _classifier_singular(design, position, direction, survey)


@pytest.fixture(scope="module")
def tool_survey():
    """The survey of M of the free-spin 5-SPU whose end-effector is its axisymmetric tool (``output: tool``, the
    point p and the direction i of Λ): largest ranks Φ 24, G 5, J 5 and (G; J) 5, so m = 6 with one idle freedom
    (the spin) and no architecture singularity; the same for every non-architecturally-singular design."""
    result = survey_of(model_of(five_spu()))
    assert (result.actuator_rank, result.end_effector_rank, result.joint_rank) == (5, 5, 5)
    return result


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_with_the_tool_output_the_classifier_finds_actuator_singularities_exactly_on_eq17(name, tool_survey):
    """Borràs, Thomas & Torras 2011 (17), with the spin free (Fig. 1) and ``output: tool``: the general classifier
    on the 5-SPU joint graph reports an actuator singularity at poses on the zero set of (17) and nowhere else,
    for one design of each family; the spin is an idle freedom, never an architecture singularity, and the tool
    (p, i) has no end-effector singularity there (J of rank 5 = dim N)."""
    design = DESIGNS[name]()
    rng = np.random.default_rng(22)
    on = singular_poses(design, rng, 2)
    off = random_poses(rng, 2)
    for (positions, directions), on_locus in ((on, True), (off, False)):
        for position, direction in zip(positions, directions):
            assert (singularity_margin(design, position, direction) < 1e-12) == on_locus
            mechanism = _five_spu(design, position, direction, spin="free", end_effector="tool")
            report = classify(mechanism, home(mechanism), survey=tool_survey)
            assert report.kinds == (("actuator",) if on_locus else ())
            assert report.actuator.rank == (4 if on_locus else 5) and report.actuator.expected_rank == 5
            assert (report.dof, report.idle_freedoms, report.moving_idle_freedoms) == (6, 1, 0)
            assert not report.architecture_singular
            assert report.end_effector.rank == report.end_effector.expected_rank == 5
            if on_locus:
                assert report.degeneracy == "nondegenerate"  # a fold of the assembly modes, the spin aside


def test_the_classifier_agrees_before_and_after_a_rearrangement(survey):
    design = quartic_design(11)
    rng = np.random.default_rng(21)
    moved = move_base(design, 1, 0.9)
    platform = design.platform.copy()
    platform[3] -= 0.6
    forbidden = line_plane_design(design.base, platform)
    on = singular_poses(design, rng, 2)
    off = random_poses(rng, 1)
    for position, direction in zip(*on):
        assert _classifier_singular(moved, position, direction, survey)
        assert not _classifier_singular(forbidden, position, direction, survey)
    for position, direction in zip(*off):
        assert not _classifier_singular(moved, position, direction, survey)


# ------------------------------------------------------------------------------------------------ mechanisms, figures

def test_design_and_pose_of_the_catalogue_mechanism():
    item = entry("5-spu")
    design, position, direction = design_from_mechanism(item.assemble(item.values("eq35_vertical_tool")))
    assert np.allclose(design.base, QUADRATIC_BASE) and np.allclose(design.platform, DELTA * design.base[:, 0])
    assert np.allclose(direction, [0, 0, 1]) and family(design).name == "quadratic"
    assert singularity_reading(design, position, direction).singular
    design, position, direction = design_from_mechanism(item.assemble(item.values("regular")))
    assert not singularity_reading(design, position, direction).singular


def test_b_line_figure_draws_each_b_line_through_its_attachment_and_b():
    from classify.figures.line_plane import draw_b_lines, draw_rearrangement

    design = quartic_design(3)
    figure = draw_b_lines(design)
    lines = {line.get_label(): line for line in figure.axes[0].get_lines()}
    assert {"B-line 1", "B-line 5", "B", "B_inf", "Lambda+", "base"} <= set(lines)
    point = b_point(design)
    for index in range(5):
        data = lines[f"B-line {index + 1}"].get_xydata()
        for target in (design.base[index], point):
            assert abs(cross(data[1] - data[0], target - data[0])) < 1e-8 * np.linalg.norm(data[1] - data[0]) ** 2
    moved = move_base(design, 2, 0.8)
    figure = draw_rearrangement(design, moved)
    slices = {line.get_label(): line.get_xydata() for line in figure.axes[2].get_lines()}
    assert np.allclose(slices["locus before"], slices["locus after"], atol=1e-9)
    assert [axes.get_title() for axes in figure.axes[:2]] == ["before", "after"]
