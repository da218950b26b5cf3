"""Mechanisms built for the tests, each with the paper and figure it comes from.

(The user-facing catalogue is a later issue; these builders are the minimum
the core tests need and are written from the papers' geometry.)

The survey of M is the costly part of a classification; it is computed once
per model, and :func:`classify.model_of` keeps one model per mechanism
*object*. :func:`shared_mechanism` maps every mechanism to one object per
description, so the tests that build the same mechanism (a catalogue entry at
a named configuration, a scaled copy of a spherical one) share its model and
survey within a test process. Nothing is lost: a classification is a
deterministic function of the description (the survey's seed is fixed).
"""

import tracemalloc
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

from classify import Model
from manifold import AmbientSpace, ImplicitManifold
from mechanisms import EndEffector, Joint, Mechanism
from mechanisms.catalogue import entry

# --------------------------------------------------------------------------- the command


def command(arguments, capsys):
    """(status, stdout, stderr) of ``closedchain ARGUMENTS``, the streams read from pytest's `capsys`."""
    from classify.cli import main

    status = main(arguments)
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def command_streams(arguments):
    """(status, stdout, stderr) of ``closedchain ARGUMENTS`` without a fixture (module-scoped fixtures can use it):
    stdout is the command's `out` stream, stderr redirected."""
    import contextlib
    import io

    from classify.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err):
        status = main(arguments, out=out)
    return status, out.getvalue(), err.getvalue()


# --------------------------------------------------------------------------- shared mechanisms

#: description -> the first mechanism object seen with it (see :func:`shared_mechanism`)
_SHARED_MECHANISMS = {}


def description(mechanism):
    """The exact description of a mechanism, as text: name, space, joints, ground and end-effector.

    Joints and end-effector are frozen dataclasses of strings, booleans and
    tuples of Python floats, whose repr is exact (it tells -0.0 from 0.0).

    Parameters
    ----------
    mechanism : Mechanism

    Returns
    -------
    str
    """
    return repr((mechanism.name, mechanism.space, mechanism.joints, mechanism.ground, mechanism.end_effector))


def shared_mechanism(mechanism):
    """The one mechanism object of this process with `mechanism`'s description.

    Its model (:func:`classify.model_of`), and so the survey of M, is
    computed once and reused by every test that classifies the same
    description.

    Parameters
    ----------
    mechanism : Mechanism

    Returns
    -------
    Mechanism
        The first object seen with this description (`mechanism` itself if it is the first).
    """
    return _SHARED_MECHANISMS.setdefault(description(mechanism), mechanism)


def catalogue_mechanism(name, configuration=None, **parameters):
    """``catalogue.entry(name).mechanism(configuration, **parameters)``, shared (:func:`shared_mechanism`).

    Parameters
    ----------
    name : str
        Catalogue name.
    configuration : str, optional
        Named configuration (default: the builder's defaults).
    **parameters
        The builder's parameters.

    Returns
    -------
    Mechanism
    """
    return shared_mechanism(entry(name).mechanism(configuration, **parameters))


# --------------------------------------------------------------------------- five-bar

def five_bar(points, actuated=("J1", "J5"), end_effector="distal1"):
    """Planar 5R (Park & Kim eq. 8) with joints J1..J5 at the given points, J1 and J5 on the ground.

    The end-effector is the middle joint J3 carried by `end_effector` (Park & Kim Figs. 6, 13).
    """
    points = [tuple(float(v) for v in p) for p in points]
    links = ["ground", "proximal1", "distal1", "distal2", "proximal2", "ground"]
    joints = [Joint(f"J{i + 1}", "R", (links[i], links[i + 1]), point=points[i],
                    actuated=f"J{i + 1}" in actuated) for i in range(5)]
    return Mechanism("five-bar", "planar", joints,
                     end_effector=EndEffector(end_effector, points[2], "position"))


def five_bar_positions(theta1, theta5, base=2.0, proximal=1.0, distal=1.0, elbow=1):
    """Joint positions for crank angles θ1 (at J1 = 0) and θ5 (at J5 = (base, 0))."""
    j1, j5 = np.zeros(2), np.array([base, 0.0])
    j2 = j1 + proximal * np.array([np.cos(theta1), np.sin(theta1)])
    j4 = j5 + proximal * np.array([np.cos(theta5), np.sin(theta5)])
    chord = j4 - j2
    half = np.linalg.norm(chord) / 2
    normal = np.array([-chord[1], chord[0]]) / (2 * half)
    j3 = (j2 + j4) / 2 + elbow * np.sqrt(distal ** 2 - half ** 2) * normal
    return [j1, j2, j3, j4, j5]


