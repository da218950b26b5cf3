"""``closedchain draw``: a figure file written without a display, bad input refused with exit status 2."""

from builders import command_streams as run


def test_draw_writes_a_figure(tmp_path):
    path = tmp_path / "five.svg"
    status, out, err = run(["draw", "five-bar", "--configuration", "eq9_distal_aligned", "--out", str(path)])
    assert status == 0, err
    assert "actuator" in out and path.stat().st_size > 1000
    assert "lost:actuator" in path.read_text()


def test_draw_at_a_displacement(tmp_path):
    path = tmp_path / "slider.png"
    status, _, err = run(["draw", "slider-crank", "--at", '{"crank": 0.2}', "--project", "--out", str(path)])
    assert status == 0, err
    assert path.stat().st_size > 1000


def test_draw_refuses_bad_input(tmp_path):
    status, _, err = run(["draw", "five-bar", "--out", str(tmp_path / "x.txt")])
    assert status == 2 and "--out" in err and "Traceback" not in err
    status, _, err = run(["draw", "five-bar", "--kinds", "wrong", "--out", str(tmp_path / "x.png")])
    assert status == 2 and "--kinds" in err
    status, _, err = run(["draw", "five-bar", "--at", '{"A": 0.1}', "--out", str(tmp_path / "x.png")])
    assert status == 2 and "--at" in err
    status, _, err = run(["draw", "five-bar", "--out", str(tmp_path / "missing" / "x.png")])
    assert status == 2 and "--out" in err


def test_draw_an_imported_urdf_with_its_closures(tmp_path):
    from pathlib import Path

    robot = Path(__file__).parent.parent / "data" / "robots" / "5bar_linkage_iso3d"
    path = tmp_path / "robot.svg"
    status, out, err = run(["draw", str(robot / "robot.urdf"), "--closures", str(robot / "robot.yaml"),
                            "--out", str(path)])
    assert status == 0, err
    assert "5bar_linkage_iso3d" in out
    drawing = path.read_text()
    assert drawing.count('id="actuated:') == 2  # the two motors named in the closures file


def test_a_title_matplotlib_cannot_draw_is_refused_before_any_work(tmp_path):
    """Mathtext it cannot parse ended in an internal error; a control character in a glyph warning on stderr."""
    path = tmp_path / "x.png"
    for title, message in (("$$", "--title: matplotlib cannot typeset"), ("$x^$", "--title: matplotlib cannot"),
                           ("a\x1bb", "--title: control characters are not drawn; got a\\x1bb"),
                           ("a\tb", "--title: control characters are not drawn; got a\\tb")):
        status, out, err = run(["draw", "five-bar", "--title", title, "--out", str(path)])
        assert status == 2 and out == "" and err.count("\n") == 1 and message in err, err
        assert not path.exists()
    for title in ("$\\theta_1$ and a lone $", "two lines\nof title"):
        status, _, err = run(["draw", "five-bar", "--title", title, "--out", str(path)])
        assert status == 0 and err == "", err


def test_a_mechanism_name_with_dollar_signs_is_drawn_as_written(tmp_path, monkeypatch):
    """The default title is the mechanism's name: '$$' in it is no formula (it ended in an internal error)."""
    import dataclasses

    import matplotlib

    from mechanisms import catalogue
    from mechanisms.io import save

    monkeypatch.setitem(matplotlib.rcParams, "svg.fonttype", "none")  # text as text, to read it back
    mechanism = dataclasses.replace(catalogue.entry("five-bar").mechanism(), name="price $$ of $x^$")
    save(mechanism, tmp_path / "dollars.yaml")
    status, _, err = run(["draw", str(tmp_path / "dollars.yaml"), "--out", str(tmp_path / "x.svg")])
    assert status == 0, err
    assert "price $$ of $x^$: regular" in (tmp_path / "x.svg").read_text()
