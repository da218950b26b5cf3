"""A survey cache file: the survey of M kept across processes (:func:`read_survey`, :func:`write_survey`).

A survey (:class:`classify.survey.Survey`) belongs to a mechanism, its
actuators, its end-effector metric and the rank cut: the file records a
fingerprint of all of them, in parts (:func:`fingerprint_parts`), and a file
made for anything else is refused, naming the parts that differ:

- ``mechanism``: SHA-256 of the mechanism file's fields and the model's name;
- ``coordinates``: of the ambient factors, their scales and the starts;
- ``actuators``: of the weighted actuator rows;
- ``end_effector_metric``: of H (another ``--length-scale`` changes it);
- ``probe``: of Φ, DΦ·diag(s), the end-effector Jacobian Df and the rows
  of the end-effector rank's reference scale (the model's
  ``end_effector_reference``, where it has them) evaluated at
  the first start (the home) and at three fixed points near it (each tangent
  coordinate moved by a fixed multiple, at most 0.1, of its scale), every
  value rounded to 1e-10 of its row's scale (the largest magnitude of that
  row over the four points, at least 1e-2 of the whole array's), so that the
  rounding of another platform or BLAS does not change it while a model
  with other closure equations or end-effector (e.g. a model given by Φ
  alone, or a joint-output model of another joint) does;
- ``rtol`` (the rank cut) and ``seed`` (:data:`classify.survey.SURVEY_SEED`).

The survey's numbers are bound to the file by ``checksum``, SHA-256 of every
other field (canonical JSON), and must be ones a survey of the model can
have (:func:`read_survey`): a file whose numbers were edited (and its
checksum not recomputed) is refused, naming the field, rather than deciding
verdicts. The checksum is no signature: a file edited *and* given a new
checksum is refused only where its numbers are impossible (a rank above the
dof or below the home's, …); ranks lowered to those of a singular home pass.
A cache is a convenience of the user's own runs, not a file to take from
elsewhere.

Format (JSON)::

    {"format": "closedchain-survey", "version": 6, "mechanism": NAME,
     "fingerprint": {"mechanism": HEX, …, "rtol": 1e-06, "seed": 0}, "rtol": 1e-06,
     "survey": {"samples": …, …}, "checksum": HEX}
"""

from __future__ import annotations

import hashlib
import inspect
import json
import os

import numpy as np

from manifold import DEFAULT_RTOL, scaled_jacobian

from .model import cache_lock
from .survey import MARGIN_KINDS, SURVEY_SEED, Survey, survey_of
from .survey import survey as sampled_survey

__all__ = ["read_survey", "write_survey", "cached_survey", "fingerprint", "fingerprint_parts", "SurveyCacheError"]

_FORMAT = "closedchain-survey"
#: 2: the survey's random points of K are projected onto the closing map first (version 1's surveys of
#: spatial and spherical mechanisms had the walk from home as their only samples, every random start ending at
#: a half-turn); 3: that projection is damped (Levenberg-Marquardt: random starts where Gauss-Newton stalled
#: far from M now reach it, and are samples), and every step is capped in dimensionless units (the caps added
#: radians and lengths, so the samples changed with the unit of length); 4: where DΦ is short of its rows the
#: ranks are taken on the directions M extends along (a part that only flexes counted as idle freedoms that
#: move the end-effector), and the survey carries its margins; 5: the fingerprint is stored in parts and
#: probes Φ, DΦ and Df (a model given by Φ alone, or a joint-output model, shared the fingerprint of another),
#: and a checksum binds the survey to the file; 6: the end-effector decisions' reference scale is σ₁ of the rate
#: every joint coordinate gives the end-effector (the model's ``end_effector_reference``, probed too), not of
#: Df's path, so the end-effector and joint margins changed. A file of an earlier version is refused, not reused
_VERSION = 6
#: largest survey cache file read (bytes)
_LARGEST_FILE = 1 << 20
#: the fields of a survey cache file, and of its survey
_FIELDS = ("format", "version", "mechanism", "fingerprint", "rtol", "survey", "checksum")
_SURVEY_FIELDS = ("samples", "constraint_rank", "actuator_rank", "end_effector_rank", "joint_rank", "margins")
#: what each part of the fingerprint stands for, in refusals
_PARTS = {
    "mechanism": "the mechanism (its file's fields or name)",
    "coordinates": "the coordinates (factors and scales of K) or the starts",
    "actuators": "the actuation (the weighted actuator rows)",
    "end_effector_metric": "the end-effector metric H (e.g. another --length-scale)",
    "probe": "Φ, DΦ or the end-effector Jacobian (their values at the home and near it)",
    "rtol": "the rank cut",
    "seed": "the survey's seed",
}
#: the probe's values are kept to this fraction of their row's scale ...
_PROBE_RESOLUTION = 1e-10
#: ... a row's scale being at least this fraction of its array's (a row of rounding noise rounds to zeros)
_PROBE_ROW_FLOOR = 1e-2
#: the probe's points near the home: tangent steps of these multiples of the coordinates' scales
_PROBE_STEP = 0.1
_PROBE_POINTS = 3
#: what ends a refusal because the file was made for something else
_ELSEWHERE = ("made for another mechanism, actuation, end-effector, rank cut or closedchain version; "
              "delete it or name another file")


