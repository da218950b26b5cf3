"""Classification of closed-chain singularities (Park & Kim) and their metrics.

Metrics E, G, H and manipulability proper values; the three kinds of
singularity with their expected ranks; the second-order test for actuator
singularities; batches of configurations; reports. Imports :mod:`mechanisms`
and :mod:`manifold`.

The names below are imported on first use (PEP 562), so that importing a
light submodule (the command line's, :mod:`classify.text`) does not import
SymPy or SciPy: ``from classify import classify`` works as usual.
"""

from manifold._lazy import attach

#: exported name → the submodule that defines it (imported when the name is first used)
_SOURCES = {
    "classify": ".classification",
    "classify_many": ".batch", "Classifications": ".batch",
    **dict.fromkeys(("REASONS", "Comparison", "ComparisonRow", "compare", "comparison_row", "correspondence",
                     "expected_kinds", "sample_configurations"), ".comparison"),
    **dict.fromkeys(("GA_KINDS", "GosselinAngeles", "InputOutputRelation", "derived_gosselin_angeles",
                     "gosselin_angeles", "kinds_of_matrices", "relation_from_callables", "relation_from_sympy",
                     "variable_scales"),
                    ".gosselin_angeles"),
    **dict.fromkeys(("Manipulability", "actuator_metric", "end_effector_metric", "manipulability", "metric_root",
                     "pullback_metric", "weighted_actuator_jacobian"), ".metrics"),
    **dict.fromkeys(("Model", "joint_output_model", "model_of"), ".model"),
    **dict.fromkeys(("Crossing", "NoPathError", "follow_path", "path_configurations", "singular_crossings"),
                    ".paths"),
    **dict.fromkeys(("KINDS", "KindResult", "Report"), ".report"),
    **dict.fromkeys(("HigherOrderResult", "higher_order_test"), ".higher_order"),
    **dict.fromkeys(("SECOND_ORDER_RTOL", "SecondOrderResult", "SelfMotion", "fibre", "second_order_test"),
                    ".second_order"),
    **dict.fromkeys(("Survey", "survey", "survey_of"), ".survey"),
}

__getattr__, __dir__, __all__ = attach(__name__, _SOURCES)
