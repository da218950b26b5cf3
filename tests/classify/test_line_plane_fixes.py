"""Line-plane 5-SPU (Borràs, Thomas & Torras 2011): regressions of an audit — Λ⁺ (23) and the leg numbering,
double assembly modes at singular leg lengths, architecturally singular designs (Section III-A), a base
attachment far along its B-line (Section III-B), hand-written mechanism files, messages and margins."""

import json
import re

import numpy as np
import pytest
import yaml

from classify.cli import main
from classify.line_plane import (
    RearrangementError, architecture_margin, b_infinity, b_line, b_line_direction, cofactors, design_from_mechanism,
    family, lambda_plus, line_plane_design, move_base, singularity_polynomial)
from classify.line_plane_kinematics import assembly_modes, leg_lengths
from mechanisms.catalogue.five_spu import five_spu

QUARTIC_BASE = [(0.1, 0.2), (1.3, -0.4), (-0.7, 1.1), (0.9, 1.6), (-1.2, -0.8)]
QUARTIC_PLATFORM = [0.3, -1.1, 0.6, 1.4, -0.2]


def quartic():
    return line_plane_design(QUARTIC_BASE, QUARTIC_PLATFORM)


def run(arguments, capsys):
    status = main(arguments)
    captured = capsys.readouterr()
    return status, captured.out, captured.err


# ------------------------------------------------------------------------------------------------ Λ⁺ (23)

@pytest.mark.parametrize("order", [[1, 0, 2, 3, 4], [4, 2, 3, 0, 1], [0, 1, 2, 4, 3]])
@pytest.mark.parametrize("flip", [1.0, -1.0])
def test_lambda_plus_does_not_depend_on_the_leg_numbering_or_the_sign_of_i(order, flip):
    """(23), Fig. 8: a renumbering (odd ones flip the sign of every Cⱼ) or a flip of i is the same robot, so the
    same Λ⁺ and the same copies b⁺ᵢ (in the legs' own order); the printed (23) gave the mirror line."""
    design = quartic()
    line, copies = lambda_plus(design)
    other = line_plane_design(design.base[order], flip * design.platform[order])
    other_line, other_copies = lambda_plus(other)
    assert np.allclose(other_line, line, atol=1e-12)
    assert np.allclose(other_copies, copies[order], atol=1e-10)
    assert np.allclose(b_infinity(other), b_infinity(design), atol=1e-12)


def test_lambda_plus_is_the_fig8_copy_on_the_side_of_the_base_centroid():
    """Both mirror images in B∞ carry the copies onto their B-lines (Fig. 8); the one taken is on the side of ā,
    at distance ``|C₂C₅ − C₃C₄|``/(C₄² + C₅²) from B∞ (23)."""
    design = quartic()
    line, copies = lambda_plus(design)
    infinity = b_infinity(design)
    c1, c2, c3, c4, c5, c6 = cofactors(design)
    assert line[2] == pytest.approx(infinity[2] - abs(c2 * c5 - c3 * c4) / (c4 ** 2 + c5 ** 2), abs=1e-12)
    centre = design.centre[:2]
    assert line[:2] @ centre + line[2] > 0 and infinity[:2] @ centre + infinity[2] > 0
    own = b_line(design, design.platform)
    assert np.all(np.abs(np.sum(own[:, :2] * copies, axis=1) + own[:, 2]) < 1e-9 * np.linalg.norm(own[:, :2], axis=1))
    gaps = (copies - copies[0]) @ np.array([line[1], -line[0]])
    assert np.allclose(np.abs(gaps), np.abs(design.platform - design.platform[0]), atol=1e-10)


# ------------------------------------------------------------------------------------------------ double roots of (10)

def singular_lengths():
    """Leg lengths of a pose on the zero set of (17) (linear in pₓ): the polynomial (10) has a double root."""
    design = quartic()
    direction = np.array([0.3, -0.2, 0.9]) / np.linalg.norm([0.3, -0.2, 0.9])
    position = np.array([0.0, 0.1, 2.0])
    at_zero = singularity_polynomial(design, position, direction)
    at_one = singularity_polynomial(design, position + [1.0, 0.0, 0.0], direction)
    position[0] = -at_zero / (at_one - at_zero)
    return design, position, direction, leg_lengths(design, position, direction)


