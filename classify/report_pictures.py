"""The pictures of the HTML report: each configuration drawn, and the loci of each design of one to three dof.

For every classified configuration, :func:`configuration_picture` draws the
mechanism there (:func:`classify.figures.drawing.draw_mechanism`) with the
directions it loses at a singularity as arrows. For a mechanism of one or two
degrees of freedom, :func:`loci_picture` traces its singularity loci from a
configuration (:func:`classify.loci.trace_loci`, every traced point confirmed
by the classification) and draws its C-space map with the loci overlaid
(:func:`classify.figures.loci.draw_cspace_map`), in the default coordinates
(the actuated ones where they are independent at the start).
Three dof: the loci in sections of the first actuated coordinate, one panel
per section (:func:`classify.figures.loci.draw_sections`), on a coarser grid
(:data:`SECTIONS_GRID`). More dof: no loci.
"""

from __future__ import annotations

import numpy as np

from .html_report import Picture, figure_png
from .text import drawn

__all__ = ["configuration_picture", "loci_picture", "LOCI_GRID", "SECTIONS_GRID"]

#: grid points per axis of a report's 2-dof loci (coarse: the report draws every design; ``closedchain loci``
#: takes ``--grid`` for finer)
LOCI_GRID = (20, 20)
#: a report's 3-dof loci: grid points per axis of each section, and the number of sections (``closedchain loci``
#: takes ``--grid`` and ``--section``)
SECTIONS_GRID = (12, 12, 3)


def configuration_picture(mechanism, point, report, caption):
    """The mechanism drawn at `point`, its lost directions as arrows where `report` finds it singular.

    Parameters
    ----------
    mechanism : Mechanism
    point : ndarray, shape=[point_size]
    report : Report
        The classification of `point`.
    caption : str

    Returns
    -------
    Picture
    """
    from .figures.drawing import draw_mechanism

    kinds = report.label
    figure = draw_mechanism(mechanism, point, report=report, title=f"{drawn(mechanism.name)}: {kinds}")
    return Picture(caption, figure_png(figure))


def loci_picture(mechanism, start, survey, caption, seed=0):
    """The C-space map of a 1- or 2-dof mechanism with its singularity loci (3 dof: in sections), or None.

    Parameters
    ----------
    mechanism : Mechanism
    start : ndarray, shape=[point_size]
        A configuration of M: a 2-dof grid follows its assembly branch.
    survey : Survey
        The mechanism's survey of M (its C-space dimension is the dof).
    caption : str
        The start of the caption; the coverage (pieces found, closed) is appended.
    seed : int
        Seed of the sampling of a 1-dof C-space.

    Returns
    -------
    Picture or None
        None for more than three dof, or when the grid reaches no configuration from `start`.
    """
    from .figures.loci import draw_cspace_map, draw_sections
    from .loci import default_columns, trace_loci

    dof = mechanism.ambient_dimension - survey.constraint_rank
    if dof not in (1, 2, 3):
        return None
    columns = default_columns(mechanism, dof, start)
    loci = trace_loci(mechanism, start, columns=columns if dof > 1 else None,
                      counts=SECTIONS_GRID if dof == 3 else LOCI_GRID, rng=np.random.default_rng(seed), survey=survey)
    if dof > 1 and not loci.coverage["reached"]:  # the grid reached no configuration from the start: nothing to draw
        return None
    title = f"{drawn(mechanism.name)}: singularity loci"
    figure = (draw_sections(mechanism, loci, columns[:2], title=title) if dof == 3
              else draw_cspace_map(mechanism, loci, columns, title=title))
    found = ", ".join(f"{kind.replace('_', '-')}: {count} piece(s)" for kind, count in loci.coverage["pieces"].items())
    return Picture(f"{caption} ({found})", figure_png(figure))
