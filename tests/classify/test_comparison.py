"""The comparison of Park–Kim and Gosselin–Angeles: the correspondence I ↔ end-effector,
II ↔ actuator, III ↔ both or C-space (docs/design.rst, "Gosselin–Angeles"), and every entry of the closed
list of reasons for a disagreement, each exercised on a concrete mechanism."""

import numpy as np
import pytest

from classify import (
    REASONS, Model, classify, compare, correspondence, expected_kinds, joint_output_model, model_of,
    path_configurations, singular_crossings, survey_of,
)
from classify.gosselin_angeles_examples import eq9_relation, slider_crank_coordinates, squared_relation
from manifold import AmbientSpace, ImplicitManifold
from mechanisms import home
from mechanisms.catalogue import entry

EXERCISED = set()


def reasons_of(comparison):
    found = {row.reason for row in comparison.rows}
    EXERCISED.update(found)
    return found


def slider_crank(**parameters):
    """The catalogue slider-crank, crank driven, the slider's displacement as the output."""
    mechanism = entry("slider-crank").mechanism(**parameters)
    return mechanism, joint_output_model(mechanism, ["slide"])


def test_regular_and_singular_slider_crank_correspond():
    for configuration, kinds in ((None, ()), ("fig3b_actuator", ("II",)), ("fig3c_dead_centre", ("I",))):
        mechanism = entry("slider-crank").mechanism(configuration)
        result = compare(joint_output_model(mechanism, ["slide"]), [home(mechanism)])
        row = result.rows[0]
        assert row.agree and row.reason is None and row.gosselin_angeles.kinds == kinds
        assert result.summary["agree"] == 1


def test_redundant_actuation():
    """Park & Kim, introduction: G–A does not handle redundant actuation; a five-bar with three motors."""
    mechanism = entry("five-bar").mechanism(actuated="A,B,D")
    result = compare(mechanism, [home(mechanism)])
    assert reasons_of(result) == {"redundant_actuation"}
    assert result.rows[0].park_kim.kinds == ()  # Park–Kim: regular, E semidefinite is no difficulty


def test_unequal_dimensions():
    """One input, the slider's planar position (two coordinates) as output."""
    mechanism = entry("slider-crank").mechanism()
    assert reasons_of(compare(mechanism, [home(mechanism)])) == {"unequal_dimensions"}


def test_idle_freedom():
    """A five-bar driven at A only, with the angle at B as the output: B moves with A locked."""
    mechanism = entry("five-bar").mechanism(actuated="A")
    result = compare(joint_output_model(mechanism, ["B"]), [home(mechanism)])
    assert reasons_of(result) == {"idle_freedom"}
    assert result.rows[0].gosselin_angeles.velocity_dimension == 2


def test_cspace_singularity():
    """Fig. 3a: the equal-link slider-crank where its two branches cross (Park & Kim Fig. 3a)."""
    mechanism, model = slider_crank(crank=1.0, coupler=1.0, theta=np.pi / 2)
    result = compare(model, [home(mechanism)])
    assert reasons_of(result) == {"cspace_singularity"}
    assert result.rows[0].park_kim.kinds == ("cspace",)
    assert expected_kinds(result.rows[0].park_kim) == ("I", "II", "III")


def test_a_crank_of_a_stretched_four_bar_is_lost_to_the_cspace_singularity_not_redundant():
    """A four-bar fully stretched (1 + 1 + 1 = 3) is a point of M, dof 0: its one crank is not a redundant
    actuator (the four-bar has k − 3 = 1 freedom wherever DΦ has its rank 3); G–A is undefined because of
    the C-space singularity (it said ``redundant_actuation``)."""
    from builders import stretched_four_bar

    mechanism = stretched_four_bar()
    result = compare(joint_output_model(mechanism, ["J3"]), [home(mechanism)])
    assert result.rows[0].park_kim.dof == 0
    assert reasons_of(result) == {"cspace_singularity"}


