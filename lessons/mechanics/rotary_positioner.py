"""Problem 2.2: the rotary positioner, eqs (2.3)-(2.4).

A rotor carries three point masses m_i at distances h_i from the axis Z.  The moment
equation about Z (2.3), ``J_z,pr phi'' = sum M_z(F^e)``, with the reduced moment of
inertia (2.4) ``J_z,pr = sum m_i h_i^2``, here derived by ``LagrangesMethod`` from the
kinetic energy of the three masses and the virtual work of the drive moment M_dv and the
resisting moment M_c.  Forward problem: the moments give the turn phi(t); inverse
problem: a law phi(t) gives the drive moment.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
import trimesh
from analyzer_lab.lessons.kit.bodies import bounds_of, combine, cylinder, quat_z
from analyzer_lab.lessons.kit.contract import (
    Claim,
    ClaimResult,
    DerivationStep,
    Frame,
    Param,
    ParamError,
    Params,
    PlotSpec,
    Preset,
    SceneSpec,
    Series,
    close,
)
from analyzer_lab.lessons.kit.formula import t_symbol
from analyzer_lab.lessons.mechanics.lagrange.model import LagrangeModel
from analyzer_lab.lessons.mechanics.positioners.lesson import (
    T_,
    Coord,
    Input,
    PositionerLesson,
    arrow,
    is_zero,
    positioner_groups,
    positioner_params,
    positioner_series,
    sym,
    symbolic_claim,
)
from sympy.physics.mechanics import Point, ReferenceFrame, dynamicsymbols

Array = np.ndarray


class RotaryPositioner(PositionerLesson):
    """Problem 2.2: J_z,pr phi'' = sum M_z(F^e) (2.3), J_z,pr = sum m_i h_i^2 (2.4)."""

    id = "rotary-positioner"
    title = "Rotary positioner"
    problem = "Problem 2.2"
    source = "Textbook §2.1, Problem 2.2, eqs (2.3)-(2.4)"
    summary = (
        "Three masses m_i at distances h_i from the axis Z: (sum m_i h_i^2) phi'' = M_dv - M_c."
    )
    order = 2.02
    coords = (Coord("phi", "phi", "rad", 0.0, "pi/2*(t - sin(t))/(2*pi)"),)
    inputs = (
        Input("M_dv", "drive moment M_dv", "N m", "0.2*sin(t)"),
        Input("M_c", "resisting moment M_c", "N m", "0", unknown=False),
    )
    physical = ("m1", "h1", "m2", "h2", "m3", "h3")
    groups = positioner_groups("Rotor: masses m_i at radii h_i")
    params = positioner_params(
        coords,
        inputs,
        tuple(
            Param(n, "float", v, label=n, unit=u, min=0.0, max=hi, group="body")
            for n, v, u, hi in (
                ("m1", 1.0, "kg", 1e3),
                ("h1", 0.2, "m", 10.0),
                ("m2", 0.5, "kg", 1e3),
                ("h2", 0.3, "m", 10.0),
                ("m3", 2.0, "kg", 1e3),
                ("h3", 0.1, "m", 10.0),
            )
        ),
    )
    series = (
        *positioner_series(coords, inputs),
        Series("J_z", "kg m^2", "reduced moment of inertia J_z,pr = sum m_i h_i^2 (2.4)"),
    )
    readout = ("phi", "phi_dot", "phi_ddot", "M_dv")
    presets = (
        Preset(
            "forward-harmonic-moment",
            "Forward: M_dv = 0.2 sin t",
            {"problem": "forward"},
            t_end=10.0,
        ),
        Preset(
            "forward-constant-moment",
            "Forward: M_dv = 0.1 N m, M_c = 0.02 N m",
            {"problem": "forward", "M_dv": "0.1", "M_c": "0.02"},
            t_end=5.0,
        ),
        Preset(
            "inverse-quarter-turn",
            "Inverse: a smooth quarter turn per 2 pi s",
            {"problem": "inverse"},
            t_end=10.0,
        ),
    )
    plots = (
        PlotSpec("Angle", ("phi",), "rad"),
        PlotSpec("Angular velocity", ("phi_dot",), "rad/s"),
        PlotSpec("Moments", ("M_dv", "M_c"), "N m"),
    )

    def validate(self, params: Params) -> None:
        J = sum(float(params[f"m{i}"]) * float(params[f"h{i}"]) ** 2 for i in (1, 2, 3))
        if J <= 0:
            raise ParamError(
                "m1",
                (
                    "the reduced moment of inertia sum m_i h_i^2 is zero: give some mass a "
                    "non-zero radius"
                ),
            )

    def extra_series(self, params: Params, q: Array, qd: Array, qdd: Array) -> dict[str, Array]:
        J = sum(float(params[f"m{i}"]) * float(params[f"h{i}"]) ** 2 for i in (1, 2, 3))
        return {"J_z": np.full(q.shape[1], J)}

    problem_notes = (
        "Inverse problem: M_c stays as given; M_dv is the moment the law phi(t) needs, (2.3).",
        "Forward problem: the motion law phi(t) is not used.",
        "(2.3)",
    )

    def build_model(self, key: str) -> LagrangeModel:
        phi = dynamicsymbols("phi")
        ms = [sym(f"m{i}", nonnegative=True) for i in (1, 2, 3)]
        hs = [sym(f"h{i}", nonnegative=True) for i in (1, 2, 3)]
        Md, Mc = sym("M_dv"), sym("M_c")
        N = ReferenceFrame("N")
        R = N.orientnew("R", "Axis", [phi, N.z])
        R.set_ang_vel(N, phi.diff(T_) * N.z)
        O = Point("O")
        O.set_vel(N, 0)
        T = sp.S.Zero
        for k, (m, h) in enumerate(zip(ms, hs)):
            ang = 2 * sp.pi * k / 3
            P = O.locatenew(f"P{k}", h * (sp.cos(ang) * R.x + sp.sin(ang) * R.y))
            P.v2pt_theory(O, N, R)
            T += m * P.vel(N).dot(P.vel(N)) / 2
        return LagrangeModel.build(
            [phi],
            sp.simplify(T),
            sp.S.Zero,
            T_,
            [*[v for pair in zip(ms, hs) for v in pair]],
            [Md, Mc],
            forcelist=[(R, (Md - Mc) * N.z)],
            frame=N,
        )

    def derivation(self, params: Params) -> list[DerivationStep]:
        m = self.model(params)
        phi = m.q[0]
        ms = [m.params[0], m.params[2], m.params[4]]
        hs = [m.params[1], m.params[3], m.params[5]]
        J = sp.Symbol(r"J_{z\,pr}")
        Md, Mc = m.inputs
        steps = [
            DerivationStep(
                "Kinetic energy of the rotating masses",
                "Each point M_i moves on a circle of radius h_i about Z.",
                sp.Eq(sp.Symbol("T"), m.lagrangian),
            ),
            DerivationStep(
                "Reduced moment of inertia",
                "",
                sp.Eq(J, sum(mi * hi**2 for mi, hi in zip(ms, hs))),
                "(2.3)",
            ),
            DerivationStep(
                "Equation of rotation (Lagrange equation of the 2nd kind)",
                "Moment of the drive and the resistance about Z.",
                m.equations()[0],
                "(2.4)",
            ),
        ]
        if params["problem"] == "inverse":
            law = params["phi_t"].expr.subs(t_symbol, T_)
            steps.append(
                DerivationStep(
                    "Inverse problem",
                    "The drive moment the law needs.",
                    sp.Eq(
                        Md,
                        sp.simplify(
                            sum(mi * hi**2 for mi, hi in zip(ms, hs)) * sp.diff(law, T_, 2) + Mc
                        ),
                    ),
                    "(2.4)",
                )
            )
        else:
            steps.append(
                DerivationStep(
                    "Forward problem", "", sp.Eq(phi.diff(T_, 2), (Md - Mc) / J), "(2.3)"
                )
            )
        return steps

    def scene_size(self, params: Params) -> float:
        return 2.6 * max(float(params[f"h{i}"]) for i in (1, 2, 3))

    def scene(self, params: Params) -> SceneSpec:
        R = max(float(params[f"h{i}"]) for i in (1, 2, 3))
        parts = [trimesh.creation.cylinder(radius=0.08 * R, height=0.2 * R)]
        for k in range(3):
            h = float(params[f"h{k + 1}"])
            ang = 2 * np.pi * k / 3
            c = np.array([np.cos(ang), np.sin(ang), 0.0])
            if h > 0:
                arm = trimesh.creation.box(extents=[h, 0.03 * R, 0.03 * R])
                arm.apply_transform(trimesh.transformations.rotation_matrix(ang, [0, 0, 1]))
                arm.apply_translation(c * h / 2)
                parts.append(arm)
            ball = trimesh.creation.icosphere(
                subdivisions=2, radius=0.04 * R * (1 + float(params[f"m{k + 1}"])) ** (1 / 3)
            )
            ball.apply_translation(c * h)
            parts.append(ball)
        rotor = combine("rotor", parts, (200, 140, 60))
        axis = cylinder("axis Z", 0.01 * R, 1.2 * R, (60, 60, 60))
        pts = np.array([[-1.3 * R, -1.3 * R, -0.6 * R], [1.3 * R, 1.3 * R, 0.8 * R]])
        return SceneSpec(
            bounds=bounds_of(pts, 0.02),
            meshes=[axis],
            bodies=[rotor],
            moving_vectors={"M_dv": (40, 160, 60), "M_c": (200, 60, 60)},
            moving_points={"M1": (200, 60, 60)},
        )

    def pose(self, params: Params, fr: Frame, q: Array, u: Array, scale: float) -> None:
        phi = float(q[0])
        R = max(float(params[f"h{i}"]) for i in (1, 2, 3))
        fr.poses["rotor"] = (np.zeros(3), quat_z(phi))
        h1 = float(params["h1"])
        fr.points["M1"] = np.array([[h1 * np.cos(phi), h1 * np.sin(phi), 0.0]])
        fr.vectors["M_dv"] = arrow([0, 0, 0.15 * R], [0, 0, scale * u[0]])
        fr.vectors["M_c"] = arrow([0.02 * R, 0, 0.15 * R], [0, 0, -scale * u[1]])

    def claims(self) -> list[Claim]:
        def eq_ok() -> bool:
            m = self.model(self.resolve())
            phi = m.q[0]
            J = sum(m.params[2 * k] * m.params[2 * k + 1] ** 2 for k in range(3))
            return is_zero(m.eom()[0] - (J * phi.diff(T_, 2) - (m.inputs[0] - m.inputs[1])))

        def constant() -> ClaimResult:
            r = self.run("forward-constant-moment")
            J = 1.0 * 0.04 + 0.5 * 0.09 + 2.0 * 0.01
            return close(0.08 / J * 25 / 2, float(r.series["phi"][-1]), rtol=1e-8)

        return [
            Claim(
                "eq-2.3-2.4",
                (
                    "LagrangesMethod on three point masses gives (sum m_i h_i^2) phi'' = M_dv - "
                    "M_c, i.e. J_z,pr = sum m_i h_i^2"
                ),
                "(2.3)-(2.4)",
                symbolic_claim(eq_ok, "(2.4)"),
            ),
            Claim(
                "forward-constant",
                (
                    "Forward: M_dv - M_c = 0.08 N m on J = 0.105 kg m^2 from rest: phi(5) = "
                    "0.08/0.105 * 25/2 = 9.524 rad"
                ),
                "(2.3)",
                constant,
            ),
            Claim(
                "round-trip-forward-inverse",
                "Forward then inverse recovers M_dv = 0.2 sin t (within 1e-4 of its peak)",
                "(2.4)",
                self.forward_inverse_check(
                    {"M_dv": "0.2*sin(t)", "M_c": "0.01"}, "max |M_dv recovered - M_dv| "
                ),
            ),
            Claim(
                "round-trip-inverse-forward",
                "Inverse then forward reproduces the law phi(t) to 1e-8 rad",
                "(2.4)",
                self.inverse_forward_check({}, "max |phi forward - phi law| (rad) "),
            ),
        ]


LESSON = RotaryPositioner()
