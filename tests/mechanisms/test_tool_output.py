"""The ``tool`` end-effector output: an axisymmetric tool, f(p) = (x, u) ∈ ℝ³ × S² (docs/design.rst,
"End-effector outputs").

Its value, chart and Df are checked against independent computations (the ``position`` output of
two points of the axis, central finite differences); its invariances (the axis's sign and length,
the basis of u^⊥, the point along the axis for direction-only quantities) are checked on the
pulled-back metric JᵀHJ, from which every rank and proper value of the classification follows.
The Taylor (slope) tests of Df and D²f are in test_kinematics.py ("RSUR tool", "mix tool").
"""

import json

import numpy as np
import pytest

from builders import rsur, spatial_mix
from classify import end_effector_metric
from classify.cli import main
from mechanisms import (
    EndEffector, Mechanism, MechanismError, end_effector, end_effector_chart, end_effector_dimension,
    end_effector_jacobian, home, kinematics_of, loads, save,
)
from mechanisms.io import load, mechanism_to_dict
from mechanisms.kinematics import tool_basis

AXIS = (0.3, -0.5, 0.8)


def with_end_effector(mechanism, point, output, axis=None):
    end = EndEffector(mechanism.end_effector.link, tuple(point), output, axis)
    return Mechanism(mechanism.name, mechanism.space, mechanism.joints, mechanism.ground, end)


def tool(mechanism=None, axis=AXIS, along=0.0):
    """The RSUR (or `mechanism`) with a tool on its end-effector link: the point moved `along` the unit axis."""
    mechanism = rsur("position") if mechanism is None else mechanism
    unit = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    point = np.asarray(mechanism.end_effector.point, dtype=float) + along * unit
    return with_end_effector(mechanism, point, "tool", tuple(float(value) for value in axis))


def random_points(mechanism, rng, count=4):
    return kinematics_of(mechanism).ambient.random_point(rng, size=count)


def world_rates(mechanism, points):
    """(Dx, Du) in world components, shape=[..., 3, k] each, from the ``position`` output at the tool point
    and at the tool point plus the unit axis: an independent model of the tool's derivatives."""
    unit = np.asarray(mechanism.end_effector.axis) / np.linalg.norm(mechanism.end_effector.axis)
    point = np.asarray(mechanism.end_effector.point)
    at_point = with_end_effector(mechanism, point, "position")
    at_tip = with_end_effector(mechanism, point + unit, "position")
    first = end_effector_jacobian(at_point, points)
    return first, end_effector_jacobian(at_tip, points) - first


def pulled_back(mechanism, points):
    """JᵀHJ, shape=[..., k, k]."""
    jacobian = end_effector_jacobian(mechanism, points)
    return np.swapaxes(jacobian, -1, -2) @ end_effector_metric(mechanism) @ jacobian


# ----------------------------------------------------------------------------- value, chart, basis

def test_value_is_the_carried_point_and_unit_axis():
    mechanism = tool()
    points = random_points(mechanism, np.random.default_rng(1))
    value = end_effector(mechanism, points)
    assert value.shape == (4, 6) and end_effector_dimension(mechanism) == 5
    position = end_effector(with_end_effector(mechanism, mechanism.end_effector.point, "position"), points)
    tip = end_effector(with_end_effector(mechanism, np.add(mechanism.end_effector.point,
                                                           np.divide(AXIS, np.linalg.norm(AXIS))), "position"),
                       points)
    np.testing.assert_allclose(value[:, :3], position, atol=1e-12)
    np.testing.assert_allclose(value[:, 3:], tip - position, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(value[:, 3:], axis=1), 1.0, atol=1e-12)
    at_home = end_effector(mechanism, home(mechanism))
    np.testing.assert_allclose(at_home[3:], np.divide(AXIS, np.linalg.norm(AXIS)), atol=1e-12)


