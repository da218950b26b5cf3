"""The survey cache file binds its numbers, fingerprints what the survey depends on, says what differs, and a
model's survey is computed once however many threads ask for it."""

import importlib
import io
import json
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from classify import Model, classify, model_of
from classify.cli import main
from classify.model import joint_output_model
from classify.survey import survey_of, unit_actuator_rows
from classify import survey_cache
from classify.survey_cache import SurveyCacheError, fingerprint, read_survey, write_survey
from manifold import AmbientSpace, ImplicitManifold
from mechanisms import catalogue
from mechanisms.io import read

ROOT = Path(__file__).resolve().parents[2]
SLIDER_CRANK = str(ROOT / "examples" / "slider_crank.yaml")


def _written(tmp_path, model):
    path = tmp_path / "survey.json"
    write_survey(path, model, survey_of(model))
    return path, json.loads(path.read_text())


def _forged(path, data):
    """`data` written with a checksum that matches it: only the sanity checks stand between it and a verdict."""
    data = {key: value for key, value in data.items() if key != "checksum"}
    path.write_text(json.dumps({**data, "checksum": survey_cache._checksum(data)}))


def _line(fixed, counter=None):
    """M = {q[fixed] = 0} in ℝ², actuator q1 (the two models differ only by Φ)."""
    def constraint(point):
        if counter is not None:
            counter.append(threading.get_ident())
            time.sleep(0.01)
        return np.asarray(point, float)[..., fixed:fixed + 1]

    def jacobian(point):
        return np.broadcast_to(np.eye(2)[fixed:fixed + 1], np.shape(point)[:-1] + (1, 2))

    manifold = ImplicitManifold(AmbientSpace(("R", "R")), constraint, jacobian)
    return Model("line", manifold, np.eye(2)[1:], ("q0", "q1"), np.zeros((1, 2)))


# ------------------------------------------------------------------------------------------------ 1. bound numbers

@pytest.mark.parametrize("edit", [
    {"samples": 48},
    {"margins": None},
    {"margins": {"constraint": {"kept": 1.0, "dropped": None}, "actuator": {"kept": 1.0, "dropped": None},
                 "end_effector": {"kept": 1.0, "dropped": None}, "joint": {"kept": 1.0, "dropped": None}}},
])
def test_an_edited_survey_is_refused_naming_the_checksum(tmp_path, edit):
    """Numbers a survey of the model could have, but not the ones written."""
    model = model_of(read(SLIDER_CRANK).mechanism)
    path, data = _written(tmp_path, model)
    assert "checksum" in data
    data["survey"].update(edit)
    path.write_text(json.dumps(data))
    with pytest.raises(SurveyCacheError, match="'checksum'"):
        read_survey(path, model)


def test_the_cli_refuses_an_edited_cache_with_exit_2_and_one_line(tmp_path, capsys):
    path = tmp_path / "r.json"
    assert main(["classify", SLIDER_CRANK, "--survey", str(path)], out=io.StringIO()) == 0
    data = json.loads(path.read_text())
    data["survey"].update(actuator_rank=0, end_effector_rank=0, joint_rank=0)
    path.write_text(json.dumps(data))
    capsys.readouterr()
    out = io.StringIO()
    status = main(["classify", SLIDER_CRANK, "--configuration", "fig3c_dead_centre", "--survey", str(path)], out=out)
    err = capsys.readouterr().err
    assert status == 2 and out.getvalue() == ""
    assert err.startswith("closedchain: error: --survey:") and err.count("\n") == 1 and "'actuator_rank'" in err
    data["survey"].update(actuator_rank=1, end_effector_rank=1, joint_rank=1, samples=48)
    path.write_text(json.dumps(data))
    status = main(["classify", SLIDER_CRANK, "--survey", str(path)], out=out)
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and "'checksum'" in err


def test_the_checksum_is_missing_from_an_older_file(tmp_path):
    model = model_of(read(SLIDER_CRANK).mechanism)
    path, data = _written(tmp_path, model)
    del data["checksum"]
    path.write_text(json.dumps(data))
    with pytest.raises(SurveyCacheError, match="field 'checksum' missing"):
        read_survey(path, model)


