"""Assembly at chosen inputs (mechanisms.assembly).

The catalogue builds the five-bar and the slider-crank *at* given inputs and
branches (Chablat, Wenger & Angeles 1998 Fig. 1, Fig. 2; Park & Kim 1999
Fig. 3; Gosselin & Angeles 1990 eqs. 6-17): a mechanism built at one input
and assembled at another must reach the configurations the catalogue builds
directly there, on every branch and working mode.
"""

import math

import numpy as np
import pytest

from builders import rsur
from mechanisms import (
    CLOSURE_TOLERANCE, Assembly, AssemblyError, ConfigurationError, EndEffector, Joint, Mechanism, assemble,
    assemblies, closes, configuration, constraint, kinematics_of, link_pose,
)
from mechanisms.catalogue import entry
from mechanisms.catalogue.five_bar import WORKING_MODES, five_bar
from mechanisms.catalogue.gough_stewart import gough_stewart
from mechanisms.catalogue.slider_crank import slider_crank


def joint_positions(mechanism, point):
    """Joint name -> position of the joint centre at `point` (joints with a point only)."""
    positions = {}
    for joint in mechanism.joints:
        if joint.point is None:
            continue
        pose = link_pose(mechanism, joint.links[1], point)
        size = pose.shape[-1] - 1
        positions[joint.name] = pose[:size, :size] @ np.asarray(joint.point) + pose[:size, size]
    return positions


def built_positions(mechanism):
    """Joint name -> the joint centre of a mechanism as the catalogue built it (its home)."""
    return {joint.name: np.asarray(joint.point) for joint in mechanism.joints if joint.point is not None}


def matches(mechanism, assembly, built, atol=1e-9):
    reached = joint_positions(mechanism, assembly.point)
    expected = built_positions(built)
    return all(np.allclose(reached[name], expected[name], atol=atol) for name in expected)


def the_match(mechanism, found, built):
    """The one assembly of `found` at the configuration the catalogue built."""
    hits = [item for item in found if matches(mechanism, item, built)]
    assert len(hits) == 1, f"{len(hits)} assemblies match the catalogue's configuration"
    return hits[0]


# ----------------------------------------------------------------------------- five-bar

#: the five_bar defaults (the design of Chablat, Wenger & Angeles 1998 Sec. 3.4)
HOME_INPUTS = {"theta1": 1.8, "theta2": 1.3}


def five_bar_values(theta1, theta2):
    """Displacements from the home inputs; B turns the ground relative to proximal_right, hence −Δθ2."""
    return {"A": theta1 - HOME_INPUTS["theta1"], "B": HOME_INPUTS["theta2"] - theta2}


@pytest.mark.parametrize("home_assembly", [1, -1])
def test_five_bar_reaches_both_assembly_modes(home_assembly):
    """Chablat, Wenger & Angeles 1998 Fig. 1: P left (+1) or right (−1) of C→D at the same inputs."""
    mechanism = five_bar(**HOME_INPUTS, assembly=home_assembly)
    values = five_bar_values(1.7, 1.4)
    found = assemblies(mechanism, values, np.random.default_rng(0))
    assert len(found) == 2
    assert [item.branch for item in found] == [0, 1]
    assert all(item.branches == 2 for item in found)
    for assembly in (1, -1):
        built = five_bar(theta1=1.7, theta2=1.4, assembly=assembly)
        the_match(mechanism, found, built)
    reached = assemble(mechanism, values)
    assert reached.method == "newton"
    assert matches(mechanism, reached, five_bar(theta1=1.7, theta2=1.4, assembly=home_assembly))


