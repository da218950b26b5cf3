"""Seeded mutations of mechanism files for the fuzz tests of the ``closedchain`` command.

A mutation takes the parsed contents of a catalogue entry written as a file
(``closedchain catalog NAME --write f.yaml``), its text and a seeded
``numpy.random.Generator``, and returns ``(content, suffix)``: the text (or
bytes) of the mutated file and its extension. Each :class:`Mutation` also
says which exit status it must give (2: refused) or ``None`` when either 0 or
2 is right (a random flip may leave a valid file), and whether it may reach a
full classification (then it runs on a few cheap entries only, to keep the
fuzz module fast).
"""

from __future__ import annotations

import copy
import json
from dataclasses import dataclass
from typing import Callable, Optional

import yaml

__all__ = ["Mutation", "MUTATIONS", "CHEAP_ENTRIES", "points_scaled", "billion_laughs", "pendulums"]

#: catalogue entries whose classification takes a fraction of a second
CHEAP_ENTRIES = ("slider-crank", "five-bar", "planar-six-bar", "hybrid", "spherical-six-bar")


@dataclass(frozen=True)
class Mutation:
    """One way of breaking (or bending) a mechanism file.

    Parameters
    ----------
    name : str
    mutate : callable
        ``mutate(data, text, rng) -> (content, suffix)``.
    expected : int or None
        The exit status it must give; None for "0 or 2".
    costly : bool
        Whether a valid result reaches a full classification (run on :data:`CHEAP_ENTRIES` only).
    """

    name: str
    mutate: Callable
    expected: Optional[int] = 2
    costly: bool = False


# ------------------------------------------------------------------ helpers

def _yaml(data):
    return yaml.safe_dump(data, sort_keys=False, default_flow_style=None, allow_unicode=False), ".yaml"


def _json(data):
    return json.dumps(data, ensure_ascii=True, allow_nan=True), ".json"


def _choice(rng, items):
    return items[int(rng.integers(len(items)))]


def _joint(data, rng, *fields):
    """A random joint that has all `fields` (the first joint with them if none is drawn)."""
    joints = [joint for joint in data["joints"] if all(field in joint for field in fields)]
    return _choice(rng, joints)


def _vector_field(joint):
    return "point" if "point" in joint else "axis" if "axis" in joint else "axes"


def _set_coordinate(data, rng, value):
    """Put `value` in one coordinate of a random joint's point, axis or first U axis."""
    data = copy.deepcopy(data)
    joint = _choice(rng, data["joints"])
    field = _vector_field(joint)
    vector = joint[field][0] if field == "axes" else joint[field]
    vector[int(rng.integers(len(vector)))] = value
    return data


def _with(function):
    """A mutation of the parsed data written back as YAML."""
    return lambda data, text, rng: _yaml(function(copy.deepcopy(data), rng))


def _with_json(function):
    """A mutation of the parsed data written as JSON (escapes such as \\ud800 survive)."""
    return lambda data, text, rng: _json(function(copy.deepcopy(data), rng))


def points_scaled(data, factor):
    """`data` with every point (joints and end-effector) multiplied by `factor`."""
    data = copy.deepcopy(data)
    for joint in data["joints"]:
        if "point" in joint:
            joint["point"] = [factor * value for value in joint["point"]]
    end_effector = data.get("end_effector") or {}
    if "point" in end_effector:
        end_effector["point"] = [factor * value for value in end_effector["point"]]
    return data


def _link_names(data):
    return [link for joint in data["joints"] for link in joint["links"]]


def _shared_link(data, rng):
    """A link (not the ground) named by two joints or more, of at least 5 characters with two adjacent
    letters (so that swapping them is a slip the loader recognises)."""
    names = _link_names(data)
    shared = sorted({link for link in names if names.count(link) > 1 and link != data.get("ground", "ground")
                     and len(link) >= 5 and any(a.isalpha() and b.isalpha() and a != b
                                                for a, b in zip(link, link[1:]))})
    return _choice(rng, shared)