def test_tool_basis_is_an_orthonormal_basis_of_the_normal_plane():
    rng = np.random.default_rng(2)
    directions = rng.standard_normal((50, 3))
    directions = np.concatenate([directions, np.eye(3), -np.eye(3)])
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    basis = tool_basis(directions)
    assert basis.shape == (56, 2, 3)
    np.testing.assert_allclose(basis @ np.swapaxes(basis, 1, 2), np.broadcast_to(np.eye(2), (56, 2, 2)), atol=1e-12)
    np.testing.assert_allclose(np.einsum("nij,nj->ni", basis, directions), 0.0, atol=1e-12)
    flipped = tool_basis(-directions)  # the sign of u keeps e₁ and reverses e₂
    np.testing.assert_allclose(flipped[:, 0], basis[:, 0], atol=1e-12)
    np.testing.assert_allclose(flipped[:, 1], -basis[:, 1], atol=1e-12)


def test_chart_is_the_difference_and_the_logarithm_of_the_sphere():
    """chart(f₀, f) = (x − x₀, E(u₀) log_{u₀} u): zero at f₀, and |direction part| = the angle from u₀ to u."""
    mechanism = tool()
    rng = np.random.default_rng(3)
    values = end_effector(mechanism, random_points(mechanism, rng, 6)).reshape(2, 3, 6)
    base = values[0]
    chart = end_effector_chart(mechanism, base, values[1])
    assert chart.shape == (3, 5)
    np.testing.assert_allclose(chart[:, :3], values[1, :, :3] - base[:, :3], atol=1e-12)
    angles = np.arccos(np.clip(np.sum(base[:, 3:] * values[1, :, 3:], axis=1), -1, 1))
    np.testing.assert_allclose(np.linalg.norm(chart[:, 3:], axis=1), angles, atol=1e-12)
    np.testing.assert_allclose(end_effector_chart(mechanism, base, base), 0.0, atol=1e-15)
    for index in range(3):
        np.testing.assert_allclose(chart[index], end_effector_chart(mechanism, base[index], values[1, index]),
                                   atol=1e-14)


# ----------------------------------------------------------------------------- Df

def test_jacobian_matches_central_finite_differences():
    """Df against (chart(f(p), f(p ⊕ h e_j)) − chart(f(p), f(p ⊕ −h e_j))) / 2h, coordinate by coordinate."""
    for mechanism in (tool(), tool(spatial_mix("position"), (1.0, 2.0, -0.5))):
        space = kinematics_of(mechanism).ambient
        for point in random_points(mechanism, np.random.default_rng(4), 3):
            value = end_effector(mechanism, point)
            jacobian = end_effector_jacobian(mechanism, point)
            step = 1e-6
            differences = np.array([
                (end_effector_chart(mechanism, value, end_effector(mechanism, space.retract(point, step * unit)))
                 - end_effector_chart(mechanism, value, end_effector(mechanism, space.retract(point, -step * unit))))
                / (2 * step) for unit in np.eye(space.dim)]).T
            np.testing.assert_allclose(jacobian, differences, atol=1e-7 * max(1.0, np.abs(jacobian).max()))


def test_jacobian_is_the_point_rate_and_the_direction_rate_in_a_basis_of_its_normal_plane():
    """The direction rows are E(u)·(ω × u), the point rows ∂x; so JᵀHJ = DxᵀDx + L² DuᵀDu with the rates in world
    components from two ``position`` outputs (no basis at all), and H = diag(I₃, L² I₂)."""
    mechanism = tool()
    points = random_points(mechanism, np.random.default_rng(5))
    length = kinematics_of(mechanism).length
    np.testing.assert_allclose(end_effector_metric(mechanism), np.diag([1, 1, 1, length ** 2, length ** 2]))
    np.testing.assert_allclose(end_effector_metric(mechanism, length_scale=2.0), np.diag([1, 1, 1, 4, 4]))
    point_rates, direction_rates = world_rates(mechanism, points)
    values = end_effector(mechanism, points)
    np.testing.assert_allclose(np.einsum("ni,nik->nk", values[:, 3:], direction_rates), 0.0, atol=1e-12)
    expected = (np.swapaxes(point_rates, 1, 2) @ point_rates
                + length ** 2 * np.swapaxes(direction_rates, 1, 2) @ direction_rates)
    np.testing.assert_allclose(pulled_back(mechanism, points), expected, atol=1e-11)


