"""The gallery of the papers' figures (docs/gallery): every script captioned with its paper and figure.

The docs build (``make docs``, sphinx-gallery) runs the scripts; these tests only read them (their
docstrings and imports), so they cost nothing.
"""

import ast
import re
from pathlib import Path

import pytest

GALLERY = Path(__file__).resolve().parents[1] / "docs" / "gallery"

#: the gallery's folder of each paper -> how the paper is cited (docs/references.rst)
PAPERS = {
    "park_kim_1999": "Park & Kim 1999",
    "gosselin_angeles_1990": "Gosselin & Angeles 1990",
    "chablat_wenger_angeles_1998": "Chablat, Wenger & Angeles 1998",
    "chablat_caro_wenger_angeles_2002": "Chablat, Caro, Wenger & Angeles 2002",
    "borras_thomas_torras_2011": "Borràs, Thomas & Torras 2011",
}

SCRIPTS = sorted(GALLERY.glob("*/plot_*.py"))
#: a figure number as the papers print them: "Fig. 3", "Figs. 6-8", "Figure 2"
FIGURE = re.compile(r"\bFig(?:s?\.|ure)\s*\d+")


def _docstring(path):
    return ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or ""


def test_every_paper_has_a_folder_with_a_header_and_scripts():
    folders = {path.name for path in GALLERY.iterdir() if path.is_dir() and not path.name.startswith("__")}
    assert folders == set(PAPERS)
    assert (GALLERY / "README.txt").is_file()
    for folder, paper in PAPERS.items():
        header = (GALLERY / folder / "README.txt").read_text(encoding="utf-8")
        assert header.splitlines()[0] == paper, folder
        assert list((GALLERY / folder).glob("plot_*.py")), f"{folder}: no script"


def test_the_headers_say_which_figures_are_not_regenerated_where_some_are_not():
    """Each paper's header lists its figures regenerated, and names the ones that are not, if any."""
    for folder in PAPERS:
        header = (GALLERY / folder / "README.txt").read_text(encoding="utf-8")
        assert FIGURE.search(header), folder
        if "Not regenerated" in header:
            assert re.search(r"Not regenerated[^*]*\*\*Figs?\. \d+", header), folder


@pytest.mark.parametrize("path", SCRIPTS, ids=lambda path: f"{path.parent.name}/{path.name}")
def test_script_is_captioned_with_its_paper_and_figure(path):
    text = _docstring(path)
    lines = text.splitlines()
    title, underline = lines[0], lines[1]
    assert underline == "=" * len(title), "the title's underline must match it (sphinx -W)"
    assert FIGURE.search(title) or re.search(r"\beqs?\. \d+", title, re.IGNORECASE), f"title names no figure: {title!r}"
    body = "\n".join(lines[2:])
    assert PAPERS[path.parent.name] in body, f"the docstring does not cite {PAPERS[path.parent.name]}"
    assert FIGURE.search(body), "the docstring names no figure"
    source = path.read_text(encoding="utf-8")
    assert "shared/" not in source and not re.search(r"\d{3}_[0-9a-f]{16}", source), "cite papers, not files"


@pytest.mark.parametrize("path", SCRIPTS, ids=lambda path: f"{path.parent.name}/{path.name}")
def test_script_uses_only_the_public_api_and_prints_what_it_found(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            module = node.module or ""
            assert not any(part.startswith("_") for part in module.split(".")), module
            assert not any(alias.name.startswith("_") for alias in node.names), module
            assert module.split(".")[0] in {"classify", "mechanisms", "manifold", "numpy", "matplotlib", "math"}
        elif isinstance(node, ast.Import):
            assert all(alias.name.split(".")[0] in {"numpy", "math"} for alias in node.names)
    assert "pyplot" not in path.read_text(encoding="utf-8"), "figures are matplotlib.figure.Figure (no pyplot)"
    printed = [node for node in ast.walk(tree) if isinstance(node, ast.Call)
               and isinstance(node.func, ast.Name) and node.func.id == "print"]
    assert printed, "the script prints nothing: the gallery shows what the code found under the figure"


def test_the_docs_build_the_gallery_once_and_do_not_version_its_output():
    root = GALLERY.parents[1]
    configuration = (root / "docs" / "conf.py").read_text(encoding="utf-8")
    assert "sphinx_gallery.gen_gallery" in configuration
    assert '"gallery_dirs": "gallery_output"' in configuration
    ignored = (root / ".gitignore").read_text(encoding="utf-8").splitlines()
    assert "docs/gallery_output/" in ignored
    for page in ("index.rst", "pictures.rst"):
        assert "gallery_output/index" in (root / "docs" / page).read_text(encoding="utf-8"), page
