"""Sphinx configuration of the closedchain documentation.

Build with ``sphinx-build -b html docs docs/_build/html``; run the examples
of the pages and of the docstrings with ``sphinx-build -b doctest docs
docs/_build/doctest``.
"""

import os
import sys

# The three packages (manifold, mechanisms, classify) live at the repository root.
ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, ROOT)
# the gallery's image scraper (docs/gallery/gallery_scraper.py)
sys.path.insert(0, os.path.join(ROOT, "docs", "gallery"))

project = "closedchain"
author = "the closedchain authors"
copyright = "the closedchain authors"
release = "0.1.0"
version = "0.1"

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.doctest",
    "sphinx_gallery.gen_gallery",
]

# numpy-style docstrings only
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
# an "Attributes" section as fields of its class, not as objects of their own (a NamedTuple's fields are
# documented by autodoc already)
napoleon_use_ivar = True

# numpydoc types name shapes ("ndarray, shape=[rows, columns]"): Sphinx makes each word a cross-reference,
# and a shape name that is also an attribute somewhere (``rows``, ``blocks``) is ambiguous, not a link
suppress_warnings = ["ref.python"]

autodoc_member_order = "bysource"
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_typehints = "none"

# The doctest builder runs every example in one namespace (not its module's): the public names of the
# three packages, numpy as np, and the few module-level helpers whose docstrings have examples.
doctest_global_setup = """
import numpy as np
from manifold import *
from mechanisms import *
from mechanisms.io import *
from mechanisms.mechanism import dense_memory_estimate
from classify import *
from classify.report import format_values
from classify.text import printable
"""

source_suffix = {".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "_generated"]
pygments_style = "sphinx"

html_theme = "alabaster"
html_title = "closedchain"


# The gallery of the papers' figures (docs/gallery, one folder per paper): sphinx-gallery runs each
# ``plot_*.py`` once and writes docs/gallery_output (not versioned); a later build (the doctest one of
# ``make docs`` and of tests/test_docs.py) finds the scripts unchanged and their outputs present, and does not run them again.
sphinx_gallery_conf = {
    "examples_dirs": "gallery",
    "gallery_dirs": "gallery_output",
    "filename_pattern": r"plot_",
    "ignore_pattern": r"__init__\.py|gallery_scraper\.py",
    # the package draws on Figure objects, not through pyplot: save those the example's variables hold
    "image_scrapers": ("gallery_scraper.namespace_figures",),
    # the papers in the order of the references page; within one, by figure (the files are plot_figNN_...)
    "subsection_order": ["gallery/park_kim_1999", "gallery/gosselin_angeles_1990",
                         "gallery/chablat_wenger_angeles_1998", "gallery/chablat_caro_wenger_angeles_2002",
                         "gallery/borras_thomas_torras_2011"],
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    # the examples run in parallel when Sphinx does (``sphinx -j auto``, as ``make docs``), through joblib
    "parallel": True,
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "remove_config_comments": True,
    "show_memory": False,
    "min_reported_time": 1,
    # no sg_execution_times.rst pages in the source tree (each example still shows its running time)
    "write_computation_times": False,
    "capture_repr": (),
    "first_notebook_cell": None,
}


def _write_catalogue_table(app):
    """Write ``_generated/catalogue_table.rst`` from the catalogue, so the page never goes stale."""
    from mechanisms.catalogue import entries

    lines = []
    for item in entries():
        lines += [item.name, "~" * len(item.name), "", item.summary, "",
                  f"*From* {item.reference}. *Builder:* :func:`{item.build.__module__}.{item.build.__name__}`.", ""]
        lines += ["Parameters (defaults): " + ", ".join(f"``{name}={value!r}``"
                                                       for name, value in item.parameters.items()) + ".", ""]
        if item.configurations:
            lines += ["Named configurations:", ""]
            lines += [f"* ``{name}``: " + ", ".join(f"``{key}={value!r}``" for key, value in presets.items())
                      for name, presets in item.configurations.items()]
            lines.append("")
    folder = os.path.join(app.srcdir, "_generated")
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "catalogue_table.rst"), "w", encoding="utf-8") as handle:
        handle.write("\n".join(lines))


#: ``closedchain compare`` runs shown in comparison.rst: file stem → arguments
COMPARISONS = {
    "outputs_slide": ["slider-crank", "--configuration", "fig3b_actuator", "--outputs", "slide", "--samples", "2"],
    "branch_point_eq9": ["slider-crank", "--configuration", "fig3b_actuator", "--outputs", "slide",
                         "--relation", "eq9", "--samples", "3"],
    "branch_point_eq12": ["slider-crank", "--configuration", "fig3b_actuator", "--outputs", "slide",
                          "--relation", "eq12", "--samples", "0"],
    "squared": ["slider-crank", "--param", "crank=3", "--param", "coupler=5", "--param", "theta=1.5707963267948966",
                "--outputs", "slide", "--relation", "squared", "--samples", "2"],
    "redundant": ["five-bar", "--inputs", "A,B,D", "--samples", "2"],
    "idle_freedom": ["five-bar", "--inputs", "A", "--outputs", "B", "--samples", "2"],
    "architecture": ["gough-stewart", "--configuration", "eq87_parallel_legs", "--samples", "2"],
    "cspace": ["slider-crank", "--configuration", "fig3a_self_intersection", "--outputs", "slide", "--samples", "2"],
    "cspace_eq12": ["slider-crank", "--configuration", "fig3a_self_intersection", "--outputs", "slide",
                    "--relation", "eq12", "--samples", "0"],
    "stationary": ["gough-stewart", "--configuration", "eq84_leg1_zero_length", "--samples", "0"],
    "path": ["slider-crank", "--param", "theta=0.4", "--outputs", "slide", "--path", "10", "--path-step", "0.2",
             "--samples", "0"],
}


def _write_comparisons(app):
    """Run the ``closedchain compare`` examples of comparison.rst into ``_generated/compare_*.txt``."""
    import contextlib
    import io

    from classify.cli import main

    folder = os.path.join(app.srcdir, "_generated")
    os.makedirs(folder, exist_ok=True)
    for stem, arguments in COMPARISONS.items():
        out = io.StringIO()
        with contextlib.redirect_stderr(io.StringIO()):
            status = main(["compare", *arguments], out=out)
        if status != 0:
            raise RuntimeError(f"closedchain compare {' '.join(arguments)} exited with {status}")
        with open(os.path.join(folder, f"compare_{stem}.txt"), "w", encoding="utf-8") as handle:
            handle.write("$ closedchain compare " + " ".join(arguments) + "\n" + out.getvalue())


def setup(app):
    app.connect("builder-inited", _write_catalogue_table)
    app.connect("builder-inited", _write_comparisons)
