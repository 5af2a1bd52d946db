"""Tests of analyzer_lab.lessons.servo.claims: the article's claims, listed by the face."""

from __future__ import annotations

from analyzer_lab.lessons.servo import LESSON
from analyzer_lab.lessons.servo.claims import servo_claims
from analyzer_lab.lessons.servo.claims.contours import claim_circle_28
from analyzer_lab.lessons.servo.claims.parabola import claim_beta


def test_the_face_lists_every_claim_once() -> None:
    ids = [c.id for c in servo_claims()]
    assert len(ids) == len(set(ids)) == 18
    assert [c.id for c in LESSON.claims()] == ids
    modules = {c.check.__module__.rsplit(".", 1)[-1] for c in servo_claims()}
    assert modules == {"contours", "parabola", "correction"}


def test_quick_checks_pass() -> None:
    assert claim_beta().passed
    assert claim_circle_28().passed
