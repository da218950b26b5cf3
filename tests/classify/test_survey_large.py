"""The survey of a large mechanism handled block by block: a stack of spatial RSUR loops (one block each)."""

import math

import numpy as np

from builders import rsur_stack
from classify import model_of
from classify.survey import survey

LOOPS = 60


def test_every_random_start_of_a_stack_of_loops_reaches_m_with_work_linear_in_the_loops(monkeypatch):
    """Projected whole, every one of the 24 random starts had a loop stuck at a critical point and failed (25
    samples: the walk alone), after about 1800 block decompositions per loop (100 iterations of each start);
    settled block by block, each stuck loop drawn again, all 24 reach M."""
    decomposed = [0]
    svd = np.linalg.svd

    def counted(matrices, *arguments, **options):
        decomposed[0] += math.prod(np.shape(matrices)[:-2])
        return svd(matrices, *arguments, **options)

    monkeypatch.setattr(np.linalg, "svd", counted)
    model = model_of(rsur_stack(LOOPS))
    found = survey(model, np.random.default_rng(0))
    assert found.samples == 1 + 24 + 24
    assert (found.constraint_rank, found.actuator_rank, found.end_effector_rank, found.joint_rank) == \
        (6 * LOOPS, LOOPS, 6, LOOPS)
    assert decomposed[0] <= 1000 * LOOPS
