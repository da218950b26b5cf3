"""The catalogue: every mechanism of the papers (docs/references.rst), as joint graphs.

Each family module defines builders (keyword-only parameters with the
paper's defaults, returning the mechanism assembled at the requested
configuration) and an ``ENTRIES`` tuple of :class:`Entry`. Tests, docs and
the ``closedchain catalog`` command share these.

Examples
--------
>>> from mechanisms.catalogue import entry, names
>>> "slider-crank" in names()
True
>>> [joint.name for joint in entry("slider-crank").mechanism("fig3c_dead_centre").joints]
['crank', 'pin', 'wrist', 'slide']
"""

from __future__ import annotations

from ..errors import MechanismError
from . import (
    eclipse, five_bar, five_spu, gough_stewart, hybrid, planar_3rrr, planar_six_bar, slider_crank,
    spherical_3rrr, spherical_six_bar, three_prr, watt,
)
from ._entry import Entry, parse_parameter

__all__ = ["Entry", "entries", "entry", "names", "parse_parameter"]

_FAMILIES = (
    slider_crank, five_bar, spherical_six_bar, planar_six_bar, eclipse,  # Park & Kim
    watt, planar_3rrr, spherical_3rrr, gough_stewart,  # Gosselin & Angeles
    three_prr, hybrid, five_spu,  # Chablat et al., Borràs et al.
)


def entries():
    """Every catalogue entry, in catalogue order."""
    return tuple(item for family in _FAMILIES for item in family.ENTRIES)


def names():
    """The catalogue names, in catalogue order."""
    return tuple(item.name for item in entries())


def entry(name):
    """The entry called `name`; MechanismError listing the names otherwise."""
    for item in entries():
        if item.name == name:
            return item
    raise MechanismError(f"no catalogue entry {name!r} (entries: {', '.join(names())})")
