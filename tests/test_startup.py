"""Start-up of the command: ``closedchain --help``, ``closedchain catalog`` and ``closedchain catalog NAME`` import
nothing heavy, and the lazy packages still export every name.

Each command runs through :func:`classify.cli.main` in a fresh interpreter (what a user's shell starts), which then
reports the modules it imported. Speed itself is measured in benchmarks/, not here.
"""

import importlib
import io
import json
import subprocess
import sys
from pathlib import Path

import pytest

from classify.cli import COMMANDS, main
from mechanisms.catalogue import _index, entries, entry, listing, names

ROOT = Path(__file__).resolve().parents[1]

#: imported only by the commands that use them, never at start-up
HEAVY = ("sympy", "matplotlib", "scipy.optimize", "scipy.spatial", "scipy.sparse", "dask", "pyarrow", "tqdm")
#: not imported to print the help or list the catalogue either (building a mechanism needs them)
NUMERICAL = ("numpy", "scipy", "networkx", "yaml")

#: runs ``main(argv)`` and prints its exit status, its output and the modules it imported, as JSON
RUN_COMMAND = """\
import contextlib, io, json, sys
from classify.cli import main
output = io.StringIO()
with contextlib.redirect_stdout(output):
    try:
        status = main(sys.argv[1:], output)
    except SystemExit as stop:  # --help
        status = stop.code
print(json.dumps({"status": status, "output": output.getvalue(), "modules": sorted(sys.modules)}))
"""


def fresh(script, *arguments):
    """Run `script` in a new interpreter from the repository; its last line of output, read as JSON."""
    finished = subprocess.run([sys.executable, "-c", script, *arguments], cwd=ROOT, capture_output=True,
                              text=True, timeout=120)
    assert finished.returncode == 0, finished.stderr
    return json.loads(finished.stdout.splitlines()[-1])


def command(*argv):
    return fresh(RUN_COMMAND, *argv)


def imported(modules, name):
    """Whether `name` or one of its submodules is among `modules`."""
    return any(module == name or module.startswith(name + ".") for module in modules)


def in_process(*argv):
    out = io.StringIO()
    assert main(list(argv), out) == 0
    return out.getvalue()


@pytest.fixture(scope="module")
def runs():
    """The three start-up commands, each run once in its own interpreter."""
    return {argv: command(*argv) for argv in (("--help",), ("catalog",), ("catalog", "five-bar"))}


@pytest.mark.parametrize("argv", [("--help",), ("catalog",), ("catalog", "five-bar")], ids=" ".join)
def test_start_up_commands_import_nothing_heavy(runs, argv):
    modules = runs[argv]["modules"]
    assert [name for name in HEAVY if imported(modules, name)] == []


@pytest.mark.parametrize("argv", [("--help",), ("catalog",)], ids=" ".join)
def test_help_and_the_list_import_no_numerical_library(runs, argv):
    modules = runs[argv]["modules"]
    assert [name for name in NUMERICAL if imported(modules, name)] == []


def test_help_lists_every_subcommand(runs):
    result = runs["--help",]
    assert result["status"] == 0
    assert result["output"].startswith("usage: closedchain")
    usage = " ".join(result["output"].split("\n\n")[0].split())  # the usage paragraph, however it wraps
    assert "{" + ",".join(COMMANDS) + "}" in usage


def test_the_list_shows_every_entry_with_its_summary_reference_and_configurations(runs):
    items = entries()
    width = max(len(item.name) for item in items)
    expected = ""
    for item in items:
        expected += f"{item.name.ljust(width)}  {item.summary}\n{'':{width}}  {item.reference}\n"
        if item.configurations:
            expected += f"{'':{width}}  configurations: {', '.join(item.configurations)}\n"
    assert (runs["catalog",]["status"], runs["catalog",]["output"]) == (0, expected)


def test_an_entry_is_described_as_in_process(runs):
    result = runs["catalog", "five-bar"]
    item = entry("five-bar")
    mechanism = item.mechanism()
    lines = result["output"].splitlines()
    assert result["status"] == 0
    assert lines[:2] == [f"five-bar: {item.summary}", f"from {item.reference}"]
    assert lines[-1].startswith(f"{mechanism.space} mechanism, {len(mechanism.joints)} joints, "
                                f"{mechanism.loop_count} loop(s)")
    assert result["output"] == in_process("catalog", "five-bar")


def test_the_index_lists_the_entries_themselves():
    rows = _index.index_of(entries())
    assert listing() == rows, ("mechanisms/catalogue/_index.py is out of date; its table is now:\n"
                               + _index.index_source(rows))
    assert names() == tuple(item.name for item in entries())
    assert all(entry(item.name) is item for item in entries())


def test_the_index_is_written_as_its_generator_writes_it():
    assert _index.index_source(_index.INDEX) in Path(_index.__file__).read_text(encoding="utf-8")


#: imports the named submodules first (some share their name with an exported function), then reads every exported
#: name of the package
EXPORTS = """\
import importlib, json, sys
package = importlib.import_module(sys.argv[1])
submodules = {name: importlib.import_module(f"{sys.argv[1]}.{name}") for name in sys.argv[2:]}
print(json.dumps({
    "missing": [name for name in package.__all__ if not hasattr(package, name)],
    "not_listed": sorted(set(package.__all__) - set(dir(package))),
    "repeated": len(package.__all__) - len(set(package.__all__)),
    "attributes": {name: "the function" if getattr(package, name) is getattr(module, name, None) else
                   "the module" if getattr(package, name) is module else "other"
                   for name, module in submodules.items()},
}))
"""


@pytest.mark.parametrize("package, submodules", [
    ("classify", ["survey", "report"]), ("mechanisms", ["configuration", "catalogue"]), ("manifold", ["ambient"]),
])
def test_lazy_packages_export_every_name_whatever_was_imported_first(package, submodules):
    result = fresh(EXPORTS, package, *submodules)
    assert (result["missing"], result["not_listed"], result["repeated"]) == ([], [], 0)
    # `classify.survey` is the function survey and `mechanisms.configuration` the function configuration, as
    # exported, even once their modules are imported; other submodules are attributes as usual
    exported = importlib.import_module(package).__all__
    assert result["attributes"] == {name: "the function" if name in exported else "the module" for name in submodules}


def test_batch_names_are_exported():
    import classify
    from classify.batch import Classifications, classify_many
    from classify.survey import survey_of

    assert (classify.classify_many, classify.Classifications, classify.survey_of) == (
        classify_many, Classifications, survey_of)


def test_an_unknown_name_is_an_attribute_error():
    import classify
    import manifold
    import mechanisms

    for package in (classify, manifold, mechanisms):
        with pytest.raises(AttributeError, match="has no attribute 'no_such_name'"):
            package.no_such_name  # noqa: B018
