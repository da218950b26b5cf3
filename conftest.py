"""The docs' examples as tests: pytest runs the examples of the pages (docs/*.rst, ``--doctest-glob="*.rst"``)
in the namespace Sphinx's doctest builder gives them, ``doctest_global_setup`` of docs/conf.py, read from
its source (conf.py is not imported: its configuration is Sphinx's). Nothing else under docs/ is a test
(the gallery's scripts run in the docs build, tests/test_docs.py)."""

import ast
from pathlib import Path

import pytest

collect_ignore = [f"docs/{name}" for name in ("conf.py", "gallery", "gallery_output", "images", "_build", "_generated")]


def _global_setup():
    tree = ast.parse((Path(__file__).parent / "docs" / "conf.py").read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(target, "id", None) == "doctest_global_setup"
                                                for target in node.targets):
            return ast.literal_eval(node.value)
    raise LookupError("docs/conf.py assigns no doctest_global_setup")


@pytest.fixture(autouse=True)
def _pages_namespace(request, doctest_namespace):
    """The pages' namespace, for the examples of the pages only (a docstring's run in its module's)."""
    if request.node.path.suffix == ".rst":
        exec(_global_setup(), doctest_namespace)  # the setup is conf.py's own source, not user input
