"""Names from files and the command line as printed and as drawn (classify.text)."""

import matplotlib
import pytest

matplotlib.use("Agg")

from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from classify.text import drawn, printable  # noqa: E402


def test_printable_escapes_control_characters_and_keeps_the_rest():
    assert printable("A1 θ") == "A1 θ"
    assert printable("a\x1b[31mb\n") == "a\\x1b[31mb\\n"


def test_a_drawn_name_is_shown_as_written_by_matplotlib():
    """Dollar signs escaped: matplotlib reads '$x^$' as mathtext and cannot draw it."""
    raw = Figure()
    FigureCanvasAgg(raw)
    raw.suptitle("price $$ of $x^$")
    with pytest.raises(ValueError):
        raw.canvas.draw()
    for name in ("price $$ of $x^$", "joint $1", "θ_1"):
        figure = Figure()
        FigureCanvasAgg(figure)
        figure.suptitle(drawn(name))
        figure.canvas.draw()
    assert drawn("a\x1bb $") == "a\\x1bb \\$"
