"""Fuzz of the ``closedchain`` command, in-process: mutated mechanism files and mutated flags.

Every run must end with exit status 0 or 2 (never 1, an internal error),
without a traceback, within 10 s; a refusal (2) prints exactly one line on
stderr, starting ``closedchain: error:``, and nothing on stdout; a success
(0) prints JSON without NaN or Infinity. No output may hold a raw control
character or text UTF-8 cannot encode. Random mutations are seeded per case
(:mod:`mutations`); the dangerous inputs (bombs, special files, huge files)
run in a memory-limited subprocess in :mod:`test_fuzz_limits`.
"""

import contextlib
import io
import json
import os
import re
import time
import zlib
from dataclasses import dataclass

import numpy as np
import pytest
import yaml

from classify.cli import main
from mechanisms import catalogue
from mutations import CHEAP_ENTRIES, MUTATIONS

#: longest a single run may take, in seconds
TIME_LIMIT = 10.0
#: control characters no text output may contain raw (newline and tab are layout), bidirectional overrides included
CONTROL_CHARACTERS = re.compile(r"[\x00-\x08\x0b-\x1f\x7f-\x9f\u202a-\u202e\u2066-\u2069]")
#: what JSON must escape (other characters are data inside JSON strings)
JSON_CONTROL_CHARACTERS = re.compile(r"[\x00-\x08\x0b-\x1f]")


@dataclass(frozen=True)
class Run:
    """What one command did."""

    status: int
    out: str
    err: str
    seconds: float


def run_command(argv, capsys):
    """Run ``closedchain argv`` in-process; stdout into a StringIO, stderr from `capsys`."""
    capsys.readouterr()
    out = io.StringIO()
    start = time.perf_counter()
    status = main(argv, out=out)
    seconds = time.perf_counter() - start
    return Run(status, out.getvalue(), capsys.readouterr().err, seconds)


def _refuse_constant(name):
    raise ValueError(f"non-finite number {name} in the JSON output")


def check_run(run, expected=None, output_format="json"):
    """The fuzz contract (see the module docstring); `expected` the exact status when known."""
    assert run.status in (0, 2), f"status {run.status}: {run.err}"
    assert "Traceback" not in run.err
    assert run.seconds < TIME_LIMIT, f"took {run.seconds:.1f} s"
    run.out.encode("utf-8")
    run.err.encode("utf-8")
    assert not CONTROL_CHARACTERS.search(run.err), f"raw control character on stderr: {run.err!r}"
    forbidden = JSON_CONTROL_CHARACTERS if output_format == "json" else CONTROL_CHARACTERS
    assert not forbidden.search(run.out), f"raw control character on stdout: {forbidden.search(run.out)}"
    if run.status == 2:
        assert run.err.startswith("closedchain: error:"), run.err
        assert run.err.count("\n") == 1 and run.err.endswith("\n"), run.err
        assert run.out == ""
    elif output_format == "json":
        json.loads(run.out, parse_constant=_refuse_constant)
    if expected is not None:
        assert run.status == expected, run.err


def _seed(*parts):
    """A seed fixed by the case's name: every run of the fuzz draws the same mutations."""
    return zlib.crc32("/".join(parts).encode("utf-8"))


@pytest.fixture(scope="module")
def catalogue_files(tmp_path_factory):
    """Every catalogue entry written with ``closedchain catalog NAME --write``: name -> (data, text)."""
    folder = tmp_path_factory.mktemp("catalogue")
    files = {}
    for name in catalogue.names():
        path = folder / f"{name}.yaml"
        with contextlib.redirect_stderr(io.StringIO()):
            assert main(["catalog", name, "--write", str(path)]) == 0
        text = path.read_text(encoding="utf-8")
        files[name] = (yaml.safe_load(text), text)
    return files


FILE_CASES = [(entry, mutation) for mutation in MUTATIONS
              for entry in (CHEAP_ENTRIES if mutation.costly else catalogue.names())]


@pytest.mark.parametrize("entry, mutation", FILE_CASES,
                         ids=[f"{entry}-{mutation.name}" for entry, mutation in FILE_CASES])
