"""A survey cache file: the survey of M kept across processes (:func:`read_survey`, :func:`write_survey`).

A survey (:class:`classify.survey.Survey`) belongs to a mechanism, its
actuators, its end-effector metric and the rank cut: the file records a
fingerprint of all of them (SHA-256 of their exact description: the
mechanism file's fields, the actuator rows and H), and a file made for
anything else is refused rather than silently used.

Format (JSON)::

    {"format": "closedchain-survey", "version": 3, "mechanism": NAME,
     "fingerprint": HEX, "rtol": 1e-06, "survey": {"samples": …, …}}
"""

from __future__ import annotations

import hashlib
import json
import os

import numpy as np

from manifold import DEFAULT_RTOL

from .survey import SURVEY_SEED, Survey, survey_of

__all__ = ["read_survey", "write_survey", "cached_survey", "fingerprint", "SurveyCacheError"]

_FORMAT = "closedchain-survey"
#: 2: the survey's random points of K are projected onto the closing map first (version 1's surveys of
#: spatial and spherical mechanisms had the walk from home as their only samples, every random start ending at
#: a half-turn); 3: that projection is damped (Levenberg-Marquardt: random starts where Gauss-Newton stalled
#: far from M now reach it, and are samples), and every step is capped in dimensionless units (the caps added
#: radians and lengths, so the samples changed with the unit of length); 4: where DΦ is short of its rows the
#: ranks are taken on the directions M extends along (a part that only flexes counted as idle freedoms that
#: move the end-effector), and the survey carries its margins. A file of an earlier version is refused, not
#: reused
_VERSION = 4
#: largest survey cache file read (bytes)
_LARGEST_FILE = 1 << 20


class SurveyCacheError(ValueError):
    """A survey cache file that cannot be used (unreadable, malformed or made for something else)."""


def fingerprint(model, rtol=DEFAULT_RTOL):
    """SHA-256 (hex) of what a model's survey depends on.

    The mechanism's file fields (when the model comes from one), the model's
    name, ambient factors and scales, starts, actuator rows and end-effector
    metric, the rank cut, the survey's seed and the cache format version.
    """
    from mechanisms.io import mechanism_to_dict

    description = {
        "version": _VERSION, "seed": SURVEY_SEED, "rtol": float(rtol), "name": model.name,
        "mechanism": None if model.mechanism is None else mechanism_to_dict(model.mechanism),
        "factors": list(model.manifold.ambient.factors), "scales": list(model.manifold.ambient.scales),
        "starts": np.asarray(model.starts, dtype=float).tolist(),
        "actuators": np.asarray(model.actuators, dtype=float).tolist(),
        "end_effector_metric": None if model.end_effector_metric is None
        else np.asarray(model.end_effector_metric, dtype=float).tolist(),
    }
    text = json.dumps(description, sort_keys=True, separators=(",", ":"), default=repr)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def read_survey(path, model, rtol=DEFAULT_RTOL):
    """The survey in a cache file, or None when the file does not exist.

    Parameters
    ----------
    path : str or os.PathLike
    model : Model
    rtol : float

    Returns
    -------
    Survey or None

    Raises
    ------
    SurveyCacheError
        If the file cannot be read, is not a survey cache file, or was made for another mechanism,
        actuation, end-effector metric or rank cut (the message names the file).
    """
    from mechanisms import MechanismError
    from mechanisms._text import read_text_file

    if not os.path.lexists(path):
        return None
    try:
        text = read_text_file(path, limit=_LARGEST_FILE)  # refuses FIFOs, devices and folders at once
    except MechanismError as error:
        raise SurveyCacheError(f"survey cache: {error}") from None
    try:
        data = json.loads(text)
    except (ValueError, RecursionError):
        raise SurveyCacheError(f"survey cache {os.fspath(path)!r}: not a JSON file") from None
    if not isinstance(data, dict) or data.get("format") != _FORMAT:
        raise SurveyCacheError(f"survey cache {os.fspath(path)!r}: not a closedchain survey cache "
                               f"(field 'format' must be {_FORMAT!r})")
    if data.get("version") != _VERSION or data.get("fingerprint") != fingerprint(model, rtol):
        raise SurveyCacheError(f"survey cache {os.fspath(path)!r} was made for another mechanism, actuation, "
                               f"end-effector, rank cut or closedchain version; delete it or name another file")
    where = f"survey cache {os.fspath(path)!r}: field 'survey'"
    try:
        survey = Survey.from_dict(data.get("survey"), where=where)
    except ValueError as error:
        raise SurveyCacheError(str(error)) from None
    _check_fits(survey, model, where)
    return survey


def _check_fits(survey, model, where):
    """SurveyCacheError unless every rank can be the model's: present exactly when it has an end-effector (the
    end-effector and stacked ranks), and at most the size of its map (a rank of DΦ above min(c, k)...)."""
    size = model.manifold.ambient.dim
    rows = model.constraint_rows
    actuators, outputs = len(model.actuators), model.end_effector_dimension
    largest = {"constraint_rank": min(rows, size), "actuator_rank": min(actuators, size),
               "end_effector_rank": min(outputs, size), "joint_rank": min(actuators + outputs, size)}
    for name, bound in largest.items():
        value = getattr(survey, name)
        if name in ("end_effector_rank", "joint_rank") and (value is None) != (outputs == 0):
            expected = "null (the mechanism has no end-effector)" if outputs == 0 else \
                "a non-negative integer (the mechanism has an end-effector)"
            raise SurveyCacheError(f"{where}: field {name!r}: expected {expected}, got {value!r}")
        if value is not None and value > bound:
            raise SurveyCacheError(f"{where}: field {name!r}: expected at most {bound} (the size of the map), "
                                   f"got {value}")


def write_survey(path, model, survey, rtol=DEFAULT_RTOL):
    """Write a survey cache file for `model` (see the module's format).

    Raises
    ------
    SurveyCacheError
        If the file cannot be written.
    """
    data = {"format": _FORMAT, "version": _VERSION, "mechanism": model.name,
            "fingerprint": fingerprint(model, rtol), "rtol": float(rtol), "survey": survey.to_dict()}
    from mechanisms import MechanismError
    from mechanisms._text import write_text_file

    try:
        write_text_file(path, json.dumps(data, indent=1) + "\n")
    except MechanismError as error:
        raise SurveyCacheError(f"survey cache: {error}") from None


def cached_survey(path, model, rtol=DEFAULT_RTOL):
    """The model's survey from the cache file if it is there, else computed and written to it.

    Either way the survey becomes the model's own (:func:`classify.survey.survey_of` returns it).

    Returns
    -------
    survey : Survey
    read : bool
        Whether it came from the file.
    """
    survey = read_survey(path, model, rtol)
    if survey is not None:
        model.cache[("survey", float(rtol))] = survey
        return survey, True
    survey = survey_of(model, rtol)
    write_survey(path, model, survey, rtol)
    return survey, False