@pytest.mark.parametrize("edit, message", [
    ({"actuator_rank": 0, "end_effector_rank": 0, "joint_rank": 0}, "'actuator_rank'.*at the home"),
    ({"actuator_rank": 1, "end_effector_rank": 2, "joint_rank": 2}, "'end_effector_rank'.*at most 1"),
    ({"joint_rank": 0}, "'joint_rank'.*at least"),
    ({"constraint_rank": 2}, "'constraint_rank'.*at the home"),
    ({"samples": 0}, "'samples'"),
    ({"samples": 10 ** 400}, "'samples'"),
    ({"samples": 1.5}, "'samples'"),
    ({"extra": 1}, "'extra'"),
])
def test_a_forged_survey_that_no_survey_of_the_model_can_be_is_refused(tmp_path, edit, message):
    """The slider-crank: k = 4, DΦ of rank 3 (dof 1), one actuator, a 1-dimensional end-effector; at its home every
    rank is 1."""
    model = model_of(read(SLIDER_CRANK).mechanism)
    path, data = _written(tmp_path, model)
    data["survey"].update(edit)
    _forged(path, data)
    with pytest.raises(SurveyCacheError, match=message) as error:
        read_survey(path, model)
    assert "\n" not in str(error.value)


def test_an_unknown_top_level_field_is_refused(tmp_path):
    model = model_of(read(SLIDER_CRANK).mechanism)
    path, data = _written(tmp_path, model)
    _forged(path, {**data, "comment": "hello"})
    with pytest.raises(SurveyCacheError, match="'comment'"):
        read_survey(path, model)


def test_margins_of_an_end_effector_the_model_has_not_are_refused(tmp_path):
    model = model_of(catalogue.entry("five-bar").mechanism(end_effector="none"))
    path, data = _written(tmp_path, model)
    data["survey"]["margins"]["joint"] = {"kept": 1.0, "dropped": None}
    _forged(path, data)
    with pytest.raises(SurveyCacheError, match="'margins.joint'"):
        read_survey(path, model)


def test_a_genuine_file_still_reads_back(tmp_path):
    for model in (model_of(read(SLIDER_CRANK).mechanism),
                  model_of(catalogue.entry("five-bar").mechanism(end_effector="none"))):
        path, _ = _written(tmp_path, model)
        assert read_survey(path, model).to_dict() == survey_of(model).to_dict()


# ------------------------------------------------------------------------------------------------ 2. the fingerprint

def test_models_that_differ_only_by_phi_have_different_fingerprints(tmp_path):
    first, second = _line(0), _line(1)
    assert fingerprint(first) != fingerprint(second)
    path, _ = _written(tmp_path, first)
    with pytest.raises(SurveyCacheError, match="another mechanism"):
        read_survey(path, second)
    assert classify(second, np.zeros(2)).kinds == ()


def test_joint_output_models_of_other_joints_have_different_fingerprints():
    mechanism = read(SLIDER_CRANK).mechanism
    slide, pin = joint_output_model(mechanism, ["slide"]), joint_output_model(mechanism, ["pin"])
    assert fingerprint(slide) != fingerprint(pin)
    assert fingerprint(slide) == fingerprint(joint_output_model(mechanism, ["slide"]))


def test_the_same_model_has_the_same_fingerprint_in_another_process():
    mechanism = catalogue.entry("five-bar").mechanism()
    here = fingerprint(model_of(mechanism))
    script = ("import sys; sys.path.insert(0, sys.argv[1]); from classify import model_of;"
              "from classify.survey_cache import fingerprint; from mechanisms import catalogue;"
              "print(fingerprint(model_of(catalogue.entry('five-bar').mechanism())))")
    there = subprocess.run([sys.executable, "-c", script, str(ROOT)], capture_output=True, text=True, check=True,
                           env={"PYTHONHASHSEED": "123", "PATH": "/usr/bin:/bin"}, cwd=ROOT).stdout.split()[-1]
    assert here == there


