"""Fixes of the report's pictures and page: the loci traced as ``closedchain loci`` traces them (C-space included,
what is not traced said), one legend over a 3-dof figure's panels, names escaped in the conditioning text and on
the HTML page, and axes labelled with what they show and in which unit.

Figures are checked by their content (artists, labels, data), never by pixels.
"""

import json
import re
from dataclasses import replace

import numpy as np
import pytest

from classify import model_of, survey_of
from classify.cli import main
from mechanisms import configuration, home
from tests.builders import catalogue_mechanism

#: characters no page or terminal line may hold raw (C0 controls but newline and tab, DEL, C1 controls)
CONTROL = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f]")


@pytest.fixture
def drawn_figures(monkeypatch):
    """The figures :func:`classify.report_pictures.loci_picture` draws, kept instead of encoded."""
    import classify.report_pictures as report_pictures

    figures = []

    def keep(figure, dpi=80):
        figures.append(figure)
        return b"\x89PNG\r\n\x1a\n"

    monkeypatch.setattr(report_pictures, "figure_png", keep)
    return figures


# ------------------------------------------------------------------------ 1. the report's loci are the CLI's


def test_report_loci_trace_the_cspace_singularities_as_the_loci_command(drawn_figures, capsys):
    """The slider-crank at Park & Kim's Fig. 3a: ``closedchain loci`` finds its 2 C-space singularities; the
    report's picture draws them (black crosses) and its caption counts every kind as the command does."""
    from classify.report_pictures import loci_picture

    mechanism = catalogue_mechanism("slider-crank", "fig3a_self_intersection")
    start = configuration(mechanism, {}).point
    picture = loci_picture(mechanism, start, survey_of(model_of(mechanism)), "slider-crank")
    assert main(["loci", "slider-crank", "--configuration", "fig3a_self_intersection", "--format", "json"]) == 0
    coverage = json.loads(capsys.readouterr().out)["coverage"]
    assert coverage["pieces"]["cspace"] == 2
    for kind, label in (("actuator", "actuator"), ("end_effector", "end-effector"), ("cspace", "C-space")):
        assert f"{label}: {coverage['pieces'][kind]} piece(s)" in picture.caption
    axes = drawn_figures[-1].axes[0]
    crosses = [line for line in axes.lines if (line.get_gid() or "").startswith("branch-point:")]
    assert len(crosses) == 2
    assert "C-space singularity" in axes.get_legend_handles_labels()[1]


def test_report_loci_say_what_is_not_traced_and_why(drawn_figures):
    """The planar six-bar (3 dof, a 2-coordinate end-effector): its end-effector loci are not traced, and the
    caption says so with the command's reason rather than "0 piece(s)"."""
    from classify.report_pictures import loci_picture

    mechanism = catalogue_mechanism("planar-six-bar")
    picture = loci_picture(mechanism, home(mechanism), survey_of(model_of(mechanism)), "planar-six-bar")
    assert "end-effector: not traced (2 end-effector coordinate(s) for 3 degree(s) of freedom)" in picture.caption
    assert "end-effector: 0 piece(s)" not in picture.caption
    assert re.search(r"actuator: [1-9]\d* piece\(s\)", picture.caption)
    assert re.search(r"C-space: \d+ piece\(s\)", picture.caption)


# ------------------------------------------------------------------------ 2. 3-dof sections: one legend, labels


@pytest.fixture(scope="module")
def hybrid_loci_empty_first_section():
    """The hybrid's loci in 2 sections, everything of the first section removed (its panel draws nothing)."""
    from classify.displacements import displacements_of
    from classify.loci import trace_loci

    mechanism = catalogue_mechanism("hybrid")
    loci = trace_loci(mechanism, home(mechanism), counts=(4, 4, 2), kinds=("actuator", "end_effector", "cspace"))
    (name, _), = loci.coverage["section"].items()
    first = loci.coverage["sections"][0]["value"]
    column = mechanism.coordinate_names.index(name)
    offsets = (displacements_of(mechanism, loci.samples)[:, column] - first + np.pi) % (2 * np.pi) - np.pi
    kept = np.abs(offsets) > 1e-9
    emptied = replace(loci, pieces=tuple(piece for piece in loci.pieces if piece.section != first),
                      samples=loci.samples[kept], sample_signs=loci.sample_signs[kept],
                      sample_branches=None if loci.sample_branches is None else loci.sample_branches[kept])
    return mechanism, loci, emptied


