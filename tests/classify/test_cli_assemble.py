"""``closedchain classify --assemble``: the --at joints held at exactly the given values, the loops solved."""

import io
import json

import pytest

from classify.cli import main

FIVE_BAR = "examples/five_bar.yaml"


def run(argv, capsys):
    out = io.StringIO()
    status = main(argv, out=out)
    return status, out.getvalue(), capsys.readouterr().err


def test_the_input_is_held_exactly_where_projection_would_move_it(capsys):
    """--project moves J1 from the asked −0.373; --assemble keeps it bit for bit and closes the loops."""
    status, text, _ = run(["classify", FIVE_BAR, "--at", '{"J1": -0.373}', "--assemble", "--format", "json"], capsys)
    assert status == 0
    result = json.loads(text)
    assert result["assembly"]["held"]["J1"] == -0.373
    assert result["assembly"]["residual"] < 1e-10
    assert result["configuration"]["J1"] == -0.373
    status, text, _ = run(["classify", FIVE_BAR, "--at", '{"J1": -0.373}', "--project", "--format", "json"], capsys)
    assert status == 0 and json.loads(text)["configuration"]["J1"] != pytest.approx(-0.373, abs=1e-3)


def test_branches_are_selected_and_named_in_the_text(capsys):
    first = run(["classify", FIVE_BAR, "--at", '{"J1": 0.1}', "--assemble", "--branch", "0", "--format", "json"],
                capsys)
    second = run(["classify", FIVE_BAR, "--at", '{"J1": 0.1}', "--assemble", "--branch", "1", "--format", "json"],
                 capsys)
    one, other = (json.loads(result[1])["assembly"] for result in (first, second))
    assert (one["branch"], other["branch"]) == (0, 1) and one["branches"] == other["branches"] == 2
    assert one["displacements"]["J2"] != pytest.approx(other["displacements"]["J2"], abs=1e-6)
    status, text, _ = run(["classify", FIVE_BAR, "--at", '{"J1": 0.1}', "--assemble"], capsys)
    assert status == 0 and "branch 0 of 2" in text


def test_an_assembly_that_is_not_isolated_is_said_so(capsys):
    """The 5-SPU's five legs leave the tool's spin free: no branch number, which the text printed as
    "branch None of None found"."""
    status, text, _ = run(["classify", "5-spu", "--at", '{"P1": 0.01}', "--assemble"], capsys)
    assert status == 0 and "None" not in text and "not an isolated assembly" in text


@pytest.mark.parametrize("arguments, fragment", [
    (["--at", '{"J1": 3.0}', "--assemble"], "no assembly with J1 = 3.0"),
    (["--at", '{"J1": 0.1}', "--assemble", "--branch", "7"], "branch 7"),
    (["--at", '{"J1": 0.1}', "--branch", "1"], "--branch"),
    (["--at", '{"J1": 0.1}', "--assemble", "--project"], "--assemble"),
    (["--assemble"], "--assemble"),
    (["--at", '{"J9": 0.1}', "--assemble"], "J9"),
])
def test_what_cannot_be_assembled_exits_2_with_one_line(arguments, fragment, capsys):
    status, text, error = run(["classify", FIVE_BAR, *arguments], capsys)
    assert status == 2 and text == ""
    assert error.count("\n") == 1 and error.startswith("closedchain: error:") and fragment in error
