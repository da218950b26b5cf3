"""The papers' own direct- and inverse-kinematics matrices A and B, vectorised over stacks of postures.

* The 3-PRR of Chablat, Caro, Wenger & Angeles 2002 (eqs. 3-4): A rows
  ``[lᵢᵀ, −lᵢᵀE(p − cᵢ)]``, B = diag(mᵢ), lᵢ = cᵢ − bᵢ, mᵢ = lᵢᵀαᵢ (eqs. 8a-c),
  in the catalogue's layout (:mod:`mechanisms.catalogue.three_prr`), posed by
  (x, y, φ) and a working mode (signs of mᵢ).
* The five-bar of Chablat, Wenger & Angeles 1998 (eqs. 3b-c):
  A = [(p − c)ᵀ; (p − d)ᵀ], B = diag(L1 L2 sin(θ3 − θ1), L3 L4 sin(θ4 − θ2)).
* The 3-dof hybrid of the same paper (eqs. 22a-b), in the frame turning with
  the five-bar's plane (i across AB, j along AB, k normal; the frame in which
  eq. 24 holds): A = [L2 kᵀ; (p − c)ᵀ; (p − d)ᵀ],
  B = L1 L2 diag(sin θ2 + λ1 sin θ4, sin(θ2 − θ4), sin(θ3 − θ5)), λ1 = L2/L1.

Every function returns ``(A, B, reachable)``; where a posture is out of reach
A and B are NaN.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "E", "three_prr_design", "three_prr_matrices", "three_prr_pose_of",
    "five_bar_leg_angles", "five_bar_matrices", "five_bar_inverse_kinematics", "five_bar_direct_kinematics",
    "hybrid_matrices",
]

#: the rotation by π/2 of both papers (Chablat et al. 2002 eq. 1; Chablat, Wenger & Angeles 1998 eq. 1)
E = np.array([[0.0, -1.0], [1.0, 0.0]])


def _unit(angles):
    return np.stack([np.cos(angles), np.sin(angles)], axis=-1)


# ------------------------------------------------------------------------------------------------ 3-PRR

def three_prr_design(platform_radius=100.0, base_radius=200.0, leg_length=200.0):
    """The 3-PRR layout of the catalogue: ``(r, l, vertices Aᵢ [3, 2], rail directions αᵢ [3, 2], aᵢ [3])``.

    Chablat, Caro, Wenger & Angeles 2002 §2 (Fig. 1); the design of Figs. 6-8 is
    r = 100, R = 200, l = 200 (mm).
    """
    from mechanisms.catalogue import three_prr as layout

    vertex_angles = np.radians([210.0, 330.0, 90.0])
    return (float(platform_radius), float(leg_length), layout.base_vertices(base_radius), layout.rail_directions(),
            vertex_angles)


def three_prr_matrices(poses, signs, platform_radius=100.0, base_radius=200.0, leg_length=200.0):
    """A (eq. 4a) and B (eq. 4b) of the 3-PRR at stacks of poses in working modes.

    Parameters
    ----------
    poses : array_like, shape=[..., 3]
        (x, y, φ): the operation point P and the platform orientation.
    signs : array_like, shape=[..., 3]
        The signs of mᵢ (the working mode, §3.5), ±1, broadcast against `poses`.
    platform_radius, base_radius, leg_length : float
        r, R, l.

    Returns
    -------
    direct : ndarray, shape=[..., 3, 3]
        A, columns (ẋ, ẏ, θ̇); the third column in length², the others in length.
    inverse : ndarray, shape=[..., 3, 3]
        B = diag(m₁, m₂, m₃).
    reachable : ndarray of bool, shape=[...]
        Every pivot Cᵢ within l of its rail.

    Notes
    -----
    With dᵢ = cᵢ − aᵢ, νᵢ = Eαᵢ: mᵢ = sᵢ √(l² − (νᵢᵀdᵢ)²) and lᵢ = (νᵢᵀdᵢ) νᵢ + mᵢ αᵢ (the
    catalogue's inverse kinematics, Bᵢ = Aᵢ + ρᵢαᵢ); row i of A is [lᵢᵀ, −lᵢᵀE(p − cᵢ)] (eq. 4a).
    """
    radius, length, vertices, directions, vertex_angles = three_prr_design(platform_radius, base_radius,
                                                                            leg_length)
    poses = np.asarray(poses, dtype=float)
    signs = np.broadcast_to(np.asarray(signs, dtype=float), poses.shape)
    position = poses[..., None, :2]
    pivots = position + radius * _unit(vertex_angles + poses[..., 2:3])          # cᵢ, [..., 3, 2]
    normals = directions @ E.T                                                    # νᵢ = Eαᵢ
    across = np.einsum("...ij,ij->...i", pivots - vertices, normals)
    reach = length ** 2 - across ** 2
    reach = np.where(np.abs(reach) <= 1e-12 * length ** 2, 0.0, reach)
    reachable = np.all(reach >= 0.0, axis=-1)
    diagonal = signs * np.sqrt(np.clip(reach, 0.0, None))                        # mᵢ
    legs = across[..., None] * normals + diagonal[..., None] * directions        # lᵢ
    moments = -np.einsum("...ij,jk,...ik->...i", legs, E, position - pivots)     # −lᵢᵀE(p − cᵢ)
    direct = np.concatenate([legs, moments[..., None]], axis=-1)
    inverse = diagonal[..., :, None] * np.eye(3)
    nan = np.where(reachable, 1.0, np.nan)[..., None, None]
    return direct * nan, inverse * nan, reachable


def three_prr_pose_of(mechanism, point):
    """(x, y, φ) and the signs of mᵢ of a catalogue 3-PRR at a configuration.

    Reads the links' poses (:func:`mechanisms.link_pose`): P is the home centroid of the pivots carried by the
    platform; φ = the home orientation (the angle of C₃ − P minus π/2) plus the platform's rotation; mᵢ from
    the slider Bᵢ carried by carriageᵢ.

    Returns
    -------
    pose : ndarray, shape=[3]
    signs : ndarray, shape=[3]
        sign of mᵢ = (cᵢ − bᵢ)ᵀαᵢ (+1 at 0).
    """
    from mechanisms import link_pose

    pivots_home = np.array([mechanism.joint(f"C{leg}").point for leg in (1, 2, 3)], dtype=float)
    sliders_home = np.array([mechanism.joint(f"B{leg}").point for leg in (1, 2, 3)], dtype=float)
    centre_home = pivots_home.mean(axis=0)
    phi_home = np.arctan2(*(pivots_home[2] - centre_home)[::-1]) - np.pi / 2
    platform = link_pose(mechanism, "platform", point)
    centre = (platform @ np.append(centre_home, 1.0))[:2]
    phi = phi_home + np.arctan2(platform[1, 0], platform[0, 0])
    pivots = (platform @ np.hstack([pivots_home, np.ones((3, 1))]).T).T[:, :2]
    sliders = np.array([(link_pose(mechanism, f"carriage{leg}", point) @ np.append(sliders_home[leg - 1], 1.0))[:2]
                        for leg in (1, 2, 3)])
    from mechanisms.catalogue import three_prr as layout

    diagonal = np.einsum("ij,ij->i", pivots - sliders, layout.rail_directions())
    return np.array([centre[0], centre[1], phi]), np.where(diagonal >= 0, 1.0, -1.0)


# ------------------------------------------------------------------------------------------------ five-bar

def five_bar_matrices(angles, proximal=8.0, distal=5.0, proximal_right=None, distal_right=None):
    """A (eq. 3b) and B (eq. 3c) of the five-bar at stacks of angles θ1..θ4.

    Parameters
    ----------
    angles : array_like, shape=[..., 4]
        θ1, θ2 (actuated, of C − A and D − B), θ3, θ4 (of P − C and P − D), from the direction AB.
    proximal, distal : float
        L1, L2; `proximal_right`, `distal_right` L3, L4 (default L1, L2: the symmetric design).

    Returns
    -------
    direct, inverse : ndarray, shape=[..., 2, 2]
    """
    angles = np.asarray(angles, dtype=float)
    proximal_right = proximal if proximal_right is None else proximal_right
    distal_right = distal if distal_right is None else distal_right
    theta1, theta2, theta3, theta4 = np.moveaxis(angles, -1, 0)
    direct = np.stack([distal * _unit(theta3), distal_right * _unit(theta4)], axis=-2)
    inverse = np.zeros(angles.shape[:-1] + (2, 2))
    inverse[..., 0, 0] = proximal * distal * np.sin(theta3 - theta1)
    inverse[..., 1, 1] = proximal_right * distal_right * np.sin(theta4 - theta2)
    return direct, inverse


def five_bar_leg_angles(points, base_point, proximal, distal, sign):
    """Inverse kinematics of one RR leg: the angles (of the proximal, of the distal link) reaching points.

    The proximal angle is atan2(w) − s ψ, cos ψ = (L1² + ρ² − L2²)/(2 L1 ρ), w = p − base, ρ = ‖w‖,
    ψ ∈ [0, π]; then sin(distal − proximal) has the sign s (or is 0).

    Returns
    -------
    proximal_angles, distal_angles : ndarray, shape=[...]
    reachable : ndarray of bool, shape=[...]
    """
    points = np.asarray(points, dtype=float)
    offset = points - np.asarray(base_point, dtype=float)
    distance = np.hypot(offset[..., 0], offset[..., 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        cosine = (proximal ** 2 + distance ** 2 - distal ** 2) / (2 * proximal * distance)
    cosine = np.where(np.abs(np.abs(cosine) - 1) <= 1e-12, np.sign(cosine), cosine)
    reachable = (np.abs(cosine) <= 1.0) & (distance > 0)
    proximal_angles = np.arctan2(offset[..., 1], offset[..., 0]) - sign * np.arccos(np.clip(cosine, -1.0, 1.0))
    elbows = proximal * _unit(proximal_angles)
    distal_vectors = offset - elbows
    distal_angles = np.arctan2(distal_vectors[..., 1], distal_vectors[..., 0])
    return (np.where(reachable, proximal_angles, np.nan), np.where(reachable, distal_angles, np.nan), reachable)


def five_bar_inverse_kinematics(points, signs, base=6.0, proximal=8.0, distal=5.0, proximal_right=None,
                                distal_right=None):
    """Angles θ1..θ4 reaching P = (x, y) in a working mode (Chablat, Wenger & Angeles 1998 §3.3).

    Parameters
    ----------
    points : array_like, shape=[..., 2]
    signs : tuple of two ±1
        The signs of sin(θ3 − θ1) and sin(θ4 − θ2), B's diagonal (eq. 3c).
    base, proximal, distal : float
        L0 = ‖AB‖, L1, L2 (the left leg).
    proximal_right, distal_right : float, optional
        L3, L4 (the right leg); default L1, L2 (the symmetric design of the paper's §4).

    Returns
    -------
    angles : ndarray, shape=[..., 4]
        NaN where out of reach.
    reachable : ndarray of bool, shape=[...]
    """
    proximal_right = proximal if proximal_right is None else proximal_right
    distal_right = distal if distal_right is None else distal_right
    theta1, theta3, left = five_bar_leg_angles(points, (0.0, 0.0), proximal, distal, signs[0])
    theta2, theta4, right = five_bar_leg_angles(points, (base, 0.0), proximal_right, distal_right, signs[1])
    return np.stack([theta1, theta2, theta3, theta4], axis=-1), left & right


def five_bar_direct_kinematics(inputs, assembly, base=6.0, proximal=8.0, distal=5.0):
    """Angles θ1..θ4 at actuated angles (θ1, θ2) on a branch of the direct kinematics.

    Parameters
    ----------
    inputs : array_like, shape=[..., 2]
    assembly : {1, -1}
        P to the left (+1) or right (−1) of C→D, as :func:`mechanisms.catalogue.five_bar.five_bar_points`.

    Returns
    -------
    angles : ndarray, shape=[..., 4]
    reachable : ndarray of bool, shape=[...]
        ‖CD‖ ≤ 2 L2 and C ≠ D.
    """
    inputs = np.asarray(inputs, dtype=float)
    elbow_left = proximal * _unit(inputs[..., 0])
    elbow_right = np.array([base, 0.0]) + proximal * _unit(inputs[..., 1])
    chord = elbow_right - elbow_left
    gap = np.hypot(chord[..., 0], chord[..., 1])
    height_squared = distal ** 2 - (gap / 2) ** 2
    reachable = (height_squared >= 0) & (gap > 1e-12 * (base + proximal))
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = chord / gap[..., None]
    height = assembly * np.sqrt(np.clip(height_squared, 0.0, None))
    point = elbow_left + chord / 2 + height[..., None] * (unit @ E.T)
    left, right = point - elbow_left, point - elbow_right
    angles = np.stack([inputs[..., 0], inputs[..., 1], np.arctan2(left[..., 1], left[..., 0]),
                       np.arctan2(right[..., 1], right[..., 0])], axis=-1)
    return np.where(reachable[..., None], angles, np.nan), reachable


# ------------------------------------------------------------------------------------------------ hybrid

def hybrid_matrices(angles, proximal=8.0, distal=5.0):
    """A (eq. 22a) and B (eq. 22b) of the 3-dof hybrid manipulator, in the plane's frame (i, j, k).

    Parameters
    ----------
    angles : array_like, shape=[..., 4]
        θ2, θ3 (actuated, of C − A and D − B), θ4, θ5 (of P − C and P − D), from the direction AB (the
        paper's numbering for Fig. 6; θ1, the turn about AB, does not enter A nor B).
    proximal, distal : float
        L1 = L3, L2 = L4.

    Returns
    -------
    direct, inverse : ndarray, shape=[..., 3, 3]
        Columns (ẋ, ẏ, ż) in the frame turning with the plane: i across AB, j along AB, k normal. A point of
        the plane at angle θ from AB and distance ρ is ρ (sin θ, cos θ, 0).
    """
    angles = np.asarray(angles, dtype=float)
    theta2, theta3, theta4, theta5 = np.moveaxis(angles, -1, 0)
    zero = np.zeros_like(theta2)
    def in_plane(angle):
        return np.stack([np.sin(angle), np.cos(angle), zero], axis=-1)
    normal = np.stack([zero, zero, np.ones_like(theta2)], axis=-1)
    direct = np.stack([distal * normal, distal * in_plane(theta4), distal * in_plane(theta5)], axis=-2)
    inverse = np.zeros(angles.shape[:-1] + (3, 3))
    inverse[..., 0, 0] = proximal * distal * (np.sin(theta2) + distal / proximal * np.sin(theta4))
    inverse[..., 1, 1] = proximal * distal * np.sin(theta2 - theta4)
    inverse[..., 2, 2] = proximal * distal * np.sin(theta3 - theta5)
    return direct, inverse
