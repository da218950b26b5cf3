"""Catalogue input errors: the hybrid's messages name its own parameters, and a parameter the chosen variant
does not read is refused when set (not silently ignored).

The hybrid manipulator hands its angles θ2, θ3, θ4 to the five-bar's direct kinematics, where they are the
five-bar's θ1, θ2, θ3: its error messages must still name the hybrid's parameters. A parameter documented as
read only in one variant (five-bar θ3 and hybrid θ4 with ``assembly=0``, planar-3rrr θᵢ with ``modeᵢ=0``,
Watt ψ with ``branch_rocker=0``, spherical-3rrr ``theta_folded`` where a leg is folded) is refused when the
user sets it and the variant does not read it; the named configurations, which set such parameters
themselves, are unaffected.
"""

import math
import sys

import pytest

from classify.cli import main
from classify.cli import sweep_command
from classify.cli._common import InputError, Parser
from mechanisms import MechanismError, catalogue
from mechanisms.catalogue.hybrid import hybrid_points


def refusal(name, configuration=None, **parameters):
    """The one-line message of the MechanismError building the entry raises."""
    with pytest.raises(MechanismError) as raised:
        catalogue.entry(name).mechanism(configuration, **parameters)
    message = str(raised.value)
    assert "\n" not in message
    return message


def cli(arguments, capsys):
    status = main(arguments)
    captured = capsys.readouterr()
    return status, captured.out, captured.err


# ----------------------------------------------------------------------------- 1. the hybrid's names


def test_hybrid_unreachable_inputs_name_the_hybrids_angles():
    message = refusal("hybrid", theta2=3.5)
    assert "theta2 = 3.5, theta3 = 1.3" in message
    assert "five-bar" not in message and "theta1 = 3.5" not in message


def test_hybrid_assembly_zero_names_the_hybrids_angles():
    message = refusal("hybrid", assembly=0)
    assert "at theta2 = 1.8, theta3 = 1.3" in message
    assert "five-bar" not in message and "theta1" not in message


def test_hybrid_coincident_elbows_advise_the_hybrids_theta4():
    message = refusal("hybrid", "eq25_elbows_coincide", assembly=1)
    assert "use assembly = 0 with theta4" in message
    assert "theta1" not in message and "five-bar" not in message


def test_hybrid_advice_is_followed_back_to_the_configuration():
    """Following the advice (assembly = 0 with theta4) rebuilds the named configuration."""
    item = catalogue.entry("hybrid")
    preset = item.configurations["eq25_elbows_coincide"]
    advised = item.mechanism("eq25_elbows_coincide", assembly=0, theta4=preset["theta4"])
    assert [joint.point for joint in advised.joints] == [joint.point
                                                        for joint in item.mechanism("eq25_elbows_coincide").joints]


def test_hybrid_non_positive_length_names_the_hybrid():
    message = refusal("hybrid", base=-1.0)
    assert "hybrid: base must be positive" in message
    assert "five-bar" not in message


def test_hybrid_points_name_the_hybrids_angles():
    with pytest.raises(MechanismError, match=r"^hybrid: theta2 = 3\.5, theta3 = 1\.3: the circles do not meet"):
        hybrid_points(theta2=3.5)


def test_five_bar_messages_are_unchanged():
    assert "five-bar: theta1 = 3.5, theta2 = 1.3: the circles do not meet" in refusal("five-bar", theta1=3.5)
    assert "five-bar: base must be positive" in refusal("five-bar", base=-1.0)
    assert "use assembly = 0 with theta3" in refusal("five-bar", "sec34_elbows_coincide", assembly=1)


def test_hybrid_cli_error_names_the_hybrids_angles(capsys):
    status, out, err = cli(["classify", "hybrid", "--param", "theta2=3.5"], capsys)
    assert status == 2 and not out
    assert len(err.strip().splitlines()) == 1
    assert "theta2 = 3.5, theta3 = 1.3" in err and "five-bar" not in err


# ----------------------------------------------------------------------------- 2. parameters not read


UNREAD = [
    ("five-bar", None, {"theta3": 1.0}, "theta3", "assembly = 0"),
    ("five-bar", None, {"theta3": 0.0}, "theta3", "assembly = 0"),  # set, even to its default
    ("five-bar", "fig2_working_mode_pp", {"theta3": 2.5}, "theta3", "assembly = 0"),
    ("hybrid", None, {"theta4": 2.0}, "theta4", "assembly = 0"),
    ("planar-3rrr", None, {"theta1": 0.3}, "theta1", "mode1 = 0"),
    ("planar-3rrr", "eq58_leg_stretched", {"theta2": 0.3}, "theta2", "mode2 = 0"),
    ("planar-3rrr", "eq65_vertices_on_motors", {"mode3": 1, "theta3": 0.3}, "theta3", "mode3 = 0"),
    ("watt-six-bar", None, {"psi": 1.0}, "psi", "branch_rocker = 0"),
    ("spherical-3rrr", None, {"theta_folded": 0.7}, "theta_folded", "folded"),
    ("spherical-3rrr", "section6_equal_alphas_folded", {"rotation_z": 0.4, "theta_folded": 0.7}, "theta_folded",
     "folded"),
]


