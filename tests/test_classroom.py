"""Classroom: instructor code, follow me / release, and hardening against hand-made clients.

Every page here is a real websocket client speaking viser's protocol
(:class:`tests.support.client.ProtoClient`) against an in-process :class:`LabServer`.
"""

from __future__ import annotations

import asyncio
import math
import statistics
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from analyzer_lab.classroom.instructor_code import normalize_code
from analyzer_lab.classroom.room import INSTRUCTOR_GRACE, Classroom
from analyzer_lab.lessons.analyzers.sphere import LESSON as SPHERE
from analyzer_lab.session.session import LabError

from tests.support.client import ProtoClient, handled
from tests.support.waiting import until
from tests.support.wire import gui_update

CODE = "test-code-4271"
pytestmark = pytest.mark.timeout(120)


@pytest.fixture(scope="module")
def lab(make_lab: Callable[..., Any]) -> Any:
    return make_lab(
        lessons=[SPHERE], lesson="sphere", instructor_code=CODE, warm_up=False, restore=False
    )


@pytest.fixture(autouse=True)
def fresh_room(lab: Any) -> Iterator[None]:
    """Each test starts with no demo, no lockouts."""
    yield
    lab.classroom.release()
    lab.classroom.codes.wrong.clear()
    lab.classroom.codes.addresses.clear()


def run(coro: Any) -> Any:
    return asyncio.run(coro)


async def page(lab: Any) -> tuple[ProtoClient, Any]:
    """A connected page and its server-side view."""
    before = set(lab.views)
    c = await ProtoClient(lab.url).start()
    await c.wait_for("Run")
    new = await until(lambda: set(lab.views) - before, 10, "the view")
    return c, lab.views[max(new)]


async def close(*clients: ProtoClient) -> None:
    for c in clients:
        await c.close()


# ------------------------------------------------------------------ the code


def test_code_normalized_generated_and_compared() -> None:
    assert normalize_code(" Test-Code 42 ") == "testcode42"
    assert normalize_code(None) == "" and normalize_code("x" * 10_000) == "x" * 64

    class FakeLab:
        lessons = ()
        fps = 30.0
        port = 0
        server = None
        ticks = 0
        report_interval = 0.0

        def open_views(self) -> list:
            return []

        def derivation_html(self, lesson: Any, params: Any) -> str:
            return ""

    room = Classroom(FakeLab(), None)  # type: ignore[arg-type]
    try:
        assert len(room.code) == 14 and room.code[4] == room.code[9] == "-"
        assert room.check_code(1, room.code.upper())[0]
        assert not room.check_code(2, "")[0]
    finally:
        room.stop()


def test_wrong_codes_are_rate_limited_per_page_and_address(lab: Any) -> None:
    room = lab.classroom
    for _ in range(3):
        ok, msg = room.check_code(991, "nope", "10.9.9.9")
        assert not ok
    ok, msg = room.check_code(991, CODE, "10.9.9.9")  # its own wrong codes: it waits
    assert not ok and "wait" in msg
    # many pages of one address guessing: the address's bucket stops them (and their
    # new pages after a wrong code: reconnecting does not reset it) ...
    for cid in range(1000, 1012):
        room.check_code(cid, "guess", "10.1.1.1")
    ok, msg = room.check_code(1005, "guess", "10.1.1.1")
    assert not ok and "address" in msg
    ok, msg = room.check_code(3000, "guess", "10.1.1.1")  # a new page: checked once ...
    assert msg.startswith("wrong code; next try in")
    ok, msg = room.check_code(3000, "guess2", "10.1.1.1")  # ... then waits with the others
    assert not ok and "wait" in msg
    # ... but the right code from a page that did not guess works, from any address
    assert room.check_code(2000, CODE, "10.1.1.1") == (True, "ok")
    assert room.check_code(2001, CODE, "10.2.2.2") == (True, "ok")


def test_a_short_chosen_code_is_refused() -> None:
    from analyzer_lab.classroom.room import Classroom

    with pytest.raises(LabError, match="at least 12"):
        Classroom(object(), "short-code")  # type: ignore[arg-type]