@pytest.mark.parametrize("mode", WORKING_MODES)
def test_five_bar_reaches_every_working_mode(mode):
    """Chablat, Wenger & Angeles 1998 Fig. 2: P = (3, 7) in each working mode is an assembly at its inputs."""
    name = f"fig2_working_mode_{mode.replace('+', 'p').replace('-', 'm')}"
    five = entry("five-bar")
    built = five.mechanism(name)
    inputs = five.values(name)
    mechanism = five_bar(**HOME_INPUTS)
    values = five_bar_values(inputs["theta1"], inputs["theta2"])
    found = assemblies(mechanism, values, np.random.default_rng(1))
    match = the_match(mechanism, found, built)
    assert np.allclose(joint_positions(mechanism, match.point)["P"], (3.0, 7.0), atol=1e-9)
    selected = assemble(mechanism, values, branch=match.branch, rng=np.random.default_rng(1))
    assert np.array_equal(selected.point, match.point)
    nudged = {name: np.asarray(value) + 0.05 for name, value in match.displacements.items()}
    guessed = assemble(mechanism, values, guess={k: float(v) for k, v in nudged.items()},
                       rng=np.random.default_rng(1))
    assert guessed.branch == match.branch and matches(mechanism, guessed, built)


def test_continuation_follows_the_home_branch():
    """Forced continuation moves the inputs from home and stays on the home's assembly mode."""
    mechanism = five_bar(**HOME_INPUTS, assembly=1)
    values = five_bar_values(1.6, 1.5)
    reached = assemble(mechanism, values, method="continuation")
    assert reached.method == "continuation"
    assert matches(mechanism, reached, five_bar(theta1=1.6, theta2=1.5, assembly=1))
    assert reached.displacements["A"] == values["A"] and reached.displacements["B"] == values["B"]


def test_held_values_are_exact_unlike_projection():
    """Projection moves the input it is given; assembly holds it bit for bit."""
    mechanism = five_bar(**HOME_INPUTS)
    projected = configuration(mechanism, {"A": -0.373}, project_onto=True)
    moved = projected.point[0]
    assert abs(moved - (-0.373)) > 1e-3
    reached = assemble(mechanism, {"A": -0.373, "B": 0.05})
    assert reached.displacements["A"] == -0.373 and reached.displacements["B"] == 0.05
    assert reached.held == {"A": -0.373, "B": 0.05}
    assert bool(closes(mechanism, reached.point, CLOSURE_TOLERANCE))
    assert reached.residual == pytest.approx(np.linalg.norm(constraint(mechanism, reached.point)), abs=1e-15)
    assert np.array_equal(configuration(mechanism, reached.displacements).point, reached.point)


def test_unnamed_actuators_stay_at_home():
    """hold_actuated: an input the values do not name is held at home, not solved for."""
    mechanism = five_bar(**HOME_INPUTS)
    reached = assemble(mechanism, {"A": -0.05})
    assert reached.displacements["B"] == 0.0
    assert reached.held == {"A": -0.05, "B": 0.0}
    assert matches(mechanism, reached, five_bar(theta1=1.75, theta2=1.3, assembly=1))


def test_assembly_modes_at_the_home_inputs():
    """No values: the inputs stay at home and the list holds the home and the other assembly mode."""
    mechanism = five_bar(**HOME_INPUTS, assembly=-1)
    found = assemblies(mechanism, {})
    assert len(found) == 2 and found[0].distance == 0.0 and found[0].method == "newton"
    the_match(mechanism, found, five_bar(**HOME_INPUTS, assembly=1))


def test_assemblies_that_are_not_isolated():
    """With one input of two held, the other joints still move: no branch numbers."""
    mechanism = five_bar(**HOME_INPUTS)
    reached = assemble(mechanism, {"A": 0.05}, hold_actuated=False)
    assert reached.branch is None and reached.branches is None
    assert reached.displacements["A"] == 0.05 and reached.residual <= 1e-10
    with pytest.raises(AssemblyError, match="not isolated"):
        assemblies(mechanism, {"A": 0.05}, hold_actuated=False)
    with pytest.raises(AssemblyError, match="not isolated"):
        assemble(mechanism, {"A": 0.05}, branch=0, hold_actuated=False)


def test_five_bar_out_of_reach():
    """At θ1 = 2.0, θ2 = 1.3 the elbows are 11.5 apart, more than 2 L2 = 10."""
    mechanism = five_bar(**HOME_INPUTS)
    with pytest.raises(AssemblyError, match=r"^no assembly with A = 0\.2 \(B held at home\): the loops cannot "
                                            r"close \(smallest residual [0-9.e-]+\)$"):
        assemble(mechanism, {"A": 0.2})


