"""The notes of the servo-error lesson (Leppik 1960): what the lesson did with the values.

A parabola's start is taken on its curve; non-identical channels use the corrected
definition T_y = gamma T_x; Fig. 4's qualitative remarks are reproduced only in part;
the semi-axes (30) use cos^2; the derivative feed-forward has an article value only for
the parabola; the cubic/quartic correction is the rule (20) applied; and a cell of the
article's table is named with its printed value.
"""

from __future__ import annotations

from analyzer_lab.lessons.kit.contract import Note, Params
from analyzer_lab.lessons.servo.formulas import delta_parabola_13
from analyzer_lab.lessons.servo.table import PARABOLA_TABLE_PRINTED

ARTICLE = "Leppik (1960)"
FIG4 = {
    "parabola": "Fig. 4a's remark that the error decreases for gamma > 1 is not reproduced with "
    "gamma scaling the y channel (it grows, e.g. 0.2375 -> 0.67 mm for gamma = 2 with T1 = 0.01 s, "
    "T2^2 = 0.001 s^2); the figure's parameters are not given.",
    "parabola-horizontal": "Fig. 4b: the error grows for gamma < 1 and for gamma > 1, as the "
    "article says; which branch carries the largest error depends on the figure's parameters, "
    "which are not given.",
}


def servo_notes(params: Params, start: tuple[float, float]) -> list[Note]:
    """What the lesson did with these values and the source caveats that apply to them."""
    curve, gamma = params["curve"], float(params["gamma"])
    notes: list[Note] = []
    moved = {"parabola": ("y0", 1), "cubic": ("y0", 1), "quartic": ("y0", 1)}
    moved["parabola-horizontal"] = ("x0", 0)
    if curve in moved:
        name, i = moved[curve]
        if abs(start[i] - float(params[name])) > 1e-9 * (1.0 + abs(start[i])):
            notes.append(
                Note(
                    "info",
                    f"{name} is taken on the curve: the {curve} starts at "
                    f"({start[0]:.6g}, {start[1]:.6g}) mm.",
                )
            )
    if gamma != 1.0:
        notes.append(
            Note(
                "corrected",
                "Non-identical channels: T1y = gamma T1, T2y^2 = gamma T2^2.",
                f"{ARTICLE}, before (16)",
                "printed 'T_y != gamma T_x'; the line case and (19) use T_y = gamma T_x",
            )
        )
        if curve in FIG4:
            notes.append(Note("warning", FIG4[curve], f"{ARTICLE}, Fig. 4"))
        if curve in ("circle", "ellipse"):
            notes.append(
                Note(
                    "corrected",
                    "The semi-axes (30) use cos^2(phi2 - phi1) in the numerator.",
                    f"{ARTICLE}, (30)",
                    "printed cos; the ellipse's area must be pi m n |cos|, and the simulation "
                    "agrees",
                )
            )
    if params["correction"] == "derivative" and (curve != "parabola" or gamma != 1.0):
        notes.append(
            Note(
                "info",
                "The article gives the error of the derivative feed-forward only for the parabola "
                "with identical channels: delta_article is not defined here.",
                f"{ARTICLE}, conclusions",
            )
        )
    if params["correction"] == "on" and curve in ("cubic", "quartic"):
        notes.append(
            Note(
                "reconstructed",
                "The correction of the cubic/quartic is the rule (20) applied to their PU.",
                f"{ARTICLE}, (20)",
                "the article gives no correction for degree 3 and 4",
            )
        )
    key = (float(params["k"]), float(params["T"]))
    if curve == "parabola" and params["channel"] == "k-T" and key in PARABOLA_TABLE_PRINTED:
        f13 = delta_parabola_13(
            float(params["omega"]), float(params["p"]), 1 / key[0], key[1] / key[0]
        )
        notes.append(
            Note(
                "info",
                f"k = {key[0]:g} 1/s, T = {key[1]:g} s is a cell of the article's table: printed "
                f"{PARABOLA_TABLE_PRINTED[key]} mm; (13) gives {f13:.6g} mm (for omega = 5, p = "
                f"20), "
                "the simulation agrees with (13); every printed cell is 0.8 x (13).",
                f"{ARTICLE}, table",
            )
        )
    return notes
