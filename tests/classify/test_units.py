"""No verdict depends on the unit of length (docs/design.rst, "Metrics").

Every catalogue mechanism, at its defaults with all lengths ×1e-6, ×1e-3, ×1e3 and ×1e6, and at
every named configuration in one of these units (:func:`mechanisms.scale_lengths`; the factors cycle
over the configurations), is classified exactly as drawn in the catalogue's unit: same kinds, degeneracy,
dof, ranks, expected ranks, idle freedoms and architecture flag, and the same relative margins (every
decision is taken on dimensionless maps). Actuator weights do not decide either.

Mechanisms are classified through :func:`builders.shared_mechanism`: the catalogue's unit is surveyed
once per description, not once per factor. A spherical mechanism has no length: it is its own scaled
copy, so the spherical entries are left out (a test says why).
"""

import dataclasses
import itertools

import numpy as np
import pytest

from builders import catalogue_mechanism, shared_mechanism
from classify import classify
from mechanisms import Mechanism, catalogue, home, scale_lengths

FACTORS = (1e-6, 1e-3, 1e3, 1e6)
#: entries with no length: a spherical mechanism is its own scaled copy (checked below), so it has no case here
SPHERICAL = tuple(item.name for item in catalogue.entries() if item.mechanism().space == "spherical")
CASES = [(item.name, name) for item in catalogue.entries() if item.name not in SPHERICAL
         for name in (None, *item.configurations)]
# every entry at its defaults in all four units; every named configuration in one of them (cycling)
SCALED = ([(item.name, None, factor) for item in catalogue.entries() if item.name not in SPHERICAL
           for factor in FACTORS]
          + [(name, configuration, factor) for (name, configuration), factor
             in zip([case for case in CASES if case[1] is not None], itertools.cycle(FACTORS))])


def classified(mechanism):
    mechanism = shared_mechanism(mechanism)
    return classify(mechanism, home(mechanism), rng=np.random.default_rng(0))


def decided_values(result):
    """The singular values of a decision that are not rounding noise, relative to the cut's scale."""
    values = np.asarray(result.decision.singular_values)
    reference = result.decision.tolerance / 1e-6  # the decision's scale (the cut is rtol · scale)
    return values[values > 1e-8 * reference] / reference


def assert_same_verdict(first, second):
    assert first.kinds == second.kinds
    assert first.degeneracy == second.degeneracy
    assert (first.dof, first.idle_freedoms, first.architecture_singular) == \
        (second.dof, second.idle_freedoms, second.architecture_singular)
    for kind in ("cspace", "actuator", "end_effector"):
        a, b = getattr(first, kind), getattr(second, kind)
        assert (a is None) == (b is None), kind
        if a is None:
            continue
        assert (a.rank, a.expected_rank) == (b.rank, b.expected_rank), kind
        np.testing.assert_allclose(decided_values(a), decided_values(b), rtol=1e-6, err_msg=kind)
    assert (first.manipulability is None) == (second.manipulability is None)


@pytest.mark.parametrize("name, configuration, factor", SCALED)
def test_a_change_of_length_unit_changes_no_verdict(name, configuration, factor):
    mechanism = catalogue_mechanism(name, configuration)
    assert_same_verdict(classified(mechanism), classified(scale_lengths(mechanism, factor)))


@pytest.mark.parametrize("name", SPHERICAL)
def test_a_spherical_mechanism_has_no_length_to_scale(name):
    """Why the spherical entries have no case above: their description (unit directions about the centre) is
    unchanged by a change of unit, so classifying the scaled copy would compare a result with itself."""
    from mechanisms.io import mechanism_to_dict

    mechanism = catalogue.entry(name).mechanism()
    assert mechanism_to_dict(scale_lengths(mechanism, 1e6)) == mechanism_to_dict(mechanism)


def test_scaling_multiplies_every_length():
    mechanism = catalogue.entry("slider-crank").mechanism()
    scaled = scale_lengths(mechanism, 1e6)
    assert scaled.characteristic_length == pytest.approx(1e6 * mechanism.characteristic_length, rel=1e-12)
    with pytest.raises(ValueError, match="positive finite"):
        scale_lengths(mechanism, 0.0)


@pytest.mark.parametrize("weight", [1e-12, 1e-6, 1e6, 1e12])
def test_actuator_weights_change_no_verdict(weight):
    """E's weights scale the manipulability values, never a rank: G = Tᵀ E T has the kernel of Dπ T."""
    mechanism = catalogue_mechanism("five-bar", "fig6a_distal_aligned")
    weighted = Mechanism(mechanism.name, mechanism.space,
                         [dataclasses.replace(joint, weight=weight) if joint.actuated else joint
                          for joint in mechanism.joints], mechanism.ground, mechanism.end_effector)
    assert_same_verdict(classified(mechanism), classified(weighted))


def _has_slides(name):
    return any(joint.type == "P" for joint in catalogue.entry(name).mechanism().joints)


@pytest.mark.parametrize("name, configuration, factor", [case for case in SCALED if _has_slides(case[0])])
def test_a_change_of_length_unit_changes_no_gosselin_angeles_verdict(name, configuration, factor):
    """The derived A and B (Gosselin & Angeles 1990) were cut on the raw actuator rows against an output scale
    taken without diag(s): a 3-PRR drawn in nanometres had B of rank 0 at its regular home ('unexplained'),
    the Gough–Stewart in micrometres kind I (found by an audit). They are now decided on Park–Kim's
    dimensionless rows."""
    from classify import compare

    rows = []
    for mechanism in (catalogue_mechanism(name, configuration),
                      scale_lengths(catalogue_mechanism(name, configuration), factor)):
        mechanism = shared_mechanism(mechanism)
        rows.append(compare(mechanism, [home(mechanism)], rng=np.random.default_rng(0)).rows[0])
    first, second = (row.gosselin_angeles for row in rows)
    assert (first.defined, first.kinds, first.undefined) == (second.defined, second.kinds, second.undefined)
    assert (rows[0].agree, rows[0].reason) == (rows[1].agree, rows[1].reason)
    for decision in ("input_decision", "output_decision"):
        a, b = getattr(first, decision), getattr(second, decision)
        assert (a is None) == (b is None)
        if a is not None:
            assert a.rank == b.rank
            np.testing.assert_allclose(a.singular_values, b.singular_values, rtol=1e-6, atol=1e-12)