# ----------------------------------------------------------------------------- slider-crank

@pytest.mark.parametrize("home_branch", [1, -1])
def test_slider_crank_reaches_both_branches(home_branch):
    """Gosselin & Angeles 1990 eq. (9): x = R cos θ ± √(l² − R² sin² θ), Park & Kim 1999 Fig. 3."""
    mechanism = slider_crank(theta=0.3, branch=home_branch)
    found = assemblies(mechanism, {"crank": 0.1}, np.random.default_rng(2))
    assert len(found) == 2
    for branch in (1, -1):
        match = the_match(mechanism, found, slider_crank(theta=0.4, branch=branch))
        assert match.displacements["crank"] == 0.1
    reached = assemble(mechanism, {"crank": 0.1})
    assert matches(mechanism, reached, slider_crank(theta=0.4, branch=home_branch))
    assert reached.branch == 0  # the home's branch is the nearer one


def test_slider_crank_equal_links_constant_branch():
    """Gosselin & Angeles 1990 eq. (17): with R = l the slider stays at x = 0 on a second branch."""
    mechanism = slider_crank(crank=1.0, coupler=1.0, theta=0.7, branch=1)
    found = assemblies(mechanism, {"crank": 0.2}, np.random.default_rng(3))
    assert len(found) == 2
    for branch in (1, 0):
        the_match(mechanism, found, slider_crank(crank=1.0, coupler=1.0, theta=0.9, branch=branch))


def test_slider_driven_crank_reaches_both_elbows():
    """Park & Kim 1999 Fig. 3d: the slide driven; the crank sits above or below the slide."""
    mechanism = slider_crank(theta=0.3, actuated="slider")
    above = slider_crank(theta=0.4, actuated="slider")
    below = slider_crank(theta=-0.4, actuated="slider")
    shift = above.joint("wrist").point[0] - mechanism.joint("wrist").point[0]
    found = assemblies(mechanism, {"slide": shift}, np.random.default_rng(4))
    assert len(found) == 2
    the_match(mechanism, found, above)
    the_match(mechanism, found, below)


def test_continuation_when_newton_from_home_fails():
    """A crank shorter than the coupler turns fully; Newton from θ = 0 fails at θ = 3, continuation does not."""
    mechanism = slider_crank(crank=1.0, coupler=2.0, theta=0.0)
    reached = assemble(mechanism, {"crank": 3.0})
    assert reached.method == "continuation" and reached.displacements["crank"] == 3.0
    assert matches(mechanism, reached, slider_crank(crank=1.0, coupler=2.0, theta=3.0, branch=1))
    with pytest.raises(AssemblyError, match="no assembly with crank = 3.0"):
        assemble(mechanism, {"crank": 3.0}, method="newton")


def test_slider_crank_at_the_fold():
    """Park & Kim 1999 Fig. 3b: at sin θ = l/R the two branches meet; one (double) assembly, not two."""
    mechanism = slider_crank(theta=0.3)
    found = assemblies(mechanism, {"crank": math.asin(0.5) - 0.3})
    assert len(found) == 1
    assert matches(mechanism, found[0], slider_crank(theta=math.asin(0.5)), atol=1e-6)


def test_slider_crank_crank_out_of_reach():
    """Crank 2, coupler 1: past sin θ = 1/2 the coupler cannot reach the slide (Park & Kim 1999 Fig. 3b)."""
    mechanism = slider_crank(theta=0.3)
    with pytest.raises(AssemblyError, match=r"^no assembly with crank = 0\.7: the loops cannot close "
                                            r"\(smallest residual [0-9.e-]+\)$") as caught:
        assemble(mechanism, {"crank": 0.7})
    assert isinstance(caught.value, ConfigurationError)
    smallest = float(str(caught.value).rsplit(" ", 1)[1].rstrip(")"))
    assert smallest > 1e-3


