"""The pictures of the HTML report (classify.report_pictures) and ``closedchain report --html``."""

import base64
import re

from builders import catalogue_mechanism
from classify import classify, model_of, survey_of
from classify.cli import main
from classify.report_pictures import configuration_picture, loci_picture
from mechanisms import home

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def test_a_configuration_picture_is_a_png_with_its_caption():
    mechanism = catalogue_mechanism("slider-crank", "fig3b_actuator")
    point = home(mechanism)
    picture = configuration_picture(mechanism, point, classify(mechanism, point), "slider-crank: fig3b_actuator")
    assert picture.png.startswith(PNG_SIGNATURE)
    assert picture.caption == "slider-crank: fig3b_actuator"


def test_loci_are_drawn_for_one_dof_and_not_for_six():
    crank = catalogue_mechanism("slider-crank")
    picture = loci_picture(crank, home(crank), survey_of(model_of(crank)), "slider-crank")
    assert picture.png.startswith(PNG_SIGNATURE)
    assert re.search(r"\d+ piece\(s\)", picture.caption)
    platform = catalogue_mechanism("gough-stewart")
    assert loci_picture(platform, home(platform), survey_of(model_of(platform)), "gough-stewart") is None


def test_three_dof_loci_are_drawn_in_sections():
    """The hybrid of Chablat, Wenger & Angeles 1998 (3 dof): its loci traced in sections, both kinds found."""
    hybrid = catalogue_mechanism("hybrid")
    picture = loci_picture(hybrid, home(hybrid), survey_of(model_of(hybrid)), "hybrid")
    assert picture.png.startswith(PNG_SIGNATURE)
    assert re.search(r"actuator: [1-9]\d* piece\(s\)", picture.caption)
    assert re.search(r"end-effector: [1-9]\d* piece\(s\)", picture.caption)


def test_the_report_command_writes_a_page_with_each_configuration_drawn(tmp_path, capsys):
    page, text = tmp_path / "report.html", tmp_path / "report.txt"
    status = main(["report", "slider-crank", "--output", str(text), "--html", str(page), "--jobs", "1"])
    assert status == 0
    assert str(page) in capsys.readouterr().out
    document = page.read_text(encoding="utf-8")
    headings = re.findall(r"<h3>([^<:]+):", document)
    assert headings and len(headings) == document.count("<tr") - 1  # one account per table row
    images = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', document)
    # a drawing per configuration, and the 1-dof slider-crank's loci once per design (its named configurations
    # are of several designs: crank and coupler lengths), shown at the head of the section
    loci = re.findall(r"<figcaption>slider-crank at [^<]*: C-space and singularity loci", document)
    assert 1 <= len(loci) <= len(headings)
    assert len(images) == len(headings) + len(loci)
    assert all(base64.b64decode(image).startswith(PNG_SIGNATURE) for image in images)
    assert document.index(loci[-1]) < document.index("<h3>")


def test_an_html_path_that_cannot_be_written_exits_2_naming_the_option(tmp_path, capsys):
    status = main(["report", "slider-crank", "--html", str(tmp_path), "--jobs", "1"])
    assert status == 2
    error = capsys.readouterr().err.strip()
    assert "--html" in error and len(error.splitlines()) == 1
