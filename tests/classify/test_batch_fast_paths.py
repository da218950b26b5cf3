"""The fast paths of the batched first-order classification decide as the general ones (issue 11).

One-sided Jacobi for the singular values of small matrices, the Gram matrix's
eigenvalues for larger ones where certified, and the block-arrow kernel bases of mechanisms whose loops each own as
many joint coordinates as they have rows (Gough–Stewart, 3-RRR): each is
compared with the general computation, and a whole batch with the fast paths
switched off must give the same verdicts, ranks, margins and λ's.
"""

import numpy as np
import pytest

from classify import model_of
from classify import batch as batch_module
from classify import metrics
from classify.batch import _arrow_structure, kernel_bases, classify_many
from classify.metrics import jacobi_singular_values, singular_values
from manifold import sample_manifold
from mechanisms import catalogue


def test_jacobi_singular_values_equal_lapack_to_rounding():
    rng = np.random.default_rng(21)
    for shape in [(300, 3, 5), (200, 4, 4), (100, 3, 9), (100, 6, 9)]:
        matrices = rng.standard_normal(shape)
        matrices[:20, -1] = matrices[:20, 0] - 2.0 * matrices[:20, 1]  # rank deficient
        matrices[20:40] *= np.logspace(0, -7, shape[1])[:, None]  # graded rows, σ's down to 1e-7
        values, converged = jacobi_singular_values(matrices)
        expected = np.linalg.svd(matrices, compute_uv=False)
        assert converged.all()
        assert np.all(np.abs(values - expected) <= 2e-14 * expected[:, :1])
        # graded rows: the small σ's to high relative accuracy, not only to rounding of σ₁
        np.testing.assert_allclose(values[20:40], expected[20:40], rtol=1e-12)
    for scale in (1e-200, 1e200):  # squared norms would under- or overflow without scaling
        matrices = rng.standard_normal((20, 3, 5))
        values, converged = jacobi_singular_values(scale * matrices)
        assert converged.all()
        np.testing.assert_allclose(values / scale, np.linalg.svd(matrices, compute_uv=False), rtol=1e-13)
    _, converged = jacobi_singular_values(rng.standard_normal((50, 4, 6)), sweeps=1)
    assert not converged.all()  # one sweep does not orthogonalise: flagged, never used silently


def test_small_matrices_take_jacobi_and_tall_ones_are_transposed(monkeypatch):
    calls = []
    original = metrics.jacobi_singular_values
    monkeypatch.setattr(metrics, "jacobi_singular_values", lambda m, *a: calls.append(m.shape) or original(m, *a))
    rng = np.random.default_rng(22)
    for shape in [(80, 3, 3), (80, 5, 3), (2, 40, 4, 4), (40, 3, 3)]:
        matrices = rng.standard_normal(shape)
        expected = np.linalg.svd(matrices, compute_uv=False)
        values = singular_values(matrices)
        assert values.shape == expected.shape
        assert np.all(np.abs(values - expected) <= 2e-14 * expected[..., :1])
    assert calls == [(80, 3, 3), (80, 3, 5), (80, 4, 4)]  # a stack of 40: LAPACK


def test_gram_values_are_certified_or_lapacks():
    """σ's from the eigenvalues of J Jᵀ only where their error bound is below GRAM_ACCURACY: a
    well-conditioned stack agrees with LAPACK to it; ill-conditioned and rank-deficient matrices get
    LAPACK's values exactly."""
    rng = np.random.default_rng(26)
    matrices = rng.standard_normal((120, 6, 9))
    matrices[:10, 5] = matrices[:10, 0] + 1e-7 * matrices[:10, 1]   # σ₆ ≈ 1e-7 σ₁: near a cut
    matrices[10:20, 5] = matrices[10:20, 0]                          # rank 5
    expected = np.linalg.svd(matrices, compute_uv=False)
    values = batch_module._gram_values(matrices)
    np.testing.assert_array_equal(values[:20], expected[:20])
    conditioned = expected[20:, 0] / expected[20:, -1] < 20
    assert conditioned.sum() > 50
    np.testing.assert_allclose(values[20:][conditioned], expected[20:][conditioned], rtol=batch_module.GRAM_ACCURACY)


def _walked(name, count, seed, configuration=None):
    model = model_of(catalogue.entry(name).mechanism(configuration))
    points = sample_manifold(model.manifold, np.random.default_rng(seed), model.starts, random_count=2,
                             walk_count=count)
    return model, points


