"""Derivation pages of C2.1-C2.6: lessons/mechanics/manipulators/pages.py."""

from __future__ import annotations

from analyzer_lab.lessons.mechanics.manipulators.pages import caveat, derivation_steps, source_of
from analyzer_lab.lessons.mechanics.manipulators.tasks import model_of
from analyzer_lab.lessons.mechanics.self_study_2 import LESSON


def test_each_reading_has_its_own_caveat_and_law() -> None:
    names = ("c2-1c", "c2-1c-constants", "c2-1c-switch-pi-4", "c2-1b", "c2-1b-constant")
    texts = {caveat(LESSON.resolve(preset=n))[0] for n in names}
    assert len(texts) == len(names)
    laws = set()
    for n in names[:3]:
        params = LESSON.resolve(preset=n)
        steps = derivation_steps(params, model_of(params))
        assert steps[0].reconstructed == caveat(params)[0]
        assert steps[-1].title.startswith("Energy integral")
        laws.add(steps[0].math)
    assert len(laws) == 3


def test_sources_name_the_figure() -> None:
    assert source_of("C2.1b") == "C2.1, Fig. 2.13" and source_of("C2.6c") == "C2.6, Fig. 2.6"
    params = LESSON.resolve(preset="c2-6c")
    steps = derivation_steps(params, model_of(params))
    assert [s.source for s in steps if s.title == "Holonomic constraints"] == ["(2.17)"]