# ----------------------------------------------------------------------------- 3-RPR

BASE = np.array([(0.0, 0.0), (4.0, 0.0), (1.5, 3.5)])
PLATFORM = np.array([(1.2, 0.9), (2.4, 1.1), (1.7, 2.0)])
LEGS = np.linalg.norm(PLATFORM - BASE, axis=1)


def three_rpr():
    """Planar 3-RPR: legs R (ground) - P (actuated, along the leg) - R (platform)."""
    joints = []
    for index, (base, platform) in enumerate(zip(BASE, PLATFORM), start=1):
        joints += [Joint(f"A{index}", "R", ("ground", f"cylinder{index}"), point=tuple(base)),
                   Joint(f"P{index}", "P", (f"cylinder{index}", f"rod{index}"), axis=tuple(platform - base),
                         actuated=True),
                   Joint(f"B{index}", "R", (f"rod{index}", "platform"), point=tuple(platform))]
    return Mechanism("3-RPR", "planar", joints, end_effector=EndEffector("platform", tuple(PLATFORM[0]), "pose"))


def platform_vertices(mechanism, point):
    pose = link_pose(mechanism, "platform", point)
    return PLATFORM @ pose[:2, :2].T + pose[:2, 2]


EXTENSIONS = {"P1": 0.3, "P2": -0.2, "P3": 0.25}


def test_three_rpr_legs_have_the_requested_lengths():
    mechanism = three_rpr()
    found = assemblies(mechanism, EXTENSIONS, np.random.default_rng(5))
    assert len(found) >= 2
    targets = LEGS + np.array(list(EXTENSIONS.values()))
    for item in found:
        assert np.linalg.norm(constraint(mechanism, item.point)) <= 1e-9
        assert bool(closes(mechanism, item.point, CLOSURE_TOLERANCE))
        lengths = np.linalg.norm(platform_vertices(mechanism, item.point) - BASE, axis=1)
        assert np.allclose(lengths, targets, atol=1e-9)
        assert all(item.displacements[name] == value for name, value in EXTENSIONS.items())
    assert [item.distance for item in found] == sorted(item.distance for item in found)
    poses = [link_pose(mechanism, "platform", item.point) for item in found]
    assert all(not np.allclose(poses[i], poses[j], atol=1e-6) for i in range(len(poses)) for j in range(i))


def test_three_rpr_is_deterministic():
    mechanism = three_rpr()
    first = assemblies(mechanism, EXTENSIONS, np.random.default_rng(7))
    again = assemblies(mechanism, EXTENSIONS, np.random.default_rng(7))
    assert len(first) == len(again)
    for one, other in zip(first, again):
        assert np.array_equal(one.point, other.point) and one.method == other.method
    other_seed = assemblies(mechanism, EXTENSIONS, np.random.default_rng(8), count=256)
    assert len(other_seed) == len(first)
    for one, other in zip(first, other_seed):
        assert np.allclose(one.point, other.point, atol=1e-8)
    assert np.array_equal(assemble(mechanism, EXTENSIONS).point, assemble(mechanism, EXTENSIONS).point)


def test_three_rpr_legs_that_cannot_close():
    """Legs 0.05 long cannot carry a platform whose sides are about 1 long over a base about 4 wide."""
    mechanism = three_rpr()
    values = {f"P{index}": float(0.05 - length) for index, length in enumerate(LEGS, start=1)}
    with pytest.raises(AssemblyError, match=r"^no assembly with P1 = -1\.45, P2 = .*, P3 = .*: the loops cannot "
                                            r"close \(smallest residual"):
        assemble(mechanism, values)


# ----------------------------------------------------------------------------- spatial

def test_gough_stewart_at_other_leg_lengths():
    """6-UPS (Gosselin & Angeles 1990 Sec. VII): the legs take the requested lengths exactly."""
    mechanism = gough_stewart()
    extensions = {f"P{index}": 0.02 * (-1) ** index for index in range(1, 7)}
    reached = assemble(mechanism, extensions, count=8)
    assert reached.method == "newton"
    assert np.linalg.norm(constraint(mechanism, reached.point)) <= 1e-10
    assert all(reached.displacements[name] == value for name, value in extensions.items())


