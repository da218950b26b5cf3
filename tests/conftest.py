"""Shared test data: valid mechanism files and the catalogue of malformed ones.

``MALFORMED_CASES`` holds ``(case_id, file_text, file_suffix, expected_fragment)``:
the text of a mechanism file that must be refused, the extension to save it
under, and a substring the one-line error message must contain. Any test with
an argument named ``malformed_case`` runs once per case (see
:func:`pytest_generate_tests`).
"""

import pytest

FIVE_BAR_YAML = """\
name: five-bar
space: planar
joints:
  - {name: J1, type: R, links: [ground, proximal1], point: [0, 0], actuated: true}
  - {name: J2, type: R, links: [proximal1, distal1], point: [0, 1]}
  - {name: J3, type: R, links: [distal1, distal2], point: [1, 2]}
  - {name: J4, type: R, links: [distal2, proximal2], point: [2, 1]}
  - {name: J5, type: R, links: [proximal2, ground], point: [2, 0], actuated: true}
end_effector: {link: distal1, point: [1, 2]}
"""

SLIDER_JSON = """\
{
  "name": "slider",
  "space": "planar",
  "joints": [
    {"name": "J1", "type": "R", "links": ["ground", "crank"], "point": [0, 0], "actuated": true},
    {"name": "J2", "type": "R", "links": ["crank", "rod"], "point": [1, 0]},
    {"name": "J3", "type": "R", "links": ["rod", "block"], "point": [3, 0]},
    {"name": "S1", "type": "P", "links": ["block", "ground"], "axis": [1, 0]}
  ]
}
"""

SPHERICAL_FOUR_BAR_YAML = """\
name: spherical-four-bar
space: spherical
joints:
  - {name: A, type: R, links: [ground, crank], axis: [0, 0, 1], actuated: true}
  - {name: B, type: R, links: [crank, coupler], axis: [1, 0, 1]}
  - {name: C, type: R, links: [coupler, rocker], axis: [0, 1, 1]}
  - {name: D, type: R, links: [rocker, ground], axis: [0, 1, 0]}
end_effector: {link: coupler, output: orientation}
"""

SPATIAL_CHAIN_YAML = """\
name: spatial-chain
space: spatial
ground: base
joints:
  - {name: R1, type: R, links: [base, a], point: [0, 0, 0], axis: [0, 0, 1], actuated: true}
  - {name: P1, type: P, links: [a, b], axis: [1, 0, 0], actuated: true, weight: 2.5}
  - {name: U1, type: U, links: [b, c], point: [1, 0, 0], axes: [[0, 0, 1], [0, 1, 0]]}
  - {name: S1, type: S, links: [c, d], point: [1, 1, 0]}
  - {name: C1, type: C, links: [d, base], point: [0, 1, 0], axis: [0, 0, 1]}
end_effector: {link: c, point: [1, 0.5, 0], output: pose}
configurations:
  bent: {R1: 0.1, U1: [0.2, -0.1], S1: [0, 0, 0.3], C1: [0.05, 0.01]}
"""

VALID_FILES = {
    "five-bar": (FIVE_BAR_YAML, ".yaml"),
    "slider": (SLIDER_JSON, ".json"),
    "spherical-four-bar": (SPHERICAL_FOUR_BAR_YAML, ".yaml"),
    "spatial-chain": (SPATIAL_CHAIN_YAML, ".yml"),
}


def _edit(text, old, new):
    """`text` with its one occurrence of `old` replaced (a typo in a case must not make it valid)."""
    if text.count(old) != 1:
        raise ValueError(f"{old!r} occurs {text.count(old)} times in the base text")
    return text.replace(old, new)


def _five_bar(old, new):
    return _edit(FIVE_BAR_YAML, old, new)


def _spatial(old, new):
    return _edit(SPATIAL_CHAIN_YAML, old, new)


def _slider(old, new):
    return _edit(SLIDER_JSON, old, new)


_J1 = "{name: J1, type: R, links: [ground, proximal1], point: [0, 0], actuated: true}"
_J3 = "{name: J3, type: R, links: [distal1, distal2], point: [1, 2]}"
_END_EFFECTOR = "end_effector: {link: distal1, point: [1, 2]}"
_JSON_J2 = '{"name": "J2", "type": "R", "links": ["crank", "rod"], "point": [1, 0]}'