# ----------------------------------------------------------------------------- invariances

@pytest.mark.parametrize("axis", [tuple(-value for value in AXIS), tuple(3.0 * value for value in AXIS)])
def test_sign_and_length_of_the_axis_change_nothing(axis):
    """Reversing (or scaling) the axis changes u's sign (or nothing): JᵀHJ — hence every rank, kernel and proper
    value — is the same, and the direction rows differ by an orthogonal 2 × 2 map."""
    reference, other = tool(), tool(axis=axis)
    points = random_points(reference, np.random.default_rng(6))
    np.testing.assert_allclose(pulled_back(other, points), pulled_back(reference, points), atol=1e-12)
    first, second = end_effector_jacobian(reference, points), end_effector_jacobian(other, points)
    np.testing.assert_allclose(second[:, :3], first[:, :3], atol=1e-12)
    turn = np.linalg.lstsq(first[0, 3:].T, second[0, 3:].T, rcond=None)[0].T
    np.testing.assert_allclose(turn @ turn.T, np.eye(2), atol=1e-10)


def test_another_basis_of_the_normal_plane_changes_nothing(monkeypatch):
    """With E(u) replaced by a rotated basis, the direction rows turn and JᵀHJ stays."""
    import mechanisms.kinematics as kinematics

    mechanism = tool()
    points = random_points(mechanism, np.random.default_rng(7))
    reference = pulled_back(mechanism, points)
    original = kinematics.tool_basis
    angle = 0.7
    turn = np.array([[np.cos(angle), -np.sin(angle)], [-np.sin(angle), -np.cos(angle)]])  # a reflection
    monkeypatch.setattr(kinematics, "tool_basis", lambda direction: turn @ original(direction))
    np.testing.assert_allclose(pulled_back(mechanism, points), reference, atol=1e-12)


def test_the_point_along_the_axis_does_not_change_direction_quantities_nor_ranks():
    """Moving the tool point by s along the axis leaves the direction rows as they are and adds s·(ω × u) to
    the point rows: an invertible change of rows, so ranks (and kernels) of J are unchanged."""
    reference, moved = tool(), tool(along=0.8)
    points = random_points(reference, np.random.default_rng(8))
    first, second = end_effector_jacobian(reference, points), end_effector_jacobian(moved, points)
    np.testing.assert_allclose(second[:, 3:], first[:, 3:], atol=1e-12)
    np.testing.assert_allclose(end_effector(moved, points)[:, 3:], end_effector(reference, points)[:, 3:], atol=1e-12)
    _, direction_rates = world_rates(reference, points)
    np.testing.assert_allclose(second[:, :3] - first[:, :3], 0.8 * direction_rates, atol=1e-12)
    # second = [[I₃, 0.8 E(u)ᵀ], [0, I₂]] · first: block triangular, invertible
    basis = tool_basis(end_effector(reference, points)[:, 3:])
    rows = np.concatenate([np.concatenate([np.broadcast_to(np.eye(3), (4, 3, 3)), 0.8 * np.swapaxes(basis, 1, 2)], 2),
                           np.concatenate([np.zeros((4, 2, 3)), np.broadcast_to(np.eye(2), (4, 2, 2))], 2)], 1)
    np.testing.assert_allclose(second, rows @ first, atol=1e-12)
    for one, other in zip(first, second):
        assert np.linalg.matrix_rank(one) == np.linalg.matrix_rank(other) == 4  # the coupler has 4 freedoms


# ----------------------------------------------------------------------------- files

