"""Regenerate the conditioning pictures of docs/conditioning.rst (run from the repository's root).

    python docs/images/make_conditioning_figures.py

Each picture is what a ``closedchain conditioning`` command draws (the command is printed beside it), at a
lower resolution and dpi to keep the files small:

* ``conditioning-five-bar.png`` — Chablat, Wenger & Angeles 1998 Fig. 5: 1/κ(A) of the five-bar
  (L0 = 6, L1 = 8, L2 = 5) in its four working modes;
* ``conditioning-three-prr.png`` — Chablat, Caro, Wenger & Angeles 2002 Figs. 6-7: 1/κ(K̄) of the 3-PRR
  (r = 100, R = 200, l = 200 mm, L = √2 r) in working modes 1 and 2, best over the orientation;
* ``conditioning-hybrid.png`` — Chablat, Wenger & Angeles 1998 §5.1: the hybrid's isoconditioning surfaces
  (its in-plane curves turned about AB), working mode ``+-``;
* ``conditioning-five-bar-general.png`` — any mechanism: the general engine's 1/κ(J̄) of the five-bar over
  P = (x, y), each working mode found (inverse-kinematics branches) followed up to its serial singularities;
* ``conditioning-five-bar-joints.png`` — any mechanism: the five-bar's 1/κ(J̄) over its actuated angles,
  assembled on a working mode's branch, singular grid points marked (the general engine).
"""

import math
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DPI = 60


def _save(figure, name, command):
    path = HERE / name
    figure.savefig(path, dpi=DPI)
    print(f"{path.name}: {command}")


def main():
    from classify.figures.conditioning import isoconditioning_figure, isoconditioning_surface_figure
    from classify.isoconditioning import five_bar_cartesian_map, hybrid_plane_map, three_prr_map
    from mechanisms.catalogue.three_prr import WORKING_MODES

    axis_x, axis_y = np.linspace(-8.0, 14.0, 90), np.linspace(-12.0, 12.0, 90)
    maps = [five_bar_cartesian_map(axis_x, axis_y, (1 if label[0] == "+" else -1, 1 if label[1] == "+" else -1),
                                   mode=label) for label in ("++", "+-", "-+", "--")]
    _save(isoconditioning_figure(maps, "A"), "conditioning-five-bar.png",
          "closedchain conditioning five-bar --grid X=-8:14:90 Y=-12:12:90 --matrix A --out FILE.png")

    positions = np.linspace(-295.0, 295.0, 70)
    orientations = np.linspace(-math.pi, math.pi, 48, endpoint=False)
    maps = [three_prr_map(positions, positions, WORKING_MODES[mode], math.sqrt(2) * 100.0, orientations,
                          mode=str(mode)) for mode in (1, 2)]
    _save(isoconditioning_figure(maps, "B-1A", units="mm"), "conditioning-three-prr.png",
          "closedchain conditioning 3-prr --grid X=-295:295:70 Y=-295:295:70 PHI=-3.14159:3.01069:48 --out FILE.png"
          " (modes 1 and 2 of the eight)")

    plane = hybrid_plane_map(np.linspace(0.0, 13.0, 80), np.linspace(-7.0, 13.0, 80), (1, -1), mode="+-")
    _save(isoconditioning_surface_figure([plane], "B-1A", levels=(0.2, 0.4, 0.6)), "conditioning-hybrid.png",
          "closedchain conditioning hybrid --mode +- --grid X=-13:13:40 Y=-7:13:40 Z=-13:13:40 --out FILE.png")

    _save(_five_bar_general_figure(), "conditioning-five-bar-general.png",
          "closedchain conditioning FIVE_BAR_FILE --grid X=-8:14:45 Y=-12:12:49 --out FILE.png "
          "(the catalogue's five-bar at fig2_working_mode_pp saved as a file: no paper formula)")

    _save(_five_bar_joint_figure(), "conditioning-five-bar-joints.png",
          "closedchain conditioning five-bar --configuration fig2_working_mode_pp --mode 1 "
          "--grid A=-1.5:1.5:31 B=-1.5:1.5:31 --out FILE.png")


def _five_bar_general_figure():
    """The general engine's Cartesian maps of the five-bar, one per working mode it finds and follows."""
    from classify.figures.conditioning import isoconditioning_figure
    from classify.isoconditioning import cartesian_grid_maps
    from classify.inverse_kinematics_branches import mechanism_working_modes
    from mechanisms import catalogue, configuration

    item = catalogue.entry("five-bar")
    mechanism = item.assemble(dict(item.configurations["fig2_working_mode_pp"]))
    point = configuration(mechanism, {}).point
    axes = (np.linspace(-8.0, 14.0, 45), np.linspace(-12.0, 12.0, 49))
    maps = cartesian_grid_maps(mechanism, mechanism_working_modes(mechanism, point), ("x", "y"), axes, point)
    return isoconditioning_figure(maps, "A-1B")


def _five_bar_joint_figure():
    from classify.cli import main as command

    path = HERE / "conditioning-five-bar-joints.png"
    command(["conditioning", "five-bar", "--configuration", "fig2_working_mode_pp", "--mode", "1", "--grid",
             "A=-1.5:1.5:31", "B=-1.5:1.5:31", "--out", str(path.with_suffix(".npz"))], out=_Sink())
    arrays = np.load(path.with_suffix(".npz"))
    path.with_suffix(".npz").unlink()
    from classify.figures.conditioning import isoconditioning_figure
    from classify.isoconditioning import ConditioningMap

    inverse = {matrix: arrays[f"inverse_kappa_{matrix}_1"] for matrix in ("A", "B", "A-1B", "B-1A", "lambda")}
    conditioning_map = ConditioningMap("1", ("A", "B"), (arrays["axis_0"], arrays["axis_1"]), inverse,
                                       arrays["reachable_1"], 1.0, extra={"singular": arrays["singular_1"]})
    return isoconditioning_figure([conditioning_map], "A-1B", equal_aspect=False)


class _Sink:
    def write(self, text):
        return len(text)


if __name__ == "__main__":
    main()