def test_mutated_mechanism_file(entry, mutation, catalogue_files, tmp_path, capsys):
    data, text = catalogue_files[entry]
    rng = np.random.default_rng(_seed(entry, mutation.name))
    content, suffix = mutation.mutate(data, text, rng)
    path = tmp_path / f"mutated{suffix}"
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content, encoding="utf-8", errors="surrogatepass")
    for output_format in ("json", "text") if mutation.expected == 0 else ("json",):
        run = run_command(["classify", str(path), "--format", output_format], capsys)
        check_run(run, mutation.expected, output_format)


# ----------------------------------------------------------------------- flags

@pytest.fixture
def files(tmp_path):
    """Files the flag cases refer to as {folder}/…: a binary file, an empty one, a folder, /dev/full."""
    (tmp_path / "binary.json").write_bytes(bytes(range(256)) * 4)
    (tmp_path / "empty.json").write_bytes(b"")
    (tmp_path / "folder.yaml").mkdir()
    (tmp_path / "at.json").write_text('{"A": 0.0}', encoding="utf-8")
    if os.path.exists("/dev/full"):
        (tmp_path / "full.yaml").symlink_to("/dev/full")
        (tmp_path / "full.txt").symlink_to("/dev/full")
    return tmp_path


DEEP = "[" * 100_000 + "]" * 100_000
DIGITS = "9" * 5000

