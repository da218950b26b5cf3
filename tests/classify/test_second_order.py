"""The second-order test on its own: common roots of forms on ker G, whatever basis K is given in."""

import functools

import numpy as np
import pytest
from scipy.stats import special_ortho_group

from classify.second_order import common_roots

TOLERANCE = 1e-9


def rotated(forms, rotation):
    """The same forms written in the basis K·rotation."""
    return np.einsum("ai,eab,bj->eij", rotation, forms, rotation)


def test_two_forms_without_common_root_are_separated():
    """Q₁ = x² − y², Q₂ = xy: no common nonzero root (x² + y² > 0 on the circle)."""
    forms = np.array([[[1.0, 0.0], [0.0, -1.0]], [[0.0, 0.5], [0.5, 0.0]]])
    smallest, roots = common_roots(forms, TOLERANCE, np.random.default_rng(0))
    assert smallest > 0.4 and len(roots) == 0


def test_two_forms_with_a_common_root_are_found():
    """Q₁ = xy, Q₂ = y²: common root v = (1, 0)."""
    forms = np.array([[[0.0, 0.5], [0.5, 0.0]], [[0.0, 0.0], [0.0, 1.0]]])
    smallest, roots = common_roots(forms, TOLERANCE, np.random.default_rng(0))
    assert smallest < 1e-12 and len(roots) == 1
    np.testing.assert_allclose(abs(roots[0, 0]), 1.0, atol=1e-6)


def test_three_dimensional_kernel_finds_every_common_root():
    """Q₁ = x² − y², Q₂ = z² − xy: common roots (1, 1, ±1)/√3 — both found, up to sign."""
    forms = np.array([np.diag([1.0, -1.0, 0.0]), [[0, -0.5, 0], [-0.5, 0, 0], [0, 0, 1.0]]])
    smallest, roots = common_roots(forms, 1e-8, np.random.default_rng(0))
    assert smallest < 1e-8
    expected = np.array([[1.0, 1.0, 1.0], [1.0, 1.0, -1.0]]) / np.sqrt(3)
    for root in expected:
        assert np.max(np.abs(roots @ root)) == pytest.approx(1.0, abs=1e-6)


def test_forms_vanishing_on_a_plane_give_its_directions():
    """Q = z² on ℝ³ vanishes on the whole plane z = 0 (the radical): roots span it."""
    forms = np.array([np.diag([0.0, 0.0, 1.0])])
    _, roots = common_roots(forms, TOLERANCE, np.random.default_rng(0))
    assert len(roots) >= 2
    assert np.all(roots[:, 2] ** 2 <= TOLERANCE)  # a root of z² is known to √tolerance
    assert np.linalg.matrix_rank(roots, tol=1e-3) == 2


#: Q₁ = x² − y², Q₂ = z² − xy (common roots (1, 1, ±1)/√3), in the basis of the rotation tests
KERNEL_FORMS = np.array([np.diag([1.0, -1.0, 0.0]), [[0, -0.5, 0], [-0.5, 0, 0], [0, 0, 1.0]]])


@functools.cache
def reference_roots():
    """The common roots of :data:`KERNEL_FORMS` in their own basis (seed 0), computed once for every rotation."""
    return common_roots(KERNEL_FORMS, 1e-8, np.random.default_rng(0))


@pytest.mark.parametrize("seed", range(20))
def test_roots_do_not_depend_on_the_basis_of_the_kernel(seed):
    """A rotated basis of K (as another LAPACK build may return) finds the same roots and the same
    smallest value, mapped by the rotation."""
    rng = np.random.default_rng(seed)
    forms = KERNEL_FORMS
    rotation = special_ortho_group.rvs(3, random_state=rng)
    smallest, roots = common_roots(rotated(forms, rotation), 1e-8, np.random.default_rng(seed))
    reference_smallest, reference = reference_roots()
    assert smallest < 1e-8 and reference_smallest < 1e-8
    mapped = roots @ rotation.T
    for root in reference:
        assert np.max(np.abs(mapped @ root)) == pytest.approx(1.0, abs=1e-6)
