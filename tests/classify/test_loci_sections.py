"""3-dof singularity loci traced in sections (:func:`classify.loci.trace_loci`, a section coordinate held) against
the closed forms of Chablat, Wenger & Angeles 1998 and Gosselin & Angeles 1990.

* Hybrid manipulator (Chablat, Wenger & Angeles 1998, Fig. 6), sections at fixed base angle θ1: the
  end-effector loci are det B = 0, eq. (30): d1 = L1 sin θ2 + L2 sin θ4 = 0 (P on the base revolute's axis),
  θ2 = θ4 + kπ or θ3 = θ5 + kπ (a leg stretched or folded); the actuator locus is det A = 0, eqs. (24)–(25):
  θ4 − θ5 = kπ (the distal links aligned). Checked at every traced point to 1e-6.
* Planar 3-RRR (Gosselin & Angeles 1990, Fig. 7), sections at a fixed first motor angle: the actuator locus
  is det A = 0 (eq. 60 with the rows of eqs. 44–47): the lines of the three links of length l2 concurrent or
  parallel (eqs. 61 and 63 are the cases the paper names).
"""

import numpy as np
import pytest

from classify import classify, classify_many, model_of
from classify.displacements import displacements_of
from classify.figures.drawing import joint_places
from classify.loci import TOLERANCE, default_columns, trace_loci
from mechanisms import configuration
from tests.builders import catalogue_mechanism

#: closed forms hold to this at every traced point (refined to loci.TOLERANCE = 1e-11; the hybrid's factors of
#: eq. 30 follow to a few 1e-10, the distance to the axis being the largest: a margin of 10× or more)
CLOSED_FORM = 1e-8
#: the hybrid's proximal link length L1 (Chablat, Wenger & Angeles 1998 Sec. 3.4 design), the scale of d1
PROXIMAL = 8.0


def _sine(first, second):
    """``|sin|`` of the angle between 3-D vectors, shape=[n]."""
    return (np.linalg.norm(np.cross(first, second), axis=1)
            / (np.linalg.norm(first, axis=1) * np.linalg.norm(second, axis=1)))


@pytest.fixture(scope="module")
def hybrid():
    mechanism = catalogue_mechanism("hybrid")
    start = configuration(mechanism, {}).point
    loci = trace_loci(mechanism, start, counts=(8, 8, 2), kinds=("actuator", "end_effector", "cspace"))
    return mechanism, start, loci


def _pieces(loci, kind):
    return [piece for piece in loci.pieces if piece.kind == kind]


def test_hybrid_end_effector_loci_are_eq30(hybrid):
    mechanism, _, loci = hybrid
    pieces = _pieces(loci, "end_effector")
    assert pieces and all(piece.closed for piece in pieces)
    places = joint_places(mechanism, np.concatenate([piece.points for piece in pieces]))
    axis = np.hypot(places["P"][:, 0], places["P"][:, 2]) / PROXIMAL  # |d1| / L1: P's distance to the Y axis
    left = _sine(places["C"] - places["A"], places["P"] - places["C"])  # sin(θ2 − θ4)
    right = _sine(places["D"] - places["B"], places["P"] - places["D"])  # sin(θ3 − θ5)
    assert np.max(np.minimum(np.minimum(axis, left), right)) < CLOSED_FORM
    for factor in (axis, left, right):  # each factor of eq. (30) was found
        assert np.any(factor < CLOSED_FORM)


def test_hybrid_actuator_locus_is_distal_alignment(hybrid):
    mechanism, _, loci = hybrid
    pieces = _pieces(loci, "actuator")
    assert pieces and all(piece.closed for piece in pieces)
    places = joint_places(mechanism, np.concatenate([piece.points for piece in pieces]))
    assert np.max(_sine(places["P"] - places["C"], places["P"] - places["D"])) < CLOSED_FORM  # sin(θ4 − θ5)


