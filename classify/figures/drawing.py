"""Drawings of a mechanism at a configuration: links, joints, actuators, end-effector and lost directions.

A joint is drawn where its geometry puts it at the configuration: the home
point (planar, spatial) or home axis (spherical: a point of the unit sphere)
carried by the pose of its second link, ``link_pose(second, p) · x_home``
(:func:`mechanisms.link_pose`; at a closed configuration both links carry it
to the same place). A link is drawn through the places of its joints (and the
end-effector point when it is on the link): a segment for two, a closed
polygon for more, in the order of the mechanism's joints; on the unit sphere
as great-circle arcs. A P joint has no point: it is drawn as a short guide
along its axis through the first place of its second link. Ground joints are
joined by a dashed line. Actuated joints are filled squares, passive ones
open circles, the end-effector a star.

At a singularity, each lost direction (a column of the kernel of the kind's
map in :class:`classify.Report`: ker DΦ beyond the tangent space, ker G, or
ker J — Park & Kim 1999, Section 3) is a joint-rate vector v; it is drawn as
the velocities of the joint places, ``d/dt link_pose(L, p ⊕ t v) · x`` at
t = 0 (central differences, step 1e-6 in the dimensionless coordinates),
scaled so that the longest arrow is a quarter of the mechanism's
characteristic length (of the unit sphere's radius, 1, for a spherical
mechanism). Places that do not
move (speed below 1e-6 of the largest) get no arrow.

Cost. The links' poses come from one pass over the spanning tree
(:func:`mechanisms.kinematics.link_poses`), for a stack of configurations at
once: the configuration and its two displacements along every lost
direction. A drawing of k joints with m lost directions costs O(k) array
operations on stacks of 2m + 1 configurations, not one chain product from
the ground per joint and direction (O(k² m)).

Every artist carries a ``gid`` for the tests and for later pages (the
gallery, the HTML report): ``link:NAME``, ``ground``, ``guide:JOINT``,
``joint:NAME`` (passive), ``actuated:NAME``, ``end-effector``,
``lost:KIND`` (one quiver per lost direction), ``sphere``.

The axes are labelled x, y (and z) in the mechanism's unit of length
(:func:`length_unit`: ``"x (length unit)"`` — a mechanism file states no
unit, its lengths are in whatever unit it was written in); a spherical
mechanism's in units of the sphere's radius (``"x (unit sphere)"``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["joint_places", "link_places", "place_velocities", "draw_mechanism", "lost_directions", "save_figure",
           "length_unit", "ARROW_FRACTION", "KIND_COLOURS", "LENGTH_UNIT"]

#: the longest lost-direction arrow, as a fraction of the characteristic length (planar, spatial) or radius
ARROW_FRACTION = 0.25
#: colours of the lost directions, per kind (also used by :mod:`classify.figures.loci`)
KIND_COLOURS = {"actuator": "tab:red", "end_effector": "tab:blue", "cspace": "tab:purple"}
#: the unit of length shown on axes when the mechanism names none (a mechanism file states no unit)
LENGTH_UNIT = "length unit"
#: finite-difference step of the place velocities (dimensionless tangent coordinates)
_STEP = 1e-6
#: a place slower than this fraction of the fastest gets no arrow
_STILL = 1e-6


def _home_place(mechanism, joint):
    """The home place of a joint in homogeneous/axis form, or None (a P joint has no point)."""
    if mechanism.space == "spherical":
        axis = np.asarray(joint.axis, dtype=float)
        return axis / np.linalg.norm(axis)
    if joint.point is None:
        return None
    return np.append(np.asarray(joint.point, dtype=float), 1.0)


def _carry(mechanism, poses, link, home):
    """`home` (homogeneous point, or unit axis on the sphere) carried by the pose of `link`, shape=[n, d].

    `poses` are the links' poses at n configurations (:func:`mechanisms.kinematics.link_poses`), [n, s, s] each.
    """
    moved = poses[link] @ home
    return moved if mechanism.space == "spherical" else moved[..., :-1]


def _poses(mechanism, points):
    """Every link's pose at each configuration, one pass over the spanning tree: dict of [n, s, s]."""
    from mechanisms.kinematics import link_poses

    return link_poses(mechanism, np.atleast_2d(np.asarray(points, dtype=float)))


def _joint_places(mechanism, poses):
    """:func:`joint_places` from the links' poses (:func:`_poses`)."""
    places = {}
    for joint in mechanism.joints:
        home = _home_place(mechanism, joint)
        if home is not None:
            places[joint.name] = _carry(mechanism, poses, joint.links[1], home)
    return places


