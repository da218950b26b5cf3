"""Line-plane 5-SPU (Borràs, Thomas & Torras 2011): verdicts and invariants that must not depend on the frame —
a mechanism file moved rigidly, the pencil of B-lines (B, B∞, Λ⁺) far from the origin, the leg numbering of the
signed B-lines and distances — and the paper's Fig. 5 poses (eq. 33)."""

import json

import numpy as np
import pytest
import yaml

from classify.line_plane import (
    b_infinity, b_line, b_point, design_from_mechanism, lambda_plus, line_plane_design, move_platform,
    singularity_reading)
from mechanisms.io import load
from builders import command as run

QUARTIC_BASE = np.array([[0.1, 0.2], [1.3, -0.4], [-0.7, 1.1], [0.9, 1.6], [-1.2, -0.8]])
QUARTIC_PLATFORM = np.array([0.3, -1.1, 0.6, 1.4, -0.2])
POSE = (np.array([0.2, 0.4, 1.5]), np.array([0.3, -0.2, 0.9]) / np.linalg.norm([0.3, -0.2, 0.9]))
SHIFTS = (10.0, 100.0, 1000.0, 1e4)


# ------------------------------------------------------------------------------------------------ mechanism files

@pytest.fixture
def singular_document(tmp_path, capsys):
    """The catalogue's 5-SPU at a singular pose on the second factor of (33), as a YAML document."""
    path = tmp_path / "singular.yaml"
    status, _, err = run(["catalog", "5-spu", "--configuration", "eq33_second_factor", "--write", str(path)], capsys)
    assert status == 0, err
    return yaml.safe_load(path.read_text())


def _moved(document, rotation, shift, path):
    """The document moved rigidly (points by rotation then shift, directions by rotation), written to `path`."""
    document = json.loads(json.dumps(document))
    rotation, shift = np.asarray(rotation, dtype=float), np.asarray(shift, dtype=float)

    def point(value):
        return (rotation @ np.array(value, dtype=float) + shift).tolist()

    def vector(value):
        return (rotation @ np.array(value, dtype=float)).tolist()
    for joint in document["joints"]:
        if "point" in joint:
            joint["point"] = point(joint["point"])
        if "axis" in joint:
            joint["axis"] = vector(joint["axis"])
        if "axes" in joint:
            joint["axes"] = [vector(axis) for axis in joint["axes"]]
    effector = document.get("end_effector") or {}
    if effector.get("point") is not None:
        effector["point"] = point(effector["point"])
    if effector.get("axis") is not None:
        effector["axis"] = vector(effector["axis"])
    path.write_text(yaml.safe_dump(document))
    return path


def _turn(angle, axis):
    """Rotation by `angle` about a unit `axis` (Rodrigues)."""
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    skew = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * skew + (1.0 - np.cos(angle)) * skew @ skew


MOTIONS = [(np.eye(3), [0.0, 0.0, 0.004]), (np.eye(3), [1000.0, 0.0, 0.0]), (np.eye(3), [1000.0, 0.0, 0.004]),
           (_turn(0.7, [0, 0, 1]), [-300.0, 800.0, 0.004]), (_turn(0.3, [1, 2, 0]), [1000.0, -50.0, 7.0])]