def test_stationary_motion():
    """G–A eq. 84: a Gough–Stewart leg of zero length turns freely, moving neither inputs nor outputs."""
    mechanism = entry("gough-stewart").mechanism("eq84_leg1_zero_length")
    result = compare(mechanism, [home(mechanism)])
    assert reasons_of(result) == {"stationary_motion"}
    assert result.rows[0].gosselin_angeles.velocity_dimension < 6


def test_not_differentiable_at_the_branch_point_of_eq9():
    """G–A eq. 9 at sin θ = l/R (Fig. 3): its ±√ vanishes, B is infinite; eq. 12 rescales it to kind II."""
    mechanism, model = slider_crank(theta=np.arcsin(0.5))
    relation, coordinates = eq9_relation(mechanism, branch=1)
    result = compare(model, [home(mechanism)], relation=relation, coordinates=coordinates)
    assert reasons_of(result) == {"not_differentiable"}
    assert result.rows[0].park_kim.kinds == ("actuator",)


def test_degenerate_relation_from_squared_terms():
    """cos θ eliminated by squaring eq. 9: F = (x² + R² − l²)² − 4x²R²(1 − sin²θ) also holds for the
    mirror linkage θ → π − θ; where the two meet (θ = π/2) [B A] = 0 although M is smooth."""
    mechanism, model = slider_crank(crank=3.0, coupler=5.0, theta=np.pi / 2)
    relation, coordinates = squared_relation(mechanism)
    result = compare(model, [home(mechanism)], relation=relation, coordinates=coordinates)
    assert reasons_of(result) == {"degenerate_relation"}
    row = result.rows[0]
    assert row.park_kim.kinds == () and row.gosselin_angeles.kinds == ("I", "II", "III")
    assert row.gosselin_angeles.relation_decision.rank == 0
    nearby, nearby_model = slider_crank(crank=3.0, coupler=5.0, theta=1.2)
    relation, coordinates = squared_relation(nearby)
    assert compare(nearby_model, [home(nearby)], relation=relation, coordinates=coordinates).rows[0].agree


def test_inconsistent_relation():
    """Eq. 9 with the other sign describes the other assembly branch, not this configuration."""
    mechanism, model = slider_crank(theta=0.3)
    for branch, reasons in ((1, {None}), (-1, {"inconsistent_relation"})):
        relation, coordinates = eq9_relation(mechanism, branch=branch)
        assert reasons_of(compare(model, [home(mechanism)], relation=relation, coordinates=coordinates)) == reasons


def test_numerical_margin():
    """Near the dead centre θ = 0 the two rank decisions cross the cut at slightly different θ.

    Every θ is a configuration of one design, so of one M: its largest ranks (the survey) are
    computed once, at a regular configuration, and shared."""
    shared = survey_of(slider_crank(theta=0.3)[1])
    found = set()
    for theta in np.logspace(-8, -4, 17):
        mechanism, model = slider_crank(theta=float(theta))
        found |= reasons_of(compare(model, [home(mechanism)], survey=shared))
    assert found == {None, "numerical_margin"}


def test_unexplained_is_kept_for_what_the_list_does_not_cover():
    """A report and a classification that differ for no listed reason are called unexplained."""
    mechanism, model = slider_crank(theta=0.3)
    regular = compare(model, [home(mechanism)]).rows[0]
    mechanism, model = slider_crank(theta=np.arcsin(0.5))
    singular = compare(model, [home(mechanism)]).rows[0]
    assert singular.gosselin_angeles.kinds == ("II",)
    assert correspondence(regular.park_kim, singular.gosselin_angeles)[1] == "unexplained"


