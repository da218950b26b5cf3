"""The second- and higher-order tests on a large mechanism: no c×k×k or k×m×m array.

A ladder of 50 planar four-bar loops (200 joints, one actuated joint per
loop) at a configuration where one loop's dyad is stretched straight: its
actuator, locked, still lets the dyad's middle joint move to first order, an
actuator singularity that is nondegenerate (the locked loop is a structure:
the dyad's two links cannot reach farther than straight). Both tests work a
few columns of the tangent basis at a time, within a few times
:data:`manifold.implicit.CHUNK_ENTRIES` floats (checked with tracemalloc):
at the default (2²⁰ floats, 8 MiB) within 32 MiB where the dense D²Φ alone
would be c·k² floats = 46 MiB, and with the chunks lowered to 2¹⁵ floats
within 4 MiB, where the accelerations x''(T, T) alone would be k·m² floats
= 3.8 MiB.
"""

import tracemalloc

import numpy as np
import pytest

from classify.higher_order import higher_order_test
from classify.metrics import unit_rows
from classify.second_order import second_order_test
from manifold import implicit, numerical_rank, tangent_basis
from mechanisms import Joint, Mechanism, actuator_jacobian, configuration_space, home

LOOPS = 50
SINGULAR_LOOP = 20
#: (floats per chunk, bytes the tests may allocate at their peak): the default and small chunks
CHUNKS = [(None, 32 * 2 ** 20), (2 ** 15, 4 * 2 ** 20)]


def four_bar_ladder(loops, singular):
    """Four-bar loops stacked on the ground, the coupler of each the base of the next.

    Loop i has its base joints A_i = (0, i − 1) and C_i = (1, i − 1), its
    coupler (rung i) from B_i to D_i, and its actuated joint A_i. In every
    loop but `singular`, B_i = (0.2 + 0.1 sin i, i) and D_i = (1.3, i): a
    generic quadrilateral. In loop `singular`, D lies between B and C on the
    segment BC: the dyad B–D–C is straight, so with A locked (B fixed) D can
    still move to first order, perpendicular to BC.
    """
    joints = []
    for index in range(1, loops + 1):
        below, above = ("ground" if index == 1 else f"rung{index - 1}"), f"rung{index}"
        base_left, base_right = np.array([0.0, index - 1.0]), np.array([1.0, index - 1.0])
        if index == singular:
            top_left = np.array([0.1, float(index)])
            top_right = top_left + 0.6 * (base_right - top_left)
        else:
            top_left, top_right = np.array([0.2 + 0.1 * np.sin(index), float(index)]), np.array([1.3, float(index)])
        joints += [Joint(f"A{index}", "R", (below, f"left{index}"), point=tuple(base_left), actuated=True),
                   Joint(f"B{index}", "R", (f"left{index}", above), point=tuple(top_left)),
                   Joint(f"C{index}", "R", (below, f"right{index}"), point=tuple(base_right)),
                   Joint(f"D{index}", "R", (f"right{index}", above), point=tuple(top_right))]
    return Mechanism(f"four-bar ladder of {loops}", "planar", joints)


def traced_peak(function, *arguments, **options):
    """(result, peak bytes allocated while `function` ran), by tracemalloc (NumPy arrays included)."""
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        result = function(*arguments, **options)
        return result, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


@pytest.fixture(scope="module")
def singular_ladder():
    """(manifold, point, tangent basis, unit actuator rows) of the ladder at its home, actuator-singular."""
    mechanism = four_bar_ladder(LOOPS, SINGULAR_LOOP)
    manifold = configuration_space(mechanism)
    point = home(mechanism)
    basis, decision = tangent_basis(manifold, point)
    selection = unit_rows(actuator_jacobian(mechanism), manifold.ambient.tangent_scales)
    return manifold, point, basis, selection, decision


@pytest.fixture(params=CHUNKS, ids=["default chunks", "small chunks"])
def memory_bound(request, monkeypatch):
    """The memory bound of the tests, with :data:`manifold.implicit.CHUNK_ENTRIES` as the parameter says."""
    entries, bound = request.param
    if entries is not None:
        monkeypatch.setattr(implicit, "CHUNK_ENTRIES", entries)
    return bound


def test_the_ladder_is_large_regular_and_singular_in_one_actuator(singular_ladder):
    manifold, point, basis, selection, decision = singular_ladder
    size = manifold.ambient.dim
    assert size == 4 * LOOPS and decision.rank == 3 * LOOPS and basis.shape[1] == LOOPS
    assert 3 * LOOPS * size ** 2 * 8 > CHUNKS[0][1] and size * LOOPS ** 2 * 8 > 0.9 * CHUNKS[1][1]
    assert np.linalg.norm(manifold.constraint(point)) < 1e-12
    assert numerical_rank(selection @ basis).rank == LOOPS - 1


def test_second_order_test_of_a_large_ladder_stays_within_the_memory_bound(singular_ladder, memory_bound):
    manifold, point, basis, selection, _ = singular_ladder
    result, peak = traced_peak(second_order_test, manifold, point, basis, selection, np.random.default_rng(0))
    assert result.degeneracy == "nondegenerate" and result.root is None
    assert result.kernel.shape == (4 * LOOPS, 1) and result.smallest > 1e3 * result.tolerance
    assert peak < memory_bound, f"{peak / 2 ** 20:.1f} MiB"


def test_higher_order_test_of_a_large_ladder_stays_within_the_memory_bound(singular_ladder, memory_bound):
    manifold, point, basis, selection, _ = singular_ladder
    kernel = second_order_test(manifold, point, basis, selection, np.random.default_rng(0)).kernel
    result, peak = traced_peak(higher_order_test, manifold, point, basis, selection, kernel)
    assert (result.verdict, result.order) == ("isolated", 2) and result.obstruction > 1e3 * result.tolerance
    assert peak < memory_bound, f"{peak / 2 ** 20:.1f} MiB"
