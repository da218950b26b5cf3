"""Watt six-bar: Gosselin & Angeles (1990) Fig. 5, eqs. (18)-(41).

Each singular configuration the paper states is checked twice: against the paper's own
closed-form factors N₁, N₂, D₁, D₂ (eqs. 33-36, evaluated independently of the classifier) and
by the Park–Kim classifier, with a nearby configuration that must be regular.
"""

import functools
import math

import numpy as np
import pytest

from checks import classified
from mechanisms import MechanismError
from mechanisms.catalogue.watt import ENTRIES, watt_positions, watt_six_bar

(ENTRY,) = ENTRIES
SQRT3 = math.sqrt(3.0)

#: The kinds each named configuration must have (the tests below say why).
EXPECTED_KINDS = {
    "eq37_n1_crank_and_coupler_aligned": ("end_effector",),
    "eq37_n2_coupler_aligned_with_rocker": ("end_effector",),
    "eq39_d1_coupler_aligned_with_rocker": ("actuator",),
    "eq40_d2_output_and_coupler_aligned": ("actuator",),
    "eq41_joints_2_4_superimposed": ("actuator",),
    "eq41_joints_2_4_branch_crossing": ("cspace",),
    "eq41_joints_1_3_superimposed": ("end_effector",),
    "eq41_joints_4_6_constant_branch": ("end_effector",),
    "eq41_joints_4_6_branch_crossing": ("cspace",),
}
#: Factor of eq. (32) each kind-I/II configuration zeroes.
FACTOR = {
    "eq37_n1_crank_and_coupler_aligned": "N1",
    "eq37_n2_coupler_aligned_with_rocker": "N2",
    "eq39_d1_coupler_aligned_with_rocker": "D1",
    "eq40_d2_output_and_coupler_aligned": "D2",
}


@functools.lru_cache(maxsize=None)
def report(name):
    """The classification of a named configuration (shared by the tests)."""
    return classified(ENTRY.mechanism(name))


def paper_factors(values):
    """N₁, N₂, D₁, D₂ of G-A eqs. (33)-(36), written as printed, at a configuration.

    ψ is read from our assembly; the second loop is evaluated in the paper's frame of eqs.
    (18)-(23) (x₁ = −cos(ψ + π/3), output pivot at (1/2, 0)), where the paper's φ is π − φ
    (module docstring). Eq. (33) prints √2/2 in its second factor; we use √3/2, the value
    eq. (27) has in the same place.
    """
    l1, l2, l3, l4, theta = (values[key] for key in ("l1", "l2", "l3", "l4", "theta"))
    points = watt_positions(**{key: values[key] for key in
                               ("l1", "l2", "l3", "l4", "theta", "branch_rocker", "branch_output", "psi")})
    psi, phi = points["psi"], math.pi - points["phi"]
    beta = math.atan2(l1 * math.sin(theta) - SQRT3 / 2, l1 * math.cos(theta) + 0.5)  # eq. (22)
    x1, y1 = -math.cos(psi + math.pi / 3), SQRT3 / 2 + math.sin(psi + math.pi / 3)  # eqs. (18)-(19)
    x1p = x1 - 0.5  # eq. (21)
    alpha = math.atan2(y1, x1p)  # eq. (20)
    rho2 = x1p ** 2 + y1 ** 2
    crank2 = 1 - SQRT3 * l1 * math.sin(theta) + l1 * math.cos(theta) + l1 ** 2
    n1 = ((l1 * math.cos(theta) - SQRT3 * l1 * math.sin(theta) + l1 ** 2 + l2 ** 2)
          * (0.5 * l1 * math.sin(theta) + SQRT3 / 2 * l1 * math.cos(theta))
          + 2 * math.sin(psi - beta) * (l1 ** 2 + 0.5 * l1 * math.cos(theta) - SQRT3 / 2 * l1 * math.sin(theta))
          * math.sqrt(crank2))
    n2 = (math.sin(psi) * (rho2 + l4 ** 2 - l3 ** 2)
          + 2 * l3 * math.sin(alpha - phi) * (1 + math.cos(psi)) * math.sqrt(rho2))
    d1 = 2 * math.sin(psi - beta) * crank2 ** 1.5
    d2 = 2 * l3 * math.sin(alpha - phi) * rho2 ** 1.5
    return {"N1": n1, "N2": n2, "D1": d1, "D2": d2}