def test_hybrid_points_lie_in_their_sections_and_are_confirmed(hybrid):
    mechanism, _, loci = hybrid
    model = model_of(mechanism)
    section = mechanism.coordinate_names.index("base")
    values = [entry["value"] for entry in loci.coverage["sections"]]
    # two sections evenly around the start's base angle (0 at the home) without the turn's end: −π and 0
    assert values == pytest.approx([-np.pi, 0.0], abs=1e-12)
    assert loci.coverage["section"] == {"base": pytest.approx([-np.pi, 0.0, 2], abs=1e-12)}
    for piece in loci.pieces:
        assert piece.section in values
        np.testing.assert_allclose(displacements_of(mechanism, piece.points)[:, section], piece.section, atol=1e-9)
        assert np.all(piece.residuals <= TOLERANCE)
        assert classify_many(model, piece.points).kind(piece.kind).all()
    sample = loci.pieces[0]
    assert sample.kind in classify(mechanism, sample.points[len(sample.points) // 2]).kinds
    assert loci.coverage["unconfirmed"] == {"actuator": 0, "end_effector": 0}
    assert loci.coverage["dof"] == 3 and set(loci.coverage["grid"]) == {"A", "B"}


def test_hybrid_sections_are_alike(hybrid):
    """Turning the five-bar about AB (the base angle) changes none of its singularities: every section has the
    same pieces, at the same (θ2, θ3) modulo 2π (a curve may be followed a turn further in one section)."""
    mechanism, _, loci = hybrid
    first, second = loci.coverage["sections"]
    assert first["pieces"] == second["pieces"] and first["pieces"]["end_effector"] >= 3
    columns = [mechanism.coordinate_names.index(name) for name in ("A", "B")]
    for kind in ("actuator", "end_effector"):
        by_section = [np.concatenate([displacements_of(mechanism, piece.points)[:, columns]
                                      for piece in _pieces(loci, kind) if piece.section == entry["value"]])
                      for entry in (first, second)]
        differences = by_section[0][:, None] - by_section[1][None]  # angles: the same point modulo 2π
        differences = (differences + np.pi) % (2 * np.pi) - np.pi
        distances = np.linalg.norm(differences, axis=-1).min(axis=1)
        assert np.max(distances) < loci.coverage["step"]


def test_three_dof_default_columns_and_figure(hybrid):
    from classify.figures.loci import draw_cspace_map

    mechanism, _, loci = hybrid
    columns = default_columns(mechanism, 3)
    assert [mechanism.coordinate_names[column] for column in columns] == ["A", "B", "base"]
    figure = draw_cspace_map(mechanism, loci, columns, title="hybrid")
    axes = figure.axes[0]
    assert axes.name == "3d" and axes.get_zlabel() == "base"
    lines = [line for line in axes.lines if (line.get_gid() or "").startswith("locus:")]
    assert len(lines) == len(loci.pieces)


def test_planar_3rrr_actuator_locus_is_concurrent_distal_lines():
    mechanism = catalogue_mechanism("planar-3rrr")
    start = configuration(mechanism, {}).point
    names = mechanism.coordinate_names
    columns = [names.index("motor2"), names.index("motor3"), names.index("motor1")]
    loci = trace_loci(mechanism, start, columns=columns, ranges=[(-0.9, 0.9), (-0.9, 0.9), (0.2, 0.2)],
                      counts=(3, 3, 1), kinds=("actuator",))
    pieces = _pieces(loci, "actuator")
    assert pieces and loci.coverage["unconfirmed"] == {"actuator": 0}
    points = np.concatenate([piece.points for piece in pieces])
    np.testing.assert_allclose(displacements_of(mechanism, points)[:, names.index("motor1")], 0.2, atol=1e-9)
    places = joint_places(mechanism, points)
    rows = []
    for leg in (1, 2, 3):
        along = (places[f"wrist{leg}"] - places[f"elbow{leg}"])[:, :2]
        normal = np.stack([-along[:, 1], along[:, 0]], axis=1) / np.linalg.norm(along, axis=1, keepdims=True)
        rows.append(np.concatenate([normal, np.sum(normal * places[f"wrist{leg}"][:, :2], axis=1)[:, None]],
                                   axis=1))
    # the line of each link of length l2, n·x = n·w: three lines concurrent or parallel iff this vanishes
    assert np.max(np.abs(np.linalg.det(np.stack(rows, axis=1)))) < CLOSED_FORM


def test_sections_drawn_as_panels(hybrid):
    from classify.figures.loci import draw_sections

    mechanism, _, loci = hybrid
    figure = draw_sections(mechanism, loci, default_columns(mechanism, 3)[:2], title="hybrid")
    assert [axes.get_gid() for axes in figure.axes] == ["section:0", "section:1"]
    for axes, entry in zip(figure.axes, loci.coverage["sections"]):
        lines = [line for line in axes.lines if (line.get_gid() or "").startswith("locus:")]
        assert len(lines) == sum(piece.section == entry["value"] for piece in loci.pieces) > 0
        assert axes.get_xlabel() == "A" and axes.get_ylabel() == "B" and axes.get_title().startswith("base = ")


def test_default_coordinates_at_a_start_are_local_coordinates_of_m():
    """A 3-dof mechanism whose third freedom no actuated coordinate moves (the imported 5-bar: the idle spin of
    its welded leaf joints): the rule's coordinates do not fix that spin, so a grid over them reaches nothing;
    given the start, the default keeps the two motors as the grid's axes and adds a coordinate that a pivoted QR
    of DΦ·s leaves free, and the sections' grid is reached."""
    pytest.importorskip("yourdfpy")
    from tests.builders import ROBOTS
    from mechanisms import home
    from mechanisms.urdf import read_urdf

    mechanism = read_urdf(ROBOTS / "5bar_linkage" / "robot.urdf", ROBOTS / "5bar_linkage" / "robot.yaml").mechanism
    start = home(mechanism)
    rule = default_columns(mechanism, 3)
    chosen = default_columns(mechanism, 3, start)
    names = [mechanism.coordinate_names[column] for column in chosen]
    assert names[:2] == ["mot1", "mot2"] and chosen != rule
    assert trace_loci(mechanism, start, columns=rule, counts=(6, 6, 2)).coverage["reached"] == 0
    assert trace_loci(mechanism, start, columns=chosen, counts=(6, 6, 2)).coverage["reached"] > 0
    # where the rule's coordinates are local coordinates, they are kept (the hybrid: A, B, then the base angle)
    hybrid = catalogue_mechanism("hybrid")
    assert default_columns(hybrid, 3, home(hybrid)) == default_columns(hybrid, 3)
