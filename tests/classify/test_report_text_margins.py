"""The text report never shows a margin the wrong way round, and no kept entry of a direction as ±0.000.

An audit found the five-bar at 1998 eq. 3c's stretched left leg moved to θ2 = 1.3987903447198047 printed
``[smallest kept σ = 1.39e-05; cut 1.4e-05]`` for a regular end-effector (σ = 1.3940e-05 above the cut
1.3928e-05): the value with 3 significant digits, the cut with 2. And kernel entries between 1e-6 (kept) and
5e-4 printed as ``+0.000`` beside the entries left out as zero.
"""

import re

import numpy as np
import pytest

from classify import classify
from classify.report import _apart, _format_direction
from mechanisms.catalogue import entry


def test_the_audits_five_bar_prints_its_kept_value_above_its_cut():
    # kept σ within 2e-8 of the cut (theta2 moved from the audit's 1.3987903447198047 when the end-effector's
    # reference scale became every joint's rate, independent of the joints' order)
    mechanism = entry("five-bar").mechanism("eq3c_left_leg_stretched", theta2=1.3987916846028936)
    from mechanisms import home

    report = classify(mechanism, home(mechanism))
    assert not report.end_effector.singular
    line = next(line for line in report.to_text().splitlines() if line.strip().startswith("end-effector"))
    kept, cut = map(float, re.search(r"smallest kept σ = (\S+); cut (\S+)\]", line).groups())
    assert kept > cut


@pytest.mark.parametrize("seed", range(5))
def test_printed_values_keep_their_order_with_the_cut(seed):
    rng = np.random.default_rng(seed)
    for cut in 10.0 ** rng.uniform(-16, 2, 200):
        kept = cut * (1 + 10.0 ** rng.uniform(-15, 0))
        dropped = cut * (1 - 10.0 ** rng.uniform(-15, 0))
        shown_cut, shown_kept, shown_dropped = _apart(cut, kept, dropped)
        assert float(shown_kept) > float(shown_cut) >= float(shown_dropped), (cut, kept, dropped)
    assert _apart(1e-6, 0.0334, None) == ("1.0e-06", "0.0334", None)   # the usual case: unchanged


def test_small_kept_entries_of_a_direction_are_not_shown_as_zero():
    text = _format_direction({"U2[2]": 3.3e-05, "S2[z]": -0.000297, "J1": 0.707})
    assert text == "U2[2] +3.30e-05, S2[z] -2.97e-04, J1 +0.707"


def test_a_kind_without_singular_values_says_so():
    """A four-bar made a structure (dof 0) printed ``[; cut 1.0e-06]`` for its actuator."""
    from mechanisms import Joint, Mechanism, home

    triangle = Mechanism("triangle", "planar", [
        Joint("A", "R", ("ground", "one"), point=(0, 0), actuated=True),
        Joint("B", "R", ("one", "two"), point=(1, 0)),
        Joint("C", "R", ("two", "ground"), point=(0, 1))])
    line = next(line for line in classify(triangle, home(triangle)).to_text().splitlines()
                if line.strip().startswith("actuator"))
    assert "[no singular values; cut " in line
