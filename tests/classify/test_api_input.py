"""Bad input to the Python API refused with an error naming it, where it used to give a silently wrong result
(found by probing the public functions with bad and edge-case values)."""

import numpy as np
import pytest

from classify import classify, classify_many
from classify.loci import trace_loci
from manifold import numerical_rank
from mechanisms import ConfigurationError, MechanismError, catalogue, flip_axis, home, move_base, rehome, \
    scale_lengths


@pytest.fixture(scope="module")
def five_bar():
    mechanism = catalogue.entry("five-bar").mechanism()
    return mechanism, home(mechanism)


@pytest.mark.parametrize("rtol", [float("nan"), 0.0, -1.0, 1.0, 2.0, float("inf"), True])
def test_a_rank_cut_outside_zero_one_is_refused(rtol):
    """With rtol = NaN every rank was 0 and the slider-crank's fig. 3b actuator singularity came out regular."""
    mechanism = catalogue.entry("slider-crank").mechanism("fig3b_actuator")
    for call in (lambda: classify(mechanism, home(mechanism), rtol=rtol),
                 lambda: classify_many(mechanism, home(mechanism)[None], rtol=rtol),
                 lambda: numerical_rank(np.eye(2), rtol=rtol)):
        with pytest.raises(ValueError, match="rtol"):
            call()
    assert classify(mechanism, home(mechanism)).kinds == ("actuator",)


def test_flipping_a_joint_the_mechanism_lacks_is_refused(five_bar):
    mechanism, _ = five_bar
    with pytest.raises(ValueError, match="has no joint 'nope'"):
        flip_axis(mechanism, "nope")  # returned an unchanged copy


@pytest.mark.parametrize("pose, message", [
    (np.eye(4), "3×3 matrix for a planar mechanism"),        # its translation was dropped
    (np.zeros((3, 3)), "a rigid motion"),                   # every point went to the origin
    (np.diag([2.0, 2.0, 1.0]), "a rigid motion"),           # a scaling
    (np.diag([1.0, -1.0, 1.0]), "a rigid motion"),          # a mirror
    (np.full((3, 3), np.nan), "finite"),
])
def test_moving_the_base_by_what_is_not_a_rigid_motion_is_refused(five_bar, pose, message):
    mechanism, _ = five_bar
    with pytest.raises(ValueError, match=message):
        move_base(mechanism, pose)


def test_rehoming_at_a_point_off_the_configuration_space_is_refused(five_bar):
    """It built another mechanism (its proper values changed from [3717, 31] to [135, 39])."""
    mechanism, point = five_bar
    with pytest.raises(ValueError, match="does not close the loops"):
        rehome(mechanism, point + 0.3)
    with pytest.raises(ValueError, match="one configuration"):
        rehome(mechanism, point[None])


def test_the_result_of_classify_many_keeps_the_points_it_classified(five_bar):
    mechanism, point = five_bar
    points = np.repeat(point[None], 3, axis=0)
    result = classify_many(mechanism, points)
    points[0] += 0.3  # the caller's array, changed afterwards
    assert not np.shares_memory(result.points, points)
    assert result.report(0).kinds == ()


@pytest.mark.parametrize("chunk", [0, -1, 1.5, True, "3", float("nan")])
def test_a_chunk_that_is_not_a_positive_integer_is_refused(five_bar, chunk):
    mechanism, point = five_bar
    with pytest.raises(ValueError, match="chunk"):
        classify_many(mechanism, point[None], chunk=chunk)


def test_loci_from_a_start_off_the_configuration_space_or_of_unknown_kinds_are_refused(five_bar):
    """From a start that does not close, the loci came out empty; a misspelt kind was ignored."""
    mechanism, point = five_bar
    with pytest.raises(ConfigurationError, match="the start is not a configuration of M"):
        trace_loci(mechanism, point + 0.3, counts=(8, 8))
    for kinds in (("bogus",), ("ACTUATOR",), "actuator"):
        with pytest.raises(ValueError, match="kinds must be a sequence of"):
            trace_loci(mechanism, point, counts=(8, 8), kinds=kinds)


