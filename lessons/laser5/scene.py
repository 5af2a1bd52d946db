"""The LSP-2000 five-axis laser machine drawn and played (LSP-2000 article, Figs 1, 2).

The granite bed with its guides, portal X across them, portal Y on it, portal Z
carrying the C lever, the B lever at its end, the workpiece and the task: as scene data
for the view; :class:`ProgramStepper` plays an executed program frame by frame.
Series and metrics stay in the machine's left-handed frame (Z towards the workpiece,
i.e. down); the scene is drawn in the viewer's right-handed z-up frame
``(x, y, -z)``, the mirror image that turns the left-handed triple right-handed.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import trimesh
from analyzer_lab.lessons.kit.contract import (
    CurveItem,
    Frame,
    MarkerItem,
    MeshItem,
    Params,
    SceneSpec,
    Stepper,
)
from analyzer_lab.lessons.laser5.kinematics import Machine5
from analyzer_lab.lessons.laser5.program import Playhead, Program
from analyzer_lab.lessons.laser5.task import Task


def to_view(v: np.ndarray) -> np.ndarray:
    """Machine frame (left-handed, Z down) -> viewer frame (right-handed, z up)."""
    v = np.asarray(v, dtype=float)
    return v * np.array([1.0, 1.0, -1.0])


BRIDGE_Z = 250.0  # viewer height of portal X's bridge [mm]
BED_Z = -1000.0  # viewer height of the granite bed's top
GUIDES_Y = (-250.0, 3250.0)  # the granite guides of portal X (the machine's 3000 mm field)


def _mesh(
    name: str, mesh: trimesh.Trimesh, color: tuple[int, int, int], opacity: float = 1.0
) -> MeshItem:
    return MeshItem(
        name, np.asarray(mesh.vertices, float), np.asarray(mesh.faces, int), color, opacity
    )


def _box(
    extents: tuple[float, float, float], centre: tuple[float, float, float]
) -> trimesh.Trimesh:
    return trimesh.creation.box(
        extents=extents, transform=trimesh.transformations.translation_matrix(centre)
    )


def _cyl(radius: float, a: np.ndarray, b: np.ndarray) -> trimesh.Trimesh:
    return trimesh.creation.cylinder(
        radius=radius, segment=np.array([a, b], dtype=float), sections=24
    )


def machine_bodies(machine: Machine5) -> list[MeshItem]:
    """Moving bodies in their local frames (posed by :func:`body_poses`)."""
    span = GUIDES_Y
    legs_h = BRIDGE_Z - BED_Z
    portal_x = trimesh.util.concatenate(
        [
            _box((160.0, span[1] - span[0], 120.0), (0.0, 0.5 * (span[0] + span[1]), BRIDGE_Z)),
            _box((160.0, 120.0, legs_h), (0.0, span[0], BED_Z + legs_h / 2)),
            _box((160.0, 120.0, legs_h), (0.0, span[1], BED_Z + legs_h / 2)),
        ]
    )
    portal_y = _box((260.0, 240.0, 200.0), (0.0, 0.0, 0.0))
    portal_z = _box((110.0, 110.0, 900.0), (0.0, 0.0, 450.0))
    lever_c = trimesh.util.concatenate(
        [
            _cyl(45.0, np.array([0, 0, -30.0]), np.array([0, 0, 30.0])),
            _box((50.0, max(machine.R_C, 1.0), 40.0), (0.0, machine.R_C / 2, 0.0)),
        ]
    )
    lever_b = trimesh.util.concatenate(
        [
            _cyl(35.0, np.array([-40.0, 0, 0]), np.array([40.0, 0, 0])),
            _cyl(18.0, np.array([0, 0, 0.0]), np.array([0, 0, -0.85 * machine.R_B])),
            _cyl(9.0, np.array([0, 0, -0.85 * machine.R_B]), np.array([0, 0, -machine.R_B])),
        ]
    )
    return [
        _mesh("portal_X", portal_x, (150, 150, 160)),
        _mesh("portal_Y", portal_y, (90, 110, 150)),
        _mesh("portal_Z", portal_z, (110, 130, 170)),
        _mesh("lever_C", lever_c, (230, 160, 40)),
        _mesh("lever_B", lever_b, (200, 90, 40)),
    ]


def body_poses(machine: Machine5, q: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Viewer poses (position, wxyz) of the moving bodies for axis positions ``q``."""
    c_pivot, b_pivot, _, _ = machine.pivots(q)
    cv, bv = to_view(c_pivot), to_view(b_pivot)
    th = float(machine.theta(q[3]))
    ident = np.array([1.0, 0.0, 0.0, 0.0])
    # rz: -theta about z; rb = rz * (B about x), as wxyz quaternions
    c1, s1 = math.cos(th / 2.0), math.sin(th / 2.0)
    c2, s2 = math.cos(float(q[4]) / 2.0), math.sin(float(q[4]) / 2.0)
    return {
        "portal_X": (np.array([cv[0], 0.0, 0.0]), ident),
        "portal_Y": (np.array([cv[0], cv[1], BRIDGE_Z]), ident),
        "portal_Z": (cv, ident),
        "lever_C": (cv, np.array([c1, 0.0, 0.0, -s1])),
        "lever_B": (bv, np.array([c1 * c2, c1 * s2, -s1 * s2, -s1 * c2])),
    }


