"""The main job's report as one self-contained HTML file: the catalogue table, and per configuration its picture.

:func:`html_report` writes the page from the rows of ``closedchain report``
(:class:`classify.cli.report_command.ReportRow`) and the figures drawn for
them; every figure is embedded (a PNG as a ``data:`` URI), so the file can be
mailed or opened anywhere, with no folder beside it. Every text is shown as
the text outputs and the table's cells show it: non-printable characters
(control characters, zero-width and bidirectional marks) written as Python
escapes (:func:`classify.text.printable`; ``\\x1b``), then HTML-escaped, in
the headings, captions, alt texts and table cells alike; the folded blocks
(summary, legend, each classification) line by line, their line breaks kept.

Matplotlib is imported only by :func:`figure_png`, when a figure is drawn.
"""

from __future__ import annotations

import base64
import html
from dataclasses import dataclass

__all__ = ["Picture", "figure_png", "html_report", "STYLE"]

#: the page's style sheet: readable tables, figures in a wrapping row
STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 75em; color: #222; }
table { border-collapse: collapse; font-size: 0.9em; }
th, td { border-bottom: 1px solid #ddd; padding: 0.2em 0.6em; text-align: left; vertical-align: top; }
th { background: #f3f3f3; position: sticky; top: 0; }
tr.singular td.kinds { color: #a40000; font-weight: 600; }
pre { background: #f8f8f8; padding: 0.6em; overflow-x: auto; font-size: 0.85em; }
figure { display: inline-block; margin: 0.4em; vertical-align: top; }
figure img { max-width: 28em; border: 1px solid #eee; }
figcaption { font-size: 0.85em; color: #555; max-width: 28em; }
details { margin: 0.3em 0 0.8em 0; }
"""


@dataclass(frozen=True)
class Picture:
    """One embedded figure.

    Attributes
    ----------
    caption : str
        Plain text under the figure and its alt text (escaped on the page as the table's cells).
    png : bytes
        The image.
    """

    caption: str
    png: bytes


def figure_png(figure, dpi=80):
    """The PNG bytes of a :class:`matplotlib.figure.Figure` (drawn with the Agg canvas, no display needed)."""
    import io

    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(figure)
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=dpi, bbox_inches="tight")
    return buffer.getvalue()


def _escape(text):
    """One line of text as HTML: :func:`classify.text.printable` (a newline too is escaped), then HTML-escaped."""
    from .text import printable

    return html.escape(printable(text), quote=True)


def _escape_block(text):
    """Lines of text as the content of a ``<pre>``: each line escaped as :func:`_escape`, the line breaks kept."""
    return "\n".join(_escape(line) for line in str(text).split("\n"))


def _picture(picture):
    encoded = base64.b64encode(picture.png).decode("ascii")
    return (f'<figure><img alt="{_escape(picture.caption)}" src="data:image/png;base64,{encoded}">'
            f"<figcaption>{_escape(picture.caption)}</figcaption></figure>")


def _table(header, lines, singular):
    head = "".join(f"<th>{_escape(cell)}</th>" for cell in header)
    body = []
    for cells, is_singular in zip(lines, singular):
        row_class = ' class="singular"' if is_singular else ""
        body.append(f"<tr{row_class}>" + "".join(
            f'<td class="{"kinds" if index == 3 else ""}">{_escape(cell)}</td>' for index, cell in enumerate(cells))
            + "</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def html_report(rows, pictures=None, title="closedchain report", summary="", legend=""):
    """The HTML text of the report.

    Parameters
    ----------
    rows : sequence of ReportRow
        The classified configurations, in report order (the table's rows).
    pictures : mapping, optional
        ``(source, configuration name) → sequence of Picture`` shown with the
        configuration's account, and ``(source, None) → sequence of Picture``
        shown once at the head of the source's section (its loci or map).
    title : str
    summary : str
        Plain text shown under the title (the command's summary lines).
    legend : str
        Plain text of the legend, shown folded.

    Returns
    -------
    str
        A complete HTML5 document; nothing outside it is referred to.
    """
    from .cli.report_command import table_cells

    pictures = pictures or {}
    header, lines = table_cells(rows)
    singular = [bool(row.report.kinds) for row in rows]
    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             f"<title>{_escape(title)}</title><style>{STYLE}</style></head><body>",
             f"<h1>{_escape(title)}</h1>"]
    if summary:
        parts.append(f"<pre>{_escape_block(summary)}</pre>")
    if legend:
        parts.append(f"<details><summary>Legend</summary><pre>{_escape_block(legend)}</pre></details>")
    parts.append(_table(header, lines, singular))
    sources = list(dict.fromkeys(row.source for row in rows))
    for number, source in enumerate(sources):
        parts.append(f'<h2 id="source-{number}">{_escape(source)}</h2>')
        parts += [_picture(picture) for picture in pictures.get((source, None), ())]
        for row in (row for row in rows if row.source == source):
            kinds = row.report.label
            parts.append(f"<h3>{_escape(row.name)}: {_escape(kinds)}</h3>")
            parts += [_picture(picture) for picture in pictures.get((source, row.name), ())]
            parts.append(f"<details><summary>classification</summary><pre>{_escape_block(row.report.to_text())}</pre>"
                         "</details>")
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"
