"""A survey cache file: the survey of M reused across processes, refused when made for something else."""

import json

import pytest

from classify import model_of
from classify.survey import survey_of
from classify.survey_cache import SurveyCacheError, cached_survey, read_survey, write_survey
from mechanisms import catalogue


def test_written_then_read_and_installed_on_a_new_model(tmp_path):
    path = tmp_path / "five-bar.survey.json"
    first = model_of(catalogue.entry("five-bar").mechanism())
    survey, read = cached_survey(path, first)
    assert not read and path.exists()
    second = model_of(catalogue.entry("five-bar").mechanism())  # another object, the same mechanism
    assert second is not first
    again, read = cached_survey(path, second)
    assert read and again.to_dict() == survey.to_dict()
    assert survey_of(second) is again


def test_a_file_for_another_mechanism_or_cut_is_refused(tmp_path):
    path = tmp_path / "survey.json"
    five_bar = model_of(catalogue.entry("five-bar").mechanism())
    write_survey(path, five_bar, survey_of(five_bar))
    other = model_of(catalogue.entry("five-bar").mechanism(base=5.5))
    with pytest.raises(SurveyCacheError, match="another mechanism"):
        read_survey(path, other)
    with pytest.raises(SurveyCacheError, match="another mechanism"):
        read_survey(path, five_bar, rtol=1e-8)
    assert read_survey(tmp_path / "missing.json", five_bar) is None


def test_a_file_of_an_earlier_version_is_refused(tmp_path):
    """Its survey sampled M otherwise (version 1: random starts ended at half-turns; 2: capped Gauss-Newton on
    the closing map stalled for some)."""
    path = tmp_path / "survey.json"
    five_bar = model_of(catalogue.entry("five-bar").mechanism())
    write_survey(path, five_bar, survey_of(five_bar))
    data = json.loads(path.read_text())
    assert read_survey(path, five_bar).to_dict() == survey_of(five_bar).to_dict()
    for version in (1, 2):
        path.write_text(json.dumps(dict(data, version=version)))
        with pytest.raises(SurveyCacheError, match="closedchain version"):
            read_survey(path, five_bar)


@pytest.mark.parametrize("text, message", [
    ("{", "not a JSON file"),
    ("[]", "not a closedchain survey cache"),
    ('{"format": "closedchain-survey"}', "another mechanism"),
])
def test_malformed_files_are_refused_naming_the_file(tmp_path, text, message):
    path = tmp_path / "bad.json"
    path.write_text(text)
    with pytest.raises(SurveyCacheError, match=message) as error:
        read_survey(path, model_of(catalogue.entry("slider-crank").mechanism()))
    assert "bad.json" in str(error.value)


def test_a_tampered_survey_field_is_named(tmp_path):
    path = tmp_path / "survey.json"
    model = model_of(catalogue.entry("slider-crank").mechanism())
    write_survey(path, model, survey_of(model))
    data = json.loads(path.read_text())
    data["survey"]["actuator_rank"] = "two"
    path.write_text(json.dumps(data))
    with pytest.raises(SurveyCacheError, match="'actuator_rank'"):
        read_survey(path, model)


@pytest.mark.parametrize("field, value, message", [
    ("joint_rank", None, "'joint_rank': expected a non-negative integer (the mechanism has an end-effector)"),
    ("end_effector_rank", None, "'end_effector_rank': expected a non-negative integer"),
    ("constraint_rank", 99, "'constraint_rank': expected at most 3"),
    ("actuator_rank", 3, "'actuator_rank': expected at most 2"),
    ("joint_rank", 5, "'joint_rank': expected at most 4"),
])
def test_a_survey_that_cannot_be_the_mechanisms_is_refused(tmp_path, field, value, message):
    """A rank missing where the mechanism has an end-effector (it reached the batch as None: an internal
    error), or beyond the size of its map (DΦ of the five-bar is 3 × 5, two actuators, two outputs)."""
    path = tmp_path / "survey.json"
    model = model_of(catalogue.entry("five-bar").mechanism())
    write_survey(path, model, survey_of(model))
    data = json.loads(path.read_text())
    data["survey"][field] = value
    path.write_text(json.dumps(data))
    with pytest.raises(SurveyCacheError, match=message.replace("(", r"\(").replace(")", r"\)")):
        read_survey(path, model)


def test_a_survey_of_a_mechanism_without_end_effector_has_no_end_effector_ranks(tmp_path):
    path = tmp_path / "survey.json"
    model = model_of(catalogue.entry("five-bar").mechanism(end_effector="none"))
    write_survey(path, model, survey_of(model))
    assert read_survey(path, model).to_dict() == survey_of(model).to_dict()
    data = json.loads(path.read_text())
    data["survey"]["joint_rank"] = 2
    path.write_text(json.dumps(data))
    with pytest.raises(SurveyCacheError, match="'joint_rank': expected null"):
        read_survey(path, model)


def test_the_survey_carries_the_margins_of_its_rank_decisions():
    """The survey's ranks decide the dof, the idle freedoms and the architecture flag: each now comes with its
    margins over the samples (largest σ_r and σ_{r+1} over the cut). Gosselin & Angeles 1990 eq. 87 (similar
    hexagons): the actuator rows never reach rank 6 on M, by far (σ₆ at most ~1e-8 of the cut), the flag holds."""
    from classify import Survey, classify
    from mechanisms import catalogue, home

    mechanism = catalogue.entry("gough-stewart").mechanism(configuration="eq87_parallel_legs")
    report = classify(mechanism, home(mechanism))
    margins = report.survey["margins"]
    assert report.architecture_singular and report.survey["actuator_rank"] == 5
    assert margins["actuator"]["kept"] > 1e3 and margins["actuator"]["dropped"] < 1e-3
    assert "margin: over the survey's samples" in report.to_text()
    assert Survey.from_dict(report.survey).to_dict() == report.survey
    with pytest.raises(ValueError, match="margins.actuator.dropped"):
        Survey.from_dict({**report.survey, "margins": {**margins, "actuator": {"kept": 1.0, "dropped": -1.0}}})