def _wrap(angle):
    return (angle + np.pi) % (2 * np.pi) - np.pi


def five_bar_eq8(points, actuated=(0, 4)):
    """The five-bar written directly as Park & Kim eq. (8): an implicit manifold in T⁵.

    x_i are the relative angles between consecutive links (link i from joint i to joint i+1,
    link 5 the ground), Φ(x) = (Σ Lᵢ cos(x₁+…+xᵢ), Σ Lᵢ sin(x₁+…+xᵢ), x₁+…+x₅ − s₀), where the
    constant s₀ (π in the paper) depends on the zero of the angles. E = diag(1, 0, 0, 0, 1).
    The end-effector is joint 3: f(x) = L₁(c₁, s₁) + L₂(c₁₂, s₁₂).

    Returns
    -------
    model : Model
    point : ndarray, shape=[5]
        The x of the given joint positions.
    """
    points = [np.asarray(p, dtype=float) for p in points]
    links = [points[(i + 1) % 5] - points[i] for i in range(5)]
    lengths = np.array([np.linalg.norm(link) for link in links])
    directions = np.array([np.arctan2(link[1], link[0]) for link in links])
    x = np.array([_wrap(directions[0] - directions[4])]
                 + [_wrap(directions[i] - directions[i - 1]) for i in range(1, 5)])
    offset = float(np.sum(x))
    ambient = AmbientSpace(("S1",) * 5)
    lower = np.tril(np.ones((5, 5)))  # cumulative sums: S = lower @ x

    def constraint(point):
        sums = point @ lower.T
        return np.stack([np.sum(lengths * np.cos(sums), axis=-1), np.sum(lengths * np.sin(sums), axis=-1),
                         np.sum(point, axis=-1) - offset], axis=-1)

    def jacobian(point):
        sums = point @ lower.T
        first = -(lengths * np.sin(sums)) @ lower
        second = (lengths * np.cos(sums)) @ lower
        return np.stack([first, second, np.ones_like(first)], axis=-2)

    def hessian(point):
        sums = point @ lower.T
        cos_part = np.einsum("i,ia,ib->ab", -lengths * np.cos(sums), lower, lower)
        sin_part = np.einsum("i,ia,ib->ab", -lengths * np.sin(sums), lower, lower)
        return np.stack([cos_part, sin_part, np.zeros((5, 5))])

    def end_effector_jacobian(point):
        sums = point @ lower.T
        partial = lower[:2]
        return np.stack([-(lengths[:2] * np.sin(sums[:2])) @ partial,
                         (lengths[:2] * np.cos(sums[:2])) @ partial])

    selection = np.zeros((len(actuated), 5))
    for row, index in enumerate(actuated):
        selection[row, index] = 1.0
    manifold = ImplicitManifold(ambient, constraint, jacobian, hessian)
    model = Model("five-bar (eq. 8)", manifold, selection, tuple(f"x{i + 1}" for i in range(5)),
                  x[None], end_effector_jacobian, np.eye(2))
    return model, x


# --------------------------------------------------------------------------- spatial

def _dh(theta, a, alpha):
    c, s, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([[c, -s * ca, s * sa, a * c], [s, c * ca, -c * sa, a * s], [0, sa, ca, 0],
                     [0, 0, 0, 1.0]])


def bennett(a=1.0, alpha=np.pi / 6, beta=np.pi / 4, theta1=0.7, actuated=True):
    """A Bennett linkage from its DH parameters: a₁₂ = a₃₄ = a, a₂₃ = a₄₁ = b = a sin β / sin α,
    twists α, β, α, β, offsets 0; assembled by solving the loop for θ₂, θ₃, θ₄ at θ₁."""
    b = a * np.sin(beta) / np.sin(alpha)
    lengths, twists = [a, b, a, b], [alpha, beta, alpha, beta]

    def chain(thetas):
        frames = [np.eye(4)]
        for theta, length, twist in zip(thetas, lengths, twists):
            frames.append(frames[-1] @ _dh(theta, length, twist))
        return frames

    def residual(rest):
        closure = chain([theta1, *rest])[-1]
        return np.concatenate([(closure[:3, :3] - np.eye(3)).ravel(), closure[:3, 3]])

    guess_2 = 2 * np.arctan(np.sin((beta + alpha) / 2) / np.sin((beta - alpha) / 2) / np.tan(theta1 / 2))
    solution = least_squares(residual, [guess_2, -theta1, -guess_2], xtol=1e-15, ftol=1e-15, gtol=1e-15)
    assert np.max(np.abs(residual(solution.x))) < 1e-12, "Bennett loop did not close"
    frames = chain([theta1, *solution.x])
    links = ["ground", "link1", "link2", "link3", "ground"]
    joints = [Joint(f"R{i + 1}", "R", (links[i], links[i + 1]), point=tuple(frames[i][:3, 3]),
                    axis=tuple(frames[i][:3, 2]), actuated=actuated and i == 0) for i in range(4)]
    return Mechanism("bennett", "spatial", joints, end_effector=EndEffector("link2", tuple(frames[2][:3, 3]), "pose"))