def test_the_probe_rounding_ignores_rounding_noise_and_signs_of_zero():
    """Values are kept to 1e-10 of their row's scale: a relative change of 1e-15, a -0.0, or noise of 1e-17 on
    a zero leave the hash alone; a change of 1e-6 does not."""
    rng = np.random.default_rng(5)
    values = rng.standard_normal((4, 3, 5)) * np.array([1.0, 1e3, 1e-3])[:, None]
    values[0, 1, 2] = 0.0
    noisy = values * (1 + 1e-15 * rng.standard_normal(values.shape))
    noisy[0, 1, 2] = -1e-17
    assert survey_cache._quantised(values) == survey_cache._quantised(noisy)
    moved = values.copy()
    moved[2, 0, 1] *= 1 + 1e-6
    assert survey_cache._quantised(values) != survey_cache._quantised(moved)


# ------------------------------------------------------------------------------------------------ 3. messages

@pytest.mark.parametrize("edit, message", [
    (lambda data: data.pop("fingerprint"), r"field 'fingerprint'.*missing"),
    (lambda data: data.update(version=4), r"field 'version'.*4.*version 6"),
    # version 5's end-effector and joint margins were decided against Df's path, not every joint's rate
    (lambda data: data.update(version=5), r"field 'version'.*5.*version 6"),
    (lambda data: data.pop("version"), r"field 'version'.*missing"),
])
def test_a_refused_file_names_the_field(tmp_path, edit, message):
    model = model_of(read(SLIDER_CRANK).mechanism)
    path, data = _written(tmp_path, model)
    edit(data)
    path.write_text(json.dumps(data))
    with pytest.raises(SurveyCacheError, match=message):
        read_survey(path, model)


def test_a_refused_file_names_what_differs(tmp_path):
    mechanism = read(SLIDER_CRANK).mechanism
    model = model_of(mechanism)
    path, _ = _written(tmp_path, model)
    text = Path(SLIDER_CRANK).read_text().replace("end_effector:\n", "end_effector:\n  output: pose\n", 1)
    (tmp_path / "pose.yaml").write_text(text)
    posed = read(str(tmp_path / "pose.yaml")).mechanism  # a pose output: H depends on the length scale
    write_survey(tmp_path / "pose.json", model_of(posed), survey_of(model_of(posed)))
    only_h = r"differs in the end-effector metric H \(e.g. another --length-scale\);"
    with pytest.raises(SurveyCacheError, match=only_h):
        read_survey(tmp_path / "pose.json", model_of(posed, length_scale=7.0))
    with pytest.raises(SurveyCacheError, match=r"rank cut.*1e-06.*1e-08"):
        read_survey(path, model, rtol=1e-8)
    with pytest.raises(SurveyCacheError, match="Φ"):
        read_survey(path, joint_output_model(mechanism, ["slide"]))


# ------------------------------------------------------------------------------------------------ 4. threads

def test_concurrent_callers_compute_a_models_survey_once(monkeypatch):
    survey_module = importlib.import_module("classify.survey")
    calls, original = [], survey_module.survey

    def counted(*args, **kwargs):
        calls.append(threading.get_ident())
        time.sleep(0.05)
        return original(*args, **kwargs)

    monkeypatch.setattr(survey_module, "survey", counted)
    model = model_of(catalogue.entry("five-bar").mechanism())
    barrier, found = threading.Barrier(3), []

    def run():
        barrier.wait()
        found.append(survey_of(model))

    threads = [threading.Thread(target=run) for _ in range(3)]
    [thread.start() for thread in threads]
    [thread.join() for thread in threads]
    assert len(calls) == 1 and len(found) == 3 and all(survey is found[0] for survey in found)


def test_concurrent_callers_compute_the_models_constants_once(monkeypatch):
    survey_module = importlib.import_module("classify.survey")
    rows_calls, original_rows = [], survey_module.unit_rows

    def counted_rows(*args, **kwargs):
        rows_calls.append(1)
        time.sleep(0.05)
        return original_rows(*args, **kwargs)

    monkeypatch.setattr(survey_module, "unit_rows", counted_rows)
    constraint_calls = []
    model = _line(0, constraint_calls)
    barrier, rows, counts = threading.Barrier(3), [], []

    def run():
        barrier.wait()
        counts.append(model.constraint_rows)
        rows.append(unit_actuator_rows(model))

    threads = [threading.Thread(target=run) for _ in range(3)]
    [thread.start() for thread in threads]
    [thread.join() for thread in threads]
    assert len(constraint_calls) == 1 and counts == [1, 1, 1]
    assert len(rows_calls) == 1 and all(found is rows[0] for found in rows)
