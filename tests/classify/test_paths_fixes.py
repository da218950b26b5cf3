"""Fixes of :mod:`classify.paths` and ``compare --path`` found by an audit: crossings the determinant's sign does
not show (two singular curves crossed at once, a pair of crossings or a touching point between two samples), a
0-dof mechanism, a start at a C-space singularity, and a closed loop that overlapped itself."""

import json

import numpy as np

from classify import Model, classify, model_of
from classify.paths import follow_path, path_configurations, singular_crossings
from manifold import AmbientSpace, ImplicitManifold, project, tangent_basis
from mechanisms.catalogue import entry
from builders import command as run


def diagonal_model(rate):
    """M = {(s, y): y = s} (a line, one degree of freedom), the actuator s (never singular), and an
    end-effector whose rate along M is ``rate(s)/√2``: ``Df = [1, rate(s) − 1]`` (σ₁ ≈ √2, so the cut is
    ≈ √2·10⁻⁶)."""
    ambient = AmbientSpace(("R", "R"))

    def constraint(point):
        point = np.asarray(point, dtype=float)
        return (point[..., 1] - point[..., 0])[..., None]

    def jacobian(point):
        shape = np.asarray(point, dtype=float).shape[:-1]
        return np.broadcast_to(np.array([[-1.0, 1.0]]), shape + (1, 2)).copy()

    def hessian(point):
        return np.zeros(np.asarray(point, dtype=float).shape[:-1] + (1, 2, 2))

    def end_effector_jacobian(point):
        return np.array([[1.0, rate(float(point[0])) - 1.0]])

    return Model("diagonal", ImplicitManifold(ambient, constraint, jacobian, hessian), np.array([[1.0, 0.0]]),
                 ("s", "y"), np.zeros((1, 2)), end_effector_jacobian, np.eye(1))


def crossing_values(model, start, count, step):
    points, _ = path_configurations(model, np.array([start, start]), count, step=step)
    return [(point[0], kind, getattr(crossing, "touching", None))
            for crossing in singular_crossings(model, points) for (_, point, kind) in [crossing]]


def test_a_touching_point_between_two_samples_is_reported():
    """rate = s²: the path touches the end-effector singular set at s = 0 without crossing it (the determinant
    keeps its sign); between samples 0.13 and −0.22 (step 0.5) it was never reported."""
    found = crossing_values(diagonal_model(lambda s: s * s), 0.13, 3, 0.5)
    assert len(found) == 1, found
    s, kind, touching = found[0]
    assert kind == "end_effector" and touching is True and abs(s) < 1e-6


def test_a_pair_of_crossings_within_one_step_is_found():
    """rate = (s − 0.1)² − 0.02²: two crossings at s = 0.08 and 0.12, both inside one step (from 0.2 to −0.15,
    where the rate has the same sign at both samples and at the midpoint): none was found."""
    found = crossing_values(diagonal_model(lambda s: (s - 0.1) ** 2 - 0.02 ** 2), 0.2, 3, 0.5)
    assert [(kind, touching) for _, kind, touching in found] == [("end_effector", False)] * 2, found
    np.testing.assert_allclose(sorted(s for s, _, _ in found), [0.08, 0.12], atol=1e-8)
    found = crossing_values(diagonal_model(lambda s: s * s - 0.05 ** 2), 0.13, 3, 0.5)  # the midpoint's sign
    np.testing.assert_allclose(sorted(s for s, _, _ in found), [-0.05, 0.05], atol=1e-8)


def test_a_simple_crossing_is_where_it_was():
    """One sign change: one crossing, located by the same bisection as before (not a touching point)."""
    found = crossing_values(diagonal_model(lambda s: s - 0.03), 0.13, 3, 0.5)
    assert [(kind, touching) for _, kind, touching in found] == [("end_effector", False)]
    assert abs(found[0][0] - 0.03) < 1e-9


FIVE_BAR = (6.0, 8.0, 5.0)  # Chablat, Wenger & Angeles 1998: base A B, proximal, distal


def five_bar_point(mechanism, target, modes):
    """The five-bar's configuration with end-effector at `target`, leg i's working mode ``sign sin(θ_distal −
    θ_proximal) = modes[i]`` (the audit's closed form), as displacements of the relative joint angles."""
    base, proximal, distal = FIVE_BAR

    def angle(vector):
        return np.arctan2(vector[1], vector[0])

    def relative(thetas):
        t1, t2, t3, t4 = thetas
        return np.array([t1, t3 - t1, t4 - t3, t2 - t4, -t2])

    joints = {name: np.array(mechanism.joint(name).point, dtype=float)[:2] for name in "ACPDB"}
    home = relative([angle(joints["C"] - joints["A"]), angle(joints["D"] - joints["B"]),
                     angle(joints["P"] - joints["C"]), angle(joints["P"] - joints["D"])])
    legs = []
    for origin, mode in (((0.0, 0.0), modes[0]), ((base, 0.0), modes[1])):
        vector = np.asarray(target) - origin
        reach = np.hypot(*vector)
        cosine = np.clip((proximal ** 2 + reach ** 2 - distal ** 2) / (2 * proximal * reach), -1.0, 1.0)
        theta = angle(vector) - mode * np.arccos(cosine)
        elbow = np.asarray(origin) + proximal * np.array([np.cos(theta), np.sin(theta)])
        legs.append((theta, angle(np.asarray(target) - elbow)))
    (t1, t3), (t2, t4) = legs
    return (relative([t1, t2, t3, t4]) - home + np.pi) % (2 * np.pi) - np.pi