def test_nothing_of_the_classroom_is_on_server_gui(lab: Any) -> None:
    async def go() -> None:
        c, view = await page(lab)
        await c.become_instructor(CODE)
        labels = {
            h.label
            for h in lab.server.gui._gui_input_handle_from_uuid.values()
            if hasattr(h, "label")
        }
        assert not labels & {
            "Follow me",
            "Release",
            "Push preset to all",
            "Notify all",
            "Instructor code",
        }
        await close(c)

    run(go())


# ------------------------------------------------------------------ follow me / release


def test_follow_release_late_joiner_and_live_changes(lab: Any) -> None:
    async def go() -> None:
        inst, iv = await page(lab)
        a, av = await page(lab)
        b, bv = await page(lab)
        await a.set("Preset", "example-1.2", 0.3)
        await inst.become_instructor(CODE)
        assert lab.classroom.is_instructor(iv.client.client_id)
        await inst.set("Preset", "example-1.3", 0.3)
        await inst.set("pause at t_end", False)
        await inst.set("Run", "Play")
        await inst.click("Follow me")
        await until(lambda: av.session is iv.session and bv.session is iv.session, 5, "followers")
        # the followers' widgets show the demo's values; a live change reaches them
        await until(lambda: a.values.get(a.gui["Preset"]) == "example-1.3", 5, "preset shown to a")
        await inst.set("u3(t) =", "2.5")
        await until(lambda: iv.session.raw_values()["u3"] == "2.5", 5, "u3 on the instructor")
        assert iv.session.raw_values()["u3"] == "2.5"
        await until(
            lambda: (
                a.values.get(a.gui["u3(t) ="]) == "2.5" and b.values.get(b.gui["u3(t) ="]) == "2.5"
            ),
            5,
            "u3 shown to the followers",
        )
        # one stepping for all: the demo advances once per frame however many follow
        tick = iv.session.shared_clock
        await until(lambda: tick.calls > 2 * tick.advances, 5, "the followers' frames")
        assert tick.advances <= lab.stats.ticks and tick.calls > 2 * tick.advances
        # followers receive the moving point
        a.measuring = True
        await until(lambda: a.point_updates >= 10, 10, "the moving point at a follower")
        a.measuring = False
        assert a.point_updates >= 10
        # the instructor panel counts them
        panel = lab.classroom.instructors[iv.client.client_id]
        panel.update()
        assert (
            "<b>2</b> student(s)" in panel.counts.content
            and '"al-following">2<' in panel.counts.content
        )
        # a late joiner joins the demo
        late, lv = await page(lab)
        await until(lambda: lv.session is iv.session, 5, "late joiner follows")
        t_demo = iv.session.frame.t
        await inst.click("Release")
        await until(
            lambda: all(v.session is not iv.session for v in (av, bv, lv)), 5, "the release"
        )
        for v in (av, bv, lv):
            assert v.session is not iv.session
            assert v.session.lesson.id == "sphere" and v.session.preset == "example-1.3"
            assert v.session.raw_values()["u3"] == "2.5"
            assert v.session.frame.t >= t_demo - 1e-9  # continues from where the demo was
        assert len({id(v.session) for v in (av, bv, lv)}) == 3
        assert not lab.classroom.followers and lab.classroom.demo is None
        assert "tick" not in iv.session.__dict__
        await close(inst, a, b, late)

    run(go())


def test_a_follower_keeps_its_own_language_during_a_demo(lab: Any) -> None:
    async def go() -> None:
        inst, iv = await page(lab)
        a, av = await page(lab)
        await inst.become_instructor(CODE)
        await inst.click("Follow me")
        await until(lambda: av.session is iv.session, 5, "the follower")
        refused = lab.classroom.stats["refused_follower"]
        await a.set("Language", "Русский")
        await until(lambda: av.language.code == "ru", 10, "the follower's page in Russian")
        assert lab.classroom.stats["refused_follower"] == refused  # its language is its own
        await until(lambda: "Векторы" in a.gui, 10, "the follower's controls in Russian")
        assert iv.language.code == "en" and iv.lesson_dd.label == "Lesson"
        assert av.following and av.lesson_dd.disabled  # still following, still read-only
        banner = av.banner.content
        assert "Вы следите за преподавателем" in banner
        await a.set("Preset", "example-1.2")  # any other input is still refused
        await until(lambda: lab.classroom.stats["refused_follower"] > refused, 5, "the refusal")
        await inst.click("Release")
        await until(lambda: av.session is not iv.session, 5, "the release")
        assert av.language.code == "ru"
        await close(inst, a)

    run(go())