#: (id, arguments with {folder} for the files fixture, expected status or None for 0 or 2)
FLAG_CASES = [
    # --at: the JSON text
    ("at-1e308", ["classify", "five-bar", "--at", '{"A": 1e308}'], 2),
    ("at-1e13", ["classify", "five-bar", "--at", '{"A": 1e13}'], 2),
    ("at-nan", ["classify", "five-bar", "--at", '{"A": NaN}'], 2),
    ("at-infinity", ["classify", "five-bar", "--at", '{"A": -Infinity}'], 2),
    ("at-1e999", ["classify", "five-bar", "--at", '{"A": 1e999}'], 2),
    ("at-5000-digits", ["classify", "five-bar", "--at", '{"A": ' + DIGITS + "}"], 2),
    ("at-deep", ["classify", "five-bar", "--at", DEEP], 2),
    ("at-nested-value", ["classify", "five-bar", "--at", '{"A": [[[0]]]}'], 2),
    ("at-surrogate-key", ["classify", "five-bar", "--at", '{"\\ud800": 0}'], 2),
    ("at-control-key", ["classify", "five-bar", "--at", '{"\\u001b[2J": 0}'], 2),
    ("at-string-value", ["classify", "five-bar", "--at", '{"A": "0.1"}'], 2),
    ("at-boolean-value", ["classify", "five-bar", "--at", '{"A": true}'], 2),
    ("at-not-an-object", ["classify", "five-bar", "--at", '"A"'], 2),
    ("at-null", ["classify", "five-bar", "--at", "null"], 2),
    ("at-duplicate-key", ["classify", "five-bar", "--at", '{"A": 0, "A": 0}'], 2),
    ("at-does-not-close", ["classify", "five-bar", "--at", '{"A": 0.1}'], 2),
    ("at-trailing-text", ["classify", "five-bar", "--at", '{"A": 0} x'], 2),
    ("at-empty-object", ["classify", "five-bar", "--at", "{}", "--format", "json"], 0),
    # --at @file
    ("at-file", ["classify", "five-bar", "--at", "@{folder}/at.json", "--format", "json"], 0),
    ("at-missing-file", ["classify", "five-bar", "--at", "@{folder}/missing.json"], 2),
    ("at-binary-file", ["classify", "five-bar", "--at", "@{folder}/binary.json"], 2),
    ("at-empty-file", ["classify", "five-bar", "--at", "@{folder}/empty.json"], 2),
    ("at-folder", ["classify", "five-bar", "--at", "@{folder}"], 2),
    ("at-no-path", ["classify", "five-bar", "--at", "@"], 2),
    ("at-nul-in-path", ["classify", "five-bar", "--at", "@{folder}/a\x00b.json"], 2),
    # --param
    ("param-1e308", ["classify", "five-bar", "--param", "base=1e308"], 2),
    ("param-minus-1e308", ["classify", "five-bar", "--param", "base=-1e308"], 2),
    ("param-nan", ["classify", "five-bar", "--param", "base=nan"], 2),
    ("param-infinity", ["classify", "five-bar", "--param", "base=inf"], 2),
    ("param-1e11", ["classify", "five-bar", "--param", "base=1e11"], 2),
    ("param-negative-length", ["classify", "five-bar", "--param", "proximal=-8"], None),
    ("param-zero-length", ["classify", "five-bar", "--param", "distal=0"], None),
    ("param-tiny-length", ["classify", "five-bar", "--param", "proximal=1e-300"], None),
    ("param-huge-angle", ["classify", "slider-crank", "--param", "theta=1e300"], 2),
    ("param-integer-5000-digits", ["classify", "five-bar", "--param", "assembly=" + DIGITS], 2),
    ("param-integer-huge", ["classify", "five-bar", "--param", "assembly=99999999999999"], 2),
    ("param-integer-odd", ["classify", "five-bar", "--param", "assembly=7"], None),
    ("param-integer-float", ["classify", "five-bar", "--param", "assembly=1.5"], 2),
    ("param-string-surrogate", ["classify", "five-bar", "--param", "actuated=\udcff"], 2),
    ("param-string-misspelt", ["classify", "five-bar", "--param", "end_effector=distal_lfet"], 2),
    ("param-string-control", ["classify", "five-bar", "--param", "actuated=A\x1b[31m"], 2),
    ("param-no-equals", ["classify", "five-bar", "--param", "base"], 2),
    ("param-no-name", ["classify", "five-bar", "--param", "=1"], 2),
    ("param-unknown", ["classify", "five-bar", "--param", "frobnication=1"], 2),
    ("param-on-a-file", ["classify", "{folder}/at.json", "--param", "base=1"], 2),
    # --seed, --length-scale, --configuration, --format
    ("seed-negative", ["classify", "five-bar", "--seed", "-1"], 2),
    ("seed-2-to-64", ["classify", "five-bar", "--seed", str(2 ** 64)], 2),
    ("seed-5000-digits", ["classify", "five-bar", "--seed", DIGITS], 2),
    ("seed-text", ["classify", "five-bar", "--seed", "one"], 2),
    ("seed-float", ["classify", "five-bar", "--seed", "1.5"], 2),
    ("seed-large", ["classify", "five-bar", "--seed", str(2 ** 64 - 1), "--format", "json"], 0),
    ("length-scale-zero", ["classify", "five-bar", "--length-scale", "0"], 2),
    ("length-scale-negative", ["classify", "five-bar", "--length-scale", "-1"], 2),
    ("length-scale-nan", ["classify", "five-bar", "--length-scale", "nan"], 2),
    ("length-scale-infinity", ["classify", "five-bar", "--length-scale", "inf"], 2),
    ("length-scale-1e300", ["classify", "five-bar", "--length-scale", "1e300"], 2),
    ("length-scale-1e-300", ["classify", "five-bar", "--length-scale", "1e-300"], 2),
    ("length-scale-text", ["classify", "five-bar", "--length-scale", "metre"], 2),
    ("configuration-unknown", ["classify", "five-bar", "--configuration", "fig99"], 2),
    ("configuration-surrogate", ["classify", "five-bar", "--configuration", "\udcff"], 2),
    ("configuration-control", ["classify", "five-bar", "--configuration", "\x1b]0;title\x07"], 2),
    ("format-unknown", ["classify", "five-bar", "--format", "xml"], 2),
    # --assemble, --branch, --project
    ("assemble-branch-negative", ["classify", "five-bar", "--assemble", "--at", '{"A": 0.1, "B": 0.1}',
                                  "--branch", "-1"], None),
    ("assemble-branch-5000-digits", ["classify", "five-bar", "--assemble", "--at", '{"A": 0.1}',
                                     "--branch", DIGITS], 2),
    ("assemble-far", ["classify", "five-bar", "--assemble", "--at", '{"A": 1e12}', "--format", "json"], None),
    ("assemble-unreachable", ["classify", "five-bar", "--assemble", "--at", '{"A": 3.0, "B": 0.0}'], None),
    ("project-far", ["classify", "five-bar", "--project", "--at", '{"A": 1e6, "B": -1e6}'], None),
    ("branch-without-assemble", ["classify", "five-bar", "--branch", "2"], 2),
    # FILE
    ("file-missing", ["classify", "{folder}/missing.yaml"], 2),
    ("file-nul", ["classify", "{folder}/a\x00b.yaml"], 2),
    ("file-name-too-long", ["classify", "x" * 5000 + ".yaml"], 2),
    ("file-surrogate", ["classify", "{folder}/\udcff.yaml"], 2),
    ("file-folder", ["classify", "{folder}/folder.yaml"], 2),
    ("file-binary", ["classify", "{folder}/binary.json"], 2),
    ("file-unknown-extension", ["classify", "{folder}/binary.txt"], 2),
    ("unknown-command", ["frobnicate"], 2),
    ("no-arguments", [], 2),
    # compare
    ("samples-a-billion", ["compare", "five-bar", "--samples", "1000000000"], 2),
    ("samples-over-the-cap", ["compare", "five-bar", "--samples", "10001"], 2),
    ("samples-negative", ["compare", "five-bar", "--samples", "-1"], 2),
    ("samples-5000-digits", ["compare", "five-bar", "--samples", DIGITS], 2),
    ("path-a-billion", ["compare", "five-bar", "--path", "1000000000"], 2),
    ("path-step-zero", ["compare", "five-bar", "--path-step", "0"], 2),
    ("path-step-nan", ["compare", "five-bar", "--path-step", "nan"], 2),
    ("path-step-1e300", ["compare", "five-bar", "--path-step", "1e300"], 2),
    ("path-step-1e-300", ["compare", "five-bar", "--path-step", "1e-300"], 2),
    ("path-step-negative", ["compare", "five-bar", "--path-step", "-0.1"], 2),
    ("inputs-unknown", ["compare", "five-bar", "--inputs", "X,Y"], 2),
    ("inputs-empty", ["compare", "five-bar", "--inputs", ","], 2),
    ("outputs-unknown", ["compare", "five-bar", "--outputs", "Z"], 2),
    ("relation-unknown", ["compare", "five-bar", "--relation", "eq99"], 2),
    ("compare-at-deep", ["compare", "five-bar", "--at", DEEP], 2),
    ("compare-seed-negative", ["compare", "five-bar", "--seed", "-5"], 2),
    ("compare-length-scale-1e300", ["compare", "five-bar", "--length-scale", "1e300"], 2),
    ("compare-small", ["compare", "slider-crank", "--samples", "1", "--format", "json"], 0),
    # catalog
    ("write-dev-full", ["catalog", "five-bar", "--write", "{folder}/full.yaml"], 2),
    ("write-missing-folder", ["catalog", "five-bar", "--write", "{folder}/missing/five_bar.yaml"], 2),
    ("write-onto-a-folder", ["catalog", "five-bar", "--write", "{folder}/folder.yaml"], 2),
    ("write-nul", ["catalog", "five-bar", "--write", "{folder}/a\x00b.yaml"], 2),
    ("write-unknown-extension", ["catalog", "five-bar", "--write", "{folder}/five_bar.txt"], 2),
    ("write-no-name", ["catalog", "--write", "{folder}/five_bar.yaml"], 2),
    ("catalog-param-1e308", ["catalog", "five-bar", "--param", "base=1e308"], 2),
    ("catalog-unknown", ["catalog", "no-such-linkage"], 2),
    ("catalog-surrogate", ["catalog", "\udcff"], 2),
    ("catalog-list", ["catalog", "--format", "json"], 0),
    # report (the input errors the fuzz found; the command itself belongs to its own tests)
    ("report-missing", ["report", "{folder}/missing"], 2),
    ("report-name-too-long", ["report", "x" * 5000], 2),
    ("report-length-scale-nan", ["report", "slider-crank", "--length-scale", "nan"], 2),
    ("report-seed-negative", ["report", "slider-crank", "--seed", "-1"], 2),
    ("report-jobs-negative", ["report", "slider-crank", "--jobs", "-1"], 2),
    ("report-jobs-5000-digits", ["report", "slider-crank", "--jobs", DIGITS], 2),
    ("report-output-missing-folder", ["report", "slider-crank", "--output", "{folder}/missing/report.txt"], 2),
    ("report-output-dev-full", ["report", "slider-crank", "--output", "{folder}/full.txt"], 2),
]


@pytest.mark.parametrize("arguments, expected", [case[1:] for case in FLAG_CASES],
                         ids=[case[0] for case in FLAG_CASES])
def test_mutated_flags(arguments, expected, files, capsys):
    arguments = [argument.replace("{folder}", str(files)) for argument in arguments]
    if any("full." in argument for argument in arguments) and not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full on this platform")
    output_format = "json" if "json" in arguments else "text"
    check_run(run_command(arguments, capsys), expected, output_format)