class SurveyCacheError(ValueError):
    """A survey cache file that cannot be used (unreadable, malformed, edited or made for something else)."""


def _digest(value):
    """SHA-256 (hex) of the canonical JSON of `value`."""
    text = json.dumps(value, sort_keys=True, separators=(",", ":"), default=repr)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def fingerprint_parts(model, rtol=DEFAULT_RTOL):
    """What a model's survey depends on, in parts (see the module's list).

    Parameters
    ----------
    model : Model
    rtol : float

    Returns
    -------
    dict
        ``mechanism``, ``coordinates``, ``actuators``, ``end_effector_metric`` and ``probe``: SHA-256 (hex);
        ``rtol``: float; ``seed``: int.
    """
    from mechanisms.io import mechanism_to_dict

    metric = model.end_effector_metric
    return {
        "mechanism": _digest({"name": model.name, "fields": None if model.mechanism is None
                              else mechanism_to_dict(model.mechanism)}),
        "coordinates": _digest({"factors": list(model.manifold.ambient.factors),
                                "scales": list(model.manifold.ambient.scales),
                                "starts": np.asarray(model.starts, dtype=float).tolist()}),
        "actuators": _digest(np.asarray(model.actuators, dtype=float).tolist()),
        "end_effector_metric": _digest(None if metric is None else np.asarray(metric, dtype=float).tolist()),
        "probe": _digest(_probe(model)),
        "rtol": float(rtol),
        "seed": SURVEY_SEED,
    }


def fingerprint(model, rtol=DEFAULT_RTOL):
    """SHA-256 (hex) of what a model's survey depends on: of its :func:`fingerprint_parts` and the cache format
    version.

    Parameters
    ----------
    model : Model
    rtol : float

    Returns
    -------
    str
    """
    return _digest({"version": _VERSION, "parts": fingerprint_parts(model, rtol)})


def _probe_points(model):
    """The home (first start) and :data:`_PROBE_POINTS` fixed points of K near it, shape=[1 + count, point_size].

    The steps are fixed rationals (no random generator, whose streams may change), each tangent coordinate moved
    by at most :data:`_PROBE_STEP` of its scale."""
    ambient = model.manifold.ambient
    home = np.asarray(model.starts[0], dtype=float)
    index = np.arange(ambient.dim)
    steps = [((7 * count + 3 * index + 1) % 11 - 5) / 5 for count in range(1, _PROBE_POINTS + 1)]
    moved = [ambient.retract(home, _PROBE_STEP * step * ambient.tangent_scales) for step in steps]
    return np.stack([home] + moved)


def _probe(model):
    """Φ, DΦ·diag(s), Df and the end-effector's reference rows at :func:`_probe_points`, rounded
    (:func:`_quantised`); a map that fails at a point is recorded by its error's type."""
    points = _probe_points(model)
    maps = {"constraint": model.manifold.constraint,
            "constraint_jacobian": lambda point: scaled_jacobian(model.manifold, point)}
    if model.end_effector_jacobian is not None:
        maps["end_effector_jacobian"] = model.end_effector_jacobian
    if model.end_effector_reference is not None:
        maps["end_effector_reference"] = model.end_effector_reference
    probe = {}
    for name, function in maps.items():
        try:
            with np.errstate(all="ignore"):
                values = np.stack([np.asarray(function(point), dtype=float) for point in points])
        except Exception as error:  # noqa: BLE001 - a model's map that fails off M is a property of the model
            probe[name] = {"error": type(error).__name__}
            continue
        probe[name] = _quantised(values)
    return probe


