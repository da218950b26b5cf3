"""Classification of closed-chain singularities (Park & Kim) and their metrics.

Metrics E, G, H and manipulability proper values; the three kinds of
singularity with their expected ranks; the second-order test for actuator
singularities; reports. Imports :mod:`mechanisms` and :mod:`manifold`.
"""

from .classification import classify, classify_many
from .comparison import (
    REASONS, Comparison, ComparisonRow, compare, comparison_row, correspondence, expected_kinds, sample_configurations,
)
from .gosselin_angeles import (
    GA_KINDS, GosselinAngeles, InputOutputRelation, derived_gosselin_angeles, gosselin_angeles,
    kinds_of_matrices, relation_from_callables, relation_from_sympy,
)
from .metrics import (
    Manipulability, actuator_metric, end_effector_metric, manipulability,
    metric_root, pullback_metric, weighted_actuator_jacobian,
)
from .model import Model, joint_output_model, model_of
from .paths import path_configurations, singular_crossings
from .report import KINDS, KindResult, Report
from .higher_order import HigherOrderResult, higher_order_test
from .second_order import SECOND_ORDER_RTOL, SecondOrderResult, SelfMotion, fibre, second_order_test
from .survey import Survey, survey

__all__ = [
    "classify", "classify_many",
    "REASONS", "Comparison", "ComparisonRow", "compare", "comparison_row", "correspondence", "expected_kinds",
    "sample_configurations", "path_configurations", "singular_crossings",
    "GA_KINDS", "GosselinAngeles", "InputOutputRelation", "derived_gosselin_angeles", "gosselin_angeles",
    "kinds_of_matrices", "relation_from_callables", "relation_from_sympy",
    "Manipulability", "actuator_metric", "end_effector_metric", "manipulability",
    "metric_root", "pullback_metric", "weighted_actuator_jacobian",
    "Model", "joint_output_model", "model_of",
    "KINDS", "KindResult", "Report",
    "SECOND_ORDER_RTOL", "SecondOrderResult", "SelfMotion", "fibre", "second_order_test",
    "HigherOrderResult", "higher_order_test",
    "Survey", "survey",
]
