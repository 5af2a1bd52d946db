"""The server and the classroom meet through the protocols of
:mod:`analyzer_lab.classroom.ports` (the layers themselves, no circle and the classroom
below the server, are checked by ``tests/test_architecture.py``)."""

from __future__ import annotations

import pytest


@pytest.mark.live
@pytest.mark.timeout(60)
def test_the_server_and_the_classroom_meet_through_the_ports() -> None:
    from analyzer_lab.classroom.ports import Lab, RoomForBoard, RoomForLink, RoomForPanels
    from analyzer_lab.lessons.analyzers.sphere import LESSON as SPHERE
    from analyzer_lab.serve.server import LabServer

    lab = LabServer(host="127.0.0.1", port=0, lessons=[SPHERE], warm_up=False, restore=False)
    try:
        assert isinstance(lab, Lab)
        room = lab.classroom
        for port in (RoomForLink, RoomForPanels, RoomForBoard):
            assert isinstance(room, port), port.__name__
        assert room.lab is lab and room.link.room is room and room.board.room is room
        assert lab.open_views() == []
    finally:
        lab.stop()
