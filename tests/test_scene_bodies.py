"""Posed bodies of one mesh drawn as one batched node (app/view/bodies.py)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import analyzer_lab.viser_boundary as vb
import numpy as np
import pytest
from analyzer_lab.lessons.catalog import all_lessons
from analyzer_lab.session.session import Session
from analyzer_lab.view.bodies import BodyGroup, body_groups, body_node

pytestmark = pytest.mark.quick

LESSONS = all_lessons()


def test_the_tables_legs_and_inductors_are_one_node_each() -> None:
    spec = Session(LESSONS, "table-6dof", "inverse-program").scene
    groups = body_groups(spec)
    assert list(groups) == [
        ("table",),
        ("inductor A", "inductor B", "inductor C"),
        ("leg AA'", "leg BB'", "leg CC'"),
    ]
    assert body_node(("table",)) == "/lab/live/body/table"
    assert body_node(("leg AA'", "leg BB'")) == "/lab/live/body/leg_AA__leg_BB_"
    # colours may differ within a group, the mesh may not
    assert len({b.color for b in groups[("inductor A", "inductor B", "inductor C")]}) == 3


def test_bodies_of_different_meshes_stay_apart() -> None:
    for lesson in ("laser-5axis", "planar-3axis", "constrained-dynamics"):
        spec = Session(LESSONS, lesson, None).scene
        for names, bodies in body_groups(spec).items():
            meshes = {np.asarray(b.vertices, np.float32).tobytes() for b in bodies}
            assert len(meshes) == 1, (lesson, names)


@pytest.fixture(scope="module")
def server() -> Iterator[Any]:
    s = vb.make_viser_server("127.0.0.1", 0, verbose=False)
    yield s
    s.stop()


def test_a_group_sends_its_members_poses_once_per_change(server: Any) -> None:
    verts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    faces = np.array([[0, 1, 2]], np.uint32)
    group = BodyGroup(("a", "b"), np.zeros((2, 3), np.float32), np.zeros((2, 4), np.float32))
    group.wxyzs[:, 0] = 1.0
    group.handle = server.scene.add_batched_meshes_simple(
        "/t/group", verts, faces, group.wxyzs.copy(), group.positions.copy()
    )
    sent: list[str] = []
    queue = group.handle._queue_update
    group.handle._queue_update = lambda name, value: (sent.append(name), queue(name, value))
    pa, pb = np.array([1.0, 2.0, 3.0]), np.array([-1.0, 0.5, 0.0])
    qa, qb = np.array([0.6, 0.8, 0.0, 0.0]), np.array([0.0, 0.0, 1.0, 0.0])
    group.pose({"a": (pa, qa), "b": (pb, qb), "other": (pa, qa)})
    assert sent == ["batched_positions", "batched_wxyzs"]
    assert np.allclose(group.handle.batched_positions, [pa, pb])
    assert np.allclose(group.handle.batched_wxyzs, [qa, qb])
    group.pose({"a": (pa, qa), "b": (pb, qb)})  # nothing moved: nothing sent
    group.pose({"a": (pa + 1e-9, qa)})  # within numpy.allclose; b keeps its pose
    assert sent == ["batched_positions", "batched_wxyzs"]
    group.pose({"b": (pb + 1.0, qb)})  # only positions
    assert sent[-1] == "batched_positions" and len(sent) == 3
    assert np.allclose(group.handle.batched_positions, [pa, pb + 1.0])


def test_instance_colors_undo_the_srgb_curve() -> None:
    from analyzer_lab.view.bodies import instance_colors

    got = instance_colors([(0, 255, 90), (10, 128, 200)])
    assert got.dtype == np.uint8
    assert got.tolist() == [[0, 255, 26], [1, 55, 147]]
