"""A space curve typed as formulas of phi (1.1): refusals, special points, distances."""

from __future__ import annotations

import math

import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.curves.space_curve import (
    curve_model,
    hausdorff,
    nearest_distance,
    vector_fn,
)
from analyzer_lab.lessons.kit.contract import ParamError

HELIX = ("sin(phi)", "cos(phi)", "phi", 0.0, math.pi)


def test_helix_model():
    cm = curve_model(*HELIX)
    assert cm.arc.S_l == pytest.approx(math.pi * math.sqrt(2), abs=1e-12)
    assert cm.origin_s == () and cm.cusp_s == () and not cm.nonsmooth
    assert cm.min_radius == pytest.approx(1.0, abs=1e-12)
    assert cm.samples[0] == pytest.approx([0.0, 1.0, 0.0]) and len(cm.samples) == 801


def test_constant_coordinate_broadcasts():
    f = vector_fn([curve_model("phi", "2", "0", 0.0, 1.0).exprs[k] for k in range(3)])
    assert f(np.array([0.5, 0.7])).tolist() == [[0.5, 2.0, 0.0], [0.7, 2.0, 0.0]]


def test_origin_pass_and_cusp_are_found():
    line = curve_model("phi", "phi", "phi", -1.0, 1.0)
    assert line.origin_s == pytest.approx((math.sqrt(3),), abs=1e-12)
    cusp = curve_model("phi^3", "phi^2", "0.5", -1.0, 1.0)
    assert len(cusp.cusp_s) == 1 and cusp.cusp_s[0] == pytest.approx(cusp.arc.S_l / 2, rel=1e-9)
    assert curve_model("abs(phi)", "phi", "1", -1.0, 1.0).nonsmooth


@pytest.mark.parametrize(
    "coords,name",
    [
        (("sqrt(phi - 1)", "phi", "0"), "x"),
        (("phi", "1/(phi - 0.5)", "0"), "y"),
        (("1", "2", "3"), "x"),
        (("phi", "phi", "t"), "z"),
    ],
)
def test_bad_curves_are_refused_naming_the_coordinate(coords, name):
    with pytest.raises(ParamError) as err:
        curve_model(*coords, 0.0, 1.0)
    assert err.value.name == name


def test_distances():
    helix = curve_model(*HELIX).arc
    other = curve_model("sin(phi)", "cos(phi)", "1.001*phi", 0.0, math.pi).arc
    assert nearest_distance(other, np.array([[0.0, -1.0, math.pi]]))[0] > 1e-3
    assert nearest_distance(helix, np.array([[0.0, -1.0, math.pi]]))[0] < 1e-12
    assert hausdorff([helix, other]) > 1e-3
