"""Shared machinery of the self-study lesson C2.1-C2.6: series, runs, live frames, scene.

:class:`ManipulatorLesson` declares every series the tasks observe (each run has the
chosen task's, :meth:`ManipulatorLesson.series_for`), runs a task headless by evaluating
its :class:`~analyzer_lab.lessons.mechanics.manipulators.tasks.Solution` on the sampling grid, plays the same
solution live, and draws the task's bodies.  A lesson built on it gives the parameters
(``task`` and the names :mod:`analyzer_lab.lessons.mechanics.manipulators.tasks` reads), the presets (one
at least per task: the scene's time span comes from the first), notes, the derivation
and the claims.
"""

from __future__ import annotations

from typing import Any

import analyzer_lab.lessons.mechanics.manipulators.tasks as tasks
import numpy as np
from analyzer_lab.lessons.kit.contract import (
    Frame,
    Lesson,
    Params,
    PlotSpec,
    RunResult,
    SceneSpec,
    Series,
    Stepper,
)
from analyzer_lab.lessons.mechanics.manipulators.scene import drawing, moving_points, poses
from analyzer_lab.lessons.mechanics.manipulators.tasks import (
    FORCES,
    SERIES,
    Solution,
    SolutionStepper,
    family,
    model_of,
)


class ManipulatorLesson(Lesson):
    """A lesson whose ``task`` parameter chooses one manipulator of C2.1-C2.6."""

    sampling = 0.01
    series = SERIES
    readout = ("phi", "phi_dot", "S", "x", "y", "z", "M_g", "s", "constraint_error")
    plots = (
        PlotSpec("Angle phi", ("phi",), "rad"),
        PlotSpec("Translations", ("S", "S1", "S2", "x", "y", "z", "s"), "m"),
        PlotSpec("Moments", ("M_g", "M_c", "Q_phi"), "N m"),
        PlotSpec("Forces", ("F_g", "F_c", "Q_S", "Q_S1", "Q_S2", "Q_x", "Q_y", "Q_z"), "N"),
        PlotSpec("Inductors (C2.6)", ("x_A", "y_A", "x_B", "y_B", "x_C", "y_C"), "m"),
        PlotSpec(
            "Multipliers, fixed inductors (C2.6a, b)",
            tuple(f"lambda_{i}" for i in range(1, 5)),
            "N",
        ),
        PlotSpec("Multipliers, circle (C2.6c)", ("lambda_A", "lambda_B", "lambda_C"), "N/m"),
    )

    def series_for(self, params: Params) -> tuple[Series, ...]:
        names = tasks.series_names(params)
        return tuple(s for s in SERIES if s.name in names)

    def observe(self, params: Params, t: np.ndarray, state: Any) -> dict[str, np.ndarray]:
        return tasks.observe(params, t, state)

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        t_end = float(self.t_end if t_end is None else t_end)
        t = self.sample_grid(t_end)
        model = model_of(params)
        solution = Solution(params, 0.0, tasks.initial_state(params, model))
        Y = solution(t)
        messages = [n.text for n in self.notes(params)]
        for name in FORCES.get(family(params["task"]), ()):
            with np.errstate(all="ignore"):
                values = np.broadcast_to(np.asarray(params[name](t), dtype=float), t.shape)
            if not np.all(np.isfinite(values)):
                at = float(t[int(np.argmax(~np.isfinite(values)))])
                messages.append(f"{name} = {params[name].text} is not finite at t = {at:.6g} s.")
        metrics: dict[str, Any] = {
            "task": params["task"],
            "n_coordinates": model.n,
            "n_constraints": len(model.constraints),
        }
        if solution.message(t_end):
            messages.append(solution.message(t_end))
        if solution.reached:
            metrics["t_180"] = solution.stop
        elif params["task"] in ("C2.1a", "C2.1b"):
            messages.append("phi does not reach 180 deg within the run.")
        result = self.result(params, t, Y, metrics, messages)
        if "constraint_error" in result.series:
            result.metrics["max_constraint_error"] = float(
                np.max(result.series["constraint_error"])
            )
        for name in model.coords:
            result.metrics[f"{name}_end"] = float(result.series[name][-1])
        return result

    def stepper(self, params: Params) -> Stepper:
        return SolutionStepper(params, self._frame)

    def _frame(
        self, params: Params, t: float, state: np.ndarray, drawn: np.ndarray, message: str
    ) -> Frame:
        model = model_of(params)
        consts = tasks.constants(params, model)
        q = drawn[: model.n]
        return Frame(
            t=t,
            points={p: model.point(p, q, consts)[None, :] for p in moving_points(params["task"])},
            poses=poses(params, model, q, consts),
            scalars=self.frame_scalars(params, t, state),
            message=message,
        )

    def scene(self, params: Params) -> SceneSpec:
        task = params["task"]
        t_end = next(p.t_end for p in self.presets if p.values["task"] == task)
        model = model_of(params)
        consts = tasks.constants(params, model)
        t = np.linspace(0.0, float(t_end), 201)
        Y = Solution(params, 0.0, tasks.initial_state(params, model))(t)
        q = Y[:, : model.n].T
        pts = np.vstack([model.point(p, q, consts) for p in model.points] + [np.zeros((1, 3))])
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        span = max(float(np.max(np.abs(pts))), 0.2)
        size = 0.08 * min(span, 1.0) if span < 5 else 0.08 * span**0.5
        lo, hi = pts.min(axis=0) - 2 * size, pts.max(axis=0) + 2 * size
        lo[2], hi[2] = min(lo[2], -size), max(hi[2], size)
        bodies, curves, markers = drawing(params, size, lo, hi)
        return SceneSpec(
            bounds=(tuple(lo.tolist()), tuple(hi.tolist())),
            curves=curves,
            markers=markers,
            moving_points=moving_points(task),
            bodies=bodies,
            planar=family(task) != "C2.4",
        )
