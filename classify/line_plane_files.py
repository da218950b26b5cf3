"""A line-plane 5-SPU design read from a mechanism's joint graph (a mechanism file or the catalogue's ``5-spu``).

The legs S-P-U from the ground give the base attachments (the S centres, in
the base plane Π) and the platform attachments (the U centres, on the line
Λ) of the design of Borràs, Thomas & Torras 2011, Section II, read in the
frame of Π.

References
----------
Borràs, Thomas & Torras 2011, Section II, Fig. 1.
"""

from __future__ import annotations

import numpy as np

from .line_plane_design import DesignError, line_plane_design

__all__ = ["FILE_RTOL", "design_from_mechanism"]

#: relative cut of the plane and line tests of :func:`design_from_mechanism`: a mechanism file written by hand
#: carries about six significant digits, i.e. errors up to 5e-7 of its largest coordinate; 1e-5 leaves a margin
FILE_RTOL = 1e-5


def design_from_mechanism(mechanism, rtol=FILE_RTOL):
    """The line-plane design and home pose of a 5-SPU joint graph (as the catalogue's ``5-spu`` builds it).

    Each leg is a chain ground –S– cylinder –P– piston –U (or R)– platform,
    the five legs ending on one platform link. The S centres are the base
    attachments and must be coplanar (Π); the U (R) centres at home are the
    platform attachments and must be collinear (Λ). The design is read in
    the frame of Π: the file's frame when Π is its plane z = 0, else the
    file's frame moved by the least rotation that turns the normal of Π to
    +z, and shifted along that normal, so that Π is z = 0. The origin p of Λ
    is the end-effector point when it lies on Λ, else the platform
    attachment of the first leg; i is the second axis of the first U joint
    (in the order of the legs) when it lies along Λ, else the direction
    from the first leg's platform attachment towards the last one's.

    Parameters
    ----------
    mechanism : Mechanism
    rtol : float
        Relative cut of the plane and line tests: a distance from the fitted
        plane or line at most rtol × the largest coordinate (or the spread of
        the attachments, if larger) is rounding (:data:`FILE_RTOL`).

    Returns
    -------
    design : LinePlaneDesign
    position : ndarray, shape=[3]
        p at home, in the frame of Π.
    direction : ndarray, shape=[3]
        i at home, in the frame of Π.

    Raises
    ------
    DesignError
        Naming the joint or the field, when the graph is not a line-plane 5-SPU.
    """
    if mechanism.space != "spatial":
        raise DesignError(f"mechanism: a line-plane 5-SPU is spatial, got a {mechanism.space} mechanism", "mechanism")
    joints = mechanism.joints
    ground = mechanism.ground

    def joints_on(link, kind, exclude):
        return [joint for joint in joints if joint is not exclude and link in joint.links and joint.type in kind]

    base, attachments, platforms, axes = [], [], set(), []
    for spherical in (joint for joint in joints if joint.type == "S" and ground in joint.links):
        cylinder = spherical.links[1] if spherical.links[0] == ground else spherical.links[0]
        sliders = joints_on(cylinder, ("P",), spherical)
        if len(sliders) != 1:
            raise DesignError(f"mechanism: joint {spherical.name}: expected one prismatic joint on link "
                              f"{cylinder!r} (a leg S-P-U)", "mechanism")
        slider = sliders[0]
        piston = slider.links[1] if slider.links[0] == cylinder else slider.links[0]
        ends = joints_on(piston, ("U", "R"), slider)
        if len(ends) != 1:
            raise DesignError(f"mechanism: joint {slider.name}: expected one U (or R) joint on link {piston!r} "
                              f"(a leg S-P-U)", "mechanism")
        end = ends[0]
        platforms.add(end.links[1] if end.links[0] == piston else end.links[0])
        base.append(np.array(spherical.point, dtype=float))
        attachments.append(np.array(end.point, dtype=float))
        axes.append(np.array(end.axes[1], dtype=float) if end.type == "U" else None)
    if len(base) != 5:
        raise DesignError(f"mechanism: a line-plane 5-SPU has five S-P-U legs from the ground, found {len(base)}",
                          "mechanism")
    if len(platforms) != 1:
        raise DesignError(f"mechanism: the five legs must end on one platform link, found {sorted(platforms)}",
                          "mechanism")
    base, attachments = np.array(base), np.array(attachments)
    scale = max(float(np.max(np.abs(np.concatenate([base, attachments])))),
                float(np.ptp(base, axis=0).max()), float(np.ptp(attachments, axis=0).max()), 1e-300)
    frame = _base_frame(base, rtol * scale)
    base, attachments = frame(base), frame(attachments)
    centre = attachments.mean(axis=0)
    _, singular_values, rows = np.linalg.svd(attachments - centre)
    direction = rows[0]
    if singular_values[1] > rtol * scale:
        raise DesignError(f"mechanism: the platform attachments (U joints) must be collinear (the line Λ): they lie "
                          f"{singular_values[1]:.3g} from the best line, more than {rtol:g} × {scale:.3g}",
                          "mechanism")
    along = [frame(axis, vector=True) for axis in axes if axis is not None]
    # along Λ: sine of the angle ≤ 1e-3 (a rounded file is off by ~1e-6; an axis not along Λ is far off)
    if along and np.linalg.norm(np.cross(along[0], direction)) <= 1e-3 * np.linalg.norm(along[0]):
        direction = along[0] / np.linalg.norm(along[0])
    else:
        steps = (attachments - centre) @ direction
        direction = direction if steps[-1] >= steps[0] else -direction
    origin = attachments[0]
    effector = mechanism.end_effector
    if effector is not None and effector.point is not None and effector.link in platforms:
        point = frame(np.array(effector.point, dtype=float))
        if np.linalg.norm(np.cross(point - centre, direction)) <= rtol * scale:
            origin = point
    platform = (attachments - origin) @ direction
    design = line_plane_design(base[:, :2], platform)
    return design, origin, direction


def _base_frame(base, tolerance):
    """The change of frame that puts the plane of the base attachments at z = 0: points -> points, shape=[..., 3].

    The identity when the attachments already lie within `tolerance` of
    z = 0; else the least rotation turning the fitted normal n (n_z ≥ 0) to
    +z, after a shift along n. With ``vector=True`` the rotation alone.
    """
    if np.max(np.abs(base[:, 2])) <= tolerance:
        return lambda points, vector=False: np.asarray(points, dtype=float)
    centre = base.mean(axis=0)
    _, singular_values, rows = np.linalg.svd(base - centre)
    if singular_values[2] > tolerance:
        raise DesignError(f"mechanism: the S joints (base attachments) must be coplanar (the base plane Π): they lie "
                          f"{singular_values[2]:.3g} from the best plane, more than the cut {tolerance:.3g}",
                          "mechanism")
    normal = rows[2] if rows[2][2] >= 0 else -rows[2]
    axis = np.cross(normal, [0.0, 0.0, 1.0])
    skew = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    rotation = np.eye(3) + skew + skew @ skew / (1.0 + normal[2])      # Rodrigues, n -> +z
    shift = (normal @ centre) * normal

    def frame(points, vector=False):
        points = np.asarray(points, dtype=float)
        return points @ rotation.T if vector else (points - shift) @ rotation.T
    return frame