def rsur(output="pose"):
    """A spatial RSUR four-bar (generic geometry, assembled at home by construction), crank driven."""
    return Mechanism("RSUR", "spatial", [
        Joint("A", "R", ("ground", "crank"), point=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0), actuated=True),
        Joint("B", "S", ("crank", "coupler"), point=(1.0, 0.1, 0.3)),
        Joint("C", "U", ("coupler", "rocker"), point=(1.6, 1.3, 0.7), axes=((0.2, 1.0, 0.1), (1.0, -0.1, 0.3))),
        Joint("D", "R", ("rocker", "ground"), point=(0.4, 1.5, 0.1), axis=(1.0, 0.2, 0.1)),
    ], end_effector=EndEffector("coupler", (1.2, 0.8, 0.6), output))


def spherical_four_bar():
    """Spherical 4R linkage (axes through the origin), end-effector orientation of the coupler."""
    axes = [(0.0, 0.0, 1.0), (0.8, 0.1, 0.6), (0.3, 0.9, 0.4), (-0.2, 0.5, 0.9)]
    links = ["ground", "crank", "coupler", "rocker", "ground"]
    return Mechanism("spherical four-bar", "spherical", [
        Joint(f"R{i + 1}", "R", (links[i], links[i + 1]), axis=axes[i], actuated=i == 0) for i in range(4)
    ], end_effector=EndEffector("coupler", None, "orientation"))


def spatial_mix(output="pose"):
    """A two-loop spatial mechanism with R, P, S, U and C joints (for derivative tests)."""
    return Mechanism("mix", "spatial", [
        Joint("A", "R", ("ground", "a"), point=(0, 0, 0), axis=(0, 0, 1), actuated=True),
        Joint("B", "S", ("b", "a"), point=(1, 0, 0)),
        Joint("C", "U", ("b", "c"), point=(1, 1, 0), axes=((1, 0, 0), (0, 1, 0))),
        Joint("D", "C", ("c", "ground"), point=(0, 1, 1), axis=(0, 1, 1)),
        Joint("E", "P", ("ground", "e"), axis=(1, 1, 0), actuated=True),
        Joint("F", "S", ("e", "c"), point=(2, 1, 0)),
    ], end_effector=EndEffector("b", None if output == "orientation" else (0.5, 0.5, 0.5), output))


# --------------------------------------------------------------------------- large mechanisms

def rsur_stack(loops):
    """`loops` spatial RSUR four-bars stacked, each hung on the coupler of the one before (R, S, U and R joints:
    ball elements and two-axis ones, in chains as deep as the stack), the last coupler's pose the end-effector.
    Every loop touches its own four joints only: DΦ has one 6 × 7 block per loop."""
    joints = []
    for index in range(1, loops + 1):
        base = "ground" if index == 1 else f"coupler{index - 1}"
        height, tilt = 1.0 * (index - 1), 0.1 * np.sin(index)
        joints += [
            Joint(f"A{index}", "R", (base, f"crank{index}"), point=(0.0, 0.0, height), axis=(tilt, 0.0, 1.0),
                  actuated=True),
            Joint(f"B{index}", "S", (f"crank{index}", f"coupler{index}"), point=(1.0, 0.1 + tilt, 0.3 + height)),
            Joint(f"C{index}", "U", (f"coupler{index}", f"rocker{index}"), point=(1.6, 1.3, 0.7 + height),
                  axes=((0.2, 1.0, 0.1 + tilt), (1.0, -0.1, 0.3))),
            Joint(f"D{index}", "R", (f"rocker{index}", base), point=(0.4, 1.5, 0.1 + height),
                  axis=(1.0, 0.2 + tilt, 0.1)),
        ]
    return Mechanism(f"RSUR stack of {loops}", "spatial", joints,
                     end_effector=EndEffector(f"coupler{loops}", (1.2, 0.8, 0.6 + loops - 1.0), "pose"))