@pytest.mark.parametrize("name, configuration, parameters, parameter, condition", UNREAD,
                         ids=[f"{row[0]}-{row[3]}-{index}" for index, row in enumerate(UNREAD)])
def test_a_parameter_the_variant_does_not_read_is_refused(name, configuration, parameters, parameter, condition):
    message = refusal(name, configuration, **parameters)
    assert parameter in message and condition in message and "read only" in message


READ = [
    ("five-bar", "sec34_elbows_coincide", {"theta3": 1.0}),
    ("five-bar", "fig1c_collinear", {"theta3": 0.5}),
    ("hybrid", "eq25_elbows_coincide", {"theta4": 2.0}),
    ("planar-3rrr", "eq65_vertices_on_motors", {"theta1": math.radians(-150)}),
    ("planar-3rrr", "eq65_vertices_on_motors", {"mode2": 0, "theta2": math.radians(-30)}),
    ("watt-six-bar", "eq41_joints_2_4_superimposed", {"psi": 1.3}),
    ("spherical-3rrr", "section6_equal_alphas_folded", {"theta_folded": 0.3}),
]


@pytest.mark.parametrize("name, configuration, parameters", READ,
                         ids=[f"{row[0]}-{row[1]}-{index}" for index, row in enumerate(READ)])
def test_a_parameter_the_variant_reads_is_accepted(name, configuration, parameters):
    assert catalogue.entry(name).mechanism(configuration, **parameters).joints


def test_every_named_configuration_reads_what_it_sets():
    """A configuration preset is never refused, and each preset of a conditional parameter is read there."""
    for item in catalogue.entries():
        for configuration, presets in item.configurations.items():
            values = item.values(configuration)  # presets are not the user's settings: never refused
            for parameter in presets:
                rule = item.read_only.get(parameter)
                if rule is not None:
                    assert rule.reads(values), (item.name, configuration, parameter)


def test_the_cli_refuses_an_unread_parameter_with_one_line(capsys):
    status, out, err = cli(["classify", "five-bar", "--param", "theta3=2.5"], capsys)
    assert status == 2 and not out
    assert len(err.strip().splitlines()) == 1
    assert "theta3" in err and "assembly = 0" in err


def test_the_cli_accepts_an_unread_parameter_set_by_a_configuration(capsys):
    status, out, err = cli(["classify", "five-bar", "--configuration", "sec34_elbows_coincide", "--param",
                            "theta3=1.0", "--format", "json"], capsys)
    assert status == 0, err


def sweep(arguments, capfd):
    parser = Parser(prog="closedchain")
    sweep_command.add_parser(parser.add_subparsers(dest="command", required=True, parser_class=Parser))
    try:
        sweep_command.run(parser.parse_args(["sweep", *arguments]), sys.stdout)
        status = 0
    except (InputError, MechanismError) as error:
        print(f"closedchain: error: {' '.join(str(error).split())}", file=sys.stderr)
        status = 2
    captured = capfd.readouterr()
    return status, captured.out, captured.err


def test_a_sweep_of_an_unread_parameter_is_refused_once_before_it_starts(capfd):
    status, out, err = sweep(["five-bar", "--param", "theta3=0:1:3", "--scheduler", "serial", "--samples", "2"],
                             capfd)
    assert status == 2 and not out
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "sweeping" not in err
    assert "theta3" in lines[0] and "assembly = 0" in lines[0]


def test_a_sweep_of_a_read_parameter_in_its_variant_runs(capfd):
    """With the fixed parameters of the variant that reads it (assembly = 0 at coincident elbows), a sweep over
    theta3 runs."""
    preset = catalogue.entry("five-bar").configurations["sec34_elbows_coincide"]
    fixed = [text for key, value in preset.items() if key != "theta3" for text in ("--param", f"{key}={value!r}")]
    status, out, err = sweep(["five-bar", *fixed, "--param", "theta3=0:1:2", "--scheduler", "serial",
                              "--samples", "2"], capfd)
    assert status == 0, err
    assert "cannot be built" not in out