def _legend_texts(figure):
    legends = list(figure.legends) + [axes.get_legend() for axes in figure.axes if axes.get_legend()]
    return [[text.get_text() for text in legend.get_texts()] for legend in legends]


def _drawn_labels(figure):
    labels = set()
    for axes in figure.axes:
        for artist in axes.lines + axes.collections:
            label = artist.get_label()
            if label and not label.startswith("_"):
                labels.add(label)
    return labels


@pytest.mark.parametrize("emptied", [False, True])
def test_sections_have_one_legend_of_every_kind_drawn_and_labelled_panels(hybrid_loci_empty_first_section,
                                                                          emptied):
    from classify.figures.loci import draw_sections
    from classify.loci import default_columns

    mechanism, full, empty = hybrid_loci_empty_first_section
    loci = empty if emptied else full
    figure = draw_sections(mechanism, loci, default_columns(mechanism, 3)[:2], title="hybrid")
    if emptied:
        first = figure.axes[0]
        assert not [line for line in first.lines if (line.get_gid() or "").startswith(("locus:", "mode:"))]
    legends = _legend_texts(figure)
    assert len(legends) == 1
    assert _drawn_labels(figure) and set(legends[0]) == _drawn_labels(figure)
    assert len(legends[0]) == len(set(legends[0]))
    for axes in figure.axes:
        assert axes.get_xlabel() and axes.get_ylabel()


# ------------------------------------------------------------------------ 3. conditioning text escapes the name


def test_conditioning_text_escapes_the_mechanism_name(tmp_path, capsys):
    from mechanisms.io import save

    mechanism = catalogue_mechanism("five-bar")
    path = tmp_path / "evil.json"
    save(replace(mechanism, name="five\x1b[2J\u200bbar"), path)
    assert main(["conditioning", str(path), "--format", "text"]) == 0
    out = capsys.readouterr().out
    first = out.splitlines()[0]
    assert first.startswith("five\\x1b[2J\\u200bbar (derived relation)")
    assert not CONTROL.search(out) and "\u200b" not in out


# ------------------------------------------------------------------------ 4. the HTML page holds no raw controls


@pytest.fixture(scope="module")
def slider_rows():
    from classify.cli.report_command import _Task, run_tasks

    return run_tasks([_Task("slider-crank", ("default",))], jobs=1)


def test_html_headings_captions_and_alt_text_are_escaped_as_the_table(slider_rows):
    from classify.cli.report_command import table_cells
    from classify.html_report import Picture, html_report

    source, name = "src\x1b[2J", "cfg\x1b[31m\nforged\u202e"
    rows = [row._replace(source=source, name=name) for row in slider_rows]
    png = b"\x89PNG\r\n\x1a\n"
    pictures = {(source, name): [Picture(f"{source}: {name}", png)], (source, None): [Picture("loci \x07", png)]}
    document = html_report(rows, pictures, summary="summary \x1b[1m", legend="legend\x00")
    assert not CONTROL.search(document)
    assert "\u202e" not in document
    _, lines = table_cells(rows)
    shown_source, shown_name = lines[0][0], lines[0][1]
    assert shown_name == "cfg\\x1b[31m\\nforged\\u202e"
    assert f'<h2 id="source-0">{shown_source}</h2>' in document
    assert f"<h3>{shown_name}: " in document
    assert f'alt="{shown_source}: {shown_name}"' in document
    assert f"<figcaption>{shown_source}: {shown_name}</figcaption>" in document
    assert "<figcaption>loci \\x07</figcaption>" in document
    assert "summary \\x1b[1m" in document and "legend\\x00" in document