@pytest.mark.parametrize("rotation, shift", MOTIONS)
def test_a_file_moved_rigidly_gives_the_same_design_pose_and_verdict(singular_document, tmp_path, capsys,
                                                                      rotation, shift):
    """Section II: the design is read in the frame of Π. A rigid motion of the file (Π at z = 0.004, or far from
    the origin, or tilted) is the same robot at the same pose: the same zᵢ, the same height p_z of p over Π, the
    same base up to a plane motion, and the singular verdict of (17) that ``classify`` gives; it was regular (margin
    3.3e-4, p_z 3.004) after the shift (1000, 0, 0.004)."""
    reference_path = _moved(singular_document, np.eye(3), np.zeros(3), tmp_path / "reference.yaml")
    reference, position, direction = design_from_mechanism(load(reference_path))
    moved_path = _moved(singular_document, rotation, shift, tmp_path / "moved.yaml")
    design, moved_position, moved_direction = design_from_mechanism(load(moved_path))
    assert np.allclose(design.platform, reference.platform, rtol=0, atol=1e-9)
    assert moved_position[2] == pytest.approx(position[2], abs=1e-9)
    assert moved_direction[2] == pytest.approx(direction[2], abs=1e-9)
    gaps = np.linalg.norm(design.base[:, None] - design.base[None], axis=-1)
    reference_gaps = np.linalg.norm(reference.base[:, None] - reference.base[None], axis=-1)
    assert np.allclose(gaps, reference_gaps, rtol=0, atol=1e-9)
    reading = singularity_reading(design, moved_position, moved_direction)
    assert reading.singular and reading.margin <= 1e-12
    status, out, err = run(["line-plane", str(moved_path), "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["singularity"]["singular"] is True and result["pose"]["p"][2] == pytest.approx(3.0, abs=1e-9)


@pytest.mark.parametrize("rotation, shift", [(np.eye(3), [0.0, 0.0, 0.0])] + MOTIONS)
def test_a_platform_attachment_off_the_line_is_refused_in_every_frame(singular_document, tmp_path, capsys,
                                                                       rotation, shift):
    """Section II: the U centres lie on Λ. U3 moved 0.005 off Λ was refused at the origin but, after a shift by
    1000, accepted, silently projected onto a line and read as quartic instead of quadratic."""
    for joint in singular_document["joints"]:
        if joint["name"] == "U3":
            joint["point"][1] += 0.005
    path = _moved(singular_document, rotation, shift, tmp_path / "off.yaml")
    status, out, err = run(["line-plane", str(path), "--format", "json"], capsys)
    lines = err.strip().splitlines()
    assert status == 2 and out == "" and len(lines) == 1
    assert "collinear" in lines[0] and str(path) in lines[0]


# ------------------------------------------------------------------------------------------------ the pencil far away

@pytest.mark.parametrize("shift", SHIFTS)
def test_b_b_infinity_lambda_plus_and_b_lines_move_with_the_frame(shift):
    """(14)-(16), (23): translating the base frame by t (and Λ's origin by t) translates B, B∞, Λ⁺ and every
    B-line by t. From the raw cofactors B was off by 1.1e-8 at t = 100 and by 2.6 at t = 1e4. A line is compared
    by its unit normal and its signed distance from the (moved) base centroid: its coefficient c, the distance
    from the far origin, carries the rounding of the shifted coordinates times t."""
    reference = line_plane_design(QUARTIC_BASE, QUARTIC_PLATFORM)
    design = line_plane_design(QUARTIC_BASE + shift, QUARTIC_PLATFORM + shift)
    tolerance = 1e-12 * shift
    assert np.allclose(b_point(design) - shift, b_point(reference), rtol=0, atol=tolerance)

    def near(lines, reference_lines):
        lines, reference_lines = np.atleast_2d(lines), np.atleast_2d(reference_lines)
        lines = lines / np.hypot(lines[:, 0], lines[:, 1])[:, None]
        reference_lines = reference_lines / np.hypot(reference_lines[:, 0], reference_lines[:, 1])[:, None]
        centre = reference.centre[:2]
        at_centre = lines[:, :2] @ (centre + shift) + lines[:, 2]
        reference_at_centre = reference_lines[:, :2] @ centre + reference_lines[:, 2]
        return (np.allclose(lines[:, :2], reference_lines[:, :2], rtol=0, atol=tolerance)
                and np.allclose(at_centre, reference_at_centre, rtol=0, atol=tolerance))
    assert near(b_infinity(design), b_infinity(reference))
    line, copies = lambda_plus(design)
    reference_line, reference_copies = lambda_plus(reference)
    assert near(line, reference_line)
    assert np.allclose(copies - shift, reference_copies, rtol=0, atol=tolerance)
    assert near(b_line(design, design.platform), b_line(reference, reference.platform))


@pytest.mark.parametrize("shift", (0.0,) + SHIFTS[:3])
def test_a_platform_move_at_b_is_allowed_far_from_the_origin(shift):
    """Section III-D, remark 2: two coincident base attachments mark B; leg 4's platform attachment may move. The
    same design with the frame translated by t was refused at t = 100 (B off a₄ by 1.4e-8)."""
    base = QUARTIC_BASE.copy()
    base[4] = base[3]
    design = line_plane_design(base + shift, QUARTIC_PLATFORM + shift)
    assert np.linalg.norm(b_point(design) - design.base[3]) <= 1e-12 * max(1.0, shift)
    moved = move_platform(design, 3, 2.0 + shift)
    assert moved.platform[3] == 2.0 + shift


def test_the_cli_allows_the_platform_move_at_b_far_from_the_origin(capsys):
    """The audit's command: exit 2 "not at B (distance 1.42e-08)" for the design translated by 100."""
    status, out, err = run(["line-plane", "--base", "100.1,100.2 101.3,99.6 99.3,101.1 100.9,101.6 100.9,101.6",
                            "--platform", "100.3 98.9 100.6 101.4 99.8", "--move-platform", "4:102",
                            "--format", "json"], capsys)
    assert status == 0, err
    assert json.loads(out)["rearranged"]["design"]["platform"][3] == 102.0


# ------------------------------------------------------------------------------------------------ leg numbering

ORDERS = [[1, 0, 2, 3, 4], [4, 2, 3, 0, 1], [0, 1, 2, 4, 3]]


@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("flip", [1.0, -1.0])
def test_the_signed_distance_to_b_mu_does_not_depend_on_the_numbering(order, flip):
    """Section III-C, (18)-(19): the distance from A to B_μ is signed by the side of B_μ holding the base centroid
    (positive there), as B∞ and Λ⁺ are; a swap of two legs flipped it."""
    design = line_plane_design(QUARTIC_BASE, QUARTIC_PLATFORM)
    other = line_plane_design(QUARTIC_BASE[order], flip * QUARTIC_PLATFORM[order])
    position, direction = POSE
    reading = singularity_reading(design, position, direction)
    other_reading = singularity_reading(other, position, flip * direction)
    assert other_reading.distance == pytest.approx(reading.distance, rel=1e-12)
    line = b_line(design, reading.z)
    centroid_side = np.sign(line[:2] @ design.centre[:2] + line[2])
    point_side = np.sign(line[:2] @ reading.intersection + line[2])
    assert np.sign(reading.distance) == centroid_side * point_side


@pytest.mark.parametrize("shift", SHIFTS)
def test_the_signed_distance_to_b_mu_moves_with_the_frame(shift):
    design = line_plane_design(QUARTIC_BASE, QUARTIC_PLATFORM)
    moved = line_plane_design(QUARTIC_BASE + shift, QUARTIC_PLATFORM + shift)
    position, direction = POSE
    reading = singularity_reading(design, position, direction)
    moved_reading = singularity_reading(moved, position + [shift, shift, 0.0] - shift * direction, direction)
    assert moved_reading.distance == pytest.approx(reading.distance, abs=1e-12 * shift)
    assert moved_reading.z == pytest.approx(reading.z + shift, abs=1e-12 * shift)


def _cli_json(base, platform, capsys):
    status, out, err = run(["line-plane", "--base", " ".join(f"{float(x)!r},{float(y)!r}" for x, y in base),
                            "--platform", " ".join(repr(float(z)) for z in platform), "--format", "json"], capsys)
    assert status == 0, err
    return json.loads(out)


@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("flip", [1.0, -1.0])
def test_the_cli_b_lines_do_not_depend_on_the_numbering(order, flip, capsys):
    """(14): the B-line of each leg is signed as B∞ (the base centroid on its positive side), so a renumbering or
    a flip of i gives the same lines in the legs' own order; a swap flipped every sign."""
    result = _cli_json(QUARTIC_BASE, QUARTIC_PLATFORM, capsys)
    other = _cli_json(QUARTIC_BASE[order], flip * QUARTIC_PLATFORM[order], capsys)
    assert np.allclose(np.array(other["b_lines"]), np.array(result["b_lines"])[order], rtol=0, atol=1e-12)
    centre = QUARTIC_BASE.mean(axis=0)
    lines = np.array(result["b_lines"])
    assert np.all(lines[:, :2] @ centre + lines[:, 2] > 0)
    assert np.allclose(np.hypot(lines[:, 0], lines[:, 1]), 1.0)


# ------------------------------------------------------------------------------------------------ Fig. 5

def test_the_fig5_poses_on_a_delta_1_quadratic_design():
    """Borràs, Thomas & Torras 2011, Fig. 5 and eq. (33): for a quadratic design in normal form (26) with δ = 1
    (zᵢ = xᵢ, x₁ = y₁ = 0), (17) is −δ²wF[δwpₓ − (δu − 1)p_z]. The singular pose p = (7√6 − 7, 4, 14),
    i = (√6/6, −√6/6, −√6/3) zeroes the factor; the regular pose p = (5, 8, 13), i = (1/3, −2/3, −2/3) gives 16/3."""
    x = np.array([0.0, 2.0, -1.0, 1.5, -2.0])
    y = np.array([0.0, 1.0, 2.0, -1.5, -1.0])
    design = line_plane_design(np.column_stack([x, y]), 1.0 * x)
    root6 = np.sqrt(6.0)
    poses = {"singular": ((7 * root6 - 7, 4.0, 14.0), (root6 / 6, -root6 / 6, -root6 / 3)),
             "regular": ((5.0, 8.0, 13.0), (1 / 3, -2 / 3, -2 / 3))}
    for name, (position, direction) in poses.items():
        p_x, _, p_z = position
        u, _, w = direction
        factor = 1.0 * w * p_x - (1.0 * u - 1.0) * p_z
        reading = singularity_reading(design, position, direction)
        if name == "singular":
            assert factor == pytest.approx(0.0, abs=1e-13)
            assert reading.singular and reading.margin <= 1e-15
            assert reading.distance == pytest.approx(0.0, abs=1e-12)
        else:
            assert factor == pytest.approx(16 / 3, rel=1e-14)
            assert not reading.singular and reading.margin == pytest.approx(0.0795, abs=5e-4)