def test_a_stationary_motion_of_a_synthetic_model():
    """M = {(s, θ, x): θ = s², x = s³}: at s = 0 neither input nor output moves to first order."""
    ambient = AmbientSpace(("R", "R", "R"))

    def constraint(point):
        s, theta, x = np.moveaxis(np.asarray(point, dtype=float), -1, 0)
        return np.stack([theta - s ** 2, x - s ** 3], axis=-1)

    def jacobian(point):
        s = np.asarray(point, dtype=float)[..., 0]
        zero, one = np.zeros_like(s), np.ones_like(s)
        return np.stack([np.stack([-2 * s, one, zero], -1), np.stack([-3 * s ** 2, zero, one], -1)], -2)
    def hessian(point):
        s = np.asarray(point, dtype=float)[..., 0]
        result = np.zeros(s.shape + (2, 3, 3))
        result[..., 0, 0, 0], result[..., 1, 0, 0] = -2.0, -6.0 * s
        return result
    model = Model("cusp", ImplicitManifold(ambient, constraint, jacobian, hessian), np.array([[0.0, 1.0, 0.0]]),
                  ("s", "theta", "x"), np.zeros((1, 3)), lambda point: np.array([[0.0, 0.0, 1.0]]), np.eye(1))
    result = compare(model, [[0.0, 0.0, 0.0], [0.5, 0.25, 0.125]])
    assert [row.reason for row in result.rows] == ["stationary_motion", None]


def test_a_path_through_the_fold_of_the_crank():
    """Along M through Fig. 3b the two classifications correspond at every step."""
    mechanism, model = slider_crank(theta=np.arcsin(0.5) - 0.05)
    points, steps = path_configurations(model, home(mechanism), 6, step=0.02)
    assert list(steps) == list(range(-6, 7))
    result = compare(model, points)
    assert all(row.agree for row in result.rows)


def test_a_path_crosses_the_fold_and_the_dead_centre_exactly():
    """From θ = 0.4 the path of the slider-crank (R = 2, l = 1) reaches the fold sin θ = l/R (eq. 14,
    actuator) one way and the dead centre θ = 0 (eq. 13, end-effector) the other; the crossings are
    located to the bisection tolerance, and both classifications agree there."""
    mechanism, model = slider_crank(theta=0.4)
    points, _ = path_configurations(model, home(mechanism), 40, step=0.05)
    crossings = singular_crossings(model, points)
    assert [kind for _, _, kind in crossings] == ["actuator", "end_effector"]
    angles = [slider_crank_coordinates(mechanism)(point)[0][0] for _, point, _ in crossings]
    np.testing.assert_allclose(angles, [np.arcsin(0.5), 0.0], atol=1e-6)
    result = compare(model, [point for _, point, _ in crossings])
    assert [row.gosselin_angeles.kinds for row in result.rows] == [("II",), ("I",)]
    assert [row.park_kim.kinds for row in result.rows] == [("actuator",), ("end_effector",)]
    assert all(row.agree for row in result.rows)


def crossings_classified(model, mechanism, count, step):
    """The crossings of a path of M through the home, each with the kinds classify finds there."""
    points, _ = path_configurations(model, home(mechanism), count, step=step)
    return [(index, kind, classify(mechanism, point).kinds) for index, point, kind in
            singular_crossings(model, points)], points


def test_a_path_of_the_3prr_keeps_its_tangent_basis_and_finds_only_true_crossings():
    """The 3-PRR's slides have scale 200 (Chablat et al. 2002): the tangent basis carried along the path was
    turned in the plain product of joint coordinates and mirrored between path+23 and path+24, which hid the
    actuator singularity there and put end-effector "crossings" at regular points. Turned in the product in
    which it is orthonormal, every crossing is a singularity of its kind, and that one is found."""
    mechanism = entry("3-prr").mechanism()
    found, _ = crossings_classified(model_of(mechanism), mechanism, 40, 0.1)
    assert all(kind in kinds for _, kind, kinds in found), found
    assert (40 + 23, "actuator") in [(index, kind) for index, kind, _ in found]


