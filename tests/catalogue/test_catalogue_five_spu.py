"""Line-plane 5-SPU: Borràs, Thomas & Torras (2011), Sections II, III-C, V.

Parallel singularities (Gosselin–Angeles type II) are Park–Kim actuator singularities. The
paper's singular set is the zero set of (17) for any design, and of the two pose factors of (33),
w = 0 and δ w pₓ − (δ u − 1) p_z = 0, for the quadratically solvable designs zᵢ = δ xᵢ (26).
The tool's free spin about the platform line is an idle freedom (dof 6, G of rank 5 on M) once the
end-effector is the tool itself (``output: tool``, the entry's default: the point p and the
direction i of Λ), or is removed by blocking leg 1's aligned revolute (dof 5). With the platform
*pose* as end-effector the spin moves it: an architecture singularity.

Random poses share one survey (the largest ranks of G and J on M) per design: the survey depends
on the design, not on the pose at which the mechanism is assembled, and it is the costly part of
a classification (≈ 4 s against ≈ 0.2 s).
"""

import numpy as np
import pytest

from builders import shared_mechanism
from classify import classify, model_of, survey
from mechanisms import Mechanism, MechanismError, home
from mechanisms.catalogue.five_spu import ENTRIES, cofactors, five_spu, singularity_polynomial

ENTRY = ENTRIES[0]
DELTA = 0.5  # the default design's δ (eq. 26)
LEGS = range(1, 6)

# ----------------------------------------------------------------------------- helpers


def classified(mechanism, shared=None):
    """Classification at the home (the requested pose), seeded; without `shared`, with the survey that the
    tests classifying the same mechanism share (:func:`builders.shared_mechanism`)."""
    mechanism = shared_mechanism(mechanism)
    return classify(mechanism, home(mechanism), survey=shared, rng=np.random.default_rng(0))


def unit(vector):
    vector = np.asarray(vector, dtype=float)
    return vector / np.linalg.norm(vector)


def design_of(parameters):
    """(x, y, z) arrays of the attachments in a parameter set."""
    return tuple(np.array([parameters[f"{name}{leg}"] for leg in LEGS]) for name in "xyz")


def pose(p, direction):
    u, v, w = unit(direction)
    return {"p_x": float(p[0]), "p_y": float(p[1]), "p_z": float(p[2]), "u": float(u), "v": float(v), "w": float(w)}


def second_factor(parameters, delta=DELTA):
    """δ w pₓ − (δ u − 1) p_z, the second pose factor of (33), with i normalised."""
    u, _, w = unit([parameters["u"], parameters["v"], parameters["w"]])
    return delta * w * parameters["p_x"] - (delta * u - 1.0) * parameters["p_z"]


def leg_lines(parameters):
    """Plücker coordinates (d, a × d) of the five legs: an independent model of the parallel singularity."""
    x, y, z = design_of(parameters)
    p = np.array([parameters["p_x"], parameters["p_y"], parameters["p_z"]])
    direction = unit([parameters["u"], parameters["v"], parameters["w"]])
    lines = []
    for a, along in zip(np.stack([x, y, np.zeros(5)], axis=1), z):
        d = unit(p + along * direction - a)
        lines.append(np.concatenate([d, np.cross(a, d)]))
    return np.array(lines)


def random_direction(rng, smallest_w=0.4):
    while True:
        direction = unit(rng.normal(size=3))
        if abs(direction[2]) >= smallest_w:
            return direction


def random_position(rng):
    return np.array([rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(1.5, 3.5)])


# ----------------------------------------------------------------------------- designs and poses

#: quadratically solvable designs with δ = 1/2 (eq. 26); "rearranged" moves every base attachment
#: along its B-line x = zᵢ/δ (Section III-B rule 1; Section V-B: the same singularity locus)
QUADRATIC_DESIGNS = {
    "default": {},
    "rearranged": {"y2": -1.0, "y3": 0.5, "y4": 2.0, "y5": 1.5},
}


def quadratic_cases():
    """Seeded random poses, some put exactly on each factor of (33) and some just off it."""
    rng = np.random.default_rng(2011)
    cases = {}
    for index in range(3):
        p, direction = random_position(rng), random_direction(rng)
        base = pose(p, direction)
        cases[f"random{index}"] = base
        on_factor = dict(base, p_x=(DELTA * base["u"] - 1.0) * base["p_z"] / (DELTA * base["w"]))
        cases[f"second_factor{index}"] = on_factor
        cases[f"near_second_factor{index}"] = dict(on_factor, p_x=on_factor["p_x"] + 0.1)
        horizontal = pose(p, (direction[0], direction[1], 0.0))
        cases[f"w_zero{index}"] = horizontal
        cases[f"near_w_zero{index}"] = pose(p, (direction[0], direction[1], 0.05))
    return cases


