"""The catalogue's index: what ``closedchain catalog`` lists of each entry, known without importing it.

Some family modules compute their named configurations when imported (with
SciPy's rotations or least squares), so listing the catalogue from the
entries themselves would cost seconds; this table lists them at once. Each
row is the entry's name, its family module (under
:mod:`mechanisms.catalogue`), the first line of its builder's docstring, its
reference and the names of its configurations, in catalogue order.

The table is kept equal to the entries by the tests (tests/test_startup.py):
after adding or changing an entry, paste the new table that the failing
test prints (:func:`index_source` of :func:`index_of` the entries).
"""

from __future__ import annotations

from typing import NamedTuple

__all__ = ["Listing", "INDEX", "index_of", "index_source"]


class Listing(NamedTuple):
    """One catalogue entry as listed, without building it.

    Attributes
    ----------
    name : str
        The catalogue name (``"slider-crank"``).
    family : str
        The module under :mod:`mechanisms.catalogue` that defines the entry (``"slider_crank"``).
    summary : str
        :attr:`mechanisms.catalogue.Entry.summary`.
    reference : str
        :attr:`mechanisms.catalogue.Entry.reference`.
    configurations : tuple of str
        The names of :attr:`mechanisms.catalogue.Entry.configurations`, in order.
    """

    name: str
    family: str
    summary: str
    reference: str
    configurations: tuple


INDEX = (
    Listing(
        "slider-crank", "slider_crank",
        "Slider-crank (RRRP) assembled at crank angle θ on the chosen branch.",
        "Park & Kim (1999) Fig. 3; Gosselin & Angeles (1990) eqs. (6)-(17)",
        ("fig3a_self_intersection", "fig3b_actuator", "fig3c_dead_centre", "fig3d_dead_centre",
         "eq17_constant_branch", "eq17_constant_branch_slider_driven"),
    ),
    Listing(
        "five-bar", "five_bar",
        "Planar five-bar (5R) assembled at actuated angles θ1, θ2 on the chosen branch.",
        "Chablat, Wenger & Angeles (1998) Fig. 1, eqs. (1)-(13), Figs. 2, 5; Park & Kim (1999) eq. (8), Figs. 1, "
        "6, 13",
        ("fig1a_collinear", "fig1b_collinear", "fig1c_collinear", "fig1d_collinear", "fig6a_distal_aligned",
         "fig6b_elbows_coincide", "fig13_combined", "fig2_working_mode_pp", "fig2_working_mode_pm",
         "fig2_working_mode_mp", "fig2_working_mode_mm", "eq9_distal_aligned", "sec34_elbows_coincide",
         "eq3c_left_leg_stretched", "eq3c_left_leg_folded", "eq3c_right_leg_stretched", "eq3c_right_leg_folded"),
    ),
    Listing(
        "spherical-six-bar", "spherical_six_bar",
        "Spherical 6R loop with equal twists, assembled at the angles of joints J1, J2, J3.",
        "Park & Kim (1999) Case 2, Figs. 7, 8a, 8b",
        ("fig7_actuator", "fig7_actuated_axes_coplanar", "fig8a_moved_actuator", "fig8b_added_actuator"),
    ),
    Listing(
        "planar-six-bar", "planar_six_bar",
        "Planar 6R loop with six equal links, assembled at the angles of joints J1, J2, J3.",
        "Park & Kim (1999) Case 3, Fig. 12a/b",
        ("fig12a_end_effector", "fig12b_relocated"),
    ),
    Listing(
        "eclipse", "eclipse",
        "The Eclipse (3 legs: track R, column P, hinge R, ball S), assembled at a platform pose.",
        "Park & Kim (1999) Case 2 (Figs. 9, 10) and Case 3 (Fig. 11c)",
        ("fig10_actuator", "fig10_turned", "fig11c_end_effector"),
    ),
    Listing(
        "watt-six-bar", "watt",
        "Watt six-bar (G-A Fig. 5) driven by the crank θ, output the angle φ of link l₃.",
        "Gosselin & Angeles (1990) Fig. 5, eqs. (18)-(41)",
        ("eq37_n1_crank_and_coupler_aligned", "eq37_n2_coupler_aligned_with_rocker",
         "eq39_d1_coupler_aligned_with_rocker", "eq40_d2_output_and_coupler_aligned",
         "eq41_joints_2_4_superimposed", "eq41_joints_2_4_branch_crossing", "eq41_joints_1_3_superimposed",
         "eq41_joints_4_6_constant_branch", "eq41_joints_4_6_branch_crossing"),
    ),
    Listing(
        "planar-3rrr", "planar_3rrr",
        "Planar 3-RRR (G-A Fig. 7) with fixed motors, assembled at the gripper pose (x, y, φ).",
        "Gosselin & Angeles (1990) Fig. 7, eqs. (42)-(65)",
        ("eq58_leg_stretched", "eq58_leg_folded", "eq61_distal_links_concurrent", "eq63_distal_links_parallel",
         "eq64_elbows_at_centroid", "eq64_elbows_at_centroid_turned", "eq65_vertices_on_motors",
         "eq65_vertices_on_motors_other_inputs"),
    ),
    Listing(
        "spherical-3rrr", "spherical_3rrr",
        "Spherical 3-RRR parallel wrist assembled at the gripper orientation Q, motors driven.",
        "Gosselin & Angeles (1990) Section VI, Fig. 9, eqs. (66)-(70)",
        ("eq70_leg1_extended", "eq70_leg1_folded", "eq68_distal_links_orthogonal", "section6_equal_alphas_folded",
         "section6_right_alphas_coplanar"),
    ),
    Listing(
        "gough-stewart", "gough_stewart",
        "Gough–Stewart platform (6-UPS) assembled at the platform pose (x, Q), legs driven.",
        "Gosselin & Angeles (1990) Section VII, Figs. 10-12, eqs. (71)-(87); Fichter (their ref. [28]) for the "
        "±90° rotation",
        ("eq84_leg1_zero_length", "fichter_rotated_plus_90", "fichter_rotated_minus_90", "eq87_parallel_legs"),
    ),
    Listing(
        "3-prr", "three_prr",
        "3-PRR assembled at the platform pose (x, y, φ) in a working mode (Chablat et al. Fig. 1).",
        "Chablat, Caro, Wenger & Angeles (2002) Fig. 1, eqs. (3)-(4), §2.2-2.3 (Figs. 2-3), §3.4 (Fig. 4a), §3.5 "
        "(Fig. 5)",
        ("fig4a_isotropic", "fig2_concurrent_at_centre", "fig2_parallel_legs", "fig3_serial_leg1"),
    ),
    Listing(
        "3-prr-inputs", "three_prr",
        "3-PRR assembled at the actuator inputs (ρ₁, ρ₂, ρ₃): the direct-kinematics solution nearest a guess.",
        "Chablat, Caro, Wenger & Angeles (2002) Fig. 1, eqs. (3)-(4)",
        ("fig4a_isotropic",),
    ),
    Listing(
        "hybrid", "hybrid",
        "The 3-dof hybrid manipulator of Chablat, Wenger & Angeles 1998, Fig. 6: a five-bar turned about AB, at "
        "inputs θ1, θ2, θ3.",
        "Chablat, Wenger & Angeles (1998) Fig. 6, eqs. (14)-(30)",
        ("regular", "eq30_on_the_axis", "eq30_left_leg_stretched", "eq30_left_leg_folded",
         "eq30_right_leg_stretched", "eq30_right_leg_folded", "eq25_distal_aligned", "eq25_elbows_coincide"),
    ),
    Listing(
        "5-spu", "five_spu",
        "5-SPU with planar base and linear platform, assembled at the line pose (p, i).",
        "Borràs, Thomas & Torras (2011) Figs. 1, 2, Section II, eqs. (17), (26), (33)-(35)",
        ("regular", "regular_locked", "eq33_w_zero", "eq33_second_factor", "eq35_vertical_tool",
         "sec3c_line_in_base", "eq33_w_zero_locked", "eq33_second_factor_locked"),
    ),
)