def joint_places(mechanism, points):
    """Where each joint is at each configuration.

    Parameters
    ----------
    mechanism : Mechanism
    points : ndarray, shape=[n, point_size]

    Returns
    -------
    dict of str to ndarray, shape=[n, d]
        Joint name → place (d = 2 planar, 3 spherical — a unit vector — and
        spatial); P joints are left out.
    """
    return _joint_places(mechanism, _poses(mechanism, points))


def _end_effector_place(mechanism, poses):
    """The end-effector point (or, on the sphere, the image of its link's first joint axis): [n, d] or None.

    `poses` are the links' poses at n configurations (:func:`_poses`).
    """
    end_effector = mechanism.end_effector
    if end_effector is None:
        return None
    if mechanism.space == "spherical":
        axis = next((joint.axis for joint in mechanism.joints if end_effector.link in joint.links), None)
        return None if axis is None else _carry(mechanism, poses, end_effector.link,
                                                np.asarray(axis, dtype=float) / np.linalg.norm(axis))
    if end_effector.point is None:
        return None
    home = np.append(np.asarray(end_effector.point, dtype=float), 1.0)
    return _carry(mechanism, poses, end_effector.link, home)


def link_places(mechanism, points):
    """The places a link is drawn through: its joints' (and the end-effector point on its link).

    Parameters
    ----------
    mechanism : Mechanism
    points : ndarray, shape=[n, point_size]

    Returns
    -------
    dict of str to list of ndarray, each shape=[n, d]
        Link name → its places in the order of the joints; the ground is included.
    """
    return _link_places(mechanism, _poses(mechanism, points))


def _link_places(mechanism, poses):
    """:func:`link_places` from the links' poses (:func:`_poses`)."""
    places = _joint_places(mechanism, poses)
    end_effector = _end_effector_place(mechanism, poses)
    result = {link: [] for link in mechanism.links}
    for joint in mechanism.joints:
        if joint.name in places:
            for link in joint.links:
                result[link].append(places[joint.name])
    if end_effector is not None:
        ones = result[mechanism.end_effector.link]
        if not any(np.allclose(place, end_effector) for place in ones):
            ones.append(end_effector)
    return result


def place_velocities(mechanism, point, direction):
    """Velocities of the joint places (and end-effector point) along joint-rate vectors.

    ``d/dt link_pose(L, p ⊕ t v) · x`` at t = 0, by central differences with
    step 1e-6 in the dimensionless tangent coordinates (over the norm of v
    divided by the tangent scales): the error is O(step²) plus rounding.
    Every direction is done at once: the links' poses at the configuration
    and at its 2m displacements come from one pass over the spanning tree
    (:func:`mechanisms.kinematics.link_poses`), O(k) array operations for
    all m directions.

    Parameters
    ----------
    mechanism : Mechanism
    point : ndarray, shape=[point_size]
    direction : ndarray, shape=[k] or [k, m]
        A joint-rate vector v (e.g. a column of a Report kind's kernel), or m of them as columns.

    Returns
    -------
    places : dict of str to ndarray, shape=[d]
        Keyed by joint name, and ``"end-effector"`` when it has a point.
    velocities : dict of str to ndarray, shape=[d] or [m, d]
        The same keys; one row per column of `direction` when it has two axes.

    Raises
    ------
    ValueError
        Where a direction is zero.
    """
    from mechanisms.kinematics import kinematics_of

    ambient = kinematics_of(mechanism).ambient
    point = np.asarray(point, dtype=float)
    direction = np.asarray(direction, dtype=float)
    directions = direction.reshape(direction.shape[0], -1).T                                  # [m, k]
    sizes = np.array([np.linalg.norm(column / ambient.tangent_scales) for column in directions])
    if np.any(sizes == 0):
        raise ValueError("the direction is zero")
    steps = _STEP / sizes                                                                     # [m]
    count = len(directions)
    stack = np.concatenate([point[None], ambient.retract(point, steps[:, None] * directions),
                            ambient.retract(point, -steps[:, None] * directions)])           # [1 + 2m, point_size]
    poses = _poses(mechanism, stack)
    places = _joint_places(mechanism, poses)
    end_effector = _end_effector_place(mechanism, poses)
    if end_effector is not None:
        places["end-effector"] = end_effector
    velocities = {name: (value[1:count + 1] - value[count + 1:]) / (2 * steps[:, None]) for name, value in
                  places.items()}                                                             # [m, d] each
    if direction.ndim == 1:
        velocities = {name: value[0] for name, value in velocities.items()}
    return {name: value[0] for name, value in places.items()}, velocities


