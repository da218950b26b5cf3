"""Shared helpers of the classification tests."""

import numpy as np

from classify import classify
from mechanisms import home


def classified(mechanism, seed=0, **options):
    """The classification of a mechanism at its home, with a seeded rng."""
    return classify(mechanism, home(mechanism), rng=np.random.default_rng(seed), **options)
