"""The catalogue as a whole: every entry builds at every named configuration, is written out
as a contract-format file and read back unchanged; parameters are parsed, never evaluated."""

import re

import pytest

from mechanisms import MechanismError, read, save
from mechanisms.catalogue import entries, entry, names, parse_parameter
from mechanisms.io import mechanism_to_dict

CASES = [(item.name, configuration) for item in entries() for configuration in (None, *item.configurations)]


def test_names_are_unique_and_lower_case_with_hyphens():
    assert len(set(names())) == len(names())
    assert all(name == name.lower() and " " not in name and "_" not in name for name in names())


@pytest.mark.parametrize("name, configuration", CASES)
def test_every_entry_round_trips_through_a_mechanism_file(name, configuration, tmp_path):
    item = entry(name)
    mechanism = item.mechanism(configuration)
    assert name.startswith(mechanism.name)  # "3-prr-inputs" builds the "3-prr"
    for suffix in (".yaml", ".json"):
        path = tmp_path / f"entry{suffix}"
        save(mechanism, path, description=item.reference)
        document = read(path)
        assert mechanism_to_dict(document.mechanism) == mechanism_to_dict(mechanism)
        assert document.description == item.reference


@pytest.mark.parametrize("item", entries(), ids=names())
def test_every_entry_cites_a_paper_and_documents_its_parameters(item):
    # cited by bibliographic reference (docs/references.rst), never by a file name
    assert re.search(r"\((19|20)\d\d\)", item.reference) and ".txt" not in item.reference
    documentation = item.build.__doc__
    for parameter in item.parameters:
        # numbered families may be documented as a range: "x1, ..., x5"
        stem = re.sub(r"\d+$", "1", parameter)
        assert parameter in documentation or stem in documentation, \
            f"{item.name}: parameter {parameter!r} is not documented"


def test_parameters_are_typed_by_their_defaults():
    item = entry("slider-crank")
    assert parse_parameter(item, "theta=0.5") == ("theta", 0.5)
    assert parse_parameter(item, " branch = -1 ") == ("branch", -1)
    assert parse_parameter(item, "end_effector=false") == ("end_effector", False)
    assert parse_parameter(item, "actuated=slider") == ("actuated", "slider")


@pytest.mark.parametrize("text, message", [
    ("theta", "expected name=value"),
    ("length=2", "has no parameter 'length'"),
    ("theta=pi/2", "--param theta: expected a number"),
    ("theta=nan", "--param theta: expected a finite number"),
    ("branch=1.5", "--param branch: expected an integer"),
    ("end_effector=yes", "--param end_effector: expected true or false"),
])
def test_bad_parameters_are_refused_naming_the_parameter(text, message):
    with pytest.raises(MechanismError, match=message):
        parse_parameter(entry("slider-crank"), text)


def test_unknown_entry_configuration_and_parameter_are_refused():
    with pytest.raises(MechanismError, match="no catalogue entry 'six-bar'.*slider-crank"):
        entry("six-bar")
    with pytest.raises(MechanismError, match="unknown configuration 'fig9'"):
        entry("slider-crank").mechanism("fig9")
    with pytest.raises(MechanismError, match="unknown parameter 'length'"):
        entry("slider-crank").mechanism(length=2.0)


def test_parameters_override_the_named_configuration():
    values = entry("slider-crank").values("fig3c_dead_centre", crank=3.0)
    assert values["theta"] == 0.0 and values["crank"] == 3.0 and values["coupler"] == 1.0


def test_a_configuration_out_of_reach_names_the_parameter():
    with pytest.raises(MechanismError, match="theta = 1.2: the coupler cannot reach"):
        entry("slider-crank").mechanism(theta=1.2)