QUADRATIC_CASES = quadratic_cases()


def quartic_design():
    """A seeded generic design (B finite: the quartic family, Section IV)."""
    rng = np.random.default_rng(1991)
    x, y, z = rng.uniform(-2, 2, size=(3, 5))
    return {f"{name}{leg}": float(value) for name, values in zip("xyz", (x, y, z))
            for leg, value in zip(LEGS, values)}


QUARTIC_DESIGN = quartic_design()


def quartic_cases():
    """Seeded random poses, some put on the zero set of (17) by solving it (affine) for pₓ."""
    rng = np.random.default_rng(1995)
    c1, c2, c3, c4, c5, c6 = cofactors(*design_of(QUARTIC_DESIGN))
    cases = {}
    for index in range(3):
        base = pose(random_position(rng), random_direction(rng))
        cases[f"random{index}"] = base
        at_zero = singularity_polynomial(**QUARTIC_DESIGN, **dict(base, p_x=0.0))
        at_one = singularity_polynomial(**QUARTIC_DESIGN, **dict(base, p_x=1.0))
        on_zero_set = dict(base, p_x=-at_zero / (at_one - at_zero))
        cases[f"eq17_{index}"] = on_zero_set
        cases[f"near_eq17_{index}"] = dict(on_zero_set, p_x=on_zero_set["p_x"] + 0.1)
    p = random_position(rng)
    cases["w_zero_parallel_to_B_infinity"] = pose(p, (c5, -c4, 0.0))  # eq. (20)
    cases["w_zero_other_direction"] = pose(p, (c4, c5, 0.0))
    return cases


QUARTIC_CASES = quartic_cases()


@pytest.fixture(scope="module")
def surveys():
    """One survey per design (largest ranks of DΦ, G, J on M), computed at the design's default pose, with
    the tool's spin locked (Section I): with it free, a pose end-effector makes the design
    architecturally singular (test_named_configurations)."""
    cache = {}

    def of(design_name):
        if design_name not in cache:
            design = QUARTIC_DESIGN if design_name == "quartic" else QUADRATIC_DESIGNS[design_name]
            start = five_spu(**design, **pose((1.0, 0.5, 3.0), (0.3, -0.2, 1.0)), spin="locked")
            cache[design_name] = survey(model_of(start), np.random.default_rng(0))
        return cache[design_name]

    return of


# ----------------------------------------------------------------------------- the entry

@pytest.mark.parametrize("name", sorted(ENTRY.configurations))
def test_every_named_configuration_builds(name):
    """Every preset of the ``5-spu`` entry assembles: 5 actuated legs, S centres at aᵢ = (xᵢ, yᵢ, 0),
    U (or R) centres at bᵢ = p + zᵢ i on the platform line (Borràs, Thomas & Torras 2011 Section II, Fig. 2)."""
    mechanism = ENTRY.mechanism(name)
    values = ENTRY.values(name)
    assert isinstance(mechanism, Mechanism)
    assert sum(joint.actuated for joint in mechanism.joints) == 5
    x, y, z = design_of(values)
    p = np.array([values["p_x"], values["p_y"], values["p_z"]])
    direction = unit([values["u"], values["v"], values["w"]])
    for leg in LEGS:
        spherical = mechanism.joint(f"S{leg}")
        assert np.allclose(spherical.point, (x[leg - 1], y[leg - 1], 0.0))
        top = mechanism.joint(f"R{leg}" if values["spin"] == "locked" and leg == 1 else f"U{leg}")
        assert np.allclose(top.point, p + z[leg - 1] * direction)
        leg_axis = np.asarray(mechanism.joint(f"P{leg}").axis)
        assert np.allclose(np.cross(leg_axis, np.asarray(top.point) - spherical.point), 0.0)


