"""The load tool (:mod:`benchmarks.loadtest`, measuring with :mod:`tests.support.load`)
counts the played frames of every kind of lesson: real websocket clients pick the lesson
and its first preset in the page's pickers, press Play and count the frames that update
the live scene."""

from __future__ import annotations

import asyncio
from collections.abc import Callable

import pytest
from analyzer_lab.lessons.catalog import all_lessons, get_lesson
from analyzer_lab.serve.server import DEFAULT_FPS
from analyzer_lab.view.bodies import body_groups, body_node
from analyzer_lab.view.scene import live_node

from tests.support.load import measure, page_plan
from tests.support.servers import ServeProcess
from tests.support.wire import POINT_NODE, live_update

pytestmark = pytest.mark.timeout(300)


def test_live_updates_are_the_nodes_a_frame_moves() -> None:
    body = live_node("body", "leg AA'")
    assert live_update({"type": "SetPositionMessage", "name": body, "position": (0, 0, 1)})
    assert live_update({"type": "SetOrientationMessage", "name": body, "wxyz": (1, 0, 0, 0)})
    assert live_update({"type": "SceneNodeUpdateMessage", "name": POINT_NODE, "updates": {}})
    trail = {"type": "LineSegmentsMessage", "name": live_node("trail", "D") + "/c2", "props": {}}
    assert live_update(trail)
    assert not live_update({"type": "RemoveSceneNodeMessage", "name": body})
    static = {"type": "MeshSimpleMessage", "name": "/lab/static/mesh/sphere", "props": {}}
    assert not live_update(static)
    assert not live_update({"type": "GuiUpdateMessage", "uuid": "x", "updates": {"value": 1}})


def test_every_lesson_has_a_plan_with_its_first_preset() -> None:
    for lesson in all_lessons():
        plan = page_plan(lesson.id)
        assert plan.lesson == lesson.id and lesson.title in plan.lesson_label
        assert plan.preset == (lesson.presets[0].name if lesson.presets else None)
    assert page_plan("sphere", "example-1.2").preset == "example-1.2"


@pytest.fixture(scope="module")
def server(serve: Callable[..., ServeProcess]) -> tuple[str, int]:
    live = serve("sphere")
    return live.url, live.pid


@pytest.mark.parametrize("lesson", ["table-6dof", "constrained-dynamics", "servo-errors"])
def test_pages_of_a_lesson_receive_its_played_frames(server, lesson: str) -> None:
    """Bodies posed (6-DOF table), a pendulum (bob and rod), three points and no body
    (servo errors): every page reads updates, at most one per frame the server plays."""
    url, pid = server
    plan = page_plan(lesson)
    fig = asyncio.run(measure(url, 2, 3.0, plan, pid, 1.0))
    assert fig.errors == []
    assert len(fig.updates_per_s) == 2
    assert min(fig.updates_per_s) > 2.0, fig.updates_per_s
    assert max(fig.updates_per_s) <= DEFAULT_FPS * 1.1
    assert min(fig.mb_per_s) > 0.0
    assert f"| {lesson} | {plan.preset} | 2 |" in fig.markdown_row()
    # the pages play this lesson (picked in the page), not the server's first one
    spec = get_lesson(lesson).scene(get_lesson(lesson).resolve(preset=plan.preset))
    moved = {live_node("point", name) for name in spec.moving_points}
    moved |= {body_node(names) for names in body_groups(spec)}
    assert moved and moved <= fig.nodes, moved - fig.nodes
    assert POINT_NODE not in fig.nodes  # the sphere's point