def _quantised(values):
    """Values at the probe's points, shape=[points, rows, ...], as integers: each in units of
    :data:`_PROBE_RESOLUTION` times its row's scale (the row's largest magnitude over every point, at least
    :data:`_PROBE_ROW_FLOOR` of the array's largest), non-finite ones by their repr.

    Rounding noise of another platform (a relative 1e-15 of the row's scale, a zero's sign) leaves the integers
    alone except for a value within that noise of a rounding boundary (about 1e-5 of the values).

    Returns
    -------
    dict
        ``shape`` and ``values`` (a list of int or str).
    """
    values = np.asarray(values, dtype=float)
    if values.ndim < 2:
        values = values.reshape(values.shape + (1,) * (2 - values.ndim))
    finite = np.isfinite(values)
    magnitudes = np.where(finite, np.abs(values), 0.0)
    rows = magnitudes.max(axis=tuple(axis for axis in range(values.ndim) if axis != 1), initial=0.0)
    reference = np.maximum(rows, _PROBE_ROW_FLOOR * magnitudes.max(initial=0.0))
    quantum = (_PROBE_RESOLUTION * reference).reshape((1, -1) + (1,) * (values.ndim - 2))
    safe = np.where(quantum > 0, quantum, 1.0)
    indices = np.where(quantum > 0, np.rint(np.where(finite, values, 0.0) / safe), 0.0)
    shown = [int(index) if ok else repr(float(value))
             for index, ok, value in zip(indices.ravel(), finite.ravel(), values.ravel())]
    return {"shape": list(values.shape), "values": shown}