def test_default_design_is_quadratically_solvable():
    """Eq. (27): for zᵢ = δ xᵢ, x₁ = y₁ = 0 the cofactors are (δ²F, −δ³F, 0, 0, 0, 0), F from (28)."""
    x, y, z = design_of(ENTRY.values())
    assert np.allclose(z, DELTA * x) and x[0] == y[0] == 0.0
    determinant = np.linalg.det(np.stack([x[1:] ** 2, x[1:] * y[1:], x[1:], y[1:]], axis=1))
    assert abs(determinant) > 1.0  # F ≠ 0: not architecturally singular
    assert np.allclose(cofactors(x, y, z), [DELTA ** 2 * determinant, -DELTA ** 3 * determinant, 0, 0, 0, 0],
                       atol=1e-9 * abs(determinant))


NAMED = {
    # name: (the paper's kinds, actuator rank, degeneracy), with the spin locked or free (an idle freedom)
    "regular": ((), 5, None),
    "regular_locked": ((), 5, None),
    "eq33_w_zero": (("actuator",), 4, "nondegenerate"),
    "eq33_second_factor": (("actuator",), 4, "nondegenerate"),
    "eq35_vertical_tool": (("actuator",), 4, "nondegenerate"),
    "sec3c_line_in_base": (("actuator",), 3, "nondegenerate"),
    "eq33_w_zero_locked": (("actuator",), 4, "nondegenerate"),
    "eq33_second_factor_locked": (("actuator",), 4, "nondegenerate"),
}


@pytest.mark.parametrize("name", sorted(NAMED))
def test_named_configurations(name):
    """Borràs, Thomas & Torras 2011 eq. (33) (w = 0; δ w pₓ − (δu − 1) p_z = 0), eq. (35) (tool ⟂ base:
    δ pₓ + p_z = 0), Section III-C (Λ on Π: the trivial singularity, two leg wrenches lost). Both factors
    are folds where two assembly modes of (29)/(31)-(32) merge (Δ = 0, Section V-B), i.e.
    nondegenerate — with the spin locked (Section I: one aligned revolute blocked, m = 5) and with it
    free (m = 6, Fig. 1): the end-effector is the axisymmetric tool (``output: tool``), which the spin
    does not move, so the spin is an idle freedom (docs/design.rst, "The three kinds"), no architecture
    singularity, and the second-order test runs transverse to it."""
    kinds, rank, degeneracy = NAMED[name]
    values = ENTRY.values(name)
    assert values["end_effector"] == "tool"
    assert (abs(singularity_polynomial(**values)) < 1e-9) == bool(kinds)  # the preset is where the paper says
    report = classified(ENTRY.mechanism(name))
    assert report.actuator.rank == rank
    assert report.survey["actuator_rank"] == 5
    assert report.end_effector.rank == report.end_effector.expected_rank == 5  # dim N = 5: p and i
    assert report.kinds == kinds
    assert report.degeneracy == degeneracy
    assert not report.architecture_singular and report.moving_idle_freedoms == 0
    assert report.to_dict()["architecture_singular"] is False
    if values["spin"] == "locked":
        assert report.dof == 5 and report.idle_freedoms == 0
    else:
        assert report.dof == 6 and report.idle_freedoms == 1
        assert report.actuator.expected_rank == 5
        assert not any("architecture singularity" in note for note in report.notes)


@pytest.mark.parametrize("factor", ["eq33_w_zero", "eq33_second_factor"])
def test_with_a_pose_end_effector_the_free_spin_is_an_architecture_singularity(factor):
    """With the platform *pose* as end-effector (``end_effector="pose"``), the free spin is a locked-actuator
    freedom that moves the end-effector everywhere on M: not idle but an architecture singularity, every
    configuration a degenerate actuator singularity, whose certificate is a motion of the tool about its own
    line (the legs, i.e. the actuators, locked). The tool output and locking the spin both give the paper's
    verdict."""
    pose_output = classified(ENTRY.mechanism(factor, end_effector="pose"))
    assert pose_output.dof == 6 and pose_output.idle_freedoms == 0
    assert pose_output.architecture_singular and pose_output.moving_idle_freedoms == 1
    assert pose_output.kinds == ("actuator",) and pose_output.degeneracy == "degenerate"
    assert pose_output.to_dict()["architecture_singular"] is True
    assert "architecture singularity" in pose_output.to_text()
    motion = pose_output.second_order.self_motion
    assert motion.distance >= 0.1 and motion.largest_residual < 1e-9
    tool = classified(ENTRY.mechanism(factor))
    locked = classified(ENTRY.mechanism(factor + "_locked"))
    assert tool.degeneracy == locked.degeneracy == "nondegenerate"


# ----------------------------------------------------------------------------- the paper's polynomials

