"""Run metrics of the servo-error lesson (Leppik 1960): the article's numbers for one run.

After a headless run the lesson reports, per path, the article's closed forms for the
chosen values next to what the simulation measured: the line offset (5), the parabola's
(13), the output vertices (17) and (19) and, for a cell of the article's table, the
printed value; for circles and ellipses the moduli, the tilt (29), the semi-axes (30)
(corrected and printed) and the axes fitted to the last settled period of the run.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from analyzer_lab.lessons.kit.contract import Params
from analyzer_lab.lessons.servo.formulas import (
    circle_axes_29_30,
    delta_line_5,
    delta_parabola_13,
    parabola_vertex_17,
    parabola_vertex_19,
)
from analyzer_lab.lessons.servo.geometry import fit_centred_ellipse
from analyzer_lab.lessons.servo.model import Channel
from analyzer_lab.lessons.servo.paths import Path
from analyzer_lab.lessons.servo.table import table_row


def curve_metrics(
    params: Params,
    path: Path,
    cx: Channel,
    cy: Channel,
    t: np.ndarray,
    out: dict[str, np.ndarray],
    after: np.ndarray,
) -> dict[str, Any]:
    """The article's numbers for this run's path beside the measured ones."""
    omega, p, gamma = float(params["omega"]), float(params["p"]), float(params["gamma"])
    m: dict[str, Any] = {}
    if path.curve == "line":
        m["delta_5"] = delta_line_5(float(params["v"]), float(params["angle"]), cx.T1, gamma)
        m["v"] = float(params["v"])
    elif path.curve in ("parabola", "parabola-horizontal"):
        m["delta_13"] = delta_parabola_13(omega, p, cx.T1, cx.T2sq)
        m["v_vertex"] = omega * p / 2.0
        if path.curve == "parabola":
            m["vertex_17_x"], m["vertex_17_y"] = parabola_vertex_17(omega, p, cx.T1, cx.T2sq, gamma)
            row = table_row(float(params["k"]), float(params["T"]))
            if params["channel"] == "k-T" and (omega, p) == (5.0, 20.0) and row is not None:
                m["table_printed"] = row.printed
                m["table_formula_13"] = row.formula_13
                m["table_simulated"] = row.simulated
                m["table_printed_over_13"] = row.printed_over_formula
                m["table_note"] = (
                    "the printed table is 0.8 x (13) in every cell; the simulation agrees with (13)"
                )
        else:
            m["vertex_19_x"], m["vertex_19_y"] = parabola_vertex_19(omega, p, cx.T1, cx.T2sq, gamma)
    elif path.curve in ("circle", "ellipse"):
        period = 2 * math.pi / omega
        last = after & (t >= t[-1] - period)  # the most settled full period
        if last.sum() >= 16 and t[-1] - period >= t[0]:
            after = last
        xy = (out["x1"][after] - path.g["xc"], out["y1"][after] - path.g["yc"])
        m.update(_closed_curve_metrics(path, cx.response(omega), cy.response(omega), gamma, xy))
    else:
        m["v_x"] = omega * p
    return m


def _closed_curve_metrics(
    path: Path, P1: complex, P2: complex, gamma: float, xy: tuple[np.ndarray, np.ndarray]
) -> dict[str, Any]:
    """(28)-(30) for a circle/ellipse beside the axes fitted to the settled samples ``xy``
    (relative to the centre)."""
    A0, B0 = path.size()
    m: dict[str, Any] = (
        {"R0": A0, "v": path.g["omega"] * A0} if path.curve == "circle" else {"a": A0, "b": B0}
    )
    mm, nn = A0 * abs(P1), B0 * abs(P2)
    dphi = float(np.angle(P2) - np.angle(P1))
    alpha, major, minor = circle_axes_29_30(mm, nn, dphi)
    _, major_p, minor_p = circle_axes_29_30(mm, nn, dphi, printed=True)
    m.update(
        {
            "m": mm,
            "n": nn,
            "phi2_minus_phi1_deg": math.degrees(dphi),
            "tilt_29_deg": alpha,
            "semi_major_30": major,
            "semi_minor_30": minor,
            "semi_major_30_printed": major_p,
            "semi_minor_30_printed": minor_p,
        }
    )
    identical = gamma == 1.0
    if path.curve == "circle" and identical:
        m["R0_minus_R_28"] = A0 * (1.0 - abs(P1))
    xs, ys = xy
    if len(xs) >= 16:
        a_s, b_s, ang = fit_centred_ellipse(xs, ys)
        m.update({"sim_semi_major": a_s, "sim_semi_minor": b_s})
        if not identical:
            m["sim_tilt_deg"] = ang
        if path.curve == "circle" and identical:
            m["sim_R0_minus_R"] = A0 - float(np.mean(np.hypot(xs, ys)))
    return m
