"""Structures that cannot move but flex infinitesimally: M is a point where DΦ loses rank.

A triangle with its sides flat (1 + 1 = 2) or a four-bar fully stretched (1 + 1 + 1 = 3) closes in one
configuration only, and there DΦ has rank 2 of its 3 rows. Every sample of M near p is p itself, so the
rank of DΦ on M near p is 2 and k − 2 overstated the degrees of freedom (1 and 2): the point was called
regular. ``manifold.tangent_extent`` finds that M extends along none of the directions of ker DΦ(p): a
C-space singularity with m = 0 (Park & Kim 1999, Section 3: DΦ drops rank where M is not a manifold of the
dimension its rank says).
"""

import numpy as np
import pytest

from builders import bennett, flat_triangle, stretched_four_bar
from classify import classify, classify_many
from manifold import AmbientSpace, ImplicitManifold, tangent_basis, tangent_extent
from mechanisms import EndEffector, Joint, Mechanism, home


@pytest.mark.parametrize("build, flexes", [(flat_triangle, 1), (stretched_four_bar, 2)])
@pytest.mark.parametrize("order, offset", [(None, (0.0, 0.0)), ("reversed", (0.0, 0.0)), (None, (30.0, -40.0))])
def test_a_structure_that_only_flexes_is_a_cspace_singularity_with_no_freedom(build, flexes, order, offset):
    count = 3 if build is flat_triangle else 4
    mechanism = build(tuple(range(count))[::-1] if order == "reversed" else tuple(range(count)), offset)
    report = classify(mechanism, home(mechanism))
    assert report.dof == 0 and report.kinds == ("cspace",)
    assert (report.cspace.rank, report.cspace.expected_rank) == (2, 3)
    assert report.cspace.kernel.shape[1] == flexes
    assert not report.actuator.singular and report.idle_freedoms == 0
    assert report.moving_idle_freedoms == 0  # the four-bar was said to move its end-effector with the actuator locked
    cspace = report.to_dict()["cspace"]  # the verdict's margin: every secant far below the cut
    assert len(cspace["secant_singular_values"]) == flexes and max(cspace["secant_singular_values"]) < 0.01
    assert cspace["secant_cut"] == 0.5


def test_the_batch_gives_the_flexes_as_the_single_call():
    mechanism = stretched_four_bar()
    stack = np.stack([home(mechanism)] * 3)
    batch = classify_many(mechanism, stack)
    for item in range(3):
        assert batch.report(item).to_dict() == classify(mechanism, stack[item]).to_dict()
    assert list(batch.arrays()["dof"]) == [0, 0, 0]


def test_an_overconstrained_chain_keeps_the_batch_where_it_moves(monkeypatch):
    """Bennett's 4R (rank 3 of 6 rows on M): the extent test is batched, and its configurations, where M is a
    curve, stay on the array path (no single call during the batch), equal to single calls."""
    import classify.batch as batch_module
    from classify import model_of
    from manifold import sample_manifold

    mechanism = bennett()
    model = model_of(mechanism)
    points = sample_manifold(model.manifold, np.random.default_rng(5), model.starts, random_count=0,
                             walk_count=12)
    single = batch_module.classify
    calls = []
    monkeypatch.setattr(batch_module, "classify", lambda *arguments, **options: (calls.append(1),
                                                                                  single(*arguments, **options))[1])
    batch = classify_many(model, points)
    assert calls == []
    monkeypatch.undo()
    for item in range(len(points)):
        assert batch.report(item).kinds == classify(model, points[item]).kinds
    assert list(batch.arrays()["dof"]) == [1] * len(points)


def test_an_overconstrained_linkage_that_moves_is_not_taken_for_a_flex():
    """Bennett's 4R: DΦ has rank 3 of its 6 rows on all of M, which is a curve (m = 1 despite Grübler's −2)."""
    mechanism = bennett()
    report = classify(mechanism, home(mechanism))
    assert report.dof == 1 and report.kinds == ()