def lost_directions(report, kinds=None):
    """The lost joint-rate directions of a report: a list of (kind, vector [k]) for each singular kind.

    Parameters
    ----------
    report : Report
    kinds : sequence of str, optional
        Which kinds (default every kind that holds).
    """
    directions = []
    for kind in report.kinds if kinds is None else kinds:
        result = getattr(report, kind)
        if result is None or not result.singular:
            continue
        directions += [(kind, column) for column in np.asarray(result.kernel).T]
    return directions


def _arc(first, second, count=24):
    """The great-circle arc between two unit vectors, shape=[count, 3]."""
    angle = np.arccos(np.clip(first @ second, -1.0, 1.0))
    if angle < 1e-9:
        return np.stack([first, second])
    weights = np.linspace(0.0, 1.0, count)
    arc = (np.sin((1 - weights)[:, None] * angle) * first + np.sin(weights[:, None] * angle) * second)
    return arc / np.sin(angle)


def _polyline(space, places):
    """The line through the places of a link: a segment, or a closed polygon (arcs on the sphere), [n, d]."""
    ring = list(places) + ([places[0]] if len(places) > 2 else [])
    if space != "spherical":
        return np.array(ring)
    return np.concatenate([_arc(first, second) for first, second in zip(ring[:-1], ring[1:])])


def _plot(axes, line, three, **style):
    line = np.asarray(line)
    if three:
        return axes.plot(line[:, 0], line[:, 1], line[:, 2], **style)[0]
    return axes.plot(line[:, 0], line[:, 1], **style)[0]