def output_angle(values, theta):
    """φ(θ) on the branches of `values` (closed form, eqs. 22-24 and 18-23)."""
    return watt_positions(**{**{key: values[key] for key in
                                ("l1", "l2", "l3", "l4", "branch_rocker", "branch_output", "psi")},
                             "theta": theta})["phi"]


# --------------------------------------------------------------------------- the catalogue entry

@pytest.mark.parametrize("name", EXPECTED_KINDS)
def test_named_configurations_have_the_kinds_the_tests_below_establish(name):
    assert report(name).kinds == EXPECTED_KINDS[name]
    assert report(name).dof == 1


def test_every_named_configuration_is_checked_and_builds():
    assert set(ENTRY.configurations) == set(EXPECTED_KINDS)
    for name in ENTRY.configurations:
        assert len(ENTRY.mechanism(name).joints) == 7


def test_default_configuration_is_regular():
    """The default design at θ = 0.7: no factor of eq. (32) vanishes and nothing is singular."""
    factors = paper_factors(ENTRY.values())
    assert min(abs(value) for value in factors.values()) > 0.1
    assert classified(watt_six_bar()).kinds == ()


def test_unreachable_input_names_the_parameter():
    with pytest.raises(MechanismError, match="theta"):
        watt_six_bar(theta=1.9)


# --------------------------------------------------------------------------- kinds I and II

@pytest.mark.parametrize("name", sorted(FACTOR))
def test_the_papers_factor_vanishes_at_the_named_configuration(name):
    """G-A eqs. (33)-(36), as printed: the named factor vanishes there and the other three
    do not (an independent check of our reading of Fig. 5 and of the configuration).

    The factors are of order 1-10 here, the named one zero to rounding: at D₁ = 0 and D₂ = 0 the
    input θ is at a fold, where the assembly's triangle is flat; its angle is taken as exactly 0
    or π there (through the double root of the arccosine it was exact only to about √ε ≈ 1e-8)."""
    factors = paper_factors(ENTRY.values(name))
    zero = FACTOR[name]
    assert abs(factors[zero]) < 1e-12
    assert min(abs(value) for key, value in factors.items() if key != zero) > 0.05


@pytest.mark.parametrize("name", ["eq37_n1_crank_and_coupler_aligned", "eq37_n2_coupler_aligned_with_rocker"])
def test_kind_one_is_an_end_effector_singularity(name):
    """G-A eq. (37): B = N₁N₂ = 0, l₁ and l₂ aligned (N₁) or l₄ aligned with joints 4-5 (N₂):
    "the velocity of the output is always zero, regardless of the input velocity". The closed
    form φ(θ) is stationary there (central difference), and the classifier finds the
    end-effector (the angle of l₃) singular, the actuator not."""
    values = ENTRY.values(name)
    step = 1e-6
    theta = values["theta"]
    slope = (output_angle(values, theta + step) - output_angle(values, theta - step)) / (2 * step)
    assert abs(slope) < 1e-5
    result = report(name)
    assert result.kinds == ("end_effector",)
    assert (result.end_effector.rank, result.end_effector.expected_rank) == (0, 1)


@pytest.mark.parametrize("name", ["eq39_d1_coupler_aligned_with_rocker", "eq40_d2_output_and_coupler_aligned"])
def test_kind_two_is_a_nondegenerate_actuator_singularity(name):
    """G-A eqs. (38)-(40), Fig. 6: A = D₁D₂ = 0, l₂ aligned with joints 3-4 (D₁) or l₃ and l₄
    aligned (D₂): "the output link can undergo an infinitesimal motion even if the input is
    locked" — infinitesimal only: the two branches of the direct kinematics meet, and the
    input cannot go further (θ a hair beyond does not assemble)."""
    values = ENTRY.values(name)
    beyond = [values["theta"] + step for step in (1e-4, -1e-4)]
    failures = 0
    for theta in beyond:
        try:
            output_angle(values, theta)
        except MechanismError:
            failures += 1
    assert failures == 1  # a fold of θ: the input is at a dead point
    result = report(name)
    assert result.kinds == ("actuator",)
    assert result.degeneracy == "nondegenerate"


