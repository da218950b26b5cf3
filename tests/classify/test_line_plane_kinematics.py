"""Forward kinematics of line-plane 5-SPU platforms (Borràs, Thomas & Torras 2011): the polynomial route
(Section II-B, degrees by family, Section IV-C), the closedchain mechanism route (assemble from many starts),
and the quadratic family's closed forms (26)-(32)."""

import numpy as np
import pytest

from classify.line_plane import DesignError, family, line_plane_design, normalised
from classify.line_plane_kinematics import (
    assembly_modes, framework_assembly_modes, leg_lengths, polynomial_coefficients, quadratic_assembly_modes,
    quadratic_normal_form, quadratic_quantities, same_modes)

from test_line_plane import DELTA, QUADRATIC_BASE, cubic_design, quadratic_design, quartic_design

POSITION = np.array([0.4, -0.3, 2.5])
DIRECTION = np.array([0.2, 0.3, 0.9]) / np.linalg.norm([0.2, 0.3, 0.9])


def target_lengths(design):
    return leg_lengths(design, POSITION, DIRECTION)


def contains(modes, position, direction, length):
    return any(mode.real and np.linalg.norm(mode.position - position) < 1e-8 * length
               and np.linalg.norm(mode.direction - direction) < 1e-8 for mode in modes)


@pytest.mark.parametrize("make, count", [(quartic_design, 8), (cubic_design, 6), (quadratic_design, 4)])
def test_the_polynomial_route_gives_8_6_4_modes_and_the_real_ones_close(make, count):
    """Section II-B and IV-C: up to 8, 6, 4 assembly modes (complex included); real ones close to 1e-9."""
    design = make()
    lengths = target_lengths(design)
    modes = assembly_modes(design, lengths)
    assert len(modes) == count
    real = [mode for mode in modes if mode.real]
    assert len(real) >= 2 and real == list(modes[:len(real)])        # real first
    assert max(mode.residual for mode in real) < 1e-9
    assert np.allclose([np.linalg.norm(leg_lengths(design, mode.position, mode.direction) - lengths)
                        for mode in real], 0, atol=1e-9)
    assert contains(modes, POSITION, DIRECTION, design.characteristic_length)
    mirror = [1, 1, -1]
    assert contains(modes, POSITION * mirror, DIRECTION * mirror, design.characteristic_length)


def test_leading_coefficients_vanish_with_b_and_b_infinity_at_infinity():
    """Section IV-C: n₄ = 0 when B is at infinity (cubic); n₄ = n₃ = 0 when B∞ is too (quadratic)."""
    def relative(design):
        coefficients = polynomial_coefficients(normalised(design), target_lengths(design) /
                                               design.characteristic_length)
        return np.abs(coefficients) / np.max(np.abs(coefficients))
    quartic, cubic, quadratic = (relative(make()) for make in (quartic_design, cubic_design, quadratic_design))
    assert quartic[4] > 1e-3
    assert cubic[4] < 1e-14 and cubic[3] > 1e-3
    assert quadratic[4] < 1e-14 and quadratic[3] < 1e-14 and quadratic[2] > 1e-3


@pytest.mark.parametrize("make", [quartic_design, cubic_design, quadratic_design])
def test_the_closedchain_mechanism_route_finds_the_same_real_modes(make):
    """The 5-SPU joint graph, assembled at the lengths from random start poses, gives the polynomial's real modes."""
    design = make()
    lengths = target_lengths(design)
    modes = assembly_modes(design, lengths)
    real = sum(mode.real for mode in modes)
    found = framework_assembly_modes(design, lengths, rng=np.random.default_rng(3), starts=16, expected=real)
    assert len(found) == real
    assert same_modes(modes, found, design.characteristic_length)
    assert all(mode.closure <= 1e-10 and mode.residual < 1e-9 for mode in found)