def test_push_preset_and_notify_all(lab: Any) -> None:
    async def go() -> None:
        inst, iv = await page(lab)
        a, av = await page(lab)
        await inst.become_instructor(CODE)
        await inst.set("Preset for all", "example-1.2", 0.2)
        await inst.click("Push preset to all", 0.5)
        await until(lambda: av.session.preset == "example-1.2", 5, "pushed preset")
        await inst.set("Message", "look at the pole", 0.1)
        await inst.click("Notify all", 0.3)
        await until(
            lambda: any("look at the pole" in n for n in a.notifications), 5, "notification"
        )
        await close(inst, a)

    run(go())


def test_instructor_leaving_releases_the_class_after_the_grace(lab: Any) -> None:
    """The class goes on following while the instructor's page may come back (a reload:
    the browser test of the reload shows the page taking the demo over), then is
    released with what it watched."""
    room = lab.classroom
    room.instructor_grace = 1.5
    try:

        async def go() -> None:
            inst, iv = await page(lab)
            a, av = await page(lab)
            await inst.become_instructor(CODE)
            await inst.set("Run", "Play", 0.3)
            await inst.click("Follow me", 0.3)
            await until(lambda: av.session is iv.session, 5, "following")
            await until(lambda: iv.session.log.count > 5, 10, "a run watched")
            await close(inst)
            await until(lambda: room.away_until is not None, 5, "the instructor away")
            assert av.session is iv.session and room.is_following(av.client.client_id)
            watched = iv.session.log.count
            await until(lambda: av.session is not iv.session and not room.followers, 10, "released")
            assert room.away_until is None and room.demo is None
            # the released page keeps the run it watched (its plots, its exports)
            assert av.session.log.count >= watched
            assert av.session.log.t[0] == 0.0
            await close(a)

        run(go())
    finally:
        room.instructor_grace = INSTRUCTOR_GRACE


# ------------------------------------------------------------------ hardening


def test_student_cannot_start_stop_or_alter_a_broadcast(lab: Any) -> None:
    async def go() -> None:
        inst, iv = await page(lab)
        s, sv = await page(lab)
        await inst.become_instructor(CODE)
        panel = lab.classroom.instructors[iv.client.client_id]
        # the student sends the instructor's own button ids: nothing happens
        await s.send(gui_update(panel.follow_btn._impl.uuid, True))
        await handled(s, sv)
        assert not lab.classroom.followers and lab.classroom.demo is None
        await inst.click("Follow me", 0.3)
        await until(lambda: sv.session is iv.session, 5, "following")
        for btn in (panel.release_btn, panel.push_btn, panel.notify_btn):
            await s.send(gui_update(btn._impl.uuid, True))
        await s.send(gui_update(panel.message._impl.uuid, "hacked"))
        await handled(s, sv)
        assert sv.session is iv.session and panel.message.value != "hacked"
        # the follower's own controls cannot change the demo
        before = iv.session.raw_values()
        playing = iv.session.playing
        refused = lab.classroom.stats["refused_follower"]
        await s.set("u1(t) =", "99", 0.1)
        await s.set("Run", "Play" if not playing else "Pause", 0.1)
        await s.set("Preset", "example-1.2", 0)
        await until(
            lambda: lab.classroom.stats["refused_follower"] >= refused + 3,
            5,
            "the follower's three inputs refused",
        )
        assert (
            iv.session.raw_values() == before
            and iv.session.playing == playing
            and iv.session.preset != "example-1.2"
        )
        assert lab.classroom.stats["refused_follower"] >= 3
        # and the field the student typed in shows the demo's value again
        await until(lambda: s.values.get(s.gui["u1(t) ="]) == before["u1"], 5, "widget resynced")
        await close(inst, s)

    run(go())


