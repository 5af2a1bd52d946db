"""Tests of analyzer_lab.lessons.analyzers.curves.helix: the helix of §1.1, (1.2)-(1.4)."""

from __future__ import annotations

import math

import pytest
from analyzer_lab.lessons.analyzers.curves.helix import (
    HELIX_12,
    HELIX_13,
    HELIX_14,
    SQRT2PI,
    check_radical,
    helix_arc,
    helix_claims,
    helix_hausdorff,
    helix_program,
    helix_reversal_gap,
    reproduction_error,
)
from analyzer_lab.lessons.analyzers.motion_program import LESSON


def test_helix_lengths_and_one_point_set() -> None:
    assert SQRT2PI == pytest.approx(math.pi * math.sqrt(2.0), abs=0)
    for c in (HELIX_12, HELIX_13, HELIX_14):
        assert helix_arc(c).S_l == pytest.approx(SQRT2PI, abs=1e-9)
    assert helix_hausdorff() <= 1e-9
    assert helix_reversal_gap() <= 1e-9


def test_the_root_of_1_4_is_needed() -> None:
    r = check_radical()
    assert r.passed and r.got.endswith("0.8125")


def test_the_analyzer_reproduces_the_helix_and_ends_at_its_end() -> None:
    assert reproduction_error(1.0, 1.0, 1.0) <= 1e-6
    prog = helix_program(1.0, 1.0, 1.0)
    assert prog.Y[-1] == pytest.approx([0.0, -1.0, math.pi], abs=1e-6)


def test_the_claims_are_the_pages() -> None:
    ids = [c.id for c in helix_claims()]
    assert len(ids) == len(set(ids)) == 19
    assert [c.id for c in LESSON.claims()] == ids