def test_a_double_root_at_singular_leg_lengths_is_one_mode_of_multiplicity_two():
    """Section II-B: at a singular pose (10) has a double root; each of its two poses is listed once."""
    design, position, direction, lengths = singular_lengths()
    modes = assembly_modes(design, lengths)
    real = [mode for mode in modes if mode.real]
    assert len(real) == 2 and [mode.multiplicity for mode in real] == [2, 2]
    assert sum(mode.multiplicity for mode in modes) == 8
    assert np.linalg.norm(real[0].position - real[1].position) > 1.0
    assert min(np.linalg.norm(mode.position - position) for mode in real) < 1e-6


@pytest.mark.parametrize("relative", [1e-14, -1e-13, 1e-12, -1e-12])
def test_singular_leg_lengths_off_by_rounding_still_give_the_double_modes(relative):
    """A double root is split by about c√δ by lengths off by δ: with a merge at 1e-6, δ = 1e-12 (or the rounding
    of a design read 150 lengths from the origin) gave four real or four complex modes (found by an audit)."""
    design, _, _, lengths = singular_lengths()
    modes = assembly_modes(design, lengths * (1.0 + relative * np.array([1.0, -1.0, 1.0, -1.0, 1.0])))
    assert [mode.multiplicity for mode in modes if mode.real] == [2, 2]


