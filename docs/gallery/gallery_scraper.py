"""The gallery's image scraper: the Matplotlib Figures an example holds in its variables.

closedchain draws on ``matplotlib.figure.Figure`` objects, never through
pyplot, so sphinx-gallery's stock scraper (``pyplot.get_fignums()``) sees none
of them. :func:`namespace_figures` saves, after each code block, every Figure
bound to a name of the example (or held in a list, tuple or dict bound to
one) that no earlier block of the same example saved: a Figure is saved
once, after the block that first binds it, so an example draws each Figure
whole in one block (a later block makes a new Figure). It is named in
``sphinx_gallery_conf["image_scrapers"]`` by its import path (a module-level
function, so Sphinx can pickle the configuration).
"""

_state = {"source": None, "saved": []}


def _figures_in(namespace):
    from matplotlib.figure import Figure

    for value in list(namespace.values()):
        values = value.values() if isinstance(value, dict) else value if isinstance(value, (list, tuple)) \
            else (value,)
        for item in values:
            if isinstance(item, Figure):
                yield item


def namespace_figures(block, block_vars, gallery_conf):
    """Save the new Figures of the example's namespace; return their reST (sphinx-gallery scraper API)."""
    from sphinx_gallery.scrapers import figure_rst

    if block_vars["src_file"] != _state["source"]:
        _state["source"], _state["saved"] = block_vars["src_file"], []
    found = []
    for figure in _figures_in(block_vars["example_globals"]):
        if not any(figure is old for old in _state["saved"] + found):
            found.append(figure)
    paths = []
    for figure, path in zip(found, block_vars["image_path_iterator"]):
        figure.savefig(path, dpi=80)
        paths.append(path)
    _state["saved"] += found
    return figure_rst(paths, gallery_conf["src_dir"]) if paths else ""
