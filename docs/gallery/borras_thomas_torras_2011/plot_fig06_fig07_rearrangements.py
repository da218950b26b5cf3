"""
Figs. 6-7: singularity-invariant leg rearrangements
===================================================

Borràs, Thomas & Torras 2011, Section III-B and Figs. 6-7: (1) a base
attachment may slide along its B-line, (2) a platform attachment may move
along Λ iff its base attachment is at B; either keeps the singularity locus.
Figs. 6-7 use such moves to bring legs together or apart (a design without
multiple spherical joints; an uncoupled manipulator).

On a quartic design (that of :doc:`/line_plane`; the paper's designs of
Figs. 6-7 are not given in its text): leg 3's base attachment slides along
its B-line (:func:`classify.line_plane_rearrangements.move_base`), then is moved onto B, and
its platform attachment is moved along Λ (:func:`classify.line_plane_rearrangements.move_platform`),
as in Figs. 6-7; :func:`classify.figures.line_plane.draw_rearrangement` draws
the B-lines before and after and a slice of both loci (fixed i and p_z: a
line in (pₓ, p_y)). Printed: the locus slices before and after, which
coincide; and a forbidden move (a platform attachment whose base attachment
is not at B), refused.
"""

# %%
from classify.figures.line_plane import draw_rearrangement, locus_slice
from classify.line_plane import (
    RearrangementError, b_line_direction, b_point, line_plane_design, move_base, move_platform,
)

# a quartic design (that of the line-plane page): B is finite
def same_sign(line):
    """A line a x + b y + c = 0 with a ≥ 0 (locus_slice fixes a² + b² = 1 but not the sign)."""
    return (line * (1.0 if line[0] > 0 or (line[0] == 0 and line[1] >= 0) else -1.0)).round(6).tolist()


design = line_plane_design([(0.1, 0.2), (1.3, -0.4), (-0.7, 1.1), (0.9, 1.6), (-1.2, -0.8)],
                           [0.3, -1.1, 0.6, 1.4, -0.2])
slid = move_base(design, 2, 0.8)
fig_slide = draw_rearrangement(design, slid, title="rule 1: leg 3's base attachment slides along its B-line")
direction, height = (0.2, -0.3, 1.0), 2.0
print(f"rule 1: slice before {same_sign(locus_slice(design, direction, height))}, "
      f"after {same_sign(locus_slice(slid, direction, height))}")

# %%
# Rule 2: leg 3's base attachment to B (sliding along its B-line, which passes through B), then its
# platform attachment anywhere on Λ.
point = b_point(design)
distance = float((point - design.base[2]) @ b_line_direction(design, 2))
at_b = move_base(design, 2, distance)
moved = move_platform(at_b, 2, 1.7)
fig_platform = draw_rearrangement(design, moved, title="rule 2: leg 3 at B, its platform attachment moved")
print(f"leg 3 moved to B = {point.round(4).tolist()} (now {at_b.base[2].round(4).tolist()}), z3 from "
      f"{design.platform[2]:g} to {moved.platform[2]:g}")
print(f"rule 2: slice before {same_sign(locus_slice(design, direction, height))}, "
      f"after {same_sign(locus_slice(moved, direction, height))}")
try:
    move_platform(design, 1, 1.7)
except RearrangementError as error:
    print(f"forbidden: {error}")