@pytest.mark.parametrize("name, step", [
    ("eq37_n1_crank_and_coupler_aligned", 0.02),
    ("eq37_n1_crank_and_coupler_aligned", -0.02),
    ("eq37_n2_coupler_aligned_with_rocker", 0.02),
    ("eq39_d1_coupler_aligned_with_rocker", 0.02),
    ("eq40_d2_output_and_coupler_aligned", -0.02),
])
def test_near_kinds_one_and_two_is_regular(name, step):
    """The same design and branches with θ moved by `step` (into the assembled side)."""
    values = ENTRY.values(name)
    nearby = {**values, "theta": values["theta"] + step}
    assert min(abs(value) for value in paper_factors(nearby).values()) > 1e-3
    assert classified(watt_six_bar(**nearby)).kinds == ()


# --------------------------------------------------------------------------- kind III, eq. (41)

def test_eq41_equal_crank_and_coupler_is_a_degenerate_actuator_singularity():
    """G-A eq. (41), l₁ = l₂ = 1: joints 2 and 4 superimposed, "the output can then undergo
    finite motions while the input is at rest". Independently: the assembly closes at θ = 2π/3
    for two different ψ (a finite motion with θ locked); the classifier finds a degenerate
    actuator singularity whose self-motion turns the coupler and rocker about joints 2 = 4,
    not the crank."""
    values = ENTRY.values("eq41_joints_2_4_superimposed")
    phis = [watt_positions(**{**{key: values[key] for key in ("l1", "l2", "l3", "l4", "theta", "branch_output")},
                              "branch_rocker": 0, "psi": psi})["phi"] for psi in (1.0, 1.3)]
    assert abs(phis[1] - phis[0]) > 0.05  # the output moves, the input does not
    result = report("eq41_joints_2_4_superimposed")
    assert result.kinds == ("actuator",)
    assert result.degeneracy == "degenerate"
    motion = result.to_dict()["actuator"]["second_order"]["self_motion"]
    assert motion["distance"] >= 0.1 and motion["largest_residual"] < 1e-9
    assert "joint1" not in motion["direction"] and {"joint2", "joint4"} <= set(motion["direction"])


def test_eq41_equal_crank_and_coupler_branch_crossing_is_a_cspace_singularity():
    """Where the folded branch (θ = 2π/3, ψ free) crosses the parallelogram branch ψ = θ, the
    crank and coupler are also aligned: N₁ = 0 with D₁ = 0 (joints 1, 2 = 4 and 3 on a line),
    both A and B vanish — G-A's kind III. Park–Kim: a C-space singularity (two branches)."""
    points = watt_positions(l1=1.0, l2=1.0, l3=0.8, l4=1.5, theta=2 * math.pi / 3, branch_rocker=0,
                            psi=2 * math.pi / 3)
    assert np.allclose(points["joint2"], points["joint4"])
    assert np.allclose(points["joint3"], 2 * np.asarray(points["joint4"]))  # 1, 4, 3 aligned
    result = report("eq41_joints_2_4_branch_crossing")
    assert result.kinds == ("cspace",)
    assert (result.cspace.rank, result.cspace.expected_rank) == (5, 6)
    assert result.to_dict()["cspace"]["tangent_cone_span"] == 2