@pytest.mark.parametrize("factor", [1e-100, 1e-170, 1e-300])
def test_a_geometry_too_small_is_refused_at_any_scale(five_bar, factor):
    """At 1e-170 the squared distances underflowed to 0: the mechanism was taken for coincident points, with a
    characteristic length of 1, and classified with 3 dof instead of 2."""
    mechanism, _ = five_bar
    with pytest.raises(MechanismError, match="the geometry is too small"):
        scale_lengths(mechanism, factor)


@pytest.mark.parametrize("name, parameters, expected", [
    ("slider-crank", {"crank": "1"}, "'crank': expected a number"),        # a TypeError inside the builder
    ("five-bar", {"actuated": 3}, "'actuated': expected text"),            # an AttributeError ('split')
    ("eclipse", {"x": "1"}, "'x': expected a number"),                     # a UFuncTypeError
    ("slider-crank", {"end_effector": "yes"}, "'end_effector': expected true or false"),  # read as true
    ("five-bar", {"assembly": 1.5}, "'assembly': expected an integer"),
    ("five-bar", {"base": True}, "'base': expected a number"),
])
def test_a_catalogue_parameter_of_the_wrong_type_is_refused_naming_it(name, parameters, expected):
    with pytest.raises(MechanismError, match=expected):
        catalogue.entry(name).mechanism(**parameters)
    assert catalogue.entry("five-bar").mechanism(base=np.float64(6.0), assembly=np.int64(1)).joints


def test_projection_and_tangent_basis_refuse_a_point_that_is_not_one_finite_point(five_bar):
    """NaN ended in LAPACK's 'SVD did not converge' (and LAPACK's own message on stderr); a stack in
    '3-dimensional array given'."""
    from classify import model_of
    from manifold import project, tangent_basis

    mechanism, point = five_bar
    manifold = model_of(mechanism).manifold
    for function in (project, tangent_basis):
        with pytest.raises(ValueError, match="non-finite coordinates"):
            function(manifold, point * np.nan)
        with pytest.raises(ValueError, match="expected one point of shape"):
            function(manifold, np.stack([point, point]))


def test_the_remaining_silent_readings_are_refused(five_bar):
    """A length scale 1e300 overflowed in L²; configuration(m, 0) gave the home; a matrix with infinity had rank
    0; scale_lengths read '2' as 2 and True as 1."""
    from classify.cli._common import LENGTH_SCALE_RATIO as COMMAND_RATIO
    from classify.metrics import LENGTH_SCALE_RATIO
    from mechanisms import configuration

    assert COMMAND_RATIO == LENGTH_SCALE_RATIO  # the command's copy (it starts without NumPy)
    mechanism, point = five_bar
    pose = catalogue.entry("planar-3rrr").mechanism()
    with pytest.raises(ValueError, match="length scale within a factor 1e\\+06"):
        classify(pose, home(pose), length_scale=1e300)
    for displacements in (0, [], ""):
        with pytest.raises(ConfigurationError, match="expected a mapping of joint names"):
            configuration(mechanism, displacements)
    with pytest.raises(ValueError, match="finite numbers"):
        numerical_rank([[np.inf, 0.0], [0.0, 1.0]])
    for factor in ("2", True):
        with pytest.raises(ValueError, match="positive finite factor"):
            scale_lengths(mechanism, factor)


@pytest.mark.parametrize("options, message", [
    ({"columns": (0, -5)}, "columns are coordinate numbers from 0 to 4"),  # -5 wrapped round to column 0
    ({"columns": (0, 99)}, "columns are coordinate numbers"),             # an IndexError
    ({"counts": (2.5, 8)}, "counts are whole numbers"),                   # read as 2
    ({"counts": ("8", "8")}, "counts are whole numbers"),
    ({"ranges": ((0.0, np.nan), None)}, "each None or two finite numbers"),  # empty loci
    ({"ranges": ((0, 1), (0, 1), (0, 1))}, "at most 2 ranges"),           # the third was dropped
])
def test_a_locus_grid_is_refused_when_it_is_not_what_it_says(five_bar, options, message):
    mechanism, point = five_bar
    with pytest.raises(ValueError, match=message):
        trace_loci(mechanism, point, **{"counts": (8, 8), **options})
