"""
Fig. 4b: a second isotropic configuration of the 3-PRR, γ = π/4
===============================================================

Chablat, Caro, Wenger & Angeles 2002, §3.3-3.4 and Fig. 4: K̄ = B⁻¹Ā is
isotropic (K̄K̄ᵀ = τ²1, eqs. 9a-f) under the conditions (10a-d) — pivots Cᵢ
on an equilateral triangle, equal legs BᵢCᵢ, the segments AᵢBᵢ and BᵢCᵢ
each on the sides of an equilateral triangle — and then the characteristic
length is L = √2 r sin γ, with γ = γᵢ = ∠BᵢCᵢP (eq. 8d). The paper draws two
isotropic configurations "with two values of γ": γ = π/2 (Fig. 4a) and
another one it does not state; here γ = π/4, so L = √2 r sin(π/4) = r.

The catalogue's ``3-prr`` (r = 100 mm, R = 200 mm, l = 200 mm) with the
operation point at the centre, P = O: by the design's threefold symmetry
the three γᵢ are equal for every orientation φ, so the legs satisfy (10a-d)
and turning the platform sets γ. φ is found by bisection on
:func:`classify.characteristic_length.three_prr_leg_angles` (γ falls from
π/2 at φ = π/3, Fig. 4a, to 0 at φ = 2π/3); κ(K̄) from
:func:`classify.characteristic_length.three_prr_kappa` (eqs. 4a-b) and
κ(J̄) of the catalogue mechanism from
:func:`classify.conditioning.mechanism_condition_numbers`, both with
L = √2 r sin γ (:func:`classify.characteristic_length.three_prr_length`).
"""

# %%
import math

from matplotlib.figure import Figure

from classify import classify
from classify.characteristic_length import three_prr_kappa, three_prr_leg_angles, three_prr_length
from classify.conditioning import mechanism_condition_numbers
from classify.conditioning_matrices import three_prr_pose_of
from classify.figures.drawing import draw_mechanism
from mechanisms import catalogue, configuration

RADIUS = 100.0  # r of the catalogue's design (mm)
GAMMA = math.pi / 4
MODE = (1, 1, 1)  # the signs of mᵢ: the catalogue's working mode 1


def leg_angle(phi):
    """γ₁ at P = O, orientation φ (all three are equal there)."""
    return float(three_prr_leg_angles([0.0, 0.0, phi], MODE)[0])


low, high = math.pi / 3, 2 * math.pi / 3  # γ = π/2 at low, 0 at high; it decreases in between
for _ in range(60):
    middle = 0.5 * (low + high)
    low, high = (middle, high) if leg_angle(middle) > GAMMA else (low, middle)
phi = 0.5 * (low + high)

entry = catalogue.entry("3-prr")
figure = Figure(figsize=(10, 5), layout="constrained")
for index, (name, angle, gamma) in enumerate((("Fig. 4a", math.pi / 3, math.pi / 2), ("Fig. 4b", phi, GAMMA))):
    mechanism = entry.build(x=0.0, y=0.0, phi=angle, working_mode=1)
    point = configuration(mechanism).point
    pose, signs = three_prr_pose_of(mechanism, point)
    found_gammas = three_prr_leg_angles(pose, signs)
    length = float(three_prr_length(RADIUS, gamma))
    kappa = float(three_prr_kappa(length, pose, signs, matrix="B-1A"))
    inverse_kappa = float(mechanism_condition_numbers(mechanism, point[None], length=length).inverse("A-1B")[0])
    report = classify(mechanism, point)
    draw_mechanism(mechanism, point, report=report, axes=figure.add_subplot(1, 2, index + 1),
                   title=f"{name}: γ = {math.degrees(gamma):.0f}°, φ = {math.degrees(angle):.2f}°\n"
                         f"L = {length:.2f} mm, κ(K̄) = {kappa:.6f}")
    print(f"{name}: φ = {angle:.9f} rad, γᵢ found = {', '.join(f'{value:.9f}' for value in found_gammas)} "
          f"(asked {gamma:.9f}); L = √2 r sin γ = {length:.6f} mm; κ(K̄) = {kappa:.12f}, "
          f"1/κ(J̄) of the mechanism = {inverse_kappa:.12f}; paper: κ = 1; "
          f"classify: {', '.join(report.kinds) or 'regular'}")
figure.suptitle("Chablat, Caro, Wenger & Angeles 2002 Fig. 4: two isotropic configurations "
                "with two values of γ (P at the centre)", fontsize=10)

# %%
# Both are isotropic: κ(K̄) = 1 to rounding with L = √2 r sin γ, γ = π/2
# (L = 141.42 mm, Fig. 4a) and γ = π/4 (L = 100 mm). The catalogue's
# design reaches every γ in (0, π/2] at P = O, so it needs no change; the
# paper does not say which γ its Fig. 4b uses, so the drawing matches its
# kind of configuration, not necessarily its exact posture. L differs
# between the two (141.42 mm and 100 mm), while the paper says "the
# characteristic length L of the manipulator is unique": read here as one L
# per isotropic configuration (L = √2 r sin γ), not one for all of them.