def _transposed(name):
    """`name` with its first two adjacent, different letters swapped (a typing slip)."""
    for index in range(len(name) - 1):
        first, second = name[index], name[index + 1]
        if first.isalpha() and second.isalpha() and first != second:
            return name[:index] + second + first + name[index + 2:]
    raise ValueError(f"no two different adjacent letters in {name!r}")


def _misspell(data, rng):
    link = _shared_link(data, rng)
    for joint in data["joints"]:
        if link in joint["links"]:
            joint["links"][joint["links"].index(link)] = _transposed(link)
            return data


def _misspell_ground(data, rng):
    ground = data.get("ground", "ground")
    for joint in data["joints"]:
        if ground in joint["links"]:
            joint["links"][joint["links"].index(ground)] = "grund"
            return data


def _delete(data, rng, *path):
    target = data
    for key in path[:-1]:
        target = target[key]
    del target[path[-1]]
    return data


def _delete_joint_field(data, rng, field):
    joint = _joint(data, rng, field)
    del joint[field]
    return data


def _delete_geometry(data, rng):
    joint = _choice(rng, data["joints"])
    del joint[_vector_field(joint)]
    return data


def _set_joint_field(data, rng, field, value):
    _choice(rng, data["joints"])[field] = value
    return data


def _set_vector(data, rng, value):
    joint = _choice(rng, data["joints"])
    joint[_vector_field(joint)] = value
    return data


def _set_name(data, rng, value):
    _choice(rng, data["joints"])["name"] = value
    return data


def _set_link(data, rng, value):
    joint = _choice(rng, data["joints"])
    joint["links"][int(rng.integers(2))] = value
    return data


def _rename_link(data, rng, new):
    """`data` with a random link other than the ground renamed `new` everywhere (end-effector included)."""
    ground = data.get("ground", "ground")
    old = _choice(rng, sorted(set(_link_names(data)) - {ground}))
    for joint in data["joints"]:
        joint["links"] = [new if link == old else link for link in joint["links"]]
    end_effector = data.get("end_effector") or {}
    if end_effector.get("link") == old:
        end_effector["link"] = new
    return data


def _duplicate_name(data, rng):
    data["joints"][-1]["name"] = data["joints"][0]["name"]
    return data


def _self_loop(data, rng):
    joint = _choice(rng, data["joints"])
    joint["links"] = [joint["links"][0], joint["links"][0]]
    return data


def _extra_joint(data, links):
    first = data["joints"][0]
    extra = {key: copy.deepcopy(value) for key, value in first.items() if key not in ("actuated", "weight")}
    extra.update(name="extra_joint", links=list(links))
    data["joints"].append(extra)
    return data


def _disconnected(data, rng):
    return _extra_joint(data, ["moon", "rover"])


def _pendant(data, rng):
    return _extra_joint(data, [data["joints"][0]["links"][1], "pendant"])


def _unknown_end_effector(data, rng):
    data["end_effector"] = {**(data.get("end_effector") or {}), "link": "nowhere"}
    return data


def _delete_joint(data, rng):
    del data["joints"][int(rng.integers(len(data["joints"])))]
    return data


def _other_space(data, rng):
    data["space"] = {"planar": "spatial", "spatial": "planar", "spherical": "planar"}[data["space"]]
    return data


def _huge_integer_text(data, text, rng):
    """JSON with a 5,000-digit integer as a coordinate (no float can hold it)."""
    mutated = _set_coordinate(data, rng, 12345)
    content, suffix = _json(mutated)
    return content.replace("12345", "9" * 5000, 1), suffix


def _byte_flips(count):
    def mutate(data, text, rng):
        content = bytearray(text.encode("utf-8"))
        for _ in range(count):
            position = int(rng.integers(len(content)))
            content[position] ^= 1 << int(rng.integers(8))
        return bytes(content), ".yaml"
    return mutate


def _truncated(data, text, rng):
    return text[: int(rng.integers(1, len(text)))], ".yaml"


def _random_bytes(data, text, rng):
    return bytes(rng.integers(0, 256, size=2048, dtype="uint8")), ".yaml"