def test_eq41_equal_crank_and_coupler_has_a_constant_branch_too():
    """Not stated in the paper: the design l₁ = l₂ = 1 of eq. (41) can also put joint 3 on
    joint 1 (ψ = −π/3), a branch on which the crank turns with the rocker, hence the output, at
    rest (ψ = −π/3 for two different θ) — kind I all along; Park–Kim: end-effector rank 0."""
    values = ENTRY.values("eq41_joints_1_3_superimposed")
    for theta in (values["theta"], values["theta"] + 0.5):
        points = watt_positions(**{**{key: values[key] for key in
                                      ("l1", "l2", "l3", "l4", "branch_rocker", "branch_output")},
                                   "theta": theta})
        assert points["psi"] == pytest.approx(-math.pi / 3, abs=1e-12)
        assert np.allclose(points["joint3"], points["joint1"])
    result = report("eq41_joints_1_3_superimposed")
    assert result.kinds == ("end_effector",)
    assert (result.end_effector.rank, result.end_effector.expected_rank) == (0, 1)


def test_eq41_equal_output_and_coupler_has_a_constant_branch():
    """G-A eq. (41), l₃ = l₄ = 1: joints 4 and 6 superimposed, "the linkage has a constant
    branch, i.e., a branch on which the output link remains at rest". Independently: φ = π/3
    (l₃ pointing at joint 4) for two different θ on that branch; the classifier finds an
    end-effector singularity (the input moves, the output does not), no actuator singularity."""
    values = ENTRY.values("eq41_joints_4_6_constant_branch")
    for theta in (values["theta"], values["theta"] + 0.5):
        assert output_angle(values, theta) == pytest.approx(math.pi / 3, abs=1e-12)
    result = report("eq41_joints_4_6_constant_branch")
    assert result.kinds == ("end_effector",)
    assert (result.end_effector.rank, result.end_effector.expected_rank) == (0, 1)


def test_eq41_equal_output_and_coupler_branch_crossing_is_a_cspace_singularity():
    """Where the constant branch crosses the parallelogram branch (ψ = 0: joints 7, 4, 5 on a
    line, l₃ and l₄ aligned), D₂ = 0 joins N₂ = 0 — G-A's kind III; Park–Kim: a C-space
    singularity."""
    values = ENTRY.values("eq41_joints_4_6_branch_crossing")
    points = watt_positions(**{key: values[key] for key in
                               ("l1", "l2", "l3", "l4", "theta", "branch_rocker", "branch_output")})
    assert points["psi"] == pytest.approx(0.0, abs=1e-12)
    assert np.allclose(points["joint6"], points["joint4"])
    result = report("eq41_joints_4_6_branch_crossing")
    assert result.kinds == ("cspace",)
    assert (result.cspace.rank, result.cspace.expected_rank) == (5, 6)


@pytest.mark.parametrize("values", [
    # l1 = l2 = 1 on the parallelogram branch ψ = θ, away from θ = 2π/3
    {"l1": 1.0, "l2": 1.0, "theta": 2 * math.pi / 3 + 0.1, "branch_rocker": -1},
    # l3 = l4 = 1 on the other output branch near the crossing ψ = 0
    {"l3": 1.0, "l4": 1.0, "theta": 2.75, "branch_rocker": 1, "branch_output": -1},
], ids=["equal_crank_and_coupler", "equal_output_and_coupler"])
def test_near_the_kind_three_designs_is_regular(values):
    """The kind-III designs are regular on their parallelogram branches (ψ = θ, resp.
    φ = π/3 + ψ), away from the special branches."""
    full = ENTRY.values(**values)
    points = watt_positions(**{key: full[key] for key in
                               ("l1", "l2", "l3", "l4", "theta", "branch_rocker", "branch_output", "psi")})
    if full["l1"] == 1.0:
        parallelogram = points["psi"] - full["theta"]
    else:
        parallelogram = points["phi"] - math.pi / 3 - points["psi"]
    assert math.remainder(parallelogram, 2 * math.pi) == pytest.approx(0.0, abs=1e-12)
    assert not np.allclose(points["joint2"], points["joint4"])
    assert not np.allclose(points["joint6"], points["joint4"], atol=1e-3)
    assert classified(watt_six_bar(**full)).kinds == ()
