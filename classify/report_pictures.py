"""The pictures of the HTML report: each configuration drawn, and the loci of each design of one to three dof.

For every classified configuration, :func:`configuration_picture` draws the
mechanism there (:func:`classify.figures.drawing.draw_mechanism`) with the
directions it loses at a singularity as arrows. For a mechanism of one or two
degrees of freedom, :func:`loci_picture` traces its singularity loci from a
configuration (:func:`classify.loci.trace_loci`, every traced point confirmed
by the classification) and draws its C-space map with the loci overlaid
(:func:`classify.figures.loci.draw_cspace_map`), in the default coordinates
(the actuated ones where they are independent at the start), each axis a
displacement from home in its unit. The kinds are those ``closedchain loci``
traces (:data:`LOCI_KINDS`: actuator, end-effector and C-space, the C-space
singularities also searched for where σ_r(DΦ) is locally smallest, 1 and 2
dof); the caption counts the pieces of each kind, or says that a kind was
not traced and why (:func:`coverage_caption`, the reason of the loci's
``coverage["not_traced"]``: e.g. an end-effector of fewer coordinates than
degrees of freedom).
Three dof: the loci in sections of the first actuated coordinate, one panel
per section (:func:`classify.figures.loci.draw_sections`), on a coarser grid
(:data:`SECTIONS_GRID`). More dof: no loci.
"""

from __future__ import annotations

import numpy as np

from .html_report import Picture, figure_png
from .text import drawn, printable

__all__ = ["configuration_picture", "loci_picture", "coverage_caption", "KIND_LABELS", "LOCI_KINDS",
           "LOCI_GRID", "SECTIONS_GRID"]

#: grid points per axis of a report's 2-dof loci (coarse: the report draws every design; ``closedchain loci``
#: takes ``--grid`` for finer)
LOCI_GRID = (20, 20)
#: a report's 3-dof loci: grid points per axis of each section, and the number of sections (``closedchain loci``
#: takes ``--grid`` and ``--section``)
SECTIONS_GRID = (12, 12, 3)
#: the kinds of loci traced, as ``closedchain loci`` traces them by default (its ``--kinds``)
LOCI_KINDS = ("actuator", "end_effector", "cspace")
#: how a loci caption names each kind
KIND_LABELS = {"actuator": "actuator", "end_effector": "end-effector", "cspace": "C-space"}


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
    return Picture(printable(caption), figure_png(figure))


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
        The start of the caption (escaped, :func:`classify.text.printable`); the coverage is appended
        (:func:`coverage_caption`: the pieces of each kind, or why a kind was not traced).
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
                      counts=SECTIONS_GRID if dof == 3 else LOCI_GRID, kinds=LOCI_KINDS,
                      rng=np.random.default_rng(seed), survey=survey)
    if dof > 1 and not loci.coverage["reached"]:  # the grid reached no configuration from the start: nothing to draw
        return None
    title = f"{drawn(mechanism.name)}: singularity loci"
    figure = (draw_sections(mechanism, loci, columns[:2], title=title, units=True) if dof == 3
              else draw_cspace_map(mechanism, loci, columns, title=title, units=True))
    return Picture(f"{printable(caption)} ({coverage_caption(loci.coverage)})", figure_png(figure))


def coverage_caption(coverage):
    """What a loci picture shows, per kind: its pieces, or that it was not traced and why.

    Parameters
    ----------
    coverage : dict
        :attr:`classify.loci.Loci.coverage` (its ``"pieces"`` and ``"not_traced"``).

    Returns
    -------
    str
        E.g. ``"actuator: 3 piece(s), end-effector: not traced (2 end-effector coordinate(s) for 3 degree(s) of
        freedom), C-space: 0 piece(s)"``; a kind searched for as points instead of traced (redundant actuation)
        gives its pieces and the reason.
    """
    parts = []
    for kind, count in coverage["pieces"].items():
        label = KIND_LABELS.get(kind, kind.replace("_", "-"))
        reason = coverage["not_traced"].get(kind)
        if reason is None:
            parts.append(f"{label}: {count} piece(s)")
        elif count:
            parts.append(f"{label}: {count} piece(s), not traced as curves ({printable(reason)})")
        else:
            parts.append(f"{label}: not traced ({printable(reason)})")
    return ", ".join(parts)