def test_report_picture_captions_are_printable(tmp_path):
    """The captions ``closedchain report --html`` gives its drawings (``_task_pictures``) hold the escaped names."""
    from classify import classify
    from classify.cli.report_command import _Task, _task_pictures
    from mechanisms.io import save

    mechanism = catalogue_mechanism("gough-stewart")  # six dof: no loci, only the drawing
    path = tmp_path / "stewart\x1b[31m.json"
    save(mechanism, path, configurations={"bad\x1b[2Jname": {}})
    source = str(path)
    reports = {(source, name): classify(mechanism, home(mechanism)) for name in ("home", "bad\x1b[2Jname")}
    pictures = _task_pictures(_Task(source, ("home", "bad\x1b[2Jname"), is_file=True), reports)
    captions = [picture.caption for found in pictures.values() for picture in found]
    assert captions and not any(CONTROL.search(caption) for caption in captions)
    assert any(caption.endswith("bad\\x1b[2Jname") for caption in captions)


# ------------------------------------------------------------------------ 5. axes say what they show, in which unit


@pytest.mark.parametrize("name", ["slider-crank", "gough-stewart", "spherical-six-bar"])
def test_mechanism_drawings_label_their_axes(name):
    from classify.figures.drawing import draw_mechanism

    mechanism = catalogue_mechanism(name)
    axes = draw_mechanism(mechanism, home(mechanism)).axes[0]
    labels = [axes.get_xlabel(), axes.get_ylabel()] + ([axes.get_zlabel()] if mechanism.space != "planar" else [])
    assert [label.split()[0] for label in labels] == ["x", "y", "z"][:len(labels)]
    if mechanism.space == "spherical":
        assert all("unit sphere" in label for label in labels)
    else:
        assert all(label.endswith("(length unit)") for label in labels)


def test_report_loci_label_displacements_from_home_with_their_unit(drawn_figures):
    """The slider-crank's map is over its crank angle (rad) and a slide of the mechanism's length."""
    from classify.loci import default_columns
    from classify.report_pictures import loci_picture

    mechanism = catalogue_mechanism("slider-crank")
    loci_picture(mechanism, home(mechanism), survey_of(model_of(mechanism)), "slider-crank")
    axes = drawn_figures[-1].axes[0]
    from classify.loci_coordinates import _is_angle

    columns = default_columns(mechanism, 1, home(mechanism))
    for label, column in zip((axes.get_xlabel(), axes.get_ylabel()), columns):
        coordinate = mechanism.coordinate_names[column]
        unit = "rad" if _is_angle(mechanism, column) else "length unit"
        assert label == f"{coordinate} − {coordinate}₀ ({unit})"


def test_report_sections_label_displacements_from_home(hybrid_loci_empty_first_section):
    from classify.figures.loci import draw_sections
    from classify.loci import default_columns

    mechanism, loci, _ = hybrid_loci_empty_first_section
    figure = draw_sections(mechanism, loci, default_columns(mechanism, 3)[:2], title="hybrid", units=True)
    for axes in figure.axes:
        assert (axes.get_xlabel(), axes.get_ylabel()) == ("A − A₀ (rad)", "B − B₀ (rad)")


def test_joint_grid_conditioning_map_labels_displacements_with_units(tmp_path, monkeypatch):
    """``closedchain conditioning five-bar-file --grid A=… B=… --out map.png``: the axes say A − A₀ (rad)."""
    from matplotlib.figure import Figure

    from mechanisms.io import save

    saved = []
    monkeypatch.setattr(Figure, "savefig", lambda figure, *args, **kwargs: saved.append(figure))
    mechanism = catalogue_mechanism("five-bar")
    path = tmp_path / "five.json"
    save(mechanism, path)
    status = main(["conditioning", str(path), "--grid", "A=-1:2:6", "B=0:3:6", "--mode", "1",
                   "--out", str(tmp_path / "map.png")])
    assert status == 0 and saved
    for axes in saved[0].axes[:1]:
        assert (axes.get_xlabel(), axes.get_ylabel()) == ("A − A₀ (rad)", "B − B₀ (rad)")