def test_two_singular_curves_crossed_at_once_are_a_crossing():
    """Between two samples 0.01 apart the five-bar passes P = (3, √160), both legs stretched (Chablat, Wenger &
    Angeles 1998, eqs. 10–13): working mode ++ → −−, det(H½ Df T) (the product of the legs' factors) keeps its
    sign, and no crossing was reported."""
    mechanism = entry("five-bar").mechanism()
    model = model_of(mechanism)
    start = project(model.manifold, five_bar_point(mechanism, (3.0, np.sqrt(160.0)), (1, 1)))
    direction = tangent_basis(model.manifold, start)[0][:, 0]
    points = np.array([project(model.manifold, start + (k + 0.5) * 0.01 * direction) for k in range(-3, 3)])
    assert all(classify(model, point).kinds == () for point in points)
    found = singular_crossings(model, points)
    assert [(index, kind, crossing.touching) for crossing in found for (index, _, kind) in [crossing]] \
        == [(2, "end_effector", False)], found
    point = found[0][1]
    assert "end_effector" in classify(model, point).kinds
    assert np.linalg.norm(point - start) < 1e-6


def test_a_path_of_a_zero_dof_mechanism_is_refused(capsys, tmp_path):
    """A 3R loop has no curve of M through its start: `compare --path` ended in 'internal error: IndexError'."""
    path = tmp_path / "triangle.yaml"
    path.write_text("name: triangle\nspace: planar\njoints:\n"
                    "- {name: a, type: R, links: [ground, l1], point: [0.0, 0.0], actuated: true}\n"
                    "- {name: b, type: R, links: [l1, l2], point: [1.0, 0.0]}\n"
                    "- {name: c, type: R, links: [l2, ground], point: [0.0, 1.0]}\n"
                    "end_effector: {link: l1, point: [1.0, 0.0]}\n")
    status, out, err = run(["compare", str(path), "--path", "3"], capsys)
    assert status == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and "--path" in err and "0 degrees of freedom" in err
    assert "internal error" not in err


def test_a_path_from_a_cspace_singularity_is_not_continued(capsys):
    """At the slider-crank's self-intersection (R = l, Gosselin & Angeles Fig. 3a) two curves of M cross: the path
    followed one of them (chosen by the SVD's basis) without a word, though the docs said it is not continued."""
    status, out, err = run(["compare", "slider-crank", "--configuration", "fig3a_self_intersection", "--path", "3",
                            "--format", "json"], capsys)
    assert status == 0, err
    assert [row["configuration"] for row in json.loads(out)["configurations"]] == ["fig3a_self_intersection"]
    assert "--path: M could not be continued from fig3a_self_intersection" in err and "C-space singularity" in err
    mechanism = entry("slider-crank").mechanism("fig3a_self_intersection")
    model = model_of(mechanism)
    result = follow_path(model, model.starts[0], 3)
    assert len(result.points) == 1 and result.reason == "cspace"


def test_a_closed_loop_reports_each_crossing_once(capsys):
    """With a coarse step the two sides of the slider-crank's path (θ = 0.4) overlapped: the fold crossed at
    −6…−5 and at +4…+5 was one configuration (pin and wrist 2π apart)."""
    status, out, err = run(["compare", "slider-crank", "--param", "theta=0.4", "--outputs", "slide", "--path", "30",
                            "--path-step", "1.0", "--format", "json"], capsys)
    assert status == 0, err
    labels = [row["configuration"] for row in json.loads(out)["configurations"]]
    crossings = [label for label in labels if label.startswith("crossing")]
    assert sorted(label.split()[-1] for label in crossings) == ["(actuator)"] * 2 + ["(end-effector)"] * 2, labels
    mechanism = entry("slider-crank").mechanism(theta=0.4)
    from classify import joint_output_model

    model = joint_output_model(mechanism, ["slide"])
    result = follow_path(model, model.starts[0], 30, step=1.0)
    assert result.closed
    found = singular_crossings(model, result.points, closed=result.closed)
    ambient = model.manifold.ambient
    for first in range(len(found)):
        for second in range(first + 1, len(found)):
            assert np.linalg.norm(ambient.inverse_retract(found[first][1], found[second][1])) > 1e-3
    fine = follow_path(model, model.starts[0], 300, step=0.05)
    fine_found = singular_crossings(model, fine.points, closed=fine.closed)
    assert sorted(kind for _, _, kind in fine_found) == sorted(kind for _, _, kind in found)


def test_a_touching_point_just_after_a_sample_is_filed_under_the_segment_it_lies_on():
    """A review found a dip's point just right of sample j filed under the segment before j (the distance to the
    segments' second ends decided): a touching point at s = 0, samples at s = −0.6, −0.1, 0.4, 0.9."""
    model = diagonal_model(lambda s: s * s)
    points = np.array([[s, s] for s in (-0.6, -0.1, 0.4, 0.9)])
    crossings = singular_crossings(model, points)
    assert [(crossing.index, crossing.touching) for crossing in crossings] == [(1, True)]
    assert abs(crossings[0].point[0]) < 1e-6
