"""3-PRR: Chablat, Caro, Wenger & Angeles (2002) Fig. 1, eqs. (3)-(4), §2.2-3.5.

Design of Figs. 6-8: r = 100, R = 200, l = 200 (mm). The paper's matrices A (eq. 4a) and B (eq. 4b)
are evaluated here from the assembled geometry (the points Bᵢ, Cᵢ, P and the rail directions αᵢ),
independently of the classifier; det A = 0 ↔ actuator, det B = 0 ↔ end_effector (docs/design.rst).
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from builders import shared_mechanism
from classify import classify, model_of, survey_of
from mechanisms import MechanismError, home
from mechanisms.catalogue.three_prr import ENTRIES, WORKING_MODES, three_prr, three_prr_at_inputs

RADIUS, BASE, LEG = 100.0, 200.0, 200.0
CHARACTERISTIC_LENGTH = math.sqrt(2) * RADIUS     # §3.4: L = √2 r sin γ, γ = π/2
E = np.array([[0.0, -1.0], [1.0, 0.0]])
ISOTROPIC_PHI = math.pi / 3


@pytest.fixture(scope="module")
def shared_survey():
    """The largest ranks on M of the paper's design (one survey: every pose below is on the same M).

    The survey ``classify`` keeps for the default mechanism (``survey(model, numpy.random.default_rng(0))``),
    shared with the other tests (:func:`builders.shared_mechanism`).
    """
    return survey_of(model_of(shared_mechanism(three_prr())))


def classified(mechanism, shared_survey=None, **options):
    mechanism = shared_mechanism(mechanism)
    return classify(mechanism, home(mechanism), survey=shared_survey, rng=np.random.default_rng(0), **options)


def geometry(mechanism):
    """(b, c, p, α) read from the assembled joints: shapes [3, 2], [3, 2], [2], [3, 2]."""
    points = {joint.name: np.array(joint.point if joint.point is not None else joint.axis)
              for joint in mechanism.joints}
    b = np.array([points[f"B{i}"] for i in (1, 2, 3)])
    c = np.array([points[f"C{i}"] for i in (1, 2, 3)])
    alpha = np.array([points[f"rail{i}"] / np.linalg.norm(points[f"rail{i}"]) for i in (1, 2, 3)])
    return b, c, np.array(mechanism.end_effector.point), alpha


def paper_matrices(mechanism, length=CHARACTERISTIC_LENGTH):
    """Ā (eq. 7: eq. 4a with the third column over L) and B (eq. 4b) of the assembled geometry."""
    b, c, p, alpha = geometry(mechanism)
    legs = c - b
    k = np.einsum("ij,jk,ik->i", legs, E, p - c)
    a_bar = np.column_stack([legs, -k / length])
    b_matrix = np.diag(np.einsum("ij,ij->i", legs, alpha))
    return a_bar, b_matrix


def cross(first, second):
    """The planar cross products of rows, shape=[n]."""
    return first[:, 0] * second[:, 1] - first[:, 1] * second[:, 0]


def relative_smallest_singular_value(matrix):
    values = np.linalg.svd(matrix, compute_uv=False)
    return values[-1] / values[0]


def lines_concurrency(mechanism):
    """Normalised det of the homogeneous coordinates (nᵢ, −nᵢᵀbᵢ) of the lines BᵢCᵢ: 0 iff the lines
    meet at one point, possibly at infinity (Fig. 2)."""
    b, c, _, _ = geometry(mechanism)
    normals = (c - b) @ E.T / LEG
    lines = np.column_stack([normals, -np.einsum("ij,ij->i", normals, b) / LEG])
    return abs(np.linalg.det(lines))


def test_default_is_the_isotropic_configuration_of_fig4a(shared_survey):
    """§3.3-3.4, Fig. 4a: γ = π/2 and AᵢBᵢ collinear with BᵢCᵢ (r = R/2); with the SE(2) length
    scale L = √2 r the normalised Jacobian is isotropic: every proper value equal, κ = 1."""
    mechanism = three_prr()
    b, c, p, alpha = geometry(mechanism)
    legs = c - b
    assert np.allclose(cross(legs, alpha), 0.0, atol=1e-9)                         # collinear with the rails
    assert np.allclose(np.einsum("ij,ij->i", legs, c - p), 0.0, atol=1e-9)         # BᵢCᵢ ⊥ CᵢP
    report = classified(mechanism, shared_survey, length_scale=CHARACTERISTIC_LENGTH)
    assert report.kinds == ()
    assert report.manipulability.condition_number == pytest.approx(1.0, abs=1e-9)
    a_bar, b_matrix = paper_matrices(mechanism)
    k_bar = np.linalg.solve(b_matrix, a_bar)
    assert np.allclose(k_bar @ k_bar.T, k_bar[0] @ k_bar[0] * np.eye(3))            # eqs. (9a-f)


@pytest.mark.parametrize("phi", [ISOTROPIC_PHI - math.acos(1 / 3), ISOTROPIC_PHI + math.acos(1 / 3)])
def test_fig2_legs_concurrent_at_the_centre_is_a_nondegenerate_actuator_singularity(phi, shared_survey):
    """§2.2, Fig. 2: the lines BᵢCᵢ meet at P = O ((r + l) cos(φ − π/3) = R/2); det A = 0 ↔ actuator.
    Locked, the platform can only turn infinitesimally about P (nondegenerate). By hand: the legs
    are radial, so A = [lᵢᵀ 0] with left null vector w = (1, 1, 1); turning the platform by θ about
    P changes every |cᵢ − bᵢ|² by 2·r·(r + l)(1 − cos θ) ≈ r(r + l)θ², and wᵀ(1, 1, 1) = 3 ≠ 0."""
    mode = 1 if phi < ISOTROPIC_PHI else 5                  # mᵢ = −l sin(φ − π/3), all of one sign
    mechanism = three_prr(phi=phi, working_mode=mode)
    assert lines_concurrency(mechanism) < 1e-12
    a_bar, b_matrix = paper_matrices(mechanism)
    assert relative_smallest_singular_value(a_bar) < 1e-12
    report = classified(mechanism, shared_survey)
    assert report.kinds == ("actuator",)
    assert report.actuator.rank == 2 and report.end_effector.rank == 3
    assert report.degeneracy == "nondegenerate"
    for nearby in (phi - 0.01, phi + 0.01):
        assert classified(three_prr(phi=nearby, working_mode=mode), shared_survey).kinds == ()


@pytest.mark.parametrize("direction", [10.0, 75.0, 200.0])
def test_fig2_parallel_legs_is_a_degenerate_actuator_singularity(direction, shared_survey):
    """§2.2, Fig. 2 "possibly at infinity": the legs all parallel to d = (cos δ, sin δ). For this
    design (r = R/2) it happens at φ = π/3, P = l d, the sliders Bᵢ at the midpoints of the rails:
    BᵢCᵢ are three equal parallel cranks, so with the actuators locked the platform translates on a
    circle (checked by hand below) — a degenerate actuator singularity (G-A type III). Turned by
    0.01 rad, the legs are no longer parallel: regular."""
    delta = math.radians(direction)
    d = np.array([math.cos(delta), math.sin(delta)])
    alpha = np.array([[math.cos(t), math.sin(t)] for t in np.radians([0.0, 120.0, 240.0])])
    signs = tuple(int(s) for s in np.sign(alpha @ d))                              # mᵢ = l dᵀαᵢ
    mode = next(mode for mode, pattern in WORKING_MODES.items() if pattern == signs)
    mechanism = three_prr(x=LEG * d[0], y=LEG * d[1], working_mode=mode)
    b, c, _, _ = geometry(mechanism)
    assert np.allclose(c - b, LEG * d)
    assert lines_concurrency(mechanism) < 1e-12
    # the self-motion by hand: sliders fixed, the platform at P = l d' (φ = π/3) closes every leg
    for turned in (delta + 0.3, delta - 1.0):
        moved = three_prr(x=LEG * math.cos(turned), y=LEG * math.sin(turned), working_mode=1)
        _, moved_pivots, _, _ = geometry(moved)
        assert np.allclose(np.linalg.norm(moved_pivots - b, axis=1), LEG)
    report = classified(mechanism, shared_survey)
    assert report.kinds == ("actuator",)
    assert report.degeneracy == "degenerate"
    assert report.second_order.self_motion.largest_residual < 1e-9
    direction_joints = report.to_dict()["actuator"]["second_order"]["self_motion"]["direction"]
    assert not any(name.startswith("rail") for name in direction_joints)
    for nearby in (ISOTROPIC_PHI - 0.01, ISOTROPIC_PHI + 0.01):                    # turned: regular
        assert classified(three_prr(x=LEG * d[0], y=LEG * d[1], phi=nearby, working_mode=mode),
                          shared_survey).kinds == ()


def test_fig2_concurrent_lines_off_centre_found_from_det_a(shared_survey):
    """§2.2, Fig. 2: a root of det A(φ) at P = (30, −20) in working mode 2, found by bisection on the
    paper's A (eq. 4a); there the lines BᵢCᵢ are concurrent, and the classifier finds an actuator
    singularity (and a regular configuration 0.01 rad away)."""
    def det_a(phi):
        a_bar, _ = paper_matrices(three_prr(x=30.0, y=-20.0, phi=phi, working_mode=2))
        return np.linalg.det(a_bar / LEG)

    def reachable_det_a(phi):
        try:
            return det_a(phi)
        except MechanismError:
            return math.nan

    grid = np.linspace(-math.pi, math.pi, 181)
    values = [reachable_det_a(phi) for phi in grid]
    start = next(i for i in range(len(grid) - 1) if values[i] * values[i + 1] < 0)   # NaN compares false
    phi = brentq(det_a, grid[start], grid[start + 1], xtol=1e-15)
    mechanism = three_prr(x=30.0, y=-20.0, phi=phi, working_mode=2)
    assert lines_concurrency(mechanism) < 1e-9
    assert classified(mechanism, shared_survey).kinds == ("actuator",)
    for nearby in (phi - 0.01, phi + 0.01):
        assert classified(three_prr(x=30.0, y=-20.0, phi=nearby, working_mode=2), shared_survey).kinds == ()


@pytest.mark.parametrize("leg, offset, phi", [(1, 0.0, ISOTROPIC_PHI), (2, 20.0, ISOTROPIC_PHI + 0.3),
                                               (3, -15.0, ISOTROPIC_PHI - 0.2)])
def test_fig3_leg_square_to_its_rail_is_an_end_effector_singularity(leg, offset, phi, shared_survey):
    """§2.3, Fig. 3: AᵢBᵢ ⊥ BᵢCᵢ, i.e. mᵢ = 0 and det B = 0 (eq. 4b) ↔ end_effector. With nᵢ the unit
    normal of rail i away from O (the rail is nᵢᵀx = R/2), P = w αᵢ − s nᵢ puts Cᵢ at distance l from
    the rail on O's side (nᵢᵀcᵢ = R/2 − l) when s = l − R/2 + r nᵢᵀuᵢ(φ). Nearby (P moved 1 towards
    the rail), both branches of leg i are regular."""
    index = leg - 1
    rail = math.radians([0.0, 120.0, 240.0][index])
    along = np.array([math.cos(rail), math.sin(rail)])
    normal = np.array([math.cos(rail - math.pi / 2), math.sin(rail - math.pi / 2)])
    vertex_angle = math.radians([210.0, 330.0, 90.0][index])
    pivot_direction = np.array([math.cos(vertex_angle + phi), math.sin(vertex_angle + phi)])
    depth = LEG - BASE / 2 + RADIUS * normal @ pivot_direction
    x, y = offset * along - depth * normal
    mechanism = three_prr(x=x, y=y, phi=phi)
    b, c, _, alpha = geometry(mechanism)
    assert abs((c - b)[index] @ alpha[index]) < 1e-9 * LEG                         # AᵢBᵢ ⊥ BᵢCᵢ
    a_bar, b_matrix = paper_matrices(mechanism)
    assert relative_smallest_singular_value(a_bar) > 1e-2
    report = classified(mechanism, shared_survey)
    assert report.kinds == ("end_effector",)
    assert report.end_effector.rank == 2 and report.actuator.rank == 3
    x, y = np.array([x, y]) + normal                                                 # 1 mm towards O
    for mode in (1, {1: 2, 2: 3, 3: 4}[leg]):
        assert classified(three_prr(x=x, y=y, phi=phi, working_mode=mode), shared_survey).kinds == ()


def test_fig3_serial_singularity_bounds_the_workspace():
    """§2.3: serial singularities bound the Cartesian workspace: a little further, leg 1 cannot reach."""
    with pytest.raises(MechanismError, match="C1"):
        three_prr(y=200.5)


@pytest.mark.parametrize("mode", sorted(WORKING_MODES))
def test_every_working_mode_builds_with_its_signs_and_is_regular(mode, shared_survey):
    """§3.5, Fig. 5: the eight working modes are the sign patterns of mᵢ (eq. 4b); at a generic pose
    each builds, has that pattern, and (det A, det B ≠ 0 there) is regular."""
    mechanism = three_prr(x=15.0, y=-10.0, phi=ISOTROPIC_PHI + 0.25, working_mode=mode)
    a_bar, b_matrix = paper_matrices(mechanism)
    assert tuple(np.sign(np.diag(b_matrix)).astype(int)) == WORKING_MODES[mode]
    assert relative_smallest_singular_value(a_bar) > 1e-2
    assert classified(mechanism, shared_survey).kinds == ()


def test_classifier_agrees_with_the_papers_matrices_on_random_poses(shared_survey):
    """Eqs. (3)-(4): on seeded random reachable poses (all modes), the classifier's ranks of G and J
    equal the ranks of A and B (all full here: the poses are at least 1e-2 from singular)."""
    rng = np.random.default_rng(7)
    checked = 0
    while checked < 8:
        x, y = rng.uniform(-120.0, 120.0, size=2)
        phi = rng.uniform(-math.pi, math.pi)
        mode = int(rng.integers(1, 9))
        try:
            mechanism = three_prr(x=float(x), y=float(y), phi=float(phi), working_mode=mode)
        except MechanismError:
            continue
        a_bar, b_matrix = paper_matrices(mechanism)
        assert relative_smallest_singular_value(a_bar) > 1e-2
        assert relative_smallest_singular_value(b_matrix) > 1e-2
        report = classified(mechanism, shared_survey)
        assert report.kinds == ()
        assert report.actuator.rank == np.linalg.matrix_rank(a_bar) == 3
        assert report.end_effector.rank == np.linalg.matrix_rank(b_matrix) == 3
        checked += 1


def loop_closure_rank(mechanism):
    """Rank of the loop-closure Jacobian by hand: leg i's planar twists (ω; v) at O are (0; αᵢ) for the
    rail and (1; −E q) for a revolute at q; closure is t₁ = t₂ = t₃, a 6 × 9 matrix."""
    b, c, _, alpha = geometry(mechanism)
    legs = [np.column_stack([np.r_[0.0, alpha[i]], np.r_[1.0, -E @ b[i]], np.r_[1.0, -E @ c[i]]])
            for i in range(3)]
    zero = np.zeros((3, 3))
    closure = np.block([[legs[0], -legs[1], zero], [legs[0], zero, -legs[2]]])
    values = np.linalg.svd(closure, compute_uv=False)
    return int(np.sum(values > 1e-9 * values[0]))


def test_legs_through_the_centre_and_square_to_the_rails_is_a_cspace_singularity(shared_survey):
    """Eqs. (3)-(4) where both matrices are singular (not stated in the paper): P = O, φ = π/3 + π, every
    Bᵢ at its rail's midpoint and every leg through P (det A = 0) and square to its rail (det B = 0).
    Then each leg's twists span only 2 dimensions and the three spans share the rotation about P, so
    the loop closure loses rank (6 -> 5, computed by hand): a C-space singularity, the Park-Kim side
    of G-A type III (docs/design.rst), where the eight working modes meet (tangent cone spanning 4 > 3)."""
    mechanism = three_prr(phi=ISOTROPIC_PHI + math.pi)
    a_bar, b_matrix = paper_matrices(mechanism)
    assert relative_smallest_singular_value(a_bar) < 1e-12
    assert np.allclose(np.diag(b_matrix), 0.0, atol=1e-9)
    assert loop_closure_rank(mechanism) == 5
    assert loop_closure_rank(three_prr(phi=ISOTROPIC_PHI + math.pi + 0.01)) == 6
    report = classified(mechanism, shared_survey)
    assert report.kinds == ("cspace", "end_effector")
    assert report.cspace.rank == 5 and report.cspace.expected_rank == 6
    assert report.to_dict()["cspace"]["tangent_cone_span"] == 4


def test_classification_without_a_shared_survey_matches():
    """The shared survey is only a speed-up: the full classification gives the same verdicts."""
    for name, expected in (("fig4a_isotropic", ()), ("fig2_concurrent_at_centre", ("actuator",)),
                           ("fig3_serial_leg1", ("end_effector",))):
        assert classified(ENTRIES[0].mechanism(name)).kinds == expected


@pytest.mark.parametrize("entry, name", [(entry, name) for entry in ENTRIES for name in entry.configurations])
def test_every_named_configuration_builds_and_closes(entry, name):
    """Each preset assembles: legs of length l, pivots on the platform circle, sliders on their rails."""
    mechanism = entry.mechanism(name)
    b, c, p, alpha = geometry(mechanism)
    vertices = BASE * np.array([[math.cos(t), math.sin(t)] for t in np.radians([210.0, 330.0, 90.0])])
    assert np.allclose(np.linalg.norm(c - b, axis=1), LEG)
    assert np.allclose(np.linalg.norm(c - p, axis=1), RADIUS)
    assert np.allclose(cross(b - vertices, alpha), 0.0, atol=1e-9)


@pytest.mark.parametrize("name, expected", [("fig4a_isotropic", ()), ("fig2_concurrent_at_centre", ("actuator",)),
                                            ("fig2_parallel_legs", ("actuator",)),
                                            ("fig3_serial_leg1", ("end_effector",))])
def test_named_configurations_have_the_papers_kinds(name, expected, shared_survey):
    """The presets of ``3-prr``: Fig. 4a regular, Fig. 2 parallel (actuator), Fig. 3 serial (end_effector)."""
    assert classified(ENTRIES[0].mechanism(name), shared_survey).kinds == expected


def test_assembly_from_the_inputs_recovers_the_pose():
    """ρᵢ read from a pose-built mechanism reassemble, from a nearby guess, at the same pose."""
    pose = dict(x=20.0, y=-15.0, phi=0.9)
    built = three_prr(working_mode=3, **pose)
    b, _, _, alpha = geometry(built)
    vertices = BASE * np.array([[math.cos(t), math.sin(t)] for t in np.radians([210.0, 330.0, 90.0])])
    rho = np.einsum("ij,ij->i", b - vertices, alpha)
    rebuilt = three_prr_at_inputs(rho1=rho[0], rho2=rho[1], rho3=rho[2], x=25.0, y=-10.0, phi=0.8)
    for first, second in zip(built.joints, rebuilt.joints):
        assert first.name == second.name
        assert np.allclose(first.point if first.point is not None else first.axis,
                           second.point if second.point is not None else second.axis)


@pytest.mark.parametrize("parameters, named", [
    ({"working_mode": 9}, "working_mode"), ({"leg_length": -1.0}, "leg_length"),
    ({"x": 400.0}, "x, y, phi"),
])
def test_bad_parameters_raise_naming_them(parameters, named):
    with pytest.raises(MechanismError, match=named):
        three_prr(**parameters)


def test_unreachable_inputs_raise():
    with pytest.raises(MechanismError, match="rho1"):
        three_prr_at_inputs(rho1=900.0)
