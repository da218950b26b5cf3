"""Shared helpers of the classification tests."""

import numpy as np

from builders import shared_mechanism
from classify import classify
from mechanisms import home


def classified(mechanism, seed=0, **options):
    """The classification of a mechanism at its home, with a seeded rng.

    The mechanism is classified through :func:`builders.shared_mechanism`: every
    test that classifies the same description shares one survey of M.
    """
    mechanism = shared_mechanism(mechanism)
    return classify(mechanism, home(mechanism), rng=np.random.default_rng(seed), **options)
