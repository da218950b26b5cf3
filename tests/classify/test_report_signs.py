"""The sign of a reported direction (a kernel vector, a root, a self-motion) does not hang on rounding.

A direction is reported up to sign, made positive at its entry of largest magnitude. Where entries tie (the
slider-crank at sin θ = l/R, Park & Kim 1999 Fig. 3b: ker G spans (J2, J3, S1) ∝ (1, −1, −1)/√3 in the
dimensionless metric), a bare argmax let the last bit of the SVD pick the entry, and so the printed sign.
"""

import numpy as np
import pytest

from classify import classify
from classify.report import _named
from mechanisms import EndEffector, Joint, Mechanism, home


def slider_crank(angle=0.0, offset=(0.0, 0.0)):
    """Crank 2, rod 1, at sin θ = l/R, its base frame turned by `angle` and moved by `offset`."""
    turn = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])

    def placed(point):
        return tuple(turn @ np.asarray(point, dtype=float) + offset)

    root = np.sqrt(3.0)
    return Mechanism("slider-crank", "planar", [
        Joint("J1", "R", ("ground", "crank"), point=placed((0, 0)), actuated=True),
        Joint("J2", "R", ("crank", "rod"), point=placed((root, 1))),
        Joint("J3", "R", ("rod", "block"), point=placed((root, 0))),
        Joint("S1", "P", ("block", "ground"), axis=tuple(turn @ (1.0, 0.0)))],
        end_effector=EndEffector("block", placed((root, 0)), "position"))


def test_tied_entries_give_the_first_of_them_positive_whatever_their_last_bits():
    names = ["J1", "J2", "J3", "S1"]
    third = 1 / np.sqrt(3.0)
    expected = {"J2": 0.57735, "J3": -0.57735, "S1": -0.57735}
    for ulps in [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (-1, 2, 3)]:
        vector = np.array([0.0] + [third * (1 + 2.2e-16 * ulp) for ulp in ulps]) * (1, 1, -1, -1)
        assert _named(vector, names) == expected
        assert _named(-vector, names) == expected
    assert _named(np.array([0.0, 0.6, -0.8, 0.0]), names) == {"J2": -0.6, "J3": 0.8}  # no tie: the largest


@pytest.mark.parametrize("angle, offset", [(0.0, (0.0, 0.0)), (0.3, (0.0, 0.0)), (1.1, (2.0, -5.0)),
                                           (2.9, (40.0, 7.0)), (-0.7, (-3.0, 0.5))])
def test_the_kernel_of_g_is_reported_with_one_sign_in_every_base_frame(angle, offset):
    mechanism = slider_crank(angle, offset)
    report = classify(mechanism, home(mechanism)).to_dict()
    assert report["actuator"]["kernel"] == [{"J2": 0.57735, "J3": -0.57735, "S1": -0.57735}]
