"""Gosselin–Angeles relations of the slider-crank (RRRP), Gosselin & Angeles 1990 eqs. 6–17.

Section III of Gosselin & Angeles: a crank of length R turns about a pivot on
the line of the slide, a coupler of length l joins it to the slider; the input
is the crank angle θ measured from the slide, the output the slider's
displacement x from the pivot along the slide (Fig. 2). With r = R/l (eq. 10)
the input–output relation is

    x = R cos θ ± l √(1 − r² sin² θ)                                 (eq. 9)

and the velocity relation ``A ẋ + B θ̇ = 0`` (eq. 11) has

    A = √(1 − r² sin² θ),   B = R sin θ (√(1 − r² sin² θ) ± r cos θ)  (eq. 12)

with the same sign as eq. 9 (the branch of the direct kinematics). Three
relations of the catalogue entry ``slider-crank``
(:mod:`mechanisms.catalogue.slider_crank`), all in the variables (θ, x):

* :func:`eq9_relation`: F = x − R cos θ ∓ l √(1 − r² sin² θ) (eq. 9), A and B
  by symbolic differentiation (eq. 3). F is not differentiable where the
  radicand vanishes (sin θ = l/R, the fold of Fig. 3): G–A is undefined there
  (``not_finite``), see :func:`eq9_relation`.
* :func:`eq12_relation`: the paper's A and B (eq. 12) as printed: kind I at
  θ = 0, π (eq. 13), kind II at sin θ = l/R (eq. 14), both at R = l
  (eqs. 15–17) where the constant branch x = 0 meets x = 2R cos θ.
* :func:`squared_relation`: a badly chosen F, the loop closure with cos θ
  eliminated by squaring, whose differential vanishes at cos θ = 0 where the
  mechanism is regular (the comparison's reason ``degenerate_relation``).

The Park–Kim side uses :func:`classify.model.joint_output_model` with the
output the ``slide`` joint (the slider's displacement), since the catalogue's
end-effector is the slider's planar position (two coordinates).

Variables are read from the mechanism's geometry (:func:`slider_crank_geometry`):
R = ‖pin − crank pivot‖, l = ‖wrist − pin‖, the slide direction u, and at a
configuration p, θ(p) = θ_home + (rotation of the crank link from its home)
and x(p) = (wrist(p) − pivot)·u, so the coordinate map is right at every
configuration of the mechanism, not only at the catalogue's parameters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import sympy

from mechanisms import link_pose

from ..gosselin_angeles import relation_from_sympy
from ._rotations import planar_angle

__all__ = [
    "SliderCrankGeometry", "slider_crank_geometry", "slider_crank_coordinates", "slider_crank_branch",
    "eq9_relation", "eq12_relation", "eq12_matrices", "squared_relation", "squared_equation",
]

REFERENCE = "Gosselin & Angeles (1990) Section III, eqs. 6-17"
#: the relations' variables, θ then x: the crank angle θ and the slide x
#: (:attr:`classify.gosselin_angeles.InputOutputRelation.units`)
UNITS = ("angle", "length")

#: largest distance of the crank pivot from the slide's line, relative to R + l (eqs. 6-7 assume 0)
_OFFSET_TOLERANCE = 1e-9

_THETA, _X = sympy.symbols("theta x", real=True)
_CRANK, _COUPLER, _SIGN = sympy.symbols("R l sigma", real=True)


@dataclass(frozen=True)
class SliderCrankGeometry:
    """The slider-crank's dimensions and home values, read from its joints (G–A Fig. 2).

    Attributes
    ----------
    crank, coupler : float
        R = ‖pin − pivot‖ and l = ‖wrist − pin‖ at home.
    pivot : ndarray, shape=[2]
        The crank's ground pivot (joint ``crank``).
    axis : ndarray, shape=[2]
        Unit direction of the slide (joint ``slide``).
    pin, wrist : ndarray, shape=[2]
        Home positions of the joints ``pin`` (crank–coupler) and ``wrist`` (coupler–slider).
    theta_home : float
        θ at home: the angle of pin − pivot from the slide direction (rad).
    """

    crank: float
    coupler: float
    pivot: np.ndarray
    axis: np.ndarray
    pin: np.ndarray
    wrist: np.ndarray
    theta_home: float

    @property
    def parameters(self):
        """``{R: crank, l: coupler}`` as SymPy parameters of the relations."""
        return {_CRANK: self.crank, _COUPLER: self.coupler}



def _cross(first, second):
    return float(first[0] * second[1] - first[1] * second[0])


def slider_crank_geometry(mechanism):
    """R, l, the slide and the home values of a slider-crank built like the catalogue's.

    Parameters
    ----------
    mechanism : Mechanism
        Joints ``crank`` (ground–crank, R), ``pin`` (crank–coupler, R), ``wrist``
        (coupler–slider, R), ``slide`` (ground–slider, P), as in
        :func:`mechanisms.catalogue.slider_crank.slider_crank`.

    Returns
    -------
    SliderCrankGeometry

    Raises
    ------
    ValueError
        If a joint is missing or the crank pivot is off the slide's line (eqs. 6–7 of
        G–A assume the crank pivot on it: x is measured from the pivot along the slide).
    """
    try:
        pivot, pin, wrist = (np.asarray(mechanism.joint(name).point, dtype=float)
                             for name in ("crank", "pin", "wrist"))
        axis = np.asarray(mechanism.joint("slide").axis, dtype=float)
    except (KeyError, TypeError, AttributeError) as error:
        raise ValueError(f"{mechanism.name}: not a slider-crank with joints crank, pin, wrist, slide "
                         f"({error})") from None
    axis = axis / np.linalg.norm(axis)
    crank, coupler = float(np.linalg.norm(pin - pivot)), float(np.linalg.norm(wrist - pin))
    offset = _cross(axis, wrist - pivot)
    if abs(offset) > _OFFSET_TOLERANCE * (crank + coupler):
        raise ValueError(f"{mechanism.name}: the crank pivot is {offset:.3g} off the slide's line; "
                         f"G-A eqs. 6-9 assume it on the line")
    theta_home = math.atan2(_cross(axis, pin - pivot), float(np.dot(axis, pin - pivot)))
    return SliderCrankGeometry(crank, coupler, pivot, axis, pin, wrist, theta_home)


def slider_crank_coordinates(mechanism, geometry=None):
    """The map ``point -> (θ, x)`` of G–A Fig. 2, from the link poses at the point.

    Parameters
    ----------
    mechanism : Mechanism
    geometry : SliderCrankGeometry, optional
        Default :func:`slider_crank_geometry` of `mechanism`.

    Returns
    -------
    callable
        ``coordinates(point) -> (theta, x)``, each an ndarray of shape [1]: θ = θ_home + the
        crank link's rotation from home (rad, in θ_home + (−π, π]); x = (wrist − pivot)·u with
        the wrist carried by the slider's pose.
    """
    geometry = slider_crank_geometry(mechanism) if geometry is None else geometry
    wrist_home = np.append(geometry.wrist, 1.0)

    def coordinates(point):
        theta = geometry.theta_home + planar_angle(link_pose(mechanism, "crank", point))
        wrist = (link_pose(mechanism, "slider", point) @ wrist_home)[:2]
        return np.array([theta]), np.array([float(np.dot(wrist - geometry.pivot, geometry.axis))])
    return coordinates


def slider_crank_branch(mechanism, point, geometry=None):
    """The sign ± of eq. 9 at a configuration: +1 where x − R cos θ ≥ 0, else −1.

    x − R cos θ = l cos ψ (eq. 6), the coupler's extent along the slide, so the sign is
    the branch of the direct kinematics the configuration is on. At the fold
    (sin θ = l/R, eq. 14) both signs describe the configuration.

    Parameters
    ----------
    mechanism : Mechanism
    point : ndarray, shape=[point_size]
    geometry : SliderCrankGeometry, optional

    Returns
    -------
    int
        +1 or −1.
    """
    geometry = slider_crank_geometry(mechanism) if geometry is None else geometry
    (theta,), (x,) = slider_crank_coordinates(mechanism, geometry)(point)
    return 1 if x - geometry.crank * math.cos(theta) >= 0 else -1


def _check_branch(branch):
    if branch not in (1, -1):
        raise ValueError(f"branch must be +1 or -1 (the sign of eq. 9), got {branch!r}")


def _radicand():
    """1 − r² sin² θ with r = R/l (eqs. 8–10)."""
    return 1 - (_CRANK / _COUPLER) ** 2 * sympy.sin(_THETA) ** 2


def eq9_relation(mechanism, branch=1):
    """F(θ, x) = x − R cos θ ∓ l √(1 − r² sin² θ) (G–A eq. 9), A and B by differentiation.

    ``B = ∂F/∂θ = R sin θ ± l r² sin θ cos θ / √(1 − r² sin² θ)`` and ``A = ∂F/∂x = 1``
    (eq. 3): the ratio B/A is that of eq. 12, but F is not differentiable where the
    radicand vanishes, at the fold sin θ = l/R (eq. 14) where eq. 12 has A = 0.

    What happens numerically there: at the catalogue preset ``fig3b_actuator``
    (R = 2, l = 1, θ = asin(1/2)) the configuration is exact in binary — sin(asin(0.5))
    evaluates to 0.5, the radicand 1 − 4.0 · 0.25 to exactly 0.0 — so the symbolic
    B divides by √0 and is ±inf: :func:`classify.gosselin_angeles.gosselin_angeles`
    reports ``undefined = "not_finite"`` and the comparison the reason
    ``not_differentiable``, deterministically. At a fold given only to rounding the
    radicand is ±ε instead: −ε gives nan (again ``not_finite``), +ε gives a finite
    B ≈ 1/√ε ≈ 1e8 against A = 1, which the rank cut (rtol = 1e-6 on the normalised
    row) reads as kind II, the limit of eq. 12.

    Parameters
    ----------
    mechanism : Mechanism
        A slider-crank as in :func:`slider_crank_geometry`.
    branch : {1, -1}
        The sign ± of eq. 9 (:func:`slider_crank_branch` of the configurations to compare).

    Returns
    -------
    relation : InputOutputRelation
        Inputs ``("theta",)``, outputs ``("x",)``, with residual F.
    coordinates : callable
        :func:`slider_crank_coordinates`.
    """
    _check_branch(branch)
    geometry = slider_crank_geometry(mechanism)
    equation = _X - _CRANK * sympy.cos(_THETA) - _SIGN * _COUPLER * sympy.sqrt(_radicand())
    relation = relation_from_sympy([_THETA], [_X], equations=[equation],
                                   parameters={**geometry.parameters, _SIGN: branch},
                                   name=f"eq9[{'+' if branch > 0 else '-'}]", reference=REFERENCE + ", eq. 9",
                                   units=UNITS)
    return relation, slider_crank_coordinates(mechanism, geometry)


def eq12_matrices(branch=1):
    """The paper's B and A of eq. 12 as SymPy 1×1 matrices in θ, R, l.

    Parameters
    ----------
    branch : {1, -1}
        The sign ± of eqs. 9 and 12.

    Returns
    -------
    input_jacobian, output_jacobian : sympy.Matrix, shape=[1, 1]
        ``B = R sin θ (√(1 − r² sin² θ) ± r cos θ)`` and ``A = √(1 − r² sin² θ)``
        with r = R/l; free symbols θ (``theta``), R, l.
    """
    _check_branch(branch)
    root = sympy.sqrt(_radicand())
    ratio = _CRANK / _COUPLER
    return (sympy.Matrix([[_CRANK * sympy.sin(_THETA) * (root + branch * ratio * sympy.cos(_THETA))]]),
            sympy.Matrix([[root]]))


def eq12_relation(mechanism, branch=1):
    """The paper's velocity relation ``A ẋ + B θ̇ = 0`` (G–A eqs. 11–12) as printed.

    Kinds: I where B = 0, i.e. θ = 0, π (eq. 13, the links aligned); II where A = 0,
    i.e. sin θ = l/R (eq. 14, Fig. 3); both at R = l (eqs. 15–17), where
    A = ‖cos θ‖ and, on the constant branch x = 0 (sign −sign cos θ), B = 0 for every θ;
    at θ = π/2 the constant branch meets x = 2R cos θ and A = B = 0 (Fig. 4).

    A is ≥ 0 here (the principal root), and at the exact fold of the preset
    ``fig3b_actuator`` it evaluates to exactly 0.0 (see :func:`eq9_relation`): kind II.

    Parameters
    ----------
    mechanism : Mechanism
        A slider-crank as in :func:`slider_crank_geometry`.
    branch : {1, -1}
        The sign ± of eqs. 9 and 12.

    Returns
    -------
    relation : InputOutputRelation
        Inputs ``("theta",)``, outputs ``("x",)``; no residual (the paper prints the
        velocity relation).
    coordinates : callable
        :func:`slider_crank_coordinates`.

    Examples
    --------
    >>> from classify import compare, joint_output_model
    >>> from classify.gosselin_angeles_examples import eq12_relation
    >>> from mechanisms import home
    >>> from mechanisms.catalogue import entry
    >>> mechanism = entry("slider-crank").mechanism("fig3b_actuator")
    >>> relation, coordinates = eq12_relation(mechanism, branch=1)
    >>> row = compare(joint_output_model(mechanism, ["slide"]), [home(mechanism)], relation=relation,
    ...               coordinates=coordinates).rows[0]
    >>> row.gosselin_angeles.kinds, row.park_kim.kinds, row.agree
    (('II',), ('actuator',), True)
    """
    geometry = slider_crank_geometry(mechanism)
    input_jacobian, output_jacobian = eq12_matrices(branch)
    relation = relation_from_sympy([_THETA], [_X], input_jacobian=input_jacobian, output_jacobian=output_jacobian,
                                   parameters=geometry.parameters,
                                   name=f"eq12[{'+' if branch > 0 else '-'}]", reference=REFERENCE + ", eq. 12",
                                   units=UNITS)
    return relation, slider_crank_coordinates(mechanism, geometry)


def squared_equation():
    """The squared closure F(θ, x) = (x² + R² − l²)² − 4 x² R² (1 − sin² θ), SymPy.

    From eqs. 6–7, l² = (x − R cos θ)² + R² sin² θ, i.e. x² + R² − l² = 2 x R cos θ;
    squaring eliminates cos θ (written 1 − sin² θ). The result also vanishes on the mirror
    linkage θ → π − θ (same x), and the two branches (θ, x), (π − θ, x) cross at
    cos θ = 0, where ``∂F/∂θ = 8 x² R² sin θ cos θ`` and
    ``∂F/∂x = 4x(x² + R² − l²) − 8 x R² cos² θ = 8 x R cos θ (x − R cos θ)`` both vanish.

    Returns
    -------
    sympy.Expr
        Free symbols θ (``theta``), x, R, l.
    """
    return ((_X ** 2 + _CRANK ** 2 - _COUPLER ** 2) ** 2
            - 4 * _X ** 2 * _CRANK ** 2 * (1 - sympy.sin(_THETA) ** 2))


def squared_relation(mechanism):
    """A badly chosen F: the closure squared to eliminate cos θ (:func:`squared_equation`).

    Where cos θ = 0 both A = ∂F/∂x and B = ∂F/∂θ vanish, so ``[B A]`` has rank 0 and
    det A = det B = 0, although the mechanism is regular there when R < l (the crank
    perpendicular to the slide, the coupler oblique: Park–Kim finds no singularity).
    The spurious zero comes from the mirror linkage θ → π − θ that squaring merged into
    F; the comparison's reason is ``degenerate_relation``.

    The configuration shown in the docs: the catalogue's ``slider-crank`` with
    ``crank=3.0, coupler=5.0, theta=π/2`` (branch +1): pin at (0, 3), slider at x = 4
    (a 3-4-5 triangle, exact in binary: R, l and x are read back as 3.0, 5.0 and 4.0,
    so x² + R² − l² = 0.0 exactly and A = 0.0). θ itself is the double nearest π/2, so
    cos θ = 6.1e-17 and B = 8 x² R² sin θ cos θ ≈ 7e-14, not 0: rounding against the row's
    size nearby (about 4 at 0.01 along the mechanism's motion, which
    :func:`classify.comparison.compare` passes as ``row_scales``), so ``[B A]`` has rank 0.

    Parameters
    ----------
    mechanism : Mechanism
        A slider-crank as in :func:`slider_crank_geometry`.

    Returns
    -------
    relation : InputOutputRelation
        Inputs ``("theta",)``, outputs ``("x",)``, with residual F; valid on both branches.
    coordinates : callable
        :func:`slider_crank_coordinates`.

    Examples
    --------
    >>> import math
    >>> from classify import compare, joint_output_model
    >>> from classify.gosselin_angeles_examples import squared_relation
    >>> from mechanisms import home
    >>> from mechanisms.catalogue import entry
    >>> mechanism = entry("slider-crank").mechanism(crank=3.0, coupler=5.0, theta=math.pi / 2)
    >>> relation, coordinates = squared_relation(mechanism)
    >>> row = compare(joint_output_model(mechanism, ["slide"]), [home(mechanism)], relation=relation,
    ...               coordinates=coordinates).rows[0]
    >>> row.park_kim.kinds, row.gosselin_angeles.kinds, row.reason
    ((), ('I', 'II', 'III'), 'degenerate_relation')
    """
    geometry = slider_crank_geometry(mechanism)
    relation = relation_from_sympy([_THETA], [_X], equations=[squared_equation()], parameters=geometry.parameters,
                                   name="squared", reference=REFERENCE + ", eqs. 6-7 squared", units=UNITS)
    return relation, slider_crank_coordinates(mechanism, geometry)
