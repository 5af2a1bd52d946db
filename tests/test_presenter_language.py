"""The presenter's words in the page's language: its palette entries, its bookmarks and
its "no presets" line follow a switch of the page's language (a real websocket page)."""

from __future__ import annotations

import asyncio
import html
from collections.abc import Callable
from typing import Any

import pytest
from analyzer_lab.classroom.instructor import NO_PRESETS
from analyzer_lab.i18n import language_of
from analyzer_lab.lessons.analyzers.sphere import LESSON as SPHERE

from tests.support.client import ProtoClient
from tests.support.waiting import until

pytestmark = pytest.mark.timeout(120)
RU = language_of("ru")


@pytest.fixture(scope="module")
def lab(make_lab: Callable[..., Any]) -> Any:
    return make_lab(lessons=[SPHERE], lesson="sphere", warm_up=False, restore=False)


def test_the_presenter_speaks_the_pages_language() -> None:
    assert RU.gettext(NO_PRESETS) == "(в этом уроке нет примеров)"


def test_the_palette_and_the_bookmarks_follow_a_switch_of_language(lab: Any) -> None:
    async def go() -> None:
        before = set(lab.views)
        c = await ProtoClient(lab.url).start()
        try:
            await c.wait_for("Run")
            new = await until(lambda: set(lab.views) - before, 10, "the view")
            view = lab.views[max(new)]
            cid = view.client.client_id
            await until(lambda: cid in lab.classroom.presenters, 10, "the presenter")
            p = lab.classroom.presenters[cid]
            with view.session.lock:
                p.set_mode(True)
                assert [x.label for x in p.commands][:2] == ["Next bookmark", "Previous bookmark"]
            await c.set("Language", "Русский")
            await until(lambda: view.language.code == "ru", 10, "the page in Russian")
            with view.session.lock:
                labels = [x.label for x in p.commands]
                assert labels == [
                    "Следующая закладка",
                    "Предыдущая закладка",
                    "Следующая закладка (N)",
                    "Предыдущая закладка (P)",
                ]
                assert p.commands[0].description == "режим показа: переход по примерам урока"
                title = SPHERE.presets[0].title
                assert RU.lesson_text(title) != title  # the catalog has the preset's title
                assert html.escape(RU.lesson_text(title)) in p.bookmarks.content
                assert html.escape(title) not in p.bookmarks.content
                p.set_mode(False)
                assert p.commands == []
        finally:
            await c.close()

    asyncio.run(go())