MALFORMED_CASES = [
    # --- the file itself
    ("yaml-unparsable", "name: five-bar\njoints: [\n  {name: J1\n", ".yaml", "cannot parse YAML"),
    ("json-unparsable", '{"name": "slider", "space": "planar",\n', ".json", "cannot parse JSON"),
    ("yaml-python-tag", "name: !!python/object/apply:os.system ['echo hacked']\n", ".yaml",
     "cannot parse YAML"),
    ("yaml-duplicate-key", _five_bar("space: planar\n", "space: planar\nspace: spatial\n"), ".yaml",
     "duplicate key 'space'"),
    ("json-duplicate-key", _slider('"space": "planar",', '"space": "planar", "space": "planar",'),
     ".json", "duplicate key 'space'"),
    ("unknown-extension", FIVE_BAR_YAML, ".txt", "unknown file format"),
    ("empty-file", "", ".yaml", "top level: expected a mapping"),
    ("top-level-list", "- five-bar\n- planar\n", ".yaml", "top level: expected a mapping"),
    ("json-top-level-string", '"five-bar"\n', ".json", "top level: expected a mapping"),
    # --- top-level fields
    ("unknown-top-level-key", _five_bar("space: planar\n", "space: planar\njoint_list: []\n"),
     ".yaml", "unknown field 'joint_list'"),
    ("missing-name", _five_bar("name: five-bar\n", ""), ".yaml", "field 'name': missing"),
    ("name-not-string", _five_bar("name: five-bar", "name: 5"), ".yaml", "field 'name'"),
    ("missing-space", _five_bar("space: planar\n", ""), ".yaml", "field 'space': missing"),
    ("unknown-space", _five_bar("space: planar", "space: hyperbolic"), ".yaml",
     "unknown space 'hyperbolic'"),
    ("unknown-ground", _five_bar("space: planar\n", "space: planar\nground: base\n"), ".yaml",
     "field 'ground'"),
    ("joints-missing", "name: five-bar\nspace: planar\n", ".yaml", "field 'joints': missing"),
    ("joints-not-list", "name: five-bar\nspace: planar\njoints: {J1: {type: R}}\n", ".yaml",
     "field 'joints': expected a list"),
    ("joints-empty", "name: five-bar\nspace: planar\njoints: []\n", ".yaml", "field 'joints'"),
    ("description-not-string", _five_bar("space: planar\n", "space: planar\ndescription: [a, b]\n"),
     ".yaml", "field 'description'"),
    # --- joints: structure
    ("joint-not-mapping", _five_bar(_J3, "J3"), ".yaml", "field 'joints': item 2"),
    ("joint-missing-name", _five_bar("{name: J3, ", "{"), ".yaml", "item 2: field 'name': missing"),
    ("unknown-joint-key", _five_bar(_J3, _J3[:-1] + ", pivot: [1, 2]}"), ".yaml",
     "joint 'J3': unknown field 'pivot'"),
    ("missing-type", _five_bar("{name: J3, type: R, ", "{name: J3, "), ".yaml",
     "joint 'J3': field 'type': missing"),
    ("unknown-joint-type", _five_bar("{name: J3, type: R,", "{name: J3, type: Q,"), ".yaml",
     "joint 'J3': field 'type': unknown joint type 'Q'"),
    ("type-not-in-space", _five_bar("{name: J3, type: R,", "{name: J3, type: S,"), ".yaml",
     "joint 'J3': field 'type'"),
    ("missing-links", _five_bar(" links: [distal1, distal2],", ""), ".yaml",
     "joint 'J3': field 'links': missing"),
    ("three-links", _five_bar("[distal1, distal2]", "[distal1, distal2, ground]"), ".yaml",
     "joint 'J3': field 'links'"),
    ("self-loop", _five_bar("[distal1, distal2]", "[distal1, distal1]"), ".yaml",
     "joint 'J3': field 'links': a joint cannot join link 'distal1' to itself"),
    ("duplicate-joint-name", _five_bar("{name: J4,", "{name: J3,"), ".yaml",
     "joint 'J3': field 'name': duplicate joint name"),
    ("not-connected", _five_bar(_J1, _J1 + "\n  - {name: J6, type: R, links: [moon, rover], "
                                           "point: [5, 5]}"),
     ".yaml", "not connected to the ground"),
    # --- joints: numbers and flags
    ("missing-point", _five_bar(_J3, "{name: J3, type: R, links: [distal1, distal2]}"), ".yaml",
     "joint 'J3': field 'point': missing"),
    ("point-too-long", _five_bar(_J3, _J3.replace("[1, 2]", "[1, 2, 0]")), ".yaml",
     "joint 'J3': field 'point': expected 2 numbers, got 3"),
    ("point-not-list", _five_bar(_J3, _J3.replace("[1, 2]", "1")), ".yaml",
     "joint 'J3': field 'point': expected a list of numbers"),
    ("point-numeric-string", _five_bar(_J3, _J3.replace("[1, 2]", "['1.0', 2]")), ".yaml",
     "joint 'J3': field 'point': item 0: expected a number, got '1.0'"),
    ("point-boolean", _five_bar(_J3, _J3.replace("[1, 2]", "[1, true]")), ".yaml",
     "joint 'J3': field 'point': item 1: expected a number, got true"),
    ("point-nan", _five_bar(_J3, _J3.replace("[1, 2]", "[.nan, 2]")), ".yaml",
     "joint 'J3': field 'point': item 0: expected a finite number"),
    ("point-infinity", _five_bar(_J3, _J3.replace("[1, 2]", "[1, -.inf]")), ".yaml",
     "joint 'J3': field 'point': item 1: expected a finite number"),
    ("json-nan", _slider(_JSON_J2, _JSON_J2.replace("[1, 0]", "[NaN, 0]")), ".json",
     "joint 'J2': field 'point': item 0: expected a finite number"),
    ("json-infinity", _slider(_JSON_J2, _JSON_J2.replace("[1, 0]", "[1, Infinity]")), ".json",
     "joint 'J2': field 'point': item 1: expected a finite number"),
    ("json-overflow", _slider(_JSON_J2, _JSON_J2.replace("[1, 0]", "[1e999, 0]")), ".json",
     "joint 'J2': field 'point': item 0: expected a finite number"),
    ("json-string-number", _slider(_JSON_J2, _JSON_J2.replace("[1, 0]", '["1", 0]')), ".json",
     "joint 'J2': field 'point': item 0: expected a number"),
    ("actuated-yes", _five_bar("[0, 0], actuated: true", "[0, 0], actuated: yes"), ".yaml",
     "joint 'J1': field 'actuated': expected true or false, got 'yes'"),
    ("actuated-one", _five_bar("[0, 0], actuated: true", "[0, 0], actuated: 1"), ".yaml",
     "joint 'J1': field 'actuated': expected true or false, got 1"),
    ("json-actuated-string", _slider('"actuated": true', '"actuated": "true"'), ".json",
     "joint 'J1': field 'actuated': expected true or false"),
    ("weight-negative", _five_bar("[0, 0], actuated: true", "[0, 0], actuated: true, weight: -1"),
     ".yaml", "joint 'J1': field 'weight'"),
    ("weight-string", _five_bar("[0, 0], actuated: true", "[0, 0], actuated: true, weight: heavy"),
     ".yaml", "joint 'J1': field 'weight': expected a number"),
    ("planar-zero-axis", _slider('"axis": [1, 0]', '"axis": [0, 0]'), ".json",
     "joint 'S1': field 'axis': the axis must not be zero"),
    ("spatial-zero-axis", _spatial("axis: [1, 0, 0]", "axis: [0, 0, 0]"), ".yaml",
     "joint 'P1': field 'axis': the axis must not be zero"),
    ("axis-wrong-length", _spatial("axis: [1, 0, 0]", "axis: [1, 0]"), ".yaml",
     "joint 'P1': field 'axis': expected 3 numbers, got 2"),
    ("parallel-u-axes", _spatial("axes: [[0, 0, 1], [0, 1, 0]]", "axes: [[0, 0, 1], [0, 0, -2]]"),
     ".yaml", "joint 'U1': field 'axes': the two axes of a U joint must not be parallel"),
    ("u-one-axis", _spatial("axes: [[0, 0, 1], [0, 1, 0]]", "axes: [[0, 0, 1]]"), ".yaml",
     "joint 'U1': field 'axes'"),
    ("u-axes-flat", _spatial("axes: [[0, 0, 1], [0, 1, 0]]", "axes: [0, 0, 1]"), ".yaml",
     "joint 'U1': field 'axes[0]'"),
    ("field-not-used", _spatial("{name: S1, type: S, links: [c, d], point: [1, 1, 0]}",
                                "{name: S1, type: S, links: [c, d], point: [1, 1, 0], "
                                "axis: [0, 0, 1]}"),
     ".yaml", "joint 'S1': field 'axis': not used"),
    ("spherical-point", _edit(SPHERICAL_FOUR_BAR_YAML, "axis: [1, 0, 1]}",
                              "axis: [1, 0, 1], point: [0, 0, 0]}"),
     ".yaml", "joint 'B': field 'point': not used"),
    # --- end-effector
    ("end-effector-not-mapping", _five_bar(_END_EFFECTOR, "end_effector: distal1"), ".yaml",
     "field 'end_effector': expected a mapping"),
    ("end-effector-unknown-link", _five_bar("link: distal1", "link: tool"), ".yaml",
     "end_effector: field 'link': unknown link 'tool'"),
    ("end-effector-missing-link", _five_bar("link: distal1, ", ""), ".yaml",
     "end_effector: field 'link': missing"),
    ("end-effector-unknown-output", _five_bar(_END_EFFECTOR, _END_EFFECTOR[:-1] + ", output: speed}"),
     ".yaml", "end_effector: field 'output'"),
    ("end-effector-missing-point", _five_bar(_END_EFFECTOR, "end_effector: {link: distal1}"), ".yaml",
     "end_effector: field 'point': missing"),
    ("end-effector-point-spherical", _edit(SPHERICAL_FOUR_BAR_YAML, "{link: coupler,",
                                           "{link: coupler, point: [0, 0, 1],"),
     ".yaml", "end_effector: field 'point': not used"),
    ("end-effector-unknown-key", _five_bar(_END_EFFECTOR, _END_EFFECTOR[:-1] + ", frame: tool}"),
     ".yaml", "end_effector: unknown field 'frame'"),
    # --- configurations
    ("configurations-not-mapping", FIVE_BAR_YAML + "configurations: [fig6a]\n", ".yaml",
     "field 'configurations': expected a mapping"),
    ("configuration-not-mapping", FIVE_BAR_YAML + "configurations: {fig6a: 0.5}\n", ".yaml",
     "configurations['fig6a']: expected a mapping"),
    ("configuration-unknown-joint", FIVE_BAR_YAML + "configurations: {fig6a: {J1: 0.1, J9: 0.2}}\n",
     ".yaml", "configurations['fig6a']: joint 'J9': unknown joint"),
    ("configuration-list-for-r", FIVE_BAR_YAML + "configurations: {fig6a: {J1: [0.1]}}\n", ".yaml",
     "configurations['fig6a']: joint 'J1': expected a number"),
    ("configuration-wrong-length-s", _spatial("S1: [0, 0, 0.3]", "S1: [0, 0.3]"), ".yml",
     "configurations['bent']: joint 'S1': expected 3 numbers"),
    ("configuration-number-for-u", _spatial("U1: [0.2, -0.1]", "U1: 0.2"), ".yml",
     "configurations['bent']: joint 'U1': expected a list of 2 numbers"),
    ("configuration-string", _spatial("R1: 0.1", "R1: '0.1'"), ".yml",
     "configurations['bent']: joint 'R1': expected a number, got '0.1'"),
    ("configuration-nan", _spatial("C1: [0.05, 0.01]", "C1: [0.05, .nan]"), ".yml",
     "configurations['bent']: joint 'C1': item 1: expected a finite number"),
    ("json-configuration-infinity",
     _slider('  ]\n}', '  ],\n  "configurations": {"far": {"S1": -Infinity}}\n}'), ".json",
     "configurations['far']: joint 'S1': expected a finite number"),
]