def machine_scene(machine: Machine5, task: Task, tolerance_um: float) -> SceneSpec:
    """The bed, the workpiece, the task (points, path, normals) and the machine's bodies;
    the tool trail is coloured green within the tolerance, red at twice it and beyond."""
    surf = task.workpiece.mesh()
    meshes = [
        MeshItem(
            "workpiece", to_view(surf.vertices), np.asarray(surf.faces), (120, 160, 220), 0.55
        ),
        _mesh("bed", _box((3800.0, 3800.0, 80.0), (1500.0, 1500.0, BED_Z - 40.0)), (90, 90, 95)),
    ]
    for y in GUIDES_Y:
        guide = _box((3800.0, 80.0, 60.0), (1500.0, y, BED_Z + 30.0))
        meshes.append(_mesh(f"guide_{int(y)}", guide, (60, 60, 65)))
    curves = [CurveItem("task path", to_view(task.points), (30, 30, 30), 2.0)]
    step = max(1, len(task.points) // 48)
    for i in range(0, len(task.points), step):
        a = to_view(task.points[i])
        curves.append(
            CurveItem(
                f"normal {i}",
                np.array([a, a - 80.0 * to_view(task.normals[i])]),
                (40, 150, 60),
                1.5,
            )
        )
    markers = [MarkerItem("task points", to_view(task.points), (220, 60, 60), 8.0, "task points")]
    lo = np.array([-400.0, -400.0, BED_Z - 100.0])
    hi = np.array([3400.0, 3400.0, BRIDGE_Z + 1000.0])
    return SceneSpec(
        bounds=(tuple(float(v) for v in lo), tuple(float(v) for v in hi)),  # type: ignore[arg-type]
        meshes=meshes,
        curves=curves,
        markers=markers,
        moving_points={"tool": (230, 40, 40)},
        moving_vectors={"beam": (255, 60, 30), "normal": (40, 160, 60)},
        bodies=machine_bodies(machine),
        trail_color_by={"tool": ("deviation", tolerance_um, 2.0 * tolerance_um)},
    )


#: lesson seconds between the times a played frame can fall on (the session's time quanta)
FRAME_GRAIN = 1.0 / 600.0
#: grain times sampled at once for played frames (see :meth:`ProgramStepper.playhead`)
TABLE_BLOCK = 256


class ProgramStepper(Stepper):
    """Plays a CNC program live; parameters may change while it runs (time is kept).

    ``program_of`` gives the (cached) program of a parameter set, ``scalars`` the
    lesson's observation at one time (its ``frame_scalars``).
    """

    def __init__(
        self,
        params: Params,
        program_of: Callable[[Params], Program],
        scalars: Callable[[Params, float, Playhead], dict[str, float]],
    ) -> None:
        self.program_of = program_of
        self.scalars = scalars
        self._t = 0.0
        self._table: tuple[tuple[Program, int], Playhead, dict[str, np.ndarray]] | None = None
        self.set_params(params)

    @property
    def t(self) -> float:
        return self._t

    def set_params(self, params: Params) -> None:
        self.params = params
        self.prog = self.program_of(params)
        self._t = min(self._t, self.prog.duration)

    def playhead(self, t: float) -> Playhead:
        """The playhead at ``t``.  A time on the grain of played frames (multiples of
        :data:`FRAME_GRAIN`) is read from a table of :data:`TABLE_BLOCK` grain times,
        sampled in one vectorized evaluation when a frame first reaches it."""
        prog = self.prog
        j = round(t / FRAME_GRAIN)
        if abs(t / FRAME_GRAIN - j) > 1e-6 or j < 0:
            return prog.playhead(t)
        b, i = divmod(j, TABLE_BLOCK)
        if self._table is None or self._table[0][0] is not prog or self._table[0][1] != b:
            head = prog.playhead((b * TABLE_BLOCK + np.arange(TABLE_BLOCK)) * FRAME_GRAIN)
            self._table = ((prog, b), head, head.values)
        _, head, values = self._table
        row = Playhead(prog, head.move[i : i + 1], head.tau[i : i + 1], head.running[i : i + 1])
        row.__dict__["values"] = {k: v[i : i + 1] for k, v in values.items()}
        return row

    def frame(self) -> Frame:
        prog = self.prog
        head = self.playhead(self._t)
        s = head.values
        pv = to_view(s["p"])
        if self._t >= prog.duration:
            message = "task finished"
        else:
            message = prog.notes[0].text if prog.notes else ""
        return Frame(
            t=self._t,
            points={"tool": pv},
            vectors={
                "beam": (pv, 150.0 * to_view(s["n"])),
                "normal": (pv, 150.0 * to_view(s["normal"])),
            },
            poses=body_poses(prog.machine, s["q"][0]),
            scalars=self.scalars(self.params, self._t, head),
            message=message,
        )

    def advance(self, dt: float) -> Frame:
        self._t = min(self._t + max(float(dt), 0.0), self.prog.duration)
        return self.frame()

    def reset(self) -> Frame:
        self._t = 0.0
        return self.frame()