@pytest.mark.parametrize("name", ["gough-stewart", "planar-3rrr", "spherical-3rrr"])
def test_block_arrow_bases_span_the_kernel(name):
    model, points = _walked(name, 12, seed=24)
    structure = _arrow_structure(model)
    assert structure is not None
    legs, loops = {"gough-stewart": (6, 5), "planar-3rrr": (3, 2), "spherical-3rrr": (3, 2)}[name]
    assert len(structure.shared) == legs and structure.own.shape == (loops, legs)
    jacobian = model.manifold.constraint_jacobian(points) * model.manifold.ambient.tangent_scales
    rank = jacobian.shape[1]
    fast, general = kernel_bases(jacobian, rank, structure), kernel_bases(jacobian, rank)
    np.testing.assert_allclose(fast @ np.swapaxes(fast, -1, -2), general @ np.swapaxes(general, -1, -2), atol=1e-12)
    np.testing.assert_allclose(np.swapaxes(fast, -1, -2) @ fast, np.broadcast_to(np.eye(legs), (len(fast), legs, legs)),
                               atol=1e-12)
    # a loop's own block made singular: that configuration takes the general way, the others stay as they were
    # (a sample of M may itself have a singular own block: a random start can reach a leg of length zero)
    before = batch_module._arrow_bases(jacobian, structure)[1]
    assert (before <= batch_module.ARROW_CONDITION).sum() >= len(before) - 2
    broken = jacobian.copy()
    broken[0][np.ix_(structure.rows[0], structure.own[0])] = 0.0
    bases, condition = batch_module._arrow_bases(broken, structure)
    assert condition[0] == np.inf and np.array_equal(condition[1:], before[1:])
    kernel = kernel_bases(broken, rank, structure)
    assert np.abs(broken @ kernel).max() < 1e-12


def test_a_single_loop_has_no_arrow_structure():
    assert _arrow_structure(model_of(catalogue.entry("five-bar").mechanism())) is None


@pytest.mark.parametrize("name, configuration", [("planar-3rrr", "eq61_distal_links_concurrent"),
                                                 ("five-bar", "fig6a_distal_aligned"),
                                                 ("gough-stewart", "eq84_leg1_zero_length")])
def test_verdicts_do_not_depend_on_the_fast_paths(name, configuration, monkeypatch):
    """At a singular configuration of the papers (Gosselin & Angeles 1990 eqs. 61 and 84, Park & Kim 1999
    Fig. 6a) and configurations walked from it."""
    model, points = _walked(name, 4, seed=25, configuration=configuration)
    with monkeypatch.context() as patch:  # the fast paths of large stacks, on this small one
        patch.setattr(metrics, "JACOBI_STACK", 1)
        patch.setattr(batch_module, "JACOBI_STACK", 1)
        fast = classify_many(model, points)
    monkeypatch.setattr(metrics, "JACOBI_ROWS", 0)
    monkeypatch.setattr(batch_module, "GRAM_ACCURACY", 0.0)
    monkeypatch.setattr(batch_module, "_arrow_structure", lambda model: None)
    general = classify_many(model, points)
    np.testing.assert_array_equal(fast.singular, general.singular)
    assert fast.singular.any()  # singular configurations are among them
    for kind in fast.ranks:
        np.testing.assert_array_equal(fast.ranks[kind], general.ranks[kind])
        np.testing.assert_allclose(fast.margins[kind], general.margins[kind], rtol=1e-9, atol=1e-14)
    np.testing.assert_allclose(fast.eigenvalues, general.eigenvalues, rtol=1e-9)


# configurations found by a fuzz of batch against single calls: a σ within rounding of its cut (the batch's QR
# basis and the single call's SVD basis put it on different sides), and a regular point next to a C-space
# singularity, where the tangent basis is ill-conditioned (κ(DΦ·s) ≈ 1e5)
AT_THE_CUT = [
    ("five-bar", "fig6a_distal_aligned", "actuator",
     [7.329264695749452e-06, -9.061314503417678e-06, 3.464099615313914e-06, 5.597217888071264e-06,
      -7.329267695716954e-06]),
    # (the end-effector's cut has been rtol·σ₁ of every joint's rate since its reference stopped depending on
    # the joints' order: the point moved out along the same direction to the new cut)
    ("slider-crank", "fig3c_dead_centre", "end_effector",
     [1.9720265946025255e-06, -5.916079783815247e-06, 3.944053189212721e-06, -1.1666661857008451e-11]),
    ("watt-six-bar", "eq41_joints_2_4_branch_crossing", "actuator",
     [4.6483887272053743e-10, -0.0001043285116418037, 4.64838872697244e-10, -0.00010432758196405829,
      -4.769770661717097e-05, -0.00022445091751081692, -0.00037647620609204614]),
]


