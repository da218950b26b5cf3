"""The grid continuation of ``closedchain map`` on a large mechanism: the blocks of DΦ solved apart, and a
regular start that no basis of the tangent space chooses.

Past :data:`manifold.implicit.BLOCK_THRESHOLD` coordinates the corrector's
and the predictor's minimum-norm solves (:func:`manifold.minimum_norm_steps`)
and the held coordinates' margins (:func:`manifold.scaled_singular_values`)
work block by block: the stack of dense c × k Jacobians of a 5 × 5 grid of
the RSUR stack at k = 400 took 32 s (180 s and 2 GB at k = 1000).
"""

import numpy as np
import pytest

from builders import ladder
from classify import grid_continuation
from classify.grid_continuation import assemble_grid, held_margins, regular_start
from manifold import JacobianPattern, implicit
from mechanisms import configuration, from_displacements, home
from mechanisms.catalogue import entry


def catalogue_point(name):
    """The five-bar of the catalogue and its named configuration `name`."""
    mechanism = entry("five-bar").mechanism(name)
    return mechanism, configuration(mechanism, {}).point


def grid(mechanism, values):
    """Targets of A1 and A2 on a square grid of `values`, the other joints at home; the held coordinates."""
    targets = np.array([from_displacements(mechanism, {"A1": first, "A2": second})
                        for first in values for second in values])
    return targets, tuple(sorted(mechanism.actuated_coordinates))


def test_a_large_grid_is_continued_block_by_block_as_densely(monkeypatch):
    mechanism = ladder(22)  # 88 joints, 66 free once the 22 actuated ones are held
    targets, held = grid(mechanism, np.linspace(-0.3, 0.3, 3))
    k = len(mechanism.joints)
    stacks = []
    dense = JacobianPattern.dense

    def recorded(pattern, entries):
        if pattern.shape[1] == k:
            stacks.append(np.ndim(entries) - 1)
        return dense(pattern, entries)

    monkeypatch.setattr(JacobianPattern, "dense", recorded)
    points, reached = assemble_grid(mechanism, home(mechanism), targets, (3, 3), held)
    margins = held_margins(mechanism, points, held)
    assert reached.all() and max(stacks, default=0) == 0  # no stack of whole Jacobians
    monkeypatch.setattr(implicit, "BLOCK_THRESHOLD", 10 ** 9)  # the dense solves
    expected, expected_reached = assemble_grid(mechanism, home(mechanism), targets, (3, 3), held)
    assert expected_reached.all()
    np.testing.assert_allclose(points, expected, atol=1e-9)
    np.testing.assert_allclose(margins, held_margins(mechanism, expected, held), rtol=1e-9)


def rocker_driven_ladder(loops):
    """A ladder whose first loop is a four-bar driven at its rocker C1 at the rocker's toggle (an actuator
    singularity at a regular point of M), the other loops as :func:`builders.ladder`'s (review of the block
    path of ``map``)."""
    from mechanisms import EndEffector, Joint, Mechanism

    joints = [Joint("A1", "R", ("ground", "left1"), point=(0.0, 0.0)),
              Joint("B1", "R", ("left1", "rung1"), point=(0.0, 1.0)),
              Joint("C1", "R", ("ground", "right1"), point=(2.0, 0.0), actuated=True),
              Joint("D1", "R", ("right1", "rung1"), point=(0.0, 2.0))]
    for index in range(2, loops + 1):
        below, above, tilt, height = f"rung{index - 1}", f"rung{index}", 0.1 + 0.3 * np.sin(index), index + 1.0
        joints += [Joint(f"A{index}", "R", (below, f"left{index}"), point=(0.0, height - 1), actuated=True),
                   Joint(f"B{index}", "R", (f"left{index}", above), point=(tilt, height)),
                   Joint(f"C{index}", "R", (below, f"right{index}"), point=(1.0, height - 1)),
                   Joint(f"D{index}", "R", (f"right{index}", above), point=(1.0 + tilt, height))]
    return Mechanism(f"rocker-driven ladder of {loops}", "planar", joints,
                     end_effector=EndEffector(f"rung{loops}", point=(0.5, loops + 1.0)))


@pytest.mark.parametrize("build", [lambda: rocker_driven_ladder(25), lambda: catalogue_point("fig6a_distal_aligned")],
                         ids=["rocker-driven ladder (blocks)", "five-bar fig6a (dense)"])
def test_the_regular_neighbour_does_not_depend_on_the_basis_of_the_tangent_space(build, monkeypatch):
    """regular_start stepped along the columns of whichever orthonormal basis of T_pM it was given: the SVD's
    (dense) or the blocks' (past BLOCK_THRESHOLD) chose another neighbour, from which ``map`` of the rocker-
    driven ladder over C1 × A2 (3 × 3) reached 3 grid points or 6. The directions are now each coordinate axis
    projected onto T_pM (grid_continuation.neighbour_directions): the same for any basis."""
    import manifold

    built = build()
    mechanism, start = built if isinstance(built, tuple) else (built, home(built))
    held = tuple(sorted(mechanism.actuated_coordinates))
    original = manifold.tangent_basis
    found = regular_start(mechanism, start, held)
    assert found.moved
    rng = np.random.default_rng(42)

    def rotated(space, point, **options):
        basis, decision = original(space, point, **options)
        turn = np.linalg.qr(rng.standard_normal((basis.shape[1],) * 2))[0]
        return basis @ turn, decision

    monkeypatch.setattr(manifold, "tangent_basis", rotated)
    again = regular_start(mechanism, start, held)
    np.testing.assert_allclose(again.point, found.point, atol=1e-9)
    assert again.margin == pytest.approx(found.margin, rel=1e-9)
    monkeypatch.setattr(grid_continuation, "NEIGHBOUR_CHUNK", 3)  # the axes a few at a time: the same choice
    chunked = regular_start(mechanism, start, held)
    np.testing.assert_allclose(chunked.point, again.point, atol=1e-9)
