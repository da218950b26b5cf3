"""The documentation builds with warnings as errors (``sphinx -W -b html``), its gallery scripts included, and
the doctest builder of ``make docs`` passes.

A test of the suite rather than a step before it: under ``pytest -n auto``
this one long test (sphinx-gallery runs every script of docs/gallery, about
a minute) shares the machine with the rest of the suite instead of delaying
it; ``tests/conftest.py`` puts it first so that a worker starts it first.
The gallery's outputs go to docs/gallery_output (sphinx-gallery writes
beside its sources and skips a script whose output is up to date). The
pages' own examples run as doctests of the suite (``--doctest-glob="*.rst"``,
docs/conftest.py), the docstrings' with ``--doctest-modules``.
"""

import subprocess
import sys
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"


def _build(builder, tmp_path, doctrees):
    """Run ``sphinx -W -b builder`` on the docs, the environment in `doctrees`; fail with its output's end."""
    finished = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", builder,
                               "-d", str(doctrees), str(DOCS), str(tmp_path / builder)],
                              capture_output=True, text=True, timeout=1800)
    assert finished.returncode == 0, (f"sphinx -b {builder} failed (exit {finished.returncode}):\n"
                                      f"{finished.stdout[-4000:]}\n{finished.stderr[-4000:]}")


@pytest.fixture(scope="module")
def doctrees(tmp_path_factory):
    """One Sphinx environment for both builds (``-d``, as the Makefile of ``sphinx-quickstart`` shares it between
    builders): the second build re-reads only the pages whose sources or inputs changed, not every page with its
    autodoc (about 9 s)."""
    return tmp_path_factory.mktemp("doctrees")


def test_docs_build_without_warnings(tmp_path, doctrees):
    pytest.importorskip("sphinx_gallery", reason="the docs extra (pip install -e '.[docs]') is not installed")
    _build("html", tmp_path, doctrees)


def test_docs_doctest_builder_passes(tmp_path, doctrees):
    """``make docs``'s second step: every example of the pages and docstrings in the doctest builder's one
    namespace (docs/conf.py's ``doctest_global_setup``), where a docstring's example must import the names it
    uses (five examples of classify.sweep and three of classify.higher_order did not, and failed there only)."""
    pytest.importorskip("sphinx_gallery", reason="the docs extra (pip install -e '.[docs]') is not installed")
    _build("doctest", tmp_path, doctrees)
