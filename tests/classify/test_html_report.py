"""The main job's HTML report (classify.html_report): one self-contained file, figures embedded, text escaped."""

import base64
import re

import pytest

from classify.cli.report_command import _Task, report_table, run_tasks, table_cells
from classify.html_report import Picture, figure_png, html_report

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def rows():
    """The slider-crank at its defaults and at the Park–Kim Fig. 3a self-intersection (a C-space singularity)."""
    return run_tasks([_Task("slider-crank", ("default", "fig3a_self_intersection"))], jobs=1)


@pytest.fixture(scope="module")
def picture():
    from matplotlib.figure import Figure

    figure = Figure(figsize=(2, 2))
    figure.add_subplot().plot([0, 1], [0, 1])
    return Picture("a <line> & more", figure_png(figure))


def test_figure_png_is_a_png(picture):
    assert picture.png.startswith(PNG_SIGNATURE)


def test_the_table_has_one_row_per_configuration_with_the_text_tables_cells(rows):
    document = html_report(rows)
    header, lines = table_cells(rows)
    assert document.count("<tr") == 1 + len(rows)
    for cells in lines:
        for cell in cells:
            assert f">{cell}</td>" in document
    # the text table is made of the same cells
    assert all(cell in report_table(rows) for cells in lines for cell in cells)
    assert all(f"<th>{name}</th>" in document for name in header)


def test_a_singular_row_is_marked_and_a_regular_one_is_not(rows):
    document = html_report(rows)
    marked = re.findall(r"<tr( class=\"singular\")?><td", document)
    assert [bool(mark) for mark in marked] == [bool(row.report.kinds) for row in rows]
    assert any(row.report.kinds for row in rows) and not all(row.report.kinds for row in rows)


def test_pictures_are_embedded_where_they_belong_and_nothing_outside_is_referred_to(rows, picture):
    source = rows[0].source
    pictures = {(source, None): [picture], (source, rows[1].name): [picture, picture]}
    document = html_report(rows, pictures)
    images = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', document)
    assert len(images) == 3
    assert all(base64.b64decode(image).startswith(PNG_SIGNATURE) for image in images)
    assert not re.search(r'(src|href)="(?!data:)', document)
    # the source's picture comes before the first configuration's heading, the two others after the second's
    first, second = (document.index(f"<h3>{row.name}:") for row in rows)
    positions = [match.start() for match in re.finditer("<figure>", document)]
    assert positions[0] < first < second < positions[1] < positions[2]


def test_text_from_files_is_escaped(rows, picture):
    hostile = rows[0]._replace(source='<script>alert("x")</script>', name="a&b")
    document = html_report([hostile], {(hostile.source, None): [picture]}, summary="1 < 2", legend="<b>")
    assert "<script>" not in document
    assert "&lt;script&gt;" in document and "a&amp;b" in document and "1 &lt; 2" in document
    assert "a &lt;line&gt; &amp; more" in document