def test_universal_joint_coordinates_are_held_one_by_one():
    mechanism = rsur()
    reached = assemble(mechanism, {"C[1]": 0.05}, hold_actuated=False)
    assert reached.displacements["C"][0] == 0.05
    assert reached.residual <= 1e-10
    with pytest.raises(ConfigurationError, match=r"values: joint coordinate 'C\[3\]': unknown coordinate "
                                                 r"\(coordinates of 'C': 'C\[1\]', 'C\[2\]'\)"):
        assemble(mechanism, {"C[3]": 0.05})
    with pytest.raises(ConfigurationError, match="joint 'C' is given twice"):
        assemble(mechanism, {"C": [0.0, 0.1], "C[1]": 0.05})
    with pytest.raises(ConfigurationError, match="an S joint is held whole"):
        assemble(mechanism, {"B[x]": 0.05})


# ----------------------------------------------------------------------------- refusals

@pytest.mark.parametrize("values, fragment", [
    ({"Z": 0.1}, "values: joint 'Z': unknown joint"),
    ({"A": float("nan")}, "values: joint 'A': expected a finite number"),
    ({"A": float("inf"), "B": 0.0}, "values: joint 'A': expected a finite number"),
    ({"A": [0.1, 0.2]}, "values: joint 'A': expected a number"),
    ({"A": "0.1"}, "values: joint 'A': expected a number"),
    ([("A", 0.1)], "values: expected a mapping"),
])
def test_bad_values_are_refused_naming_the_field(values, fragment):
    with pytest.raises(ConfigurationError, match=fragment.replace("(", r"\(")):
        assemble(five_bar(**HOME_INPUTS), values)


def test_bad_options_are_refused():
    mechanism = five_bar(**HOME_INPUTS)
    values = five_bar_values(1.7, 1.4)
    with pytest.raises(ConfigurationError, match="branch, guess: give one of them"):
        assemble(mechanism, values, branch=0, guess={"C": 0.1})
    with pytest.raises(ConfigurationError, match="branch: expected a non-negative integer"):
        assemble(mechanism, values, branch=-1)
    with pytest.raises(AssemblyError, match=r"^branch 2: only 2 assemblies found with A = .*, B = .* "
                                            r"\(branches 0 to 1\)$"):
        assemble(mechanism, values, branch=2)
    with pytest.raises(ConfigurationError, match="guess: joint 'Q': unknown joint"):
        assemble(mechanism, values, guess={"Q": 0.1})
    with pytest.raises(ConfigurationError, match="--at: joint 'Z': unknown joint"):
        assemble(mechanism, {"Z": 0.1}, where="--at")


def test_assembly_to_dict_is_json_ready():
    import json

    reached = assemble(slider_crank(theta=0.3), {"crank": 0.1})
    assert isinstance(reached, Assembly)
    record = json.loads(json.dumps(reached.to_dict()))
    assert record["method"] == "newton" and record["branch"] == 0 and record["branches"] == 2
    assert record["held"] == {"crank": 0.1} and record["displacements"]["crank"] == 0.1
    assert math.isfinite(record["residual"]) and math.isfinite(record["distance"])


def test_random_starts_find_the_gough_stewart_platforms_other_assemblies():
    """The forward kinematics of the Gough-Stewart platform (legs held at their home lengths) has several real
    solutions; Gauss-Newton on Φ from random starts ended at half-turns of some loop for nearly all of 128 starts
    and found the home alone. From the closing map first (mechanisms.kinematics.closing_space) the search finds
    other platform poses, each with every leg at its held length."""
    from mechanisms import end_effector

    mechanism = entry("gough-stewart").mechanism()
    found = assemblies(mechanism, {joint.name: 0.0 for joint in mechanism.joints if joint.actuated})
    poses = []
    for item in found:
        assert closes(mechanism, item.point)
        pose = end_effector(mechanism, item.point)
        if not any(np.allclose(pose, other, atol=1e-6) for other in poses):
            poses.append(pose)
    assert len(poses) >= 4