def test_quadratic_closed_forms_eq29_to_32_give_the_four_modes():
    """(29), (31), (32) after the change to the normal form (26) — with opposite signs in (31) and (32)."""
    design = quadratic_design()
    lengths = target_lengths(design)
    closed = quadratic_assembly_modes(design, lengths)
    assert len(closed) == 4 and all(mode.real for mode in closed)
    assert max(mode.residual for mode in closed) < 1e-9
    assert same_modes(closed, assembly_modes(design, lengths), design.characteristic_length, tolerance=1e-8)


def test_the_printed_equal_signs_in_eq31_eq32_do_not_close_the_loops():
    """The paper prints ± in both (31) and (32); t = p·i forces p_z w = t − pₓu − p_yv, so only opposite signs
    close the legs (with the cofactor-consistent E₂…E₅ that reproduce n₂, n₁, n₀ and Δ exactly)."""
    design = quadratic_design()
    modes = quadratic_assembly_modes(design, target_lengths(design), pairing=1)
    assert min(mode.residual for mode in modes) > 0.1


def test_eq30_is_the_discriminant_of_the_quadratic_and_its_roots_are_p_dot_i():
    """Section V-A: n₂t² + n₁t + n₀ = 0 has the roots t = p·i of the modes; (30) = δ¹⁰F⁶(n₁² − 4n₂n₀)/4."""
    design = quadratic_design()
    form = quadratic_normal_form(design)
    assert form.delta == pytest.approx(DELTA) and form.deviation < 1e-14
    lengths = target_lengths(design)
    quantities = quadratic_quantities(form.x, form.y, form.delta, lengths)
    n2, n1, n0 = quantities["n"]
    F = quantities["F"]
    assert F == pytest.approx(225.0)
    assert quantities["discriminant"] == pytest.approx(DELTA ** 10 * F ** 6 * (n1 ** 2 - 4 * n2 * n0) / 4, rel=1e-10)
    roots = np.sort(np.roots([n2, n1, n0]).real)
    t = sorted({round(float(mode.position @ mode.direction), 9) for mode in assembly_modes(design, lengths)})
    assert np.allclose(roots, t, atol=1e-8)


def test_quadratic_closed_forms_in_any_frame():
    """A quadratic design turned, shifted, with Λ's origin moved: the normal form finds δ and the modes."""
    angle = 0.9
    turn = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    base = np.array(QUADRATIC_BASE) @ turn.T + [1.5, -0.5]
    design = line_plane_design(base[[2, 0, 4, 1, 3]], (DELTA * np.array(QUADRATIC_BASE)[:, 0] + 0.8)[[2, 0, 4, 1, 3]])
    assert family(design).name == "quadratic"
    lengths = leg_lengths(design, [2.0, 0.5, 2.2], [0.1, -0.4, 0.9])
    closed = quadratic_assembly_modes(design, lengths)
    assert quadratic_normal_form(design).delta == pytest.approx(DELTA)
    assert same_modes(closed, assembly_modes(design, lengths), design.characteristic_length, tolerance=1e-8)


def test_leg_lengths_batched_equal_single_and_bad_inputs_are_refused():
    design = quartic_design()
    rng = np.random.default_rng(4)
    positions, directions = rng.normal(size=(3, 4, 3)), rng.normal(size=(3, 4, 3))
    batched = leg_lengths(design, positions, directions)
    assert batched.shape == (3, 4, 5)
    assert np.allclose(batched[1, 2], leg_lengths(design, positions[1, 2], directions[1, 2]), rtol=0, atol=0)
    with pytest.raises(DesignError, match="five legs") as error:
        assembly_modes(design, [1, 2, 3, 4])
    assert error.value.field == "legs"
    with pytest.raises(DesignError, match="positive finite"):
        assembly_modes(design, [1, 2, np.inf, 4, 5])
    singular = line_plane_design([(0, 0), (1, 0.5), (2, 1), (0.3, 2), (-1, 1.2)], [0.4, 0.4, 0.4, -1.0, 1.3])
    with pytest.raises(DesignError, match="architecturally singular"):
        assembly_modes(singular, [1, 1, 1, 1, 1])
    with pytest.raises(DesignError, match="quadratic"):
        quadratic_assembly_modes(design, target_lengths(design))
