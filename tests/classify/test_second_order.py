"""The second-order test on its own: forms on ker G, common roots, certificates."""

import numpy as np

from classify.second_order import _smallest_common_value


def test_two_forms_without_common_root_are_separated():
    """Q₁ = x² − y², Q₂ = xy: no common nonzero root (x² + y² > 0 on the circle)."""
    forms = np.array([[[1.0, 0.0], [0.0, -1.0]], [[0.0, 0.5], [0.5, 0.0]]])
    smallest, _ = _smallest_common_value(forms, np.random.default_rng(0))
    assert smallest > 0.4


def test_two_forms_with_a_common_root_are_found():
    """Q₁ = xy, Q₂ = y²: common root v = (1, 0)."""
    forms = np.array([[[0.0, 0.5], [0.5, 0.0]], [[0.0, 0.0], [0.0, 1.0]]])
    smallest, vector = _smallest_common_value(forms, np.random.default_rng(0))
    assert smallest < 1e-9
    np.testing.assert_allclose(abs(vector[0]), 1.0, atol=1e-6)


def test_three_dimensional_kernel_finds_the_common_root():
    """Q₁ = x² − y², Q₂ = z² − xy: common roots (1, 1, ±1)/√3."""
    forms = np.array([np.diag([1.0, -1.0, 0.0]), [[0, -0.5, 0], [-0.5, 0, 0], [0, 0, 1.0]]])
    smallest, vector = _smallest_common_value(forms, np.random.default_rng(0))
    assert smallest < 1e-6
    np.testing.assert_allclose(np.abs(vector), np.full(3, 1 / np.sqrt(3)), atol=1e-3)
