"""A stack of configurations classified at once equals one at a time (shared survey)."""

import numpy as np

from builders import five_bar, five_bar_positions
from classify import classify, classify_many, model_of, survey
from manifold import project
from mechanisms import configuration_space, home, kinematics_of


def test_classify_many_equals_single_calls():
    mechanism = five_bar(five_bar_positions(1.2, 2.0))
    manifold = configuration_space(mechanism)
    space = kinematics_of(mechanism).ambient
    rng = np.random.default_rng(30)
    points = np.array([project(manifold, space.retract(home(mechanism), 0.3 * rng.standard_normal(5)))
                       for _ in range(4)]).reshape(2, 2, -1)
    shared = survey(model_of(mechanism), np.random.default_rng(31))
    batched = classify_many(mechanism, points, survey=shared, rng=np.random.default_rng(32))
    singles = [classify(mechanism, point, survey=shared, rng=np.random.default_rng(32))
               for point in points.reshape(-1, points.shape[-1])]
    assert len(batched) == 4
    for many, one in zip(batched, singles):
        assert many.to_dict()["kinds"] == one.to_dict()["kinds"]
        np.testing.assert_allclose(many.manipulability.eigenvalues, one.manipulability.eigenvalues, rtol=1e-12)
        assert many.actuator.rank == one.actuator.rank and many.end_effector.rank == one.end_effector.rank
