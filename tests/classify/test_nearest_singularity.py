"""A degenerate actuator singularity moved a little along M (Park & Kim 1999 §3: degenerate = a self-motion).

The first-order test calls a point 1e-9 from a degenerate singularity singular (its cut is relative 1e-6), but
the fibre of the actuators through that point is no curve: the self-motion is certified from the nearest point
where the rank has really dropped (:mod:`classify.nearest_singularity`), and the report says how far it is.
"""

import numpy as np
import pytest
from scipy.stats import ortho_group

import classify.classification as classification
from classify import classify
from classify.nearest_singularity import NEAREST_SINGULARITY_DISTANCE, nearest_singularity
from manifold import hessian_form, project
from mechanisms import Joint, Mechanism, configuration_space, home, kinematics_of
from mechanisms.catalogue import entry

#: degenerate singularities of the catalogue whose self-motion leaves the singular set transversally
MOVED = [("five-bar", "sec34_elbows_coincide"), ("3-prr", "fig2_parallel_legs"), ("hybrid", "eq25_elbows_coincide"),
         ("gough-stewart", "eq84_leg1_zero_length")]


def moved_along(mechanism, size, seed):
    """A point of M at about `size` (dimensionless) from the mechanism's home, in a random direction."""
    manifold, space = configuration_space(mechanism), kinematics_of(mechanism).ambient
    step = size * space.tangent_scales * np.random.default_rng(seed).standard_normal(space.dim)
    return project(manifold, space.retract(home(mechanism), step))


@pytest.mark.parametrize("name, configuration", MOVED)
def test_a_degenerate_singularity_moved_along_m_stays_degenerate(name, configuration):
    mechanism = entry(name).mechanism(configuration)
    exact = classify(mechanism, home(mechanism))
    assert exact.degeneracy == "degenerate" and exact.second_order.self_motion.offset == 0.0
    offsets = []
    for size, seed in ((1e-11, 0), (1e-9, 1), (1e-7, 2)):
        moved = classify(mechanism, moved_along(mechanism, size, seed))
        assert moved.kinds == exact.kinds and moved.actuator.rank == exact.actuator.rank
        assert moved.degeneracy == "degenerate", (size, seed, moved.second_order.reason)
        motion = moved.second_order.self_motion
        assert motion.offset <= NEAREST_SINGULARITY_DISTANCE
        assert motion.largest_residual <= motion.cut and motion.distance >= motion.length
        entry_json = moved.to_dict()["actuator"]["second_order"]["self_motion"]
        assert entry_json["offset"] == motion.offset and entry_json["cut"] == motion.cut
        offsets.append(motion.offset)
    # a move along the self-motion keeps the fibre through the point itself; the others need the search
    assert max(offsets) > 0.0


@pytest.mark.xfail(strict=True, reason="the 3-RRR's singular set touches its self-motion to second order (σ of "
                   "the actuator block ~ d² off it): the nearest singular point found is one where the fibre is "
                   "no curve, and the higher-order test is unobstructed to order 5, so the verdict stays "
                   "undetermined (a search for the nearest *degenerate* point would need third derivatives)")
def test_the_planar_3rrr_distal_links_parallel_moved_stays_degenerate():
    mechanism = entry("planar-3rrr").mechanism("eq63_distal_links_parallel")
    assert classify(mechanism, moved_along(mechanism, 1e-9, 1)).degeneracy == "degenerate"


def test_the_nearest_singularity_has_the_rank_dropped():
    """At the five-bar's coincident elbows moved 1e-9 the extended system is solved to rounding, at a point
    about as far as the move, and the actuator block there has its smallest σ at rounding (it was 1e-10)."""
    mechanism = entry("five-bar").mechanism("sec34_elbows_coincide")
    point = moved_along(mechanism, 1e-9, 1)
    manifold = configuration_space(mechanism)
    report = classify(mechanism, point)
    selection = np.eye(manifold.ambient.dim)[[0, 4]]          # A and E, the actuated joints
    nearest, distance, residual = nearest_singularity(manifold, point, report.second_order.kernel, selection)
    assert residual < 1e-14 and 1e-11 < distance < 1e-8
    basis = np.linalg.svd(manifold.constraint_jacobian(nearest))[2][3:].T
    assert np.linalg.svd(selection @ basis, compute_uv=False)[-1] < 1e-14
    assert report.actuator.decision.singular_values[-1] > 1e-11


def test_the_extended_system_derivative_is_taylor_exact_on_ball_joints():
    """The derivative used by the search, ``D²Φ(u, W) + DΦ·B(u, W)``, matches central differences of
    ``DΦ(q ⊕ hu) W`` on the Gough–Stewart (ball joints: without B the error does not fall with h)."""
    mechanism = entry("gough-stewart").mechanism()
    manifold = configuration_space(mechanism)
    point, space = home(mechanism), manifold.ambient
    rng = np.random.default_rng(7)
    direction, vectors = rng.standard_normal(space.dim), rng.standard_normal((space.dim, 2))
    exact = (hessian_form(manifold, point, direction[:, None], vectors)[:, 0, :]
             + manifold.constraint_jacobian(point) @ space.bracket(direction[:, None], vectors)[:, 0, :])

    def error(size):
        plus, minus = space.retract(point, size * direction), space.retract(point, -size * direction)
        difference = (manifold.constraint_jacobian(plus) - manifold.constraint_jacobian(minus)) @ vectors
        return np.linalg.norm(difference / (2 * size) - exact)

    assert error(1e-3) / error(5e-4) == pytest.approx(4.0, rel=0.05)


def test_the_second_order_cut_does_not_depend_on_the_tangent_basis(monkeypatch):
    """A five-bar with short proximal links (0.01) and aligned distal links (Park & Kim Fig. 6a's kind,
    nondegenerate): the accelerations of M exceed 1 there, so they set the cut, which was taken as their largest
    entry over the basis's pairs and moved by 2× with the basis the SVD returned."""
    links = ["ground", "proximal1", "distal1", "distal2", "proximal2", "ground"]
    points = [(0, 0), (0, 0.01), (0.5, 0.01), (1, 0.01), (1, 0)]
    mechanism = Mechanism("short-cranks", "planar", [
        Joint(f"J{i + 1}", "R", (links[i], links[i + 1]), point=points[i], actuated=i in (0, 4)) for i in range(5)])
    reference = classify(mechanism, home(mechanism)).second_order
    assert reference.degeneracy == "nondegenerate" and reference.tolerance > 1e-6
    original, rng = classification.tangent_basis, np.random.default_rng(3)

    def rotated(manifold, point, **options):
        basis, decision = original(manifold, point, **options)
        return basis @ ortho_group.rvs(basis.shape[1], random_state=rng), decision

    monkeypatch.setattr(classification, "tangent_basis", rotated)
    for _ in range(3):
        again = classify(mechanism, home(mechanism)).second_order
        assert again.tolerance == pytest.approx(reference.tolerance, rel=1e-12)
        assert again.smallest == pytest.approx(reference.smallest, rel=1e-12)