def _deeply_nested(data, text, rng):
    return text.replace("name:", "name: " + "[" * 5000 + "0" + "]" * 5000 + "\nold_name:", 1), ".yaml"


def _prefixed(prefix):
    return lambda data, text, rng: (prefix + text, ".yaml")


def _alias(data, text, rng):
    content, suffix = _yaml(data)
    first = data["joints"][0]["links"][0]
    return content.replace(f"links: [{first}", f"links: [&link {first}", 1).replace(
        "description:", "alias_of_link: *link\ndescription:", 1), suffix


def _merge_key(data, text, rng):
    return "defaults: {space: planar}\n<<: {space: planar}\n" + text, ".yaml"


def billion_laughs(levels=9):
    """The YAML "billion laughs": each level an anchored list of nine aliases of the previous one."""
    lines = ['a0: &a0 ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for level in range(1, levels + 1):
        previous = f"*a{level - 1}"
        lines.append(f"a{level}: &a{level} [{', '.join([previous] * 9)}]")
    return "\n".join(lines) + "\n"


def merge_key_bomb(levels=20):
    """A chain of merge keys, each mapping merging the previous one twice over."""
    lines = ["m0: &m0 {k0: 0}"]
    for level in range(1, levels + 1):
        lines.append(f"m{level}: &m{level} {{<<: [*m{level - 1}, *m{level - 1}], k{level}: {level}}}")
    return "\n".join(lines) + "\n"


def pendulums(count):
    """The YAML text of `count` pendulums hung from the ground (no loop, k = count), about 75 bytes each."""
    lines = ["name: pendulums", "space: planar", "joints:"]
    lines += [f"  - {{name: P{index}, type: R, links: [ground, pendulum{index}], point: [{index}.0, 0.0]}}"
              for index in range(count)]
    return "\n".join(lines) + "\n"


NAN, INFINITY = float("nan"), float("inf")

MUTATIONS = (
    # --- missing keys
    Mutation("missing-name", _with(lambda data, rng: _delete(data, rng, "name"))),
    Mutation("missing-space", _with(lambda data, rng: _delete(data, rng, "space"))),
    Mutation("missing-joints", _with(lambda data, rng: _delete(data, rng, "joints"))),
    Mutation("missing-joint-type", _with(lambda data, rng: _delete_joint_field(data, rng, "type"))),
    Mutation("missing-joint-links", _with(lambda data, rng: _delete_joint_field(data, rng, "links"))),
    Mutation("missing-geometry", _with(_delete_geometry)),
    # --- wrong types
    Mutation("joints-a-string", _with(lambda data, rng: {**data, "joints": "J1"})),
    Mutation("name-a-number", _with(lambda data, rng: {**data, "name": 5})),
    Mutation("links-a-string", _with(lambda data, rng: _set_joint_field(data, rng, "links", "ground"))),
    Mutation("links-three", _with(lambda data, rng: _set_joint_field(data, rng, "links", ["a", "b", "c"]))),
    Mutation("vector-a-string", _with(lambda data, rng: _set_vector(data, rng, "0, 0"))),
    Mutation("vector-a-mapping", _with(lambda data, rng: _set_vector(data, rng, {"x": 0}))),
    Mutation("vector-of-booleans", _with(lambda data, rng: _set_vector(data, rng, [True, False, True]))),
    Mutation("actuated-yes", _with(lambda data, rng: _set_joint_field(data, rng, "actuated", "yes"))),
    Mutation("weight-negative", _with(lambda data, rng: _set_joint_field(data, rng, "weight", -1.0))),
    Mutation("weight-huge", _with(lambda data, rng: _set_joint_field(data, rng, "weight", 1e300))),
    Mutation("type-unknown", _with(lambda data, rng: _set_joint_field(data, rng, "type", "Q"))),
    Mutation("unknown-top-level-key", _with(lambda data, rng: {**data, "extra": 1})),
    Mutation("unknown-joint-key", _with(lambda data, rng: _set_joint_field(data, rng, "pivot", [0, 0]))),
    # --- numbers
    Mutation("nan", _with_json(lambda data, rng: _set_coordinate(data, rng, NAN))),
    Mutation("infinity", _with_json(lambda data, rng: _set_coordinate(data, rng, -INFINITY))),
    Mutation("1e308", _with(lambda data, rng: _set_coordinate(data, rng, 1e308))),
    Mutation("1e200", _with(lambda data, rng: _set_coordinate(data, rng, -1e200))),
    Mutation("1e13", _with(lambda data, rng: _set_coordinate(data, rng, 1e13))),
    Mutation("integer-10-to-300", _with(lambda data, rng: _set_coordinate(data, rng, 10 ** 300))),
    Mutation("integer-5000-digits", _huge_integer_text),
    Mutation("all-points-times-1e150", lambda data, text, rng: _yaml(points_scaled(data, 1e150)), expected=None),
    Mutation("all-points-times-1e-150", lambda data, text, rng: _yaml(points_scaled(data, 1e-150)), expected=None),
    Mutation("micrometres", lambda data, text, rng: _yaml(points_scaled(data, 1e-6)), expected=0, costly=True),
    Mutation("kilometres", lambda data, text, rng: _yaml(points_scaled(data, 1e6)), expected=0, costly=True),
    # --- names
    Mutation("control-characters-in-names", _with_json(lambda data, rng: _set_name(
        _rename_link(data, rng, "link\x1b[31m\x00"), rng, "J\x07\u202e\n\x7f")), expected=0, costly=True),
    Mutation("surrogate-joint-name", _with_json(lambda data, rng: _set_name(data, rng, "J\ud800"))),
    Mutation("surrogate-link", _with_json(lambda data, rng: _set_link(data, rng, "\udfff"))),
    Mutation("surrogate-mechanism-name", _with_json(lambda data, rng: {**data, "name": "\ud83d"})),
    Mutation("long-joint-name", _with(lambda data, rng: _set_name(data, rng, "J" * 10_000))),
    Mutation("empty-joint-name", _with(lambda data, rng: _set_name(data, rng, ""))),
    Mutation("duplicate-joint-name", _with(_duplicate_name)),
    Mutation("unknown-end-effector-link", _with(_unknown_end_effector)),
    Mutation("misspelt-link", _with(_misspell)),
    Mutation("misspelt-ground", _with(_misspell_ground)),
    Mutation("self-loop", _with(_self_loop)),
    Mutation("disconnected", _with(_disconnected)),
    Mutation("pendant-link", _with(_pendant)),
    # --- YAML features a mechanism file must not use
    Mutation("alias", _alias),
    Mutation("merge-key", _merge_key),
    Mutation("billion-laughs", lambda data, text, rng: (billion_laughs(5) + text, ".yaml")),
    Mutation("python-tag", _prefixed("exploit: !!python/object/apply:os.system ['echo pwned']\n")),
    Mutation("python-name-tag", _prefixed("exploit: !!python/name:os.system\n")),
    Mutation("binary-tag", _prefixed("blob: !!binary aGVsbG8=\n")),
    Mutation("set-tag", _prefixed("things: !!set {a, b}\n")),
    Mutation("local-tag", _prefixed("thing: !local value\n")),
    Mutation("deeply-nested", _deeply_nested),
    Mutation("two-documents", lambda data, text, rng: (text + "---\n" + text, ".yaml")),
    # --- broken bytes
    Mutation("empty", lambda data, text, rng: ("", ".yaml")),
    Mutation("random-bytes", _random_bytes),
    Mutation("truncated", _truncated, expected=None, costly=True),
    Mutation("one-byte-flip", _byte_flips(1), expected=None, costly=True),
    Mutation("three-byte-flips", _byte_flips(3), expected=None, costly=True),
    # --- structural changes that may leave a valid mechanism
    Mutation("delete-a-joint", _with(_delete_joint), expected=None, costly=True),
    Mutation("other-space", _with(_other_space), expected=None, costly=True),
)