def test_a_singular_start_or_a_singular_branch_is_no_crossing():
    """At a singular start (the five-bar's distal links aligned, Park & Kim Fig. 6a) the start is a row of the
    path already, and along a branch singular throughout (the slider-crank's constant branch slider driven,
    G-A eqs. 15-17) the determinant's sign is rounding: neither brackets a crossing."""
    mechanism = entry("five-bar").mechanism("fig6a_distal_aligned")
    found, _ = crossings_classified(model_of(mechanism), mechanism, 6, 0.05)
    assert found == []
    mechanism = entry("slider-crank").mechanism("eq17_constant_branch_slider_driven")
    model = joint_output_model(mechanism, ["crank"])
    points, _ = path_configurations(model, home(mechanism), 5, step=0.05)
    assert all(classify(model, point).kinds == ("actuator",) for point in points)
    assert singular_crossings(model, points) == []


def test_a_path_through_a_parallelogram_flattening_finds_the_cspace_singularity():
    """A parallelogram four-bar (crank 1, ground 2) flattens at J1 = ±π/2, where it can switch to the
    antiparallelogram: a simple bifurcation of M (a C-space singularity) that the path crossed without a row;
    the bordered Jacobian det[DΦ·diag(s); (T/s)ᵀ] changes sign there."""
    from mechanisms import EndEffector, Joint, Mechanism

    mechanism = Mechanism("parallelogram", "planar", [
        Joint("J1", "R", ("ground", "crank"), point=(0.0, 0.0), actuated=True),
        Joint("J2", "R", ("crank", "coupler"), point=(0.0, 1.0)),
        Joint("J3", "R", ("coupler", "rocker"), point=(2.0, 1.0)),
        Joint("J4", "R", ("rocker", "ground"), point=(2.0, 0.0))],
        end_effector=EndEffector("rocker", None, "orientation"))
    found, _ = crossings_classified(model_of(mechanism), mechanism, 20, 0.2)
    cspace = [(kind, kinds) for _, kind, kinds in found if kind == "cspace"]
    assert len(cspace) == 2 and all("cspace" in kinds for _, kinds in cspace)
    assert all(kind in kinds for _, kind, kinds in found)


def test_summary_counts_and_text():
    mechanism = entry("five-bar").mechanism(actuated="A,B,D")
    result = compare(mechanism, [home(mechanism)] * 2, labels=["one", "two"])
    summary = result.summary
    assert summary["configurations"] == 2 and summary["disagree"] == 2
    assert summary["reasons"] == {"redundant_actuation": 2} and summary["gosselin_angeles"]["undefined"] == 2
    text = result.to_text()
    assert "redundant_actuation" in text and "[one, two]" in text
    data = result.to_dict()
    assert set(data["configurations"][0]) >= {"park_kim", "gosselin_angeles", "agree", "note"}
    assert set(data["configurations"][0]["gosselin_angeles"]) >= {"kinds", "rank_A", "rank_B", "n"}


def test_names_for_the_report_are_used_as_given_or_refused():
    mechanism, model = slider_crank()
    point = [home(mechanism)]
    result = compare(model, point, input_names=["theta"], output_names=("x",))
    assert result.inputs == ("theta",) and result.outputs == ("x",)
    with pytest.raises(TypeError, match="input_names: expected a sequence of names"):
        compare(model, point, input_names="theta")  # not the letters t, h, e, t, a
    with pytest.raises(ValueError, match=r"output_names: 2 names given, 1 expected \(y1\)"):
        compare(model, point, output_names=["x", "y"])


def test_every_reason_of_the_closed_list_is_exercised():
    """Runs last in this module (pytest keeps file order): every REASONS key was met above."""
    missing = set(REASONS) - EXERCISED
    if len(EXERCISED) <= 1:
        pytest.skip("run the whole module to check the coverage of the reasons")
    assert not missing, f"reasons never exercised: {sorted(missing)}"