def index_of(entries):
    """The index rows of catalogue entries.

    Parameters
    ----------
    entries : iterable of Entry
        As from :func:`mechanisms.catalogue.entries`.

    Returns
    -------
    tuple of Listing
    """
    return tuple(Listing(item.name, item.build.__module__.rpartition(".")[2], item.summary, item.reference,
                         tuple(item.configurations))
                 for item in entries)


def index_source(rows):
    """The Python source of ``INDEX = (...)`` for `rows`, to paste into this module."""
    lines = ["INDEX = ("]
    for row in rows:
        lines += ["    Listing(", f"        {_quoted(row.name)}, {_quoted(row.family)},",
                  *_text_lines(row.summary), *_text_lines(row.reference), *_names_lines(row.configurations),
                  "    ),"]
    return "\n".join(lines + [")"])


_INDENT = " " * 8
_WIDTH = 116


def _quoted(text):
    """`text` as a Python string literal, in double quotes."""
    literal = repr(text)
    if literal.startswith("'"):
        literal = '"' + literal[1:-1].replace("\\'", "'").replace('"', '\\"') + '"'
    return literal


def _text_lines(text):
    """`text` as source lines of adjacent literals, each line within the width, the last one ending in a comma."""
    pieces, piece = [], ""
    for word in text.split(" "):
        candidate = f"{piece} {word}" if piece else word
        if piece and len(_INDENT) + len(_quoted(candidate + " ")) > _WIDTH:
            pieces.append(piece + " ")
            piece = word
        else:
            piece = candidate
    pieces.append(piece)
    return [_INDENT + _quoted(part) + ("," if index == len(pieces) - 1 else "") for index, part in enumerate(pieces)]


def _names_lines(names):
    """A tuple of names as source lines within the width, the last one ending in a comma."""
    items = [_quoted(name) + "," for name in names]
    if len(items) > 1:
        items[-1] = items[-1][:-1]
    lines, line = [], _INDENT + "("
    for item in items:
        if len(line) + len(item) + 1 > _WIDTH and not line.endswith("("):
            lines.append(line.rstrip())
            line = _INDENT + " "
        line += item + " "
    return lines + [line.rstrip() + "),"]
