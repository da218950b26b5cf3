"""The catalogue: every mechanism of the papers (docs/references.rst), as joint graphs.

Each family module defines builders (keyword-only parameters with the
paper's defaults, returning the mechanism assembled at the requested
configuration) and an ``ENTRIES`` tuple of :class:`Entry`. Tests, docs and
the ``closedchain catalog`` command share these.

A family module is imported when one of its entries is first asked for
(:func:`entry`, :func:`entries`); the names and the list of the catalogue
(:func:`names`, :func:`listing`) come from its index
(:mod:`mechanisms.catalogue._index`) and import none of them.

Examples
--------
>>> from mechanisms.catalogue import entry, names
>>> "slider-crank" in names()
True
>>> [joint.name for joint in entry("slider-crank").mechanism("fig3c_dead_centre").joints]
['crank', 'pin', 'wrist', 'slide']
"""

from __future__ import annotations

import importlib

from ..errors import MechanismError
from ._index import INDEX, Listing

__all__ = ["Entry", "Listing", "entries", "entry", "listing", "names", "parse_parameter"]

#: the family modules, in catalogue order
_FAMILIES = (
    "slider_crank", "five_bar", "spherical_six_bar", "planar_six_bar", "eclipse",  # Park & Kim
    "watt", "planar_3rrr", "spherical_3rrr", "gough_stewart",  # Gosselin & Angeles
    "three_prr", "hybrid", "five_spu",  # Chablat et al., Borràs et al.
)

#: names of :mod:`._entry` exported here (imported on first use, with NumPy)
_ENTRY_NAMES = ("Entry", "parse_parameter")


def __getattr__(name):
    """:class:`Entry`, :func:`parse_parameter` and the family modules, imported on first use (PEP 562)."""
    if name in _ENTRY_NAMES:
        value = getattr(importlib.import_module("._entry", __name__), name)
    elif name in _FAMILIES:
        value = importlib.import_module(f".{name}", __name__)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_ENTRY_NAMES) | set(_FAMILIES))


def _family(module):
    return importlib.import_module(f".{module}", __name__)


def entries():
    """Every catalogue entry, in catalogue order."""
    return tuple(item for module in _FAMILIES for item in _family(module).ENTRIES)


def names():
    """The catalogue names, in catalogue order."""
    return tuple(row.name for row in INDEX)


def listing():
    """What the catalogue's list shows of every entry, in catalogue order, without importing any.

    Returns
    -------
    tuple of Listing
        ``(name, family, summary, reference, configurations)`` per entry,
        equal to those of :func:`entries`.
    """
    return INDEX


def entry(name):
    """The entry called `name` (importing only its family module); MechanismError listing the names otherwise."""
    for row in INDEX:
        if row.name == name:
            for item in _family(row.family).ENTRIES:
                if item.name == name:
                    return item
    raise MechanismError(f"no catalogue entry {name!r} (entries: {', '.join(names())})")