def pytest_generate_tests(metafunc):
    """Parametrize tests over the shared files.

    An argument ``malformed_case`` runs the test once per entry of
    ``MALFORMED_CASES`` (ids: the case ids); ``valid_file`` once per entry of
    ``VALID_FILES`` as ``(name, file_text, file_suffix)``.
    """
    if "malformed_case" in metafunc.fixturenames:
        metafunc.parametrize("malformed_case", MALFORMED_CASES,
                             ids=[case[0] for case in MALFORMED_CASES])
    if "valid_file" in metafunc.fixturenames:
        metafunc.parametrize("valid_file", [(name, *entry) for name, entry in VALID_FILES.items()],
                             ids=list(VALID_FILES))


@pytest.fixture
def malformed_cases():
    """The whole list ``MALFORMED_CASES``."""
    return MALFORMED_CASES


#: files of a few long tests (6-12 s in all each, measured): started early, not last, so that no worker is left
#: alone with one of them at the end of the run
_FEW_LONG_TESTS = ("tests/classify/test_report_pictures.py", "tests/classify/test_html_report_browser.py",
                   "tests/classify/test_characteristic_length_search.py", "tests/classify/test_idle_lost_directions.py")


def pytest_collection_modifyitems(items):
    """Order the run for ``pytest -n auto --dist loadfile`` (with ``--no-loadscope-reorder``): the docs build
    (``tests/test_docs.py``, the longest single test) first, so one worker starts it while the other takes the
    rest; then the files of a few long tests (:data:`_FEW_LONG_TESTS`), then the others by decreasing number of
    tests (xdist's own default order), each file's tests in their own order."""
    by_file = {}
    for item in items:
        by_file.setdefault(item.nodeid.split("::")[0], []).append(item)
    files = sorted(by_file, key=lambda name: (not name.endswith("tests/test_docs.py"),
                                              not name.endswith(_FEW_LONG_TESTS), -len(by_file[name])))
    items[:] = [item for name in files for item in by_file[name]]