def test_student_cannot_change_another_students_session(lab: Any) -> None:
    async def go() -> None:
        a, av = await page(lab)
        b, bv = await page(lab)
        before = bv.session.raw_values()
        for label, value in (
            ("u1(t) =", "7"),
            ("Run", "Play"),
            ("Preset", "example-1.3"),
            ("sphere radius R", 3.0),
        ):
            await a.send(gui_update(b.gui[label], value))
        await handled(a, av)
        assert (
            bv.session.raw_values() == before
            and not bv.session.playing
            and bv.session.preset != "example-1.3"
        )
        await close(a, b)

    run(go())


def test_share_tunnel_cannot_be_opened(lab: Any) -> None:
    from viser import _messages

    async def go() -> None:
        a, av = await page(lab)
        await a.send(_messages.ShareUrlRequest())
        await handled(a, av)
        assert lab.server._share_tunnel is None
        assert a.seen.get("ShareUrlUpdated", 0) == 0
        await close(a)

    run(go())


def test_out_of_range_nan_and_oversized_values_are_refused(lab: Any) -> None:
    async def go() -> None:
        a, av = await page(lab)
        before = av.session.raw_values()
        await a.set("u1", 1e9, 0.15)  # slider beyond its range
        await a.set("u1", float("nan"), 0.15)
        await a.set("u1", float("inf"), 0.15)
        await a.set("sphere radius R", float("nan"), 0.15)
        await a.set("sphere radius R", -4.0, 0.15)
        await a.set("u2(t) =", "t*" * 5000 + "t", 0.3)  # 10 kB formula
        await a.set("u3(t) =", "1e999", 0.15)
        await a.set("integrator", "euler; import os", 0.15)
        await until(  # inputs over the page's rate are replayed later
            lambda: av.controls.failing() >= {"u1", "u3", "R"}, 5, "the refusals shown"
        )
        assert av.session.raw_values() == before
        assert all(
            math.isfinite(float(v)) for k, v in before.items() if k in ("R", "x0", "y0", "z0")
        )
        # each refusal is shown next to its field, naming it; the typed text stays
        assert {"u1", "u3", "R", "integrator"} & av.controls.failing() >= {"u1", "u3", "R"}
        # a 400 kB message: the transport refuses it from its header ("message too big")
        await a.set("u2(t) =", "x" * 400_000, 0)
        await until(lambda: a.ws.close_code is not None, 5, "the connection closed")
        assert a.ws.close_code == 1009
        assert av.session.raw_values() == before
        await close(a)

    run(go())


async def _rates(client: Any, seconds: float, window: float = 0.5) -> list[float]:
    """The page's point updates per second in consecutive windows."""
    rates = []
    client.measuring = True
    for _ in range(int(seconds / window)):
        start = client.point_updates
        await asyncio.sleep(window)  # a rate: the updates of a window of time
        rates.append((client.point_updates - start) / window)
    client.measuring = False
    return rates


def test_formula_flood_is_rate_limited_and_does_not_slow_others(lab: Any) -> None:
    async def go() -> None:
        # a demo left over from an earlier test (its instructor's disconnect still in
        # flight) would make the new pages followers, whose edits are refused by design
        await until(
            lambda: lab.classroom.broadcaster is None and not lab.classroom.followers,
            30,
            "no demo running",
        )
        obs, ov = await page(lab)
        await obs.set("pause at t_end", False)
        await obs.set("Run", "Play", 0.5)
        base = await _rates(obs, 2.0)
        flood, fv = await page(lab)
        uuid = flood.gui["u1(t) ="]
        applied_before = lab.classroom.stats["admitted"]
        sent = 0
        t0 = time.monotonic()
        for k in range(600):  # as fast as the socket takes them
            sent += 1
            await flood.send(gui_update(uuid, f"sin({k % 97 + 1}*t)"))
        await flood.send(gui_update(uuid, "cos(3*t)"))
        during_task = asyncio.ensure_future(_rates(obs, 2.0))
        # the server paces this one connection (150 messages/s): the flooder waits on itself
        await until(
            lambda: fv.session.raw_values()["u1"] == "cos(3*t)", 60, "the newest value applied"
        )
        dt = time.monotonic() - t0
        during = await during_task
        applied = lab.classroom.stats["admitted"] - applied_before
        assert dt > 2.0  # paced
        assert applied <= 5 * dt + 10, (applied, sent)  # formula edits cost 4 tokens of 20/s
        # superseded edits are dropped (coalesced) or refused, never all applied in turn
        assert applied < sent, (applied, sent, lab.classroom.stats)
        # medians of half-second rates: one slow half-second of a busy machine is not a trend
        assert statistics.median(during) >= 0.75 * statistics.median(base), (base, during)
        await close(obs, flood)

    run(go())