def _checksum(data):
    """SHA-256 (hex) of a cache file's fields but ``checksum`` (canonical JSON)."""
    return _digest({key: value for key, value in data.items() if key != "checksum"})


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
        One line naming the file and the field: if the file cannot be read, is not a survey cache file (of this
        version), was made for another mechanism, actuation, end-effector metric or rank cut (naming the parts
        of the fingerprint that differ), holds numbers no survey of the model can have, or numbers that do
        not match its checksum (edited).
    """
    from mechanisms import MechanismError
    from mechanisms._text import read_text_file

    if not os.path.lexists(path):
        return None
    name = repr(os.fspath(path))
    try:
        text = read_text_file(path, limit=_LARGEST_FILE)  # refuses FIFOs, devices and folders at once
    except MechanismError as error:
        raise SurveyCacheError(f"survey cache: {error}") from None
    try:
        data = json.loads(text)
    except (ValueError, RecursionError):
        raise SurveyCacheError(f"survey cache {name}: not a JSON file") from None
    if not isinstance(data, dict) or data.get("format") != _FORMAT:
        raise SurveyCacheError(f"survey cache {name}: not a closedchain survey cache "
                               f"(field 'format' must be {_FORMAT!r})")
    version = data.get("version")
    if isinstance(version, bool) or version != _VERSION:
        if "version" not in data:
            raise SurveyCacheError(f"survey cache {name}: field 'version' missing (this closedchain reads version "
                                   f"{_VERSION}): {_ELSEWHERE}")
        raise SurveyCacheError(f"survey cache {name}: field 'version': {_shown(version)}, this closedchain reads "
                               f"version {_VERSION} (a file of another closedchain version); delete it or name "
                               f"another file")
    for field in data:
        if field not in _FIELDS:
            raise SurveyCacheError(f"survey cache {name}: field {_shown(field)}: not a field of a survey cache")
    _check_fingerprint(data, model, rtol, name)
    where = f"survey cache {name}: field 'survey'"
    block = data.get("survey")
    if isinstance(block, dict):
        for field in block:
            if field not in _SURVEY_FIELDS:
                raise SurveyCacheError(f"{where}: field {_shown(field)}: not a field of a survey")
    try:
        found = Survey.from_dict(block, where=where)
    except ValueError as error:
        raise SurveyCacheError(str(error)) from None
    _check_fits(found, model, where, rtol)
    if data.get("checksum") != _checksum(data):
        problem = "missing" if "checksum" not in data else "does not match the other fields"
        raise SurveyCacheError(f"survey cache {name}: field 'checksum' {problem} (the file was edited or is "
                               f"damaged); delete it or name another file")
    return found


def _shown(value, limit=40):
    """`value` for a one-line message: its repr, cut short."""
    text = repr(value) if not isinstance(value, int) or abs(value) < 10 ** 15 \
        else f"a {len(str(abs(value)))}-digit number"
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _check_fingerprint(data, model, rtol, name):
    """SurveyCacheError naming the parts of the file's fingerprint that differ from the model's."""
    stored = data.get("fingerprint")
    if "fingerprint" not in data:
        raise SurveyCacheError(f"survey cache {name}: field 'fingerprint' missing: {_ELSEWHERE}")
    if not isinstance(stored, dict):
        raise SurveyCacheError(f"survey cache {name}: field 'fingerprint': expected an object with the parts "
                               f"{', '.join(_PARTS)}, got {type(stored).__name__}")
    for part in stored:
        if part not in _PARTS:
            raise SurveyCacheError(f"survey cache {name}: field 'fingerprint': {_shown(part)} is not a part of a "
                                   f"fingerprint")
    expected = fingerprint_parts(model, rtol)
    differing = []
    for part, value in expected.items():
        if part not in stored:
            differing.append(f"'{part}' missing")
        elif part == "rtol" and stored[part] != value:
            differing.append(f"{_PARTS[part]} (rtol {_shown(stored[part])} in the file, {value!r} here)")
        elif stored[part] != value or isinstance(stored[part], bool):
            differing.append(_PARTS[part])
    if differing:
        raise SurveyCacheError(f"survey cache {name} was {_ELSEWHERE.split(';')[0]}: its fingerprint differs in "
                               f"{'; '.join(differing)}; delete it or name another file")


def _largest_samples(model):
    """The most samples a survey of `model` (:func:`classify.survey.survey_of`) can have: its starts, the
    random points of K and the walk from each start."""
    defaults = inspect.signature(sampled_survey).parameters
    starts = len(model.starts)
    return starts + defaults["random_count"].default + starts * defaults["walk_count"].default


def _check_fits(found, model, where, rtol=DEFAULT_RTOL):
    """SurveyCacheError unless the survey can be one of the model's: its samples count its starts and at most
    :func:`_largest_samples`; every rank present exactly when it has an end-effector (the end-effector and
    stacked ranks), at most the size of its map and, but DΦ's, the dof k − rank DΦ; the stacked rank at least
    each block's; each rank at least its rank at the model's home (the starts are samples of every survey of
    the model, and visited first); margins only of the model's kinds."""
    starts, most = len(model.starts), _largest_samples(model)
    if not starts <= found.samples <= most:
        raise SurveyCacheError(f"{where}: field 'samples': expected an integer from {starts} to {most} (the "
                               f"starts, random points of K and walks of a survey), got {_shown(found.samples)}")
    size = model.manifold.ambient.dim
    rows = model.constraint_rows
    actuators, outputs = len(model.actuators), model.end_effector_dimension
    dof = size - found.constraint_rank if found.constraint_rank <= size else 0
    largest = {"constraint_rank": min(rows, size), "actuator_rank": min(actuators, size),
               "end_effector_rank": min(outputs, size), "joint_rank": min(actuators + outputs, size)}
    for name, bound in largest.items():
        value = getattr(found, name)
        if name in ("end_effector_rank", "joint_rank") and (value is None) != (outputs == 0):
            expected = "null (the mechanism has no end-effector)" if outputs == 0 else \
                "a non-negative integer (the mechanism has an end-effector)"
            raise SurveyCacheError(f"{where}: field {name!r}: expected {expected}, got {_shown(value)}")
        if value is not None and value > bound:
            raise SurveyCacheError(f"{where}: field {name!r}: expected at most {bound} (the size of the map), "
                                   f"got {_shown(value)}")
        if value is not None and name != "constraint_rank" and value > dof:
            raise SurveyCacheError(f"{where}: field {name!r}: expected at most {dof} (the dof, k − constraint_rank "
                                   f"= {size} − {found.constraint_rank}), got {value}")
    if found.joint_rank is not None and found.joint_rank < max(found.actuator_rank, found.end_effector_rank):
        raise SurveyCacheError(f"{where}: field 'joint_rank': expected at least "
                               f"{max(found.actuator_rank, found.end_effector_rank)} (the stacked rows' rank is at "
                               f"least each block's), got {found.joint_rank}")
    kinds = set(MARGIN_KINDS) if outputs else {"constraint", "actuator"}
    for kind in found.margins or {}:
        if kind not in kinds:
            raise SurveyCacheError(f"{where}: field 'margins.{kind}': the mechanism has no end-effector")
    home = sampled_survey(model, np.random.default_rng(SURVEY_SEED), random_count=0, walk_count=0, rtol=rtol)
    names = ("constraint_rank",) if home.constraint_rank != found.constraint_rank else \
        ("constraint_rank", "actuator_rank", "end_effector_rank", "joint_rank")
    for name in names:
        value, least = getattr(found, name), getattr(home, name)
        if value is not None and least is not None and value < least:
            raise SurveyCacheError(f"{where}: field {name!r}: expected at least {least}, its rank at the home "
                                   f"(the model's starts, samples of every survey of it), got {value}")


def write_survey(path, model, survey, rtol=DEFAULT_RTOL):
    """Write a survey cache file for `model` (see the module's format).

    Parameters
    ----------
    path : str or os.PathLike
    model : Model
    survey : Survey
        The model's survey.
    rtol : float

    Raises
    ------
    SurveyCacheError
        If the file cannot be written.
    """
    data = {"format": _FORMAT, "version": _VERSION, "mechanism": model.name,
            "fingerprint": fingerprint_parts(model, rtol), "rtol": float(rtol), "survey": survey.to_dict()}
    data["checksum"] = _checksum(data)
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
    found = read_survey(path, model, rtol)
    if found is not None:
        with cache_lock(model):
            model.cache[("survey", float(rtol))] = found
        return found, True
    found = survey_of(model, rtol)
    write_survey(path, model, found, rtol)
    return found, False