def ladder(loops, tail=0):
    """A planar ladder of `loops` parallelogram four-bar loops stacked on the ground (4 joints each).

    Loop i joins rung i − 1 (the ground for i = 1) to rung i by two parallel
    links of direction (tᵢ, 1), tᵢ = 0.1 + 0.3 sin i, so that the rungs'
    motions are not all parallel; the left joint of every loop is actuated.
    Every loop touches its own four joints only: DΦ has one 3×4 block per
    loop. `tail` actuated joints hang in a chain from the top rung, and the
    end-effector is a point of the last link.
    """
    joints = []
    for index in range(1, loops + 1):
        below, above = ("ground" if index == 1 else f"rung{index - 1}"), f"rung{index}"
        tilt = 0.1 + 0.3 * np.sin(index)
        joints += [Joint(f"A{index}", "R", (below, f"left{index}"), point=(0.0, index - 1.0), actuated=True),
                   Joint(f"B{index}", "R", (f"left{index}", above), point=(tilt, float(index))),
                   Joint(f"C{index}", "R", (below, f"right{index}"), point=(1.0, index - 1.0)),
                   Joint(f"D{index}", "R", (f"right{index}", above), point=(1.0 + tilt, float(index)))]
    link = f"rung{loops}"
    for index in range(1, tail + 1):
        joints.append(Joint(f"T{index}", "R", (link, f"tail{index}"), point=(0.5, loops + index - 1.0),
                            actuated=True))
        link = f"tail{index}"
    name = f"ladder of {loops}" if not tail else f"ladder of {loops} loops and {tail} tail joints"
    return Mechanism(name, "planar", joints, end_effector=EndEffector(link, point=(0.5, float(loops + tail))))


def recorded_svd_shapes(monkeypatch):
    """The shapes of the matrices (stacks) given to ``numpy.linalg.svd`` from now on, a list that grows as it is
    called (``monkeypatch.undo()`` stops it)."""
    shapes, original = [], np.linalg.svd
    monkeypatch.setattr(np.linalg, "svd", lambda matrix, *arguments, **options:
                        shapes.append(np.shape(matrix)) or original(matrix, *arguments, **options))
    return shapes


def traced_peak(function, *arguments):
    """(result, peak bytes allocated while `function` ran), by tracemalloc (NumPy arrays included)."""
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        result = function(*arguments)
        return result, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


# --------------------------------------------------------------------------- robot files

#: the robots of tests/data/robots (a URDF with its closures file per folder, an MJCF model)
ROBOTS = Path(__file__).resolve().parent / "data" / "robots"


def robot_arguments(name):
    """The command-line arguments of a sample robot: its URDF and ``--closures`` file."""
    return [str(ROBOTS / name / "robot.urdf"), "--closures", str(ROBOTS / name / "robot.yaml")]


# --------------------------------------------------------------------------- structures that only flex

def flat_triangle(order=(0, 1, 2), offset=(0.0, 0.0)):
    """Three collinear revolute joints closing a loop on the ground: a structure that only flexes (M a point)."""
    joints = [Joint("J1", "R", ("ground", "a"), point=(0.0 + offset[0], offset[1])),
              Joint("J2", "R", ("a", "b"), point=(1.0 + offset[0], offset[1])),
              Joint("J3", "R", ("b", "ground"), point=(2.0 + offset[0], offset[1]))]
    return Mechanism("flat triangle", "planar", [joints[index] for index in order])


def stretched_four_bar(order=(0, 1, 2, 3), offset=(0.0, 0.0)):
    """A four-bar stretched flat (its four joints collinear): it only flexes; the end-effector on the middle link."""
    joints = [Joint("J1", "R", ("ground", "a"), point=(0.0 + offset[0], offset[1]), actuated=True),
              Joint("J2", "R", ("a", "b"), point=(1.0 + offset[0], offset[1])),
              Joint("J3", "R", ("b", "c"), point=(2.0 + offset[0], offset[1])),
              Joint("J4", "R", ("c", "ground"), point=(3.0 + offset[0], offset[1]))]
    return Mechanism("stretched four-bar", "planar", [joints[index] for index in order],
                     end_effector=EndEffector("b", (1.5 + offset[0], offset[1]), "position"))