@pytest.mark.parametrize("name, configuration, kind, point", AT_THE_CUT, ids=[case[0] for case in AT_THE_CUT])
def test_a_configuration_the_batch_cannot_vouch_for_is_classified_one_at_a_time(name, configuration, kind, point):
    """Whichever side of its cut rounding puts σ on, the batch and the single call put it on the same one: the
    batch leaves the configuration to classify, so every column is the single call's (the margins exactly)."""
    from classify import classify

    model = model_of(catalogue.entry(name).mechanism(configuration))
    point = np.array(point)
    report = classify(model, point)
    decision = getattr(report, kind).decision
    assert abs(decision.margin[0 if decision.rank == len(decision.singular_values) else 1] / decision.tolerance
               - 1.0) < 1e-5  # the kept or dropped σ is at the cut
    result = classify_many(model, np.stack([point] * 3))  # in a stack, with its fast paths
    for index in range(3):
        assert result.kinds(index) == report.kinds
        for other in ("cspace", "actuator", "end_effector"):
            expected = [np.nan if value is None else value for value in getattr(report, other).decision.margin]
            np.testing.assert_array_equal(result.margins[other][index], expected)


def test_unsure_flags_values_near_the_cut_and_values_not_known_to_the_accuracy():
    values = np.array([[2.0, 1e-6 * (1 + 1e-9)],      # kept, at the cut: a decision that could go either way
                       [2.0, 1e-5],                   # clear of the cut, known to ε·κ
                       [2.0, 1e-5],                   # clear of the cut, but the error estimate is large
                       [2.0, 0.0],                    # a clear rank drop
                       [2.0, 1e-6 * (1 - 1e-9)],      # dropped, at the cut
                       [0.0, 0.0]])                   # rank 0: nothing kept
    tolerance = np.full(6, 1e-6)
    error = np.array([1e-16, 1e-16, 1e-13, 1e-16, 1e-16, 1e-16])
    _, margins = batch_module._decisions(values, tolerance)
    np.testing.assert_array_equal(batch_module._unsure(margins, tolerance, error),
                                  [True, False, True, False, True, False])
    np.testing.assert_array_equal(batch_module._unsure(margins, tolerance, error, reported=False),
                                  [True, False, False, False, True, False])


def test_the_error_estimate_grows_with_the_condition_of_dphi_and_of_the_arrow_blocks():
    error = batch_module.basis_error(np.array([4.0, 4.0, 4.0]), np.array([1.0, 1e-4, 2.0]),
                                     np.array([1.0, 1.0, 50.0]))
    eps = np.finfo(float).eps
    rounding = batch_module.BLOCK_ROUNDING
    np.testing.assert_allclose(error, [(4 + rounding) * eps, (4e4 + rounding) * eps, (50 + rounding) * eps])


def test_near_a_singularity_the_proper_values_agree_to_1e_9():
    """Next to the five-bar's folded right leg (a point of the fuzz): the kept end-effector σ is 1e-6 of its
    scale, and λ_min and the condition number (which go as σ²) differed by 1.06e-9 before the blocks' own
    rounding entered the estimate. (The fuzz's point moved out along M, to the same ratio 1 + 7.4e-7 of σ to its
    cut, when the end-effector's reference scale became every joint's rate, independent of the joints' order.)"""
    from classify import classify

    model = model_of(catalogue.entry("five-bar").mechanism("eq3c_right_leg_folded"))
    point = np.array([-3.2621986261440164e-07, -1.3294367396091237e-06, 4.44728135828601e-06,
                      -1.8880829548864085e-06, -9.035418011760759e-07])
    report = classify(model, point)
    result = classify_many(model, np.stack([point] * 80))
    for index in (0, 79):
        assert result.kinds(index) == report.kinds
        np.testing.assert_allclose(result.eigenvalues[index], report.manipulability.eigenvalues, rtol=1e-9)
        np.testing.assert_allclose(result.condition_number[index], report.manipulability.condition_number,
                                   rtol=1e-9)