def test_tangent_extent_of_a_circle_and_of_an_isolated_point():
    circle = ImplicitManifold(AmbientSpace(("R", "R")), lambda p: (p * p).sum(-1, keepdims=True) - 1.0,
                              lambda p: 2 * p[..., None, :])
    point = np.array([0.6, 0.8])
    extent = tangent_extent(circle, point, tangent_basis(circle, point)[0])
    assert extent.extent == 1 and extent.still.shape == (2, 0)
    assert abs(extent.singular_values[0] - 1.0) < 1e-2
    isolated = ImplicitManifold(AmbientSpace(("R", "R")), lambda p: (p * p).sum(-1, keepdims=True),
                                lambda p: 2 * p[..., None, :])
    origin = np.zeros(2)
    basis = tangent_basis(isolated, origin)[0]
    assert basis.shape[1] == 2
    extent = tangent_extent(isolated, origin, basis)
    assert extent.extent == 0 and extent.still.shape == (2, 2) and np.all(extent.singular_values < 0.5)


def stretched_four_bar_carrying_a_four_bar():
    """A four-bar J fully stretched (it cannot move, only flex) whose middle link carries a generic four-bar K
    driven at K1: M is K's curve, and at every point of M ker DΦ adds J's two flexes."""
    joints = [Joint("J1", "R", ("ground", "a"), point=(0.0, 0.0)), Joint("J2", "R", ("a", "b"), point=(1.0, 0.0)),
              Joint("J3", "R", ("b", "c"), point=(2.0, 0.0)), Joint("J4", "R", ("c", "ground"), point=(3.0, 0.0)),
              Joint("K1", "R", ("b", "d"), point=(1.5, 0.0), actuated=True),
              Joint("K2", "R", ("d", "e"), point=(1.9, 1.2)), Joint("K3", "R", ("e", "f"), point=(3.4, 1.6)),
              Joint("K4", "R", ("f", "ground"), point=(3.8, 0.2))]
    return Mechanism("flex and four-bar", "planar", joints, end_effector=EndEffector("d", (1.7, 0.6), "position"))


def test_a_part_that_only_flexes_is_no_freedom_of_the_survey():
    """The survey took its ranks on ker DΦ, J's flexes included: the end-effector 'moved' with K1 locked, so
    the design was called architecturally singular (one moving idle freedom). Its ranks are now those on the
    directions M extends along (found by an invariance audit)."""
    mechanism = stretched_four_bar_carrying_a_four_bar()
    report = classify(mechanism, home(mechanism))
    assert report.kinds == ("cspace",) and report.dof == 1
    assert not report.architecture_singular and report.moving_idle_freedoms == 0 and report.idle_freedoms == 0
    assert (report.survey["actuator_rank"], report.survey["end_effector_rank"], report.survey["joint_rank"]) == (1,) * 3
    batch = classify_many(mechanism, home(mechanism)[None])
    assert batch.report(0).to_dict() == report.to_dict()


def test_a_point_off_a_flat_triangle_within_the_closure_tolerance_is_said_to_be_perhaps_off_m():
    """Flexed by 1e-5 the triangle closes to ‖Φ‖ = 5e-11 (the closure is quadratic there), within the closure
    tolerance, though M is the flat point alone: DΦ has σ₃ = 4e-6 and the point is called regular. The verdict
    cannot be right or wrong on M; the report now says the point may lie up to ‖Φ‖/σ₃ = 1.2e-5 from M, more than
    the rank cut. On M, and 1e-7 off (called singular, as on M), no such note."""
    from mechanisms import from_displacements

    mechanism = flat_triangle()
    notes = {}
    for offset in (0.0, 1e-7, 1e-5):
        point = from_displacements(mechanism, {"J1": offset, "J2": -2 * offset, "J3": offset})
        notes[offset] = [note for note in classify(mechanism, point).notes if "may lie up to" in note]
    assert notes[0.0] == notes[1e-7] == [] and len(notes[1e-5]) == 1
    assert "project p onto M" in notes[1e-5][0]
