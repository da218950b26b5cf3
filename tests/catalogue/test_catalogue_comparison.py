"""Park–Kim and the derived Gosselin–Angeles classification on the whole catalogue: at every named
configuration (the papers' singular ones) and at configurations sampled over the assembly branches,
of every entry with as many inputs as outputs, the two correspond — or differ for a reason of the
closed list (``classify.comparison.REASONS``), never an unexplained one.

Park–Kim's side is classified with the survey of M that ``classify`` itself uses for the mechanism
(:func:`classify.survey_of`), shared with the other tests through :func:`builders.catalogue_mechanism`.
"""

import numpy as np
import pytest

from builders import catalogue_mechanism
from classify import REASONS, compare, joint_output_model, model_of, sample_configurations, survey_of
from mechanisms import end_effector_dimension, home
from mechanisms.catalogue import entries, entry

#: reasons the *derived* matrices can give (the others concern a given F)
DERIVED_REASONS = {"cspace_singularity", "idle_freedom", "stationary_motion"}


def comparable(mechanism):
    """The model whose inputs and outputs are equal in number, or None.

    The slider-crank's end-effector is the slider's planar position (2 coordinates for 1 input):
    its output is then the joint that is not driven, as in G–A Fig. 2 (crank in, slider out).
    """
    inputs = len(mechanism.actuated_coordinates)
    if inputs == end_effector_dimension(mechanism):
        return model_of(mechanism)
    if mechanism.name == "slider-crank":
        driven = [joint.name for joint in mechanism.joints if joint.actuated]
        return joint_output_model(mechanism, ["slide"] if driven == ["crank"] else ["crank"])
    return None


CASES = [(item.name, name) for item in entries() for name in ("default", *item.configurations)
         if comparable(catalogue_mechanism(item.name, None if name == "default" else name)) is not None]


def test_the_catalogue_has_comparable_entries():
    names = {item_name for item_name, _ in CASES}
    assert {"slider-crank", "five-bar", "watt-six-bar", "planar-3rrr", "spherical-3rrr", "gough-stewart",
            "3-prr", "hybrid", "eclipse", "5-spu"} <= names  # 5-spu: 5 legs in, the tool (p, i) out


def test_the_reasons_allowed_here_are_listed_reasons():
    assert DERIVED_REASONS <= set(REASONS)


@pytest.mark.parametrize("item_name", sorted({item_name for item_name, _ in CASES}))
def test_the_classifications_correspond_or_differ_for_a_listed_reason(item_name):
    rng = np.random.default_rng(5)
    singular_agreements = 0
    item = entry(item_name)
    for case_name, name in CASES:
        if case_name != item_name:
            continue
        mechanism = catalogue_mechanism(item_name, None if name == "default" else name)
        model = comparable(mechanism)
        points = np.concatenate([home(mechanism)[None], sample_configurations(model, 2, rng)])
        for row in compare(model, points, survey=survey_of(model), rng=rng).rows:
            where = f"{item.name} [{name}] {row.label}: {row.note}"
            assert row.reason in DERIVED_REASONS | {None}, where
            if "cspace" in row.park_kim.kinds:
                assert row.reason == "cspace_singularity", where
            elif row.park_kim.moving_idle_freedoms == 0 and row.gosselin_angeles.velocity_dimension == \
                    row.gosselin_angeles.n:
                assert row.agree, where
            singular_agreements += row.agree and bool(row.park_kim.kinds)
    if len(item.configurations) > 1:
        assert singular_agreements > 0  # the papers' singular configurations are compared, not only samples
