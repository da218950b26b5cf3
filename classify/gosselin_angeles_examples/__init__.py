"""Gosselin–Angeles relations F(θ, x) = 0 of the paper's examples, for the catalogue mechanisms.

Each function takes a catalogue mechanism (and the paper's branch signs where
needed) and returns ``(relation, coordinates)``: an
:class:`~classify.gosselin_angeles.InputOutputRelation` written as in
Gosselin & Angeles (1990) and ``coordinates(point) ->
(theta, x)``, the relation's variables read from the mechanism's geometry at a
configuration, ready for :func:`classify.comparison.compare`.

Planar examples: the slider-crank (:mod:`.slider_crank`, eqs. 6–17), Watt's
linkage (:mod:`.watt`, eqs. 18–41), the planar 3-RRR (:mod:`.planar_3rrr`,
eqs. 42–65). Spatial examples: the spherical 3-RRR wrist (:mod:`.spherical_3rrr`,
eqs. 66–70) and the Gough–Stewart platform (:mod:`.gough_stewart`, eqs. 71–87);
their orientation chart is in :mod:`._rotations`.
"""

from .planar_3rrr import (
    Planar3RRRGeometry, planar_3rrr_coordinates, planar_3rrr_geometry, planar_3rrr_matrices,
    planar_3rrr_relation,
)
from .slider_crank import (
    SliderCrankGeometry, eq9_relation, eq12_matrices, eq12_relation, slider_crank_branch,
    slider_crank_coordinates, slider_crank_geometry, squared_equation, squared_relation,
)
from .watt import WattGeometry, watt_coordinates, watt_factors, watt_geometry, watt_relation, watt_rocker_angle

from .gough_stewart import GoughStewartGeometry, eq75_relation, eq81_relation, gough_stewart_geometry
from .spherical_3rrr import SphericalGeometry, eq68_relation, spherical_3rrr_geometry, spherical_3rrr_relation


def _slider_crank_branch_relation(function):
    def build(mechanism, point):
        return function(mechanism, branch=slider_crank_branch(mechanism, point))
    return build


#: The joints whose coordinates are the outputs x of the paper's relations, by catalogue entry: the slider-crank's
#: slide (eqs. 9, 12); the others' x is the entry's end-effector
PAPER_OUTPUTS = {"slider-crank": ("slide",)}

#: The paper's relations by catalogue entry: ``RELATIONS[entry][name](mechanism, point) -> (relation,
#: coordinates)``; a branch sign (eqs. 9, 12) is that of `point`.
RELATIONS = {
    "slider-crank": {
        "eq9": _slider_crank_branch_relation(eq9_relation),
        "eq12": _slider_crank_branch_relation(eq12_relation),
        "squared": lambda mechanism, point: squared_relation(mechanism),
    },
    "watt-six-bar": {"eq32": lambda mechanism, point: watt_relation(mechanism)},
    "planar-3rrr": {"eq44": lambda mechanism, point: planar_3rrr_relation(mechanism)},
    "spherical-3rrr": {"closure": lambda mechanism, point: spherical_3rrr_relation(mechanism),
                       "eq68": lambda mechanism, point: eq68_relation(mechanism)},
    "gough-stewart": {"eq75": lambda mechanism, point: eq75_relation(mechanism),
                      "eq81": lambda mechanism, point: eq81_relation(mechanism)},
}

__all__ = [
    "RELATIONS", "PAPER_OUTPUTS",
    "SliderCrankGeometry", "slider_crank_geometry", "slider_crank_coordinates", "slider_crank_branch",
    "eq9_relation", "eq12_relation", "eq12_matrices", "squared_relation", "squared_equation",
    "WattGeometry", "watt_geometry", "watt_coordinates", "watt_rocker_angle", "watt_factors", "watt_relation",
    "Planar3RRRGeometry", "planar_3rrr_geometry", "planar_3rrr_coordinates", "planar_3rrr_matrices",
    "planar_3rrr_relation",
    "SphericalGeometry", "spherical_3rrr_geometry", "spherical_3rrr_relation", "eq68_relation",
    "GoughStewartGeometry", "gough_stewart_geometry", "eq75_relation", "eq81_relation",
]