TOOL_FILE = """
name: tool-rsur
space: spatial
joints:
  - {name: A, type: R, links: [ground, crank], point: [0, 0, 0], axis: [0, 0, 1], actuated: true}
  - {name: B, type: S, links: [crank, coupler], point: [1.0, 0.1, 0.3]}
  - {name: C, type: U, links: [coupler, rocker], point: [1.6, 1.3, 0.7], axes: [[0.2, 1.0, 0.1], [1.0, -0.1, 0.3]]}
  - {name: D, type: R, links: [rocker, ground], point: [0.4, 1.5, 0.1], axis: [1.0, 0.2, 0.1]}
end_effector:
  link: coupler
  point: [1.2, 0.8, 0.6]
  output: tool
  axis: [0.3, -0.5, 0.8]
"""


@pytest.mark.parametrize("suffix", [".yaml", ".json"])
def test_files_round_trip_with_the_axis(tmp_path, suffix):
    mechanism = loads(TOOL_FILE).mechanism
    assert mechanism.end_effector == EndEffector("coupler", (1.2, 0.8, 0.6), "tool", AXIS)
    data = mechanism_to_dict(mechanism)
    assert data["end_effector"] == {"link": "coupler", "point": [1.2, 0.8, 0.6], "output": "tool",
                                    "axis": list(AXIS)}
    path = tmp_path / ("tool" + suffix)
    save(mechanism, path)
    again = load(path)
    assert again.end_effector == mechanism.end_effector and again.joints == mechanism.joints
    assert loads(json.dumps(data), format="json").mechanism.end_effector == mechanism.end_effector


BAD_END_EFFECTORS = [
    ("output: tool", "", "field 'axis': missing"),
    ("output: tool", "  axis: [0, 0, 0]", "field 'axis': the axis must not be zero"),
    ("output: tool", "  axis: [0, 1]", "field 'axis': expected 3 numbers, got 2"),
    ("output: tool", "  axis: [0, .nan, 1]", "field 'axis'"),
    ("output: tool", "  axis: [0, '1', 1]", "field 'axis': item 1"),
    ("output: tool", "  axis: 1.0", "field 'axis': expected a list of numbers"),
    ("output: pose", "  axis: [0, 0, 1]", "field 'axis': only used by a 'tool' output"),
    ("output: position", "  axis: [0, 0, 1]", "field 'axis': only used by a 'tool' output"),
]


@pytest.mark.parametrize("output, axis, message", BAD_END_EFFECTORS)
def test_bad_axes_are_refused_naming_the_field(output, axis, message):
    text = TOOL_FILE.replace("  output: tool\n  axis: [0.3, -0.5, 0.8]\n", f"  {output}\n{axis}\n")
    with pytest.raises(MechanismError, match="end_effector: " + message.replace("(", r"\(").replace(".", r"\.")):
        loads(text)


def test_a_tool_needs_a_spatial_mechanism():
    planar = """
name: slider
space: planar
joints:
  - {name: A, type: P, links: [ground, slider], axis: [1, 0], actuated: true}
end_effector: {link: slider, point: [0, 0], output: tool, axis: [1, 0, 0]}
"""
    with pytest.raises(MechanismError, match="end_effector: field 'output': a 'tool' output needs a spatial"):
        loads(planar)


@pytest.mark.parametrize("output, axis, message", BAD_END_EFFECTORS[:2] + BAD_END_EFFECTORS[-2:-1])
def test_classify_exits_2_with_one_line_naming_the_axis(tmp_path, capsys, output, axis, message):
    path = tmp_path / "bad.yaml"
    path.write_text(TOOL_FILE.replace("  output: tool\n  axis: [0.3, -0.5, 0.8]\n", f"  {output}\n{axis}\n"))
    status = main(["classify", str(path)])
    captured = capsys.readouterr()
    assert status == 2 and captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and "field 'axis'" in lines[0] and message in lines[0]
    assert "Traceback" not in captured.err