@pytest.mark.parametrize("seed", [0, 1])
def test_starts_stalled_near_a_singular_assembly_are_one_assembly(seed):
    """The Eclipse's Fig. 10 home is an actuator singularity, a double root of the fibre: Newton stalls about
    √‖Φ‖ (1e-5) from it, and random starts that reached it were returned as up to 4 more assemblies 1.4e-5 to
    3.6e-5 away (solutions within 100 √tolerance are now one assembly)."""
    mechanism = entry("eclipse").mechanism("fig10_actuator")
    ambient = kinematics_of(mechanism).ambient
    found = assemblies(mechanism, {joint.name: 0.0 for joint in mechanism.joints if joint.actuated},
                       np.random.default_rng(seed))
    points = np.array([item.point for item in found])
    for index, point in enumerate(points):
        for other in points[:index]:
            assert np.linalg.norm(ambient.inverse_retract(other, point) / ambient.tangent_scales) > 1e-3


def test_the_smallest_residual_of_a_failed_assembly_is_no_half_turn_zero():
    """An RSSR whose rocker angle leaves the coupler 0.04 short: the search also reached a zero of Φ that turns
    the loop by a half-turn (residual 1.5e-10), and the refusal said 'smallest residual 1.46e-10', as if the
    loop nearly closed."""
    mechanism = Mechanism("rssr", "spatial", [
        Joint("R1", "R", ("ground", "crank"), point=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)),
        Joint("S1", "S", ("crank", "coupler"), point=(0.5403023058681398, 0.8414709848078965, 0.0)),
        Joint("S2", "S", ("coupler", "rocker"), point=(1.8757797451792864, 0.0, 1.8639461402385225)),
        Joint("R4", "R", ("rocker", "ground"), point=(2.5, 0.0, 0.5), axis=(0.0, 1.0, 0.0), actuated=True)])
    with pytest.raises(AssemblyError, match="cannot close") as refused:
        assemble(mechanism, {"R4": -0.4624188365889781}, rng=np.random.default_rng(0))
    residual = float(str(refused.value).rsplit("smallest residual ", 1)[1].rstrip(")"))
    assert residual > 1e-3
    # a lone start that turns the loop by more than a quarter-turn, far from any zero (residual 0.51), is no
    # half-turn zero: it was said to be one
    with pytest.raises(AssemblyError, match="smallest residual"):
        assemble(mechanism, {"R4": -0.4624188365889781}, rng=np.random.default_rng(0), count=1)


def test_a_large_mechanism_is_assembled_block_by_block_as_densely(monkeypatch):
    """Past BLOCK_THRESHOLD free coordinates Gauss-Newton from the random starts solves the blocks of DΦ apart
    (manifold.minimum_norm_steps): no stack of dense c × r Jacobians (128 of them for the 100-loop ladder took
    60 s and 0.5 GB), and the same assemblies as the dense solves."""
    from builders import ladder
    from manifold import JacobianPattern, implicit

    mechanism = ladder(22)  # 88 joints, 66 free once the 22 actuated ones are held
    held = {"A1": 0.1, "A2": -0.05}
    stacks = []
    dense = JacobianPattern.dense

    def recorded(pattern, entries):
        stacks.append(np.ndim(entries) - 1)
        return dense(pattern, entries)

    monkeypatch.setattr(JacobianPattern, "dense", recorded)
    found = assemblies(mechanism, held, count=32)
    assert max(stacks, default=0) == 0  # single configurations only
    monkeypatch.setattr(implicit, "BLOCK_THRESHOLD", 10 ** 9)  # the dense solves
    expected = assemblies(mechanism, held, count=32)
    assert len(found) == len(expected) > 1
    for block, solved in zip(found, expected):
        assert block.method == solved.method and block.distance == pytest.approx(solved.distance, abs=1e-9)
        np.testing.assert_allclose(block.point, solved.point, atol=1e-9)