def draw_mechanism(mechanism, point, report=None, kinds=None, axes=None, title=None):
    """Draw a mechanism at a configuration (see the module notes).

    Parameters
    ----------
    mechanism : Mechanism
    point : ndarray, shape=[point_size]
        A configuration (on M for the lost directions to mean anything).
    report : Report, optional
        Its classification: the lost directions of the singular kinds are drawn as arrows.
    kinds : sequence of str, optional
        Which kinds' lost directions (default every kind that holds).
    axes : matplotlib Axes, optional
        Where to draw (3-D axes for spherical and spatial mechanisms); default a new Figure's.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    three = mechanism.space != "planar"
    if axes is None:
        figure = Figure(figsize=(6, 6))
        axes = figure.add_subplot(projection="3d" if three else None)
    figure = axes.figure
    point = np.asarray(point, dtype=float)
    if mechanism.space == "spherical":
        _sphere(axes)
    poses = _poses(mechanism, point[None])
    places = {name: value[0] for name, value in _joint_places(mechanism, poses).items()}
    links = _link_places(mechanism, poses)
    for link, ones in links.items():
        ones = [place[0] for place in ones]
        if link == mechanism.ground:
            if len(ones) >= 2:
                _plot(axes, _polyline(mechanism.space, ones[:2] if len(ones) == 2 else ones), three, color="0.4",
                      linestyle="--", linewidth=1.0, gid="ground")
            continue
        if len(ones) >= 2:
            _plot(axes, _polyline(mechanism.space, ones), three, color="0.15", linewidth=2.5, gid=f"link:{link}",
                  solid_capstyle="round")
    length = 1.0 if mechanism.space == "spherical" else mechanism.characteristic_length
    for joint in mechanism.joints:
        if joint.name not in places:
            _guide(axes, mechanism, poses, joint, links, length, three)
            continue
        style = (dict(marker="s", markersize=9, color="tab:orange", markeredgecolor="k")
                 if joint.actuated else dict(marker="o", markersize=7, markerfacecolor="white", color="k"))
        _plot(axes, places[joint.name][None], three, linestyle="none", zorder=5,
              gid=f"{'actuated' if joint.actuated else 'joint'}:{joint.name}", **style)
    end_effector = _end_effector_place(mechanism, poses)
    if end_effector is not None:
        _plot(axes, end_effector, three, linestyle="none", marker="*", markersize=14, color="tab:green",
              markeredgecolor="k", zorder=6, gid="end-effector")
    lost = [] if report is None else lost_directions(report, kinds)
    if lost:  # every direction's velocities from one stack of configurations
        starts, velocities = place_velocities(mechanism, point, np.stack([vector for _, vector in lost], axis=-1))
        for number, (kind, _) in enumerate(lost):
            _arrows(axes, starts, {name: value[number] for name, value in velocities.items()}, kind, length, three)
    _frame(axes, mechanism, point, three, length)
    if title is not None:
        axes.set_title(title)
    return figure


def _sphere(axes):
    """A light wireframe unit sphere."""
    azimuth, polar = np.meshgrid(np.linspace(0, 2 * np.pi, 25), np.linspace(0, np.pi, 13))
    axes.plot_wireframe(np.cos(azimuth) * np.sin(polar), np.sin(azimuth) * np.sin(polar), np.cos(polar),
                        color="0.85", linewidth=0.5, gid="sphere")


def _guide(axes, mechanism, poses, joint, links, length, three):
    """A P joint. Between two moving links (a leg's cylinder and piston): the segment from the first link's
    place to the second's. Off the ground (a slider): a short guide along its axis (turned with its first link)
    through the second link's place. `poses`: the links' poses at the configuration, [1, s, s] each."""
    first, second = links[joint.links[0]], links[joint.links[1]]
    style = dict(color="tab:orange" if joint.actuated else "0.3", linewidth=4, alpha=0.6, gid=f"guide:{joint.name}")
    if joint.links[0] != mechanism.ground and first and second:
        _plot(axes, np.stack([first[0][0], second[0][0]]), three, **style)
        return
    ones = second or first
    if not ones or joint.axis is None:
        return
    centre = ones[0][0]
    axis = np.asarray(joint.axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    if joint.links[0] != mechanism.ground:  # the axis turns with the first link
        axis = poses[joint.links[0]][0, :axis.size, :axis.size] @ axis
    _plot(axes, np.stack([centre - 0.3 * length * axis, centre + 0.3 * length * axis]), three, **style)


def _arrows(axes, places, velocities, kind, length, three):
    """The velocities of the places along one lost direction (:func:`place_velocities`, [d] each), as one
    quiver."""
    names = list(places)
    starts = np.array([places[name] for name in names])
    speeds = np.array([velocities[name] for name in names])
    norms = np.linalg.norm(speeds, axis=1)
    largest = norms.max()
    if not largest > 0:
        return
    moving = norms > _STILL * largest
    starts, speeds = starts[moving], speeds[moving] * (ARROW_FRACTION * length / largest)
    colour = KIND_COLOURS.get(kind, "k")
    label = f"lost ({kind.replace('_', '-')})"
    if three:
        artist = axes.quiver(*starts.T, *speeds.T, color=colour, linewidth=1.5, arrow_length_ratio=0.25, label=label)
    else:
        artist = axes.quiver(starts[:, 0], starts[:, 1], speeds[:, 0], speeds[:, 1], color=colour, angles="xy",
                             scale_units="xy", scale=1.0, width=0.006, zorder=7, label=label)
    artist.set_gid(f"lost:{kind}")


def length_unit(mechanism):
    """The unit of length of `mechanism`'s axes: its ``length_unit`` where it names one, else
    :data:`LENGTH_UNIT` (a mechanism file states no unit: its lengths are in the unit it was written in).

    Parameters
    ----------
    mechanism : Mechanism

    Returns
    -------
    str
    """
    from ..text import drawn

    unit = getattr(mechanism, "length_unit", None)
    return drawn(unit) if isinstance(unit, str) and unit.strip() else LENGTH_UNIT


def _frame(axes, mechanism, point, three, length):
    """Equal aspect, limits around the drawing, axes labelled x, y (, z) with their unit."""
    unit = "unit sphere" if mechanism.space == "spherical" else length_unit(mechanism)
    axes.set_xlabel(f"x ({unit})")
    axes.set_ylabel(f"y ({unit})")
    if three:
        axes.set_zlabel(f"z ({unit})")
    if mechanism.space == "spherical":
        axes.set_xlim(-1.1, 1.1), axes.set_ylim(-1.1, 1.1), axes.set_zlim(-1.1, 1.1)
        axes.set_box_aspect((1, 1, 1))
        return
    collected = [line.get_data_3d() if three else line.get_xydata().T for line in axes.get_lines()]
    every = np.concatenate([np.asarray(data, dtype=float).reshape(len(data), -1) for data in collected], axis=1)
    low, high = np.nanmin(every, axis=1), np.nanmax(every, axis=1)
    centre, half = (low + high) / 2, max(np.max(high - low) / 2, 1e-9) + ARROW_FRACTION * length
    if three:
        axes.set_xlim(centre[0] - half, centre[0] + half)
        axes.set_ylim(centre[1] - half, centre[1] + half)
        axes.set_zlim(centre[2] - half, centre[2] + half)
        axes.set_box_aspect((1, 1, 1))
    else:
        axes.set_xlim(centre[0] - half, centre[0] + half)
        axes.set_ylim(centre[1] - half, centre[1] + half)
        axes.set_aspect("equal")


def save_figure(figure, path):
    """Write a Figure to `path` (format from the suffix: .png, .svg, .pdf), without a display (Agg)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(figure)
    figure.savefig(path, bbox_inches="tight")
