"""The Gosselin–Angeles matrices A = ∂F/∂x, B = ∂F/∂θ and their kinds I, II, III.

Gosselin & Angeles (1990, eqs. 1–5) relate n inputs θ
(actuated coordinates) and n outputs x by F(θ, x) = 0, so that
``A ẋ + B θ̇ = 0`` (eq. 2) with ``A = ∂F/∂x`` and ``B = ∂F/∂θ`` (eq. 3):

* kind I:   det B = 0 (eq. 4), branches of the inverse problem meet;
* kind II:  det A = 0 (eq. 5), branches of the direct problem meet;
* kind III: both, here reported as ``("I", "II", "III")``, since the
  conditions of kinds I and II both hold.

The matrices come from a user's F (:func:`relation_from_sympy`,
:func:`relation_from_callables`) or are derived from a mechanism
(:func:`derived_gosselin_angeles`): at p ∈ M with an orthonormal basis T of
T_pM, the velocities the mechanism allows are
``V = {(Dπ T u, J u)} ⊂ ℝⁿ × ℝⁿ`` and the rows of ``[B A]`` span the
annihilator of V. That annihilator has dimension n exactly when
``dim V = n``; otherwise (C-space singularities, uncontrolled freedoms,
redundant actuation, a motion moving neither inputs nor outputs) G–A is not
defined at p and the result says why.

Rank decisions (scale-aware, :func:`manifold.numerical_rank`): the columns of
``[B A]`` are first multiplied by the scales of their variables (below), the
rows then normalised to unit length and, where they have rank n, replaced by
an orthonormal basis of their span. Row operations change neither det A = 0
nor det B = 0, and after them the singular values of A and B do not depend on
how F's rows were scaled or combined (for the derived matrices: on the basis
T). The cut is ``rtol`` against 1, the norm of ``[B A]``.

Units. The entry ``∂Fᵢ/∂vⱼ`` of ``[B A]`` (eq. 3) carries the unit of Fᵢ over
that of the variable vⱼ (a leg length, a position, an angle), so one row
mixes units and its normalisation would depend on the unit of length: the
slider-crank's eq. 12 at its fold (eq. 14) was kind II in metres and regular
in millimetres. A relation declares the kind of each variable
(:attr:`InputOutputRelation.units`: ``"length"`` or ``"angle"``), and each
variable's scale σⱼ is then the mechanism's characteristic length for a
length and 1 for an angle (:func:`variable_scales`, the scales of
:mod:`manifold.implicit`'s dimensionless coordinates); the decisions are
taken on ``∂Fᵢ/∂vⱼ · σⱼ``, whose row i has the one unit of Fᵢ: a change of
the unit of length multiplies σⱼ and divides column j by the same factor, so
it changes no decision. Without scales the columns are taken as given (the
caller's units).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np
import sympy

from manifold import DEFAULT_RTOL, RankDecision, numerical_rank

from .metrics import metric_root
from .survey import decision_blocks, stacked as stacked_rows

__all__ = [
    "GA_KINDS", "InputOutputRelation", "GosselinAngeles",
    "relation_from_sympy", "relation_from_callables", "variable_scales",
    "kinds_of_matrices", "gosselin_angeles", "derived_gosselin_angeles",
]

#: the kinds of Gosselin & Angeles, in order
GA_KINDS = ("I", "II", "III")


@dataclass(frozen=True, eq=False)
class InputOutputRelation:
    """An input–output relation F(θ, x) = 0 with its Jacobians (G–A eqs. 1–3).

    Attributes
    ----------
    name : str
    input_names, output_names : tuple of str
        θ and x, n of each.
    jacobians : callable
        ``jacobians(inputs, outputs) -> (B, A)`` for arrays of shape [n]:
        ``B = ∂F/∂θ`` and ``A = ∂F/∂x``, each shape=[n, n].
    residual : callable, optional
        ``residual(inputs, outputs) -> F``, shape=[n]; None when only the
        velocity relation (the paper's A and B) is known.
    reference : str
        Where the relation comes from (paper, equation).
    units : tuple of str, optional
        The kind of each variable, θ then x: ``"length"`` or ``"angle"`` (module doc, "Units"); None: unknown,
        the columns of ``[B A]`` are taken in the caller's units.
    """

    name: str
    input_names: tuple
    output_names: tuple
    jacobians: Callable
    residual: Optional[Callable] = None
    reference: str = ""
    units: Optional[tuple] = None

    def __post_init__(self):
        if len(self.input_names) != len(self.output_names):
            raise ValueError(f"relation {self.name!r}: {len(self.input_names)} inputs but "
                             f"{len(self.output_names)} outputs; Gosselin–Angeles needs n of each")
        if self.units is not None and (len(self.units) != 2 * self.n
                                       or not set(self.units) <= {"length", "angle"}):
            raise ValueError(f"relation {self.name!r}: units must be {2 * self.n} of 'length' or 'angle' (θ then "
                             f"x), got {self.units!r}")

    @property
    def n(self):
        return len(self.input_names)


def _symbols(values, what):
    symbols = tuple(values)
    for symbol in symbols:
        if not isinstance(symbol, sympy.Symbol):
            raise TypeError(f"{what}: expected SymPy symbols, got {symbol!r}")
    return symbols


def _lambdified(matrix, arguments):
    """A numpy function of ``arguments`` returning `matrix` as a float array (constants included)."""
    function = sympy.lambdify(arguments, matrix, modules="numpy")

    def evaluate(*values):
        with np.errstate(all="ignore"):
            return np.asarray(function(*values), dtype=float)
    return evaluate


def _parameter_value(symbol, value):
    """A parameter as a SymPy number; text is refused (never parsed)."""
    if isinstance(value, sympy.Basic):
        return value
    if isinstance(value, (bool, str)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"parameter {symbol}: expected a number or a SymPy expression, got {value!r}")
    return sympy.Integer(int(value)) if isinstance(value, (int, np.integer)) else sympy.Float(float(value))


def relation_from_sympy(inputs, outputs, equations=None, input_jacobian=None, output_jacobian=None,
                        parameters=None, name="F", reference="", units=None):
    """A relation from SymPy expressions: F itself, or the paper's A and B directly.

    Give either `equations` (F; A and B are its symbolic derivatives, eq. 3)
    or both `input_jacobian` (B) and `output_jacobian` (A), as the paper
    writes them when only the velocity relation ``A ẋ + B θ̇ = 0`` is printed
    (e.g. eqs. 12, 44–48, 68–69, 81–83). Expressions are evaluated with
    :func:`sympy.lambdify`; no text is ever parsed.

    Parameters
    ----------
    inputs, outputs : sequence of sympy.Symbol
        θ and x, n of each.
    equations : sequence of sympy.Expr, optional
        F, n expressions.
    input_jacobian, output_jacobian : sympy.Matrix, optional
        B and A, each n×n.
    parameters : dict, optional
        ``{symbol: value}`` substituted before evaluation (link lengths, branch signs).
    name, reference : str
    units : sequence of str, optional
        ``"length"`` or ``"angle"`` per variable, θ then x (:attr:`InputOutputRelation.units`).

    Returns
    -------
    InputOutputRelation

    Raises
    ------
    ValueError
        If the expressions contain a symbol that is neither an input, an
        output nor a parameter, or if the shapes do not match.

    Examples
    --------
    The slider-crank as Gosselin & Angeles write it (eq. 9, '+' branch):

    >>> import sympy
    >>> from classify import gosselin_angeles, relation_from_sympy
    >>> theta, x = sympy.symbols("theta x")
    >>> R, l = 1.0, 2.0
    >>> relation = relation_from_sympy(
    ...     [theta], [x], equations=[x - R * sympy.cos(theta) - l * sympy.sqrt(1 - (R / l) ** 2 * sympy.sin(theta) ** 2)])
    >>> gosselin_angeles(relation, [0.0], [3.0]).kinds
    ('I',)
    """
    inputs, outputs = _symbols(inputs, "inputs"), _symbols(outputs, "outputs")
    parameters = dict(parameters or {})
    if equations is not None:
        if input_jacobian is not None or output_jacobian is not None:
            raise ValueError("give either the equations F or the Jacobians A and B, not both")
        residual = sympy.Matrix(list(equations))
        input_jacobian, output_jacobian = residual.jacobian(inputs), residual.jacobian(outputs)
    elif input_jacobian is None or output_jacobian is None:
        raise ValueError("give the equations F, or both Jacobians A (output_jacobian) and B (input_jacobian)")
    else:
        residual = None
    input_jacobian, output_jacobian = sympy.Matrix(input_jacobian), sympy.Matrix(output_jacobian)
    n = len(inputs)
    for label, matrix in (("input_jacobian (B)", input_jacobian), ("output_jacobian (A)", output_jacobian)):
        if matrix.shape != (n, len(outputs)) or n != len(outputs):
            raise ValueError(f"{label}: expected shape ({n}, {n}) for {n} inputs and {len(outputs)} outputs, "
                             f"got {matrix.shape}")
    known = set(inputs) | set(outputs) | set(parameters)
    pieces = [input_jacobian, output_jacobian] + ([residual] if residual is not None else [])
    unknown = set().union(*(piece.free_symbols for piece in pieces)) - known
    if unknown:
        raise ValueError(f"relation {name!r}: symbols {sorted(map(str, unknown))} are neither inputs, outputs "
                         f"nor parameters")
    arguments = (list(inputs), list(outputs))
    values = {symbol: _parameter_value(symbol, value) for symbol, value in parameters.items()}
    evaluate_b = _lambdified(input_jacobian.xreplace(values), arguments)
    evaluate_a = _lambdified(output_jacobian.xreplace(values), arguments)
    evaluate_f = None if residual is None else _lambdified(residual.xreplace(values), arguments)

    def jacobians(theta, x):
        return evaluate_b(list(theta), list(x)), evaluate_a(list(theta), list(x))

    def residual_function(theta, x):
        return evaluate_f(list(theta), list(x)).reshape(-1)

    return InputOutputRelation(name, tuple(map(str, inputs)), tuple(map(str, outputs)), jacobians,
                               None if residual is None else residual_function, reference,
                               None if units is None else tuple(units))


def relation_from_callables(input_names, output_names, input_jacobian, output_jacobian, residual=None,
                            name="F", reference="", units=None):
    """A relation from Python callables: ``B(θ, x)``, ``A(θ, x)`` and optionally ``F(θ, x)``.

    Parameters
    ----------
    input_names, output_names : sequence of str
    input_jacobian, output_jacobian : callable
        ``(theta, x) -> array, shape=[n, n]``, theta and x of shape [n].
    residual : callable, optional
        ``(theta, x) -> array, shape=[n]``.
    name, reference : str
    units : sequence of str, optional
        ``"length"`` or ``"angle"`` per variable, θ then x (:attr:`InputOutputRelation.units`).

    Returns
    -------
    InputOutputRelation
    """
    def jacobians(theta, x):
        return (np.asarray(input_jacobian(theta, x), dtype=float),
                np.asarray(output_jacobian(theta, x), dtype=float))
    return InputOutputRelation(name, tuple(input_names), tuple(output_names), jacobians,
                               residual, reference, None if units is None else tuple(units))


def variable_scales(relation, length):
    """The scale σ of each of the relation's variables, θ then x: `length` for a length, 1 for an angle.

    Parameters
    ----------
    relation : InputOutputRelation
    length : float
        The mechanism's characteristic length (:attr:`mechanisms.Mechanism.characteristic_length`).

    Returns
    -------
    ndarray, shape=[2n], or None
        None where the relation declares no units.
    """
    if relation.units is None:
        return None
    return np.array([float(length) if unit == "length" else 1.0 for unit in relation.units])


@dataclass(frozen=True, eq=False)
class GosselinAngeles:
    """The G–A classification of one configuration.

    Attributes
    ----------
    n : int
        Number of inputs (and of outputs).
    input_jacobian, output_jacobian : ndarray, shape=[n, n], or None
        B and A as given (or derived); None where undefined.
    input_decision, output_decision : RankDecision or None
        Rank decisions of B and A after the row normalisation (module doc).
    relation_decision : RankDecision or None
        Rank decision of the normalised ``[B A]`` (n for a relation that is
        a submersion; below n for a degenerate F).
    undefined : str or None
        Why G–A is not defined here: ``"not_square"`` (inputs ≠ outputs in
        number), ``"not_finite"`` (A or B not finite: F not differentiable),
        ``"not_differentiable"`` (A and B jump across the point: a kink of F),
        ``"subspace_dimension"`` (derived: the annihilator of V does not have
        dimension n), else None.
    detail : str
        A sentence for the reader.
    velocity_dimension : int or None
        dim V for derived matrices.
    variable_scales : ndarray, shape=[2n], or None
        The scales σ of θ then x that the columns of ``[B A]`` were
        multiplied by before the decisions (module doc); None: as given.
    """

    n: int
    input_jacobian: Optional[np.ndarray]
    output_jacobian: Optional[np.ndarray]
    input_decision: Optional[RankDecision]
    output_decision: Optional[RankDecision]
    relation_decision: Optional[RankDecision]
    undefined: Optional[str] = None
    detail: str = ""
    velocity_dimension: Optional[int] = None
    variable_scales: Optional[np.ndarray] = None

    @property
    def defined(self):
        return self.undefined is None

    @property
    def rank_A(self):
        return None if self.output_decision is None else self.output_decision.rank

    @property
    def rank_B(self):
        return None if self.input_decision is None else self.input_decision.rank

    @property
    def kinds(self):
        """A subset of ``("I", "II", "III")``; empty where regular or undefined."""
        if not self.defined:
            return ()
        first, second = self.rank_B < self.n, self.rank_A < self.n
        return tuple(kind for kind, holds in zip(GA_KINDS, (first, second, first and second)) if holds)

    @property
    def label(self):
        """``"I, II, III"``-style kinds, ``"regular"`` or ``"undefined"``, for tables."""
        return (", ".join(self.kinds) or "regular") if self.defined else "undefined"

    def to_dict(self):
        """``kinds``, ``rank_A``, ``rank_B``, ``n`` (the contract of ``closedchain compare``) and details."""
        def decision(value):
            return None if value is None else value.to_dict()

        def matrix(value):  # JSON has no inf or nan: a non-finite entry is null
            if value is None:
                return None
            return [[float(entry) if np.isfinite(entry) else None for entry in row]
                    for row in np.asarray(value, dtype=float)]
        return {
            "kinds": list(self.kinds), "rank_A": self.rank_A, "rank_B": self.rank_B, "n": int(self.n),
            "defined": self.defined, "undefined": self.undefined, "detail": self.detail,
            "A": matrix(self.output_jacobian), "B": matrix(self.input_jacobian),
            "A_decision": decision(self.output_decision), "B_decision": decision(self.input_decision),
            "relation_decision": decision(self.relation_decision),
            "velocity_dimension": self.velocity_dimension,
            "variable_scales": None if self.variable_scales is None else [float(value) for value in
                                                                          self.variable_scales],
        }


def _undefined(n, reason, detail, velocity_dimension=None):
    return GosselinAngeles(n, None, None, None, None, None, reason, detail, velocity_dimension)


def _variable_scales(variable_scales, n):
    """`variable_scales` as a float array of shape [2n] (finite, positive), or None."""
    if variable_scales is None:
        return None
    scales = np.asarray(variable_scales, dtype=float)
    if scales.shape != (2 * n,) or not np.all(np.isfinite(scales) & (scales > 0)):
        raise ValueError(f"variable_scales: expected {2 * n} finite positive scales (θ then x), got "
                         f"{np.array2string(scales, precision=3)}")
    return scales


def kinds_of_matrices(input_jacobian, output_jacobian, rtol=DEFAULT_RTOL, row_scales=None, variable_scales=None):
    """Classify given matrices B (∂F/∂θ) and A (∂F/∂x), eqs. 4–5.

    Parameters
    ----------
    input_jacobian, output_jacobian : array_like, shape=[n, n]
        B and A.
    rtol : float
        Relative cut of the rank decisions (module doc).
    row_scales : array_like, shape=[n], optional
        Reference size of each row of ``[B A] · diag(variable_scales)`` (e.g.
        its largest norm near the configuration). Rows are divided by it, so a
        row that vanishes here (F = g², or F = g·h with g = h = 0) is seen as
        zero. Default: each row's own norm (a row that is exactly zero stays
        zero).
    variable_scales : array_like, shape=[2n], optional
        The scale σ of each variable, θ then x, in its own unit (module doc,
        "Units"): column j of ``[B A]`` is multiplied by σⱼ before the
        decisions, so that they depend on no variable's unit. Default: 1 (the
        columns as given).

    Returns
    -------
    GosselinAngeles

    Raises
    ------
    ValueError
        If `variable_scales` is not 2n finite positive numbers.
    """
    b = np.atleast_2d(np.asarray(input_jacobian, dtype=float))
    a = np.atleast_2d(np.asarray(output_jacobian, dtype=float))
    n = b.shape[0]
    if b.shape != (n, n) or a.shape != (n, n):
        return _undefined(n, "not_square", f"B has shape {b.shape} and A {a.shape}: G–A needs n×n matrices")
    scales = _variable_scales(variable_scales, n)
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        return GosselinAngeles(n, b, a, None, None, None, "not_finite",
                               "A or B is not finite here: F is not differentiable (a branch point of its "
                               "roots, eq. 9's ±√)", variable_scales=scales)
    rows = np.hstack([b, a]) if scales is None else np.hstack([b, a]) * scales
    lengths = np.linalg.norm(rows, axis=1) if row_scales is None else np.asarray(row_scales, dtype=float)
    normalised = rows / np.where(lengths > 0, lengths, 1.0)[:, None]
    relation = numerical_rank(normalised, rtol=rtol, scale=1.0)
    if relation.rank == n:
        normalised = np.linalg.svd(normalised, full_matrices=False)[2][:n]
    detail = "" if relation.rank == n else (f"[B A] has rank {relation.rank} < {n}: F's differential is "
                                            f"degenerate, so det A = det B = 0")
    return GosselinAngeles(n, b, a, numerical_rank(normalised[:, :n], rtol=rtol, scale=1.0),
                           numerical_rank(normalised[:, n:], rtol=rtol, scale=1.0), relation, None, detail,
                           variable_scales=scales)


#: relative step of the variables when sizing the rows of a given F, and when testing that its
#: derivative is continuous (:func:`gosselin_angeles`): a variable moves by this times its scale
VARIABLE_STEP = 1e-2
#: how many times the kink test divides the step by 10 (:func:`gosselin_angeles`): from VARIABLE_STEP down
#: to VARIABLE_STEP · 10⁻⁶ = 10⁻⁸ times each variable's scale, the resolution at which a kink counts as here
KINK_LEVELS = 6


def _rows_around(relation, variables, n, steps):
    """Rows of [B A] at each variable moved by ``± steps[index]``, shape=[2 · 2n, n, 2n]."""
    rows = []
    for index in range(len(variables)):
        for sign in (-1.0, 1.0):
            moved = variables.copy()
            moved[index] += sign * steps[index]
            with np.errstate(all="ignore"):
                rows.append(np.hstack(relation.jacobians(moved[:n], moved[n:])))
    return np.array(rows)


def _jumps(rows, columns):
    """The change of each row of ``[B A] · diag(columns)`` from − to + of each variable, shape=[2n, n]."""
    return np.linalg.norm((rows[1::2] - rows[0::2]) * columns, axis=-1)


def _kinked(relation, variables, n, steps, far, columns):
    """Whether [B A] jumps across the point: its change over ± h does not shrink with h, down to a fine h.

    For a differentiable F the rows at ±h differ by O(h); where F has a kink
    (‖w‖ at w = 0) they differ by O(1) however small h. A kink at a distance
    d from the point looks the same for h > d only: below d the change
    shrinks like h. So h goes from `steps` down by factors of 10,
    :data:`KINK_LEVELS` times, and F is kinked here if, for one row and one
    variable, the change over ± h is more than a tenth of the row's size at
    the first step and more than half the previous one at every step; a
    kink farther than ``steps · 10⁻⁶`` from the point is not one here (a leg
    of length 10⁻³ is no kink of ``c − ‖w‖``). Rows that are not finite at a
    finer step end the test (no kink is claimed).

    Parameters
    ----------
    relation : InputOutputRelation
    variables : ndarray, shape=[2n]
        θ then x.
    n : int
    steps : ndarray, shape=[2n]
        The first step of each variable.
    far : ndarray, shape=[2 · 2n, n, 2n]
        :func:`_rows_around` at `steps` (finite).
    columns : ndarray, shape=[2n]
        Scales of the columns of ``[B A]`` (module doc, "Units").

    Returns
    -------
    bool
    """
    previous = _jumps(far, columns)
    size = np.max(np.linalg.norm(far * columns, axis=-1), axis=0)
    with np.errstate(all="ignore"):
        candidates = previous > 0.1 * size
    for level in range(1, KINK_LEVELS + 1):
        if not np.any(candidates):
            return False
        near = _rows_around(relation, variables, n, steps / 10.0 ** level)
        if not np.all(np.isfinite(near)):
            return False
        jump = _jumps(near, columns)
        with np.errstate(all="ignore"):
            candidates &= jump > 0.5 * previous
        previous = jump
    return bool(np.any(candidates))


def gosselin_angeles(relation, inputs, outputs, rtol=DEFAULT_RTOL, row_scales=None, variable_scales=None):
    """Classify one configuration (θ, x) with a given relation F (eqs. 3–5).

    Each row of ``[B A]`` (columns times `variable_scales`, module doc) is
    measured against its size around (θ, x): its largest norm there and with
    each variable moved by ``± VARIABLE_STEP · σ`` (off M; σ its scale, or
    ``1 + |value|`` without scales), so that a row which vanishes at (θ, x),
    or on the whole branch of M through it (F written with squared or
    factored terms), counts as zero. Where A or B is not finite, or, for a
    relation given by F, ``[B A]`` jumps across (θ, x) (its change over ± h
    does not shrink as h goes down from that step to 10⁻⁶ of it,
    :func:`_kinked`: a kink of F such as ‖w‖ at w = 0), F is not
    differentiable and G–A is undefined. (A velocity relation, the paper's A
    and B without F, may have kinks: eq. 12's A = √(1 − sin² θ) at R = l.)

    Parameters
    ----------
    relation : InputOutputRelation
    inputs, outputs : array_like, shape=[n]
        θ and x.
    rtol : float
    row_scales : array_like, shape=[n], optional
        Sizes of the rows (default: measured around (θ, x) as above); see
        :func:`kinds_of_matrices`.
    variable_scales : array_like, shape=[2n], optional
        Scale of each variable, θ then x, in its unit
        (:func:`variable_scales`); with them no decision depends on the unit
        of length. Default: the columns as
        given, steps ``VARIABLE_STEP · (1 + |value|)``.

    Returns
    -------
    GosselinAngeles

    Raises
    ------
    ValueError
        If θ or x does not have n entries, or `variable_scales` is not 2n finite positive numbers.
    """
    inputs, outputs = np.asarray(inputs, dtype=float), np.asarray(outputs, dtype=float)
    if inputs.shape != (relation.n,) or outputs.shape != (relation.n,):
        raise ValueError(f"relation {relation.name!r}: expected {relation.n} inputs and outputs, got shapes "
                         f"{inputs.shape} and {outputs.shape}")
    scales = _variable_scales(variable_scales, relation.n)
    b, a = relation.jacobians(inputs, outputs)
    if row_scales is None and np.all(np.isfinite(b)) and np.all(np.isfinite(a)):
        variables = np.concatenate([inputs, outputs])
        columns = np.ones(2 * relation.n) if scales is None else scales
        steps = VARIABLE_STEP * ((1.0 + np.abs(variables)) if scales is None else scales)
        far = _rows_around(relation, variables, relation.n, steps)
        finite = np.where(np.isfinite(far), far, 0.0)
        row_scales = np.max(np.concatenate([np.linalg.norm(np.hstack([b, a]) * columns, axis=1)[None],
                                            np.linalg.norm(finite * columns, axis=-1)]), axis=0)
        if relation.residual is not None and np.all(np.isfinite(far)) and \
                _kinked(relation, variables, relation.n, steps, far, columns):
            return GosselinAngeles(relation.n, b, a, None, None, None, "not_differentiable",
                                   "[B A] jumps across this configuration: F has a kink here (e.g. ‖w‖ at "
                                   "w = 0), its derivative is not defined", variable_scales=scales)
    return kinds_of_matrices(b, a, rtol=rtol, row_scales=row_scales, variable_scales=scales)


def derived_gosselin_angeles(model, point, basis, rtol=DEFAULT_RTOL):
    """A and B derived from a mechanism at p: ``[B A]`` spans the annihilator of V (module doc).

    On the dimensionless rows of Park–Kim's decisions
    (:func:`classify.survey.decision_blocks`): ``P = U T`` (a×m), U the unit
    actuator rows (each row of ``E^½ Dπ`` over its norm times diag(s)), and
    ``Q = H^½ Df T`` (n×m), each divided by the largest singular value of its
    unrestricted map times diag(s); ``V = range [P; Q]``. Its left null space,
    with orthonormal rows, is ``[B A]`` in those coordinates; mapping back
    gives A and B in the mechanism's coordinates (same ranks). Neither the
    weights nor the unit of length change a decision: a 3-PRR drawn in
    nanometres had B of rank 0 where in millimetres it is regular (the raw rows
    of a prismatic input grew with the unit, the output scale did not). A
    change of basis T (``T → T R``) leaves V, hence A and B, unchanged.

    Parameters
    ----------
    model : Model
    point : ndarray, shape=[point_size]
    basis : ndarray, shape=[k, m]
        Orthonormal basis of T_pM (ker DΦ(p) at a C-space singularity).
    rtol : float

    Returns
    -------
    GosselinAngeles
        Undefined (``"not_square"``) when the numbers of inputs and outputs
        differ or are both 0, (``"subspace_dimension"``) when dim V ≠ n.
    """
    actuators = model.actuators
    count_inputs, count_outputs = actuators.shape[0], model.end_effector_dimension
    if count_inputs != count_outputs:
        return _undefined(count_inputs, "not_square",
                          f"{count_inputs} inputs and {count_outputs} outputs: [B A] would be "
                          f"{count_outputs + count_inputs - basis.shape[1]}×{count_inputs + count_outputs}, "
                          f"not n×2n")
    if count_inputs == 0:
        return _undefined(0, "not_square", "no inputs and no outputs: G–A needs n ≥ 1 of each")
    n = count_inputs
    blocks = decision_blocks(model, point, basis)
    input_scale, output_scale = max(blocks[1], 1e-300), max(blocks[3], 1e-300)
    stacked = stacked_rows(*blocks)
    velocities = numerical_rank(stacked, rtol=rtol, scale=1.0)
    if velocities.rank != n:
        return _undefined(n, "subspace_dimension",
                          f"V = {{(Dπ T u, J u)}} has dimension {velocities.rank}, not {n}: its annihilator "
                          f"is not spanned by n rows [B A]", velocities.rank)
    left = np.linalg.svd(stacked, full_matrices=True)[0][:, n:].T
    weighted_b, weighted_a = left[:, :n], left[:, n:]
    # back to the mechanism's coordinates: rows annihilate (U T u / s_a, H^½ Df T u / s_j), where
    # U T u = diag(1 / |row·diag(s)|) E^½ θ̇ and E^½ = diag(|row|) (each row of E^½ Dπ selects one coordinate)
    scales = model.manifold.ambient.tangent_scales
    input_root = np.sqrt(np.sum(actuators ** 2, axis=1))
    dimensionless = np.linalg.norm(actuators * scales, axis=1)
    b = weighted_b * (input_root / np.where(dimensionless > 0, dimensionless, 1.0)) / input_scale
    a = weighted_a @ metric_root(model.end_effector_metric) / output_scale
    return GosselinAngeles(n, b, a, numerical_rank(weighted_b, rtol=rtol, scale=1.0),
                           numerical_rank(weighted_a, rtol=rtol, scale=1.0), velocities, None, "", n)