@pytest.mark.parametrize("case", sorted(QUADRATIC_CASES))
def test_eq33_factors_are_eq17_and_the_dependence_of_the_leg_lines(case):
    """Borràs, Thomas & Torras 2011 (17) with the cofactors (27) is −δ²F · w · [δ w pₓ − (δu − 1) p_z] (33), and it
    vanishes exactly when the five leg lines are linearly dependent (independent Plücker model)."""
    values = dict(ENTRY.values(), **QUADRATIC_CASES[case])
    c1 = cofactors(*design_of(values))[0]
    assert singularity_polynomial(**values) == pytest.approx(-c1 * values["w"] * second_factor(values),
                                                             abs=1e-9 * abs(c1))
    smallest = np.linalg.svd(leg_lines(values), compute_uv=False)[-1]
    on_factors = values["w"] == 0.0 or abs(second_factor(values)) < 1e-9
    assert (smallest < 1e-9) == on_factors


# ----------------------------------------------------------------------------- the classifier on random poses

@pytest.mark.parametrize("design", sorted(QUADRATIC_DESIGNS))
@pytest.mark.parametrize("case", sorted(QUADRATIC_CASES))
def test_actuator_singularities_are_the_eq33_factors(design, case, surveys):
    """Borràs, Thomas & Torras 2011 eq. (33), Section V-B: on a quadratically solvable design (zᵢ = δ xᵢ, eq. 26) the
    parallel singularities are w = 0 and δ w pₓ − (δu − 1) p_z = 0, whatever the attachments
    (the "rearranged" design moves the base attachments along their B-lines, Section III-B).
    Seeded random poses, poses put on each factor, and poses 0.1 off it: the classifier reports an
    actuator singularity (and nothing else) exactly on the factors' zero sets."""
    values = dict(ENTRY.values(), **QUADRATIC_DESIGNS[design], **QUADRATIC_CASES[case], spin="locked")
    on_factors = values["w"] == 0.0 or abs(second_factor(values)) < 1e-9 * (1 + abs(values["p_x"]))
    assert on_factors == (case.startswith("w_zero") or case.startswith("second_factor"))
    report = classified(five_spu(**values), surveys(design))
    assert report.kinds == (("actuator",) if on_factors else ())
    assert report.actuator.rank == (4 if on_factors else 5)
    assert report.dof == 5 and report.idle_freedoms == 0 and not report.architecture_singular


@pytest.mark.parametrize("case", sorted(QUARTIC_CASES))
def test_actuator_singularities_of_a_quartic_design_are_the_zeros_of_eq17(case, surveys):
    """Borràs, Thomas & Torras 2011 eq. (17) for a generic (quartic, B finite) design: seeded random poses, poses put on
    the zero set of (17) by solving it for pₓ, poses 0.1 off it; and with w = 0, eq. (20): singular
    only when Λ is parallel to B∞, i.e. i ∝ (C₅, −C₄, 0) — unlike the quadratic family, where
    every w = 0 is singular."""
    values = dict(ENTRY.values(), **QUARTIC_DESIGN, **QUARTIC_CASES[case], spin="locked")
    scale = np.linalg.norm(cofactors(*design_of(values))) * (1 + np.linalg.norm(
        [values["p_x"], values["p_y"], values["p_z"]])) ** 2
    on_zero_set = abs(singularity_polynomial(**values)) < 1e-9 * scale
    assert on_zero_set == (case.startswith("eq17") or case == "w_zero_parallel_to_B_infinity")
    report = classified(five_spu(**values), surveys("quartic"))
    assert report.kinds == (("actuator",) if on_zero_set else ())
    assert report.actuator.rank == (4 if on_zero_set else 5)


# ----------------------------------------------------------------------------- errors

@pytest.mark.parametrize("parameters, named", [
    ({"u": 0.0, "v": 0.0, "w": 0.0}, "u, v, w"),
    ({"p_x": 0.0, "p_y": 0.0, "p_z": 0.0}, "leg 1 has zero length"),
    ({"p_x": 2.0, "p_y": 0.0, "p_z": 0.0, "u": 1.0, "v": 0.0, "w": 0.0}, "leg 1 lies along the platform line"),
    ({"spin": "blocked"}, "spin"),
    ({"end_effector": "gripper"}, "end_effector"),
])
def test_unassemblable_parameters_are_refused_by_name(parameters, named):
    with pytest.raises(MechanismError, match=named):
        five_spu(**parameters)