def test_the_cli_counts_distinct_real_modes_at_singular_leg_lengths(capsys):
    _, _, _, lengths = singular_lengths()
    base = " ".join(f"{x},{y}" for x, y in QUARTIC_BASE)
    arguments = ["line-plane", "--base", base, "--platform", " ".join(map(str, QUARTIC_PLATFORM)),
                 "--legs", ",".join(repr(float(value)) for value in lengths)]
    status, out, err = run([*arguments, "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["real_modes"] == 2
    assert [mode["multiplicity"] for mode in result["assembly_modes"] if mode["real"]] == [2, 2]
    status, out, err = run(arguments, capsys)
    assert status == 0 and "singular configuration" in out and "(multiplicity 2)" in out


# ------------------------------------------------------------------------------------------------ architecture

THREE_ON_ONE_B_LINE = ["--base", "0,0 1,1 2,2 0,1 1,-1", "--platform", "0.5 0.5 0.5 1 -1"]


@pytest.mark.parametrize("arguments", [
    THREE_ON_ONE_B_LINE,
    ["--base", " ".join(f"{x},{y}" for x, y in QUARTIC_BASE), "--platform", "1 1 1 1 1"],
])
def test_an_architecturally_singular_design_has_no_cofactors_b_lines_or_b(arguments, capsys):
    """Section III-A: all Cⱼ vanish — rounding is not shown as cofactors, B-lines, B or B∞."""
    status, out, err = run(["line-plane", *arguments, "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["family"] == "architecturally singular"
    assert result["cofactors"] is None and result["b_lines"] is None
    assert result["B"] is None and result["B_inf"] is None and result["Lambda_plus"] is None
    status, out, err = run(["line-plane", *arguments], capsys)
    assert status == 0 and "undefined" in out and "∝" not in out and "at infinity" not in out


def test_the_figure_of_an_architecturally_singular_design_draws_no_b_lines():
    from classify.figures.line_plane import draw_b_lines

    design = line_plane_design([(0, 0), (1, 1), (2, 2), (0, 1), (1, -1)], [0.5, 0.5, 0.5, 1, -1])
    figure = draw_b_lines(design)
    assert [line.get_label() for line in figure.axes[0].get_lines()] == ["base"]
    assert "architecturally singular" in figure.axes[0].get_title()


@pytest.mark.parametrize("distance", [2e4, 1e6, 1e12])
def test_a_base_attachment_far_along_its_b_line_is_not_architecturally_singular(distance):
    """Section III-B rule 1: sliding a₁ along its B-line multiplies the Cⱼ by a growing factor; the design stays
    quartic with the same B, and the architecture margin does not fall with the distance."""
    design = quartic()
    reference = architecture_margin(design)
    moved = move_base(design, 0, distance)
    assert family(moved).name == "quartic"
    assert architecture_margin(moved) > 0.1 * reference
    ratio = cofactors(moved) / cofactors(design)
    assert np.ptp(ratio) < 1e-9 * abs(ratio.mean()) and abs(ratio.mean()) > 0.1 * distance


def test_architecture_margin_does_not_depend_on_numbering_frame_or_unit():
    design = quartic()
    angle = 0.8
    turn = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    variants = [line_plane_design(design.base[[3, 1, 4, 0, 2]], design.platform[[3, 1, 4, 0, 2]]),
                line_plane_design(design.base @ turn.T + [5.0, -3.0], -design.platform + 2.0),
                line_plane_design(1e-3 * design.base, 1e-3 * design.platform)]
    for variant in variants:
        assert architecture_margin(variant) == pytest.approx(architecture_margin(design), rel=1e-9)


def test_a_move_onto_three_legs_of_one_b_line_is_still_refused():
    """Section III-B: three attachments on one B-line make every Cⱼ vanish."""
    design = line_plane_design([(0, 0), (1, 1), (2.0, 2.3), (0, 1), (1, -1)], [0.5, 0.5, 0.5, 1, -1])
    direction = b_line_direction(design, 2)
    point = design.base[2]
    # the distance along leg 3's B-line to the line through a₁, a₂ (all three share z = 0.5)
    distance = float((point[1] - point[0]) / (direction[0] - direction[1]))
    with pytest.raises(RearrangementError, match="architecturally singular"):
        move_base(design, 2, distance)


# ------------------------------------------------------------------------------------------------ mechanism files

@pytest.fixture
def catalogue_file(tmp_path, capsys):
    path = tmp_path / "five_spu.yaml"
    status, _, err = run(["catalog", "5-spu", "--write", str(path)], capsys)
    assert status == 0, err
    return path


def _line_plane_json(path, capsys, *options):
    status, out, err = run(["line-plane", str(path), *options, "--format", "json"], capsys)
    assert status == 0, err
    return json.loads(out)


def test_a_file_written_to_six_significant_digits_is_accepted(catalogue_file, tmp_path, capsys):
    """A hand-written 5-SPU file (six significant digits) is a line-plane design (Section II)."""
    reference = _line_plane_json(catalogue_file, capsys)
    rounded = tmp_path / "rounded.yaml"
    rounded.write_text(re.sub(r"-?\d+\.\d+(e-?\d+)?", lambda match: f"{float(match.group(0)):.6g}",
                              catalogue_file.read_text()))
    result = _line_plane_json(rounded, capsys)
    assert np.allclose(result["design"]["platform"], reference["design"]["platform"], atol=1e-5)
    assert np.allclose(result["pose"]["i"], reference["pose"]["i"], atol=1e-5)
    assert result["singularity"]["singular"] is False


def test_the_family_of_a_rounded_file_is_decided_with_the_rtol_given(catalogue_file, tmp_path, capsys):
    """The catalogue's design is quadratic (B∞ at infinity, Section IV-C); written to six digits its margins are
    ~1e-6, above the default cut 1e-8 (quartic), below the --rtol 1e-5 a six-digit file calls for."""
    rounded = tmp_path / "rounded.yaml"
    rounded.write_text(re.sub(r"-?\d+\.\d+(e-?\d+)?", lambda match: f"{float(match.group(0)):.6g}",
                              catalogue_file.read_text()))
    assert _line_plane_json(catalogue_file, capsys)["family"] == "quadratic"
    assert _line_plane_json(rounded, capsys)["family"] == "quartic"
    loose = _line_plane_json(rounded, capsys, "--rtol", "1e-5")
    assert (loose["family"], loose["rtol"], loose["B_inf"]) == ("quadratic", 1e-5, None)
    for bad in ("0", "1", "-1e-5"):
        status, out, err = run(["line-plane", str(rounded), "--rtol", bad], capsys)
        assert status == 2 and err.count("\n") == 1 and "--rtol" in err and not out


@pytest.mark.parametrize("tilt", [0.0, 0.4])
def test_a_base_plane_off_z_equal_0_is_fitted(catalogue_file, tmp_path, capsys, tilt):
    """A change of the base frame (Π lifted by 0.5, or turned by `tilt` about x) gives the same design."""
    reference = _line_plane_json(catalogue_file, capsys)
    document = yaml.safe_load(catalogue_file.read_text())
    turn = np.array([[1, 0, 0], [0, np.cos(tilt), -np.sin(tilt)], [0, np.sin(tilt), np.cos(tilt)]])

    def move(point):
        return (turn @ np.array(point, dtype=float) + [0.0, 0.0, 0.5]).tolist()
    for joint in document["joints"]:
        if "point" in joint:
            joint["point"] = move(joint["point"])
        for key in ("axis",):
            if key in joint:
                joint[key] = (turn @ np.array(joint[key], dtype=float)).tolist()
        if "axes" in joint:
            joint["axes"] = [(turn @ np.array(axis, dtype=float)).tolist() for axis in joint["axes"]]
    effector = document.get("end_effector") or {}
    if effector.get("point") is not None:
        effector["point"] = move(effector["point"])
    if effector.get("axis") is not None:
        effector["axis"] = (turn @ np.array(effector["axis"], dtype=float)).tolist()
    moved = tmp_path / "moved.yaml"
    moved.write_text(yaml.safe_dump(document))
    result = _line_plane_json(moved, capsys)
    assert result["family"] == reference["family"]
    assert np.allclose(result["design"]["platform"], reference["design"]["platform"], atol=1e-9)
    reference_base, base = np.array(reference["design"]["base"]), np.array(result["design"]["base"])
    assert np.allclose(np.linalg.norm(base - base[0], axis=1), np.linalg.norm(reference_base - reference_base[0],
                                                                                   axis=1), atol=1e-9)
    assert result["singularity"]["margin"] == pytest.approx(reference["singularity"]["margin"], rel=1e-9)


def test_a_locked_spin_gives_the_same_frame_as_a_free_one():
    """design_from_mechanism: i is the second axis of the first U joint; with the spin locked leg 1 ends in an R
    joint, and U2 gives the same i (not −i and negated zᵢ)."""
    free, locked = (design_from_mechanism(five_spu(spin=spin)) for spin in ("free", "locked"))
    assert np.allclose(locked[0].platform, free[0].platform) and np.allclose(locked[2], free[2])


# ------------------------------------------------------------------------------------------------ messages, margins

def test_an_error_of_a_catalogue_design_names_the_entry_not_an_option_not_given(capsys):
    status, out, err = run(["line-plane", "5-spu", *[f"--param=z{index}=1" for index in range(1, 6)],
                            "--legs", "3,3,3,3,3"], capsys)
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1
    assert lines[0].startswith("closedchain: error: 5-spu:") and "--base" not in lines[0]


def test_the_margin_of_a_cubic_design_is_the_b_margin_that_decided_it():
    """Section IV-B: cubic when B is at infinity — the deciding value is the B margin, not the B∞ margin."""
    rng = np.random.default_rng(0)
    z = rng.normal(size=5)
    c1, c2, c4, c6 = rng.normal(size=4)
    design = line_plane_design(np.column_stack([-(c1 * z + c6) / (c4 * z + c2), rng.normal(size=5)]), z)
    result = family(design)
    assert result.name == "cubic" and result.margin == result.b_margin and result.margin < 1e-12


def test_framework_route_searches_when_the_polynomial_route_finds_no_real_mode(monkeypatch, capsys):
    """With no real mode the cross-check asked the search for none, assembled nothing and said 'agrees'."""
    import classify.line_plane_kinematics as kinematics

    calls = []
    original = kinematics._assemble_from
    monkeypatch.setattr(kinematics, "_assemble_from", lambda *arguments: (calls.append(1), original(*arguments))[1])
    base = " ".join(f"{x},{y}" for x, y in QUARTIC_BASE)
    status, out, err = run(["line-plane", "--base", base, "--platform", " ".join(map(str, QUARTIC_PLATFORM)),
                            "--legs", "10,10,10,10,10", "--framework", "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["real_modes"] == 0 and result["framework_modes"] == [] and result["routes_agree"]
    assert len(calls) >= 24