@pytest.mark.slow
@pytest.mark.timeout(300)
@pytest.mark.skipif(
    __import__("os").environ.get("ANALYZER_LAB_SLOW") != "1",
    reason="a 1-minute soak; set ANALYZER_LAB_SLOW=1",
)
def test_short_soak_keeps_memory_and_leaves_no_sessions() -> None:
    import subprocess
    import sys

    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "benchmarks.soak",
            "--minutes",
            "1",
            "--students",
            "6",
            "--churn",
            "2",
            "--warmup",
            "20",
        ],
        capture_output=True,
        text=True,
        timeout=240,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    assert "no orphaned sessions" in out.stdout and "-> OK (limit 10%)" in out.stdout


# ------------------------------------------------------------------ the assignments table


def _rows(c: ProtoClient) -> dict[str, str]:
    """The instructor's table rows on the page (element -> its HTML)."""
    return {u: h for u, h in c.html.items() if "al-roster-row" in h}


def test_the_table_sends_one_row_per_check_and_names_arrive_cleaned(lab: Any) -> None:
    """Real pages check answers; the instructor's page gets one element per check (the
    student's row), never the whole table; a name with U+202E, NUL and direction marks
    reaches the table cleaned."""
    from analyzer_lab.classroom.roster import clean_name

    names = [f"Student {k:02d}" for k in range(8)] + ["\u202eAnn\x00\u200f  Lee\u2066\n"]

    async def go() -> None:
        inst, _ = await page(lab)
        await inst.become_instructor(CODE)
        students = [(await page(lab))[0] for _ in names]
        for s, name in zip(students, names, strict=True):
            await s.set("Assignment", "sphere-equator", 0.2)
            await s.set("Your name", name, 0.05)
        for s in students:  # a first check each: a new row each
            before = dict(inst.html)
            n = len(_rows(inst))
            await s.click("Check my answer", 0.0)
            await until(lambda n=n: len(_rows(inst)) == n + 1, 20, "the new row")
            await asyncio.sleep(0.2)
            changed = [u for u, h in _rows(inst).items() if before.get(u) != h]
            assert len(changed) == 1 and inst.html[changed[0]].count("al-roster-row") == 1
        shown = " ".join(_rows(inst).values())
        assert "Ann Lee" in shown and "\u202e" not in shown and "\x00" not in shown
        assert clean_name(names[-1]) == "Ann Lee"
        # a second check by one student: only that row is sent again
        row_of = {u: h for u, h in _rows(inst).items() if "Student 03" in h}
        before = dict(inst.html)
        inst.bytes, inst.measuring = 0, True
        await students[3].click("Check my answer", 0.0)
        await until(
            lambda: any(before.get(u) != h for u, h in _rows(inst).items()), 20, "the changed row"
        )
        await asyncio.sleep(0.3)
        inst.measuring = False
        changed = [u for u, h in inst.html.items() if before.get(u) != h and "al-roster" in h]
        assert changed == list(row_of), changed
        assert ">2</td>" in inst.html[changed[0]]  # two attempts
        assert not any(h.count("al-roster-row") > 1 for h in inst.html.values())
        print(f"\n[roster] bytes to the instructor for one check: {inst.bytes}")
        await close(inst, *students)

    run(go())
