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

#: relative cut of the plane and line tests of :func:`design_from_mechanism`, a fraction of the size of the legs'
#: attachments (their largest distance from their centroid, which no rigid motion of the file changes): a mechanism
#: file written by hand carries about six significant digits, errors up to 5e-7 of its coordinates; 1e-5 leaves a
#: margin for a file whose origin lies within a few sizes of the robot
FILE_RTOL = 1e-5


def design_from_mechanism(mechanism, rtol=FILE_RTOL):
    """The line-plane design and home pose of a 5-SPU joint graph (as the catalogue's ``5-spu`` builds it).

    Each leg is a chain ground –S– cylinder –P– piston –U (or R)– platform,
    the five legs ending on one platform link. The S centres are the base
    attachments and must be coplanar (Π); the U (R) centres at home are the
    platform attachments and must be collinear (Λ). The design is read in
    the frame of Π, always fitted: the file's frame shifted along the fitted
    normal of Π (its offset subtracted) and turned by the least rotation
    that takes that normal to +z, so that Π is z = 0 (when Π is the file's
    plane z = c, the frame is the file's lowered by c). The tolerance of
    both tests is rtol times the size of the attachments (their largest
    distance from their centroid), so that a rigid motion of the file
    changes neither the verdicts nor the design: a point off Π or Λ by more
    is refused, never projected. The origin p of Λ
    is the end-effector point when it lies on Λ, else the platform
    attachment of the first leg; i is the second axis of the first U joint
    (in the order of the legs) when it lies along Λ, else the direction
    from the first leg's platform attachment towards the last one's.

    Parameters
    ----------
    mechanism : Mechanism
    rtol : float
        Relative cut of the plane and line tests: a distance from the fitted
        plane or line at most rtol × the size of the attachments (the largest
        distance of an S or U centre from the centroid of the ten) is
        rounding (:data:`FILE_RTOL`).

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
    points = np.concatenate([base, attachments])
    # a size no rigid motion of the file changes (the largest coordinate made the cuts frame-dependent)
    scale = max(float(np.max(np.linalg.norm(points - points.mean(axis=0), axis=1))), 1e-300)
    frame = _base_frame(base, rtol * scale)
    base, attachments = frame(base), frame(attachments)
    centre = attachments.mean(axis=0)
    _, singular_values, rows = np.linalg.svd(attachments - centre)
    direction = rows[0]
    if singular_values[1] > rtol * scale:
        raise DesignError(f"mechanism: the platform attachments (U joints) must be collinear (the line Λ): they lie "
                          f"{singular_values[1]:.3g} from the best line, more than {rtol:g} × {scale:.3g} (the "
                          f"size of the attachments)",
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

    Always fitted (the offset of Π subtracted, whatever its size): a shift
    along the fitted normal n (n_z ≥ 0) by the plane's offset n·c̄, then the
    least rotation turning n to +z (the identity when n = +z). With
    ``vector=True`` the rotation alone. Raises DesignError when the
    attachments lie farther than `tolerance` from the fitted plane.
    """
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
