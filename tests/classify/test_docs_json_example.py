"""The JSON object printed in docs/cli.rst ("The JSON object") is what ``closedchain classify`` prints.

The example had gone stale (its survey margins were those of an older survey) with nothing to notice: the
slider-crank of docs/second_order.rst (R = 2, l = 1) at sin θ = l/R, an end-effector on the slider, is written
here, classified, and every field of the page's object compared with the output (numbers to the digits printed).
"""

import contextlib
import io
import json
import math
import re
from pathlib import Path

from classify.cli import main

PAGE = Path(__file__).resolve().parents[2] / "docs" / "cli.rst"
MECHANISM = """name: slider-crank
space: planar
joints:
  - {name: J1, type: R, links: [ground, crank], point: [0, 0], actuated: true}
  - {name: J2, type: R, links: [crank, rod], point: [1.7320508075688772, 1]}
  - {name: J3, type: R, links: [rod, block], point: [1.7320508075688772, 0]}
  - {name: S1, type: P, links: [block, ground], axis: [1, 0]}
end_effector: {link: block, point: [1.7320508075688772, 0]}
"""


def page_example():
    """The first ``.. code-block:: json`` after the heading "The JSON object"."""
    text = PAGE.read_text(encoding="utf-8")
    section = text[text.index("The JSON object\n---------------"):]
    block = re.search(r"\.\. code-block:: json\n\n((?:   .*\n|\n)+)", section).group(1)
    return json.loads(block)


def differences(documented, actual, path="$"):
    """Where `actual` differs from `documented` (every documented key present, numbers within one unit of the last
    digit printed, values printed below 1e-12 as rounding: below 1e-12 too)."""
    if isinstance(documented, dict):
        if not isinstance(actual, dict):
            return [path]
        return [found for key, value in documented.items()
                for found in (differences(value, actual[key], f"{path}.{key}") if key in actual else [f"{path}.{key}"])]
    if isinstance(documented, list):
        if not isinstance(actual, list) or len(actual) != len(documented):
            return [path]
        return [found for index, pair in enumerate(zip(documented, actual))
                for found in differences(*pair, f"{path}[{index}]")]
    if isinstance(documented, float) and not isinstance(actual, bool) and isinstance(actual, (int, float)):
        if abs(documented) < 1e-12:
            return [] if abs(actual) < 1e-12 else [path]
        digits = len(re.sub(r"[^0-9]", "", f"{documented:e}".split("e")[0].rstrip("0"))) or 1
        unit = 10.0 ** (math.floor(math.log10(abs(documented))) - digits + 1)   # one in the last digit printed
        return [] if abs(documented - actual) <= unit else [f"{path}: {documented} vs {actual}"]
    return [] if documented == actual else [f"{path}: {documented!r} vs {actual!r}"]


def test_the_pages_json_object_is_the_commands(tmp_path):
    path = tmp_path / "slider-crank.yaml"
    path.write_text(MECHANISM, encoding="utf-8")
    out = io.StringIO()
    with contextlib.redirect_stderr(io.StringIO()):
        status = main(["classify", str(path), "--format", "json"], out=out)
    assert status == 0
    assert differences(page_example(), json.loads(out.getvalue())) == []
