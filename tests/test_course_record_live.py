"""The course record with real processes, a real browser and real databases: a student's
attempts survive a page reload, a server restart and ``kill -9`` of the server (no
attempt a page was told about is missing afterwards, on SQLite and on PostgreSQL); with
``--workers 2`` the instructor on worker 1 sees a student's attempt on worker 2 within
2 s; a database that goes down or is full: the page says its attempt is not recorded,
nothing stored changes, the lessons go on."""

from __future__ import annotations

import asyncio
import os
import re
import signal
import subprocess
import sys
import threading
import time
import urllib.request
from pathlib import Path
from typing import Any

import pytest
from analyzer_lab.classroom.store.sql_store import SqlStore

from tests.support.client import ProtoClient
from tests.support.postgres import PostgresCluster
from tests.support.redis_server import RedisServer
from tests.support.servers import free_port
from tests.support.waiting import until, wait_until

pytestmark = pytest.mark.timeout(400)
ROOT = Path(__file__).resolve().parent.parent
TASK = "circle-speed-10"
CODE = "record-4417-course"
JOIN = "JOIN42"
ROSTER = "student id,name,email,group\ns1,Ann Lee,ann@uni.example,G1\ns2,Bob,,G2\ns3,Chen,,G1\n"


class Server:
    """``python -m analyzer_lab serve`` with a course record, in a subprocess."""

    def __init__(self, port: int, args: list[str], ready: str = "Course record:") -> None:
        self.port = port
        self.args = args
        self.ready = ready
        self.lines: list[str] = []
        self.proc: subprocess.Popen | None = None

    def start(self) -> Server:
        env = dict(os.environ, PYTHONPATH=str(ROOT))
        self.lines = []
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "analyzer_lab", "serve", "--no-browser", "--host", "127.0.0.1"]
            + ["--port", str(self.port), "--instructor-code", CODE, "--lesson", "circle"]
            + self.args,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            env=env,
            cwd=ROOT,
        )
        threading.Thread(target=self._read, args=(self.proc,), daemon=True).start()
        deadline = time.monotonic() + 120
        while not any(self.ready in line for line in self.lines):
            assert self.proc.poll() is None, "".join(self.lines)
            assert time.monotonic() < deadline, "".join(self.lines)
            time.sleep(0.1)
        wait_until(self._answers, 60, "the server's HTTP")
        return self

    def _answers(self) -> bool:
        try:
            urllib.request.urlopen(f"http://127.0.0.1:{self.port}/", timeout=1).read(10)
            return True
        except OSError:
            return False

    def _read(self, proc: subprocess.Popen) -> None:
        assert proc.stdout is not None
        for line in proc.stdout:
            self.lines.append(line)

    def tail(self) -> str:
        return "".join(self.lines[-30:])

    def kill9(self) -> None:
        assert self.proc is not None
        self.proc.send_signal(signal.SIGKILL)
        self.proc.wait(10)

    def stop(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(15)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(5)


class Tab:
    """One browser tab on a server (labels as viser shows them)."""

    def __init__(self, context: Any, url: str) -> None:
        self.page = context.new_page()
        self.page.set_default_timeout(90000)  # a busy machine: the page's turn may be late
        self.url = url
        self.open()

    def open(self) -> None:
        self.page.goto(self.url)
        self._ready()

    def reload(self) -> None:
        self.page.reload()
        self._ready()

    def _ready(self) -> None:
        self.label("Lesson").wait_for(timeout=90000)
        wait_until(lambda: self.page.locator("math").count() > 0, 90, "rendered equations")

    def label(self, text: str) -> Any:
        return self.page.locator("label").filter(has_text=re.compile(f"^{re.escape(text)}$")).first

    def input_for(self, label: str) -> Any:
        return (
            self.label(label)
            .locator("xpath=ancestor::div[.//input[not(@type='hidden')]][1]")
            .locator("input:not([type='hidden'])")
            .first
        )

    def fill(self, label: str, text: str) -> None:
        box = self.input_for(label)
        box.fill(text)
        box.press("Enter")
        time.sleep(0.3)

    def select(self, label: str, option: str) -> None:
        self.input_for(label).click()
        self.page.get_by_role("option", name=option, exact=True).click()
        time.sleep(0.3)

    def open_task(self) -> None:
        self.select("Assignment", TASK)
        self.page.locator(".al-assignment-task").first.wait_for(timeout=90000)

    def answer(self, u: str) -> str:
        """Type ``u``, check; returns the verdict the page was told ("yes"/"no")."""
        self.page.get_by_role("tab", name="Controls").click()
        self.fill("u(t) =", u)
        before = self.page.locator(".al-assignment-result").count()
        self.page.get_by_role("button", name="Check my answer", exact=True).click()
        result = self.page.locator(".al-assignment-result, .al-assignment-error")
        wait_until(lambda: result.count() > 0 or before, 30, "a verdict or an error")
        check = self.page.locator(".al-check").first
        check.wait_for(timeout=30000)
        return str(check.get_attribute("data-pass"))


def _who(tab: Tab) -> str:
    """Who the page says it records for ("" until it knows)."""
    who = tab.page.locator(".al-student-who")
    return str(who.first.inner_text()) if who.count() else ""


def _attempts(url: str, roster_id: str) -> list[Any]:
    store = SqlStore(url)
    try:
        info = store.get_class("default")
        assert info is not None
        ids = {s.id for s in store.students(info.id) if s.roster_id == roster_id}
        return [a for a in store.attempts(info.id) if a.student_id in ids]
    finally:
        store.close()


@pytest.fixture(scope="module", params=["sqlite", "postgresql"])
def backend(
    request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory
) -> tuple[list[str], str]:
    """The serve flags of a course record, and its URL."""
    data = tmp_path_factory.mktemp("record-data")
    roster = data / "roster.csv"
    roster.write_text(ROSTER, encoding="utf-8")
    flags = ["--data", str(data), "--roster", str(roster), "--join-code", JOIN]
    if request.param == "sqlite":
        return flags, f"sqlite:///{data / 'analyzer-lab.sqlite3'}"
    cluster: PostgresCluster = request.getfixturevalue("postgres")
    return [*flags, "--db", cluster.url], cluster.url


@pytest.mark.browser
def test_attempts_survive_reload_restart_and_kill_9(
    backend: tuple[list[str], str], browser: Any
) -> None:
    flags, url = backend
    server = Server(free_port(), flags).start()
    context = browser.new_context(viewport={"width": 1100, "height": 900})
    told: list[str] = []
    try:
        tab = Tab(context, f"http://127.0.0.1:{server.port}/")
        tab.open_task()
        tab.fill("Join code", JOIN)
        tab.fill("Your name", "s1")
        told.append(tab.answer("1"))
        assert told == ["no"]
        wait_until(lambda: "Ann Lee (s1)" in _who(tab), 30, "the joined student")
        # a reload brings the student back (the token in the browser's storage)
        tab.reload()
        tab.open_task()
        wait_until(lambda: "Ann Lee (s1)" in _who(tab), 40, "the student after a reload")
        assert not tab.input_for("Your name").is_visible()
        told.append(tab.answer("2"))
        # kill -9 right after the page was told: the attempt is in the record
        server.kill9()
        assert [a.passed for a in _attempts(url, "s1")] == [t == "yes" for t in told]
        server.start()  # the same port: the page's origin, and its storage, are the same
        tab.reload()
        tab.open_task()
        try:
            wait_until(lambda: "Ann Lee (s1)" in _who(tab), 40, "the student after kill -9")
        except AssertionError as exc:
            raise AssertionError(f"{exc}; the server said:\n{server.tail()}") from None
        told.append(tab.answer("2"))
        # a plain restart
        server.stop()
        server.start()
        other = Tab(context, f"http://127.0.0.1:{server.port}/")  # another tab, same browser
        other.open_task()
        wait_until(
            lambda: "Ann Lee (s1)" in _who(other),
            20,
            "the student in another tab",
        )
        told.append(other.answer("1"))
        got = _attempts(url, "s1")
        assert told == ["no", "yes", "yes", "no"]
        assert [a.passed for a in got] == [t == "yes" for t in told]
        assert len({a.student_id for a in got}) == 1
    finally:
        context.close()
        server.stop()


@pytest.mark.browser
def test_a_forged_token_is_refused_and_the_page_told_why(
    backend: tuple[list[str], str], browser: Any
) -> None:
    flags, url = backend
    server = Server(free_port(), flags).start()
    context = browser.new_context(viewport={"width": 1100, "height": 900})
    try:
        tab = Tab(context, f"http://127.0.0.1:{server.port}/")
        tab.open_task()
        tab.fill("Join code", JOIN)
        tab.fill("Your name", "s2")
        tab.answer("1")
        token = tab.page.evaluate(
            "() => window.localStorage.getItem('viser-user:analyzer-lab-student')"
        )
        parts = token.split(".")
        store = SqlStore(url)
        info = store.get_class("default")
        assert info is not None
        ann = next(s for s in store.students(info.id) if s.roster_id == "s3")
        store.close()
        parts[2] = str(ann.id)  # Bob's token, Chen's id
        forged = ".".join(parts)
        tab.page.evaluate(
            "(t) => window.localStorage.setItem('viser-user:analyzer-lab-student', t)", forged
        )
        tab.reload()
        tab.open_task()
        wait_until(
            lambda: (
                "not signed by this server"
                in tab.page.locator(".al-student-refused").all_inner_texts()[0]
                if tab.page.locator(".al-student-refused").count()
                else False
            ),
            60,
            "the refusal of the forged token",
        )
        assert tab.input_for("Your name").is_visible()  # not Chen, not Bob: join again
        # and Bob's own id cannot be taken by a second page
        tab.fill("Join code", JOIN)
        tab.fill("Your name", "s2")
        tab.page.get_by_role("button", name="Check my answer", exact=True).click()
        tab.page.get_by_text("has already joined").first.wait_for(timeout=20000)
        assert _attempts(url, "s3") == []
    finally:
        context.close()
        server.stop()


async def _student_joins(url: str, name: str) -> ProtoClient:
    """A new page opens the assignment and types the join code and ``name``."""
    page = await ProtoClient(url).start()
    await page.wait_for("Check my answer", 60)
    await page.set("Assignment", TASK, 0.3)
    await until(
        lambda: any("al-assignment-task" in h for h in page.html.values()),
        90,
        f"{name}'s assignment opened",
    )
    await page.set("Join code", JOIN, 0.1)
    await page.set("Your name", name, 0.1)
    return page


async def _student_checks(page: ProtoClient, told: int) -> str:
    """Press "Check my answer"; returns the new verdict or error box the page got."""
    seen = {u: h for u, h in page.html.items()}
    await page.click("Check my answer", 0.0)

    def fresh() -> str:
        for u, h in page.html.items():
            if seen.get(u) != h and ("al-assignment-result" in h or "al-assignment-error" in h):
                return h
        return ""

    return await until(fresh, 60, f"the page's answer to check {told + 1}")


def _run_in_thread(coro: Any) -> None:
    """Run ``coro`` on an event loop of its own thread (the module's browser keeps one
    running in this thread)."""
    failed: list[BaseException] = []

    def target() -> None:
        try:
            asyncio.run(coro)
        except BaseException as exc:  # handed to the test's thread
            failed.append(exc)

    worker = threading.Thread(target=target, name="course-record-pages")
    worker.start()
    worker.join()
    if failed:
        raise failed[0]


def _rows(page: ProtoClient) -> list[str]:
    return [h for h in page.html.values() if "al-roster-row" in h]


def test_two_workers_share_the_record_and_a_database_that_goes_down(
    postgres: PostgresCluster, redis_server: RedisServer, tmp_path: Path
) -> None:
    """The instructor on worker 1 sees the attempt of a student on worker 2 within 2 s
    (PostgreSQL shared by both); with the database down the page is told its attempt is
    not recorded and the server goes on serving lessons; back up, attempts are recorded."""
    port = free_port()
    door = Server(
        port,
        ["--workers", "2", "--bus", redis_server.url, "--data", str(tmp_path)]
        + ["--db", postgres.url, "--class", "two-workers", "--join-code", JOIN],
        ready="(front door;",
    ).start()

    async def go() -> None:
        inst = await ProtoClient(f"ws://127.0.0.1:{port + 1}/").start()
        await inst.become_instructor(CODE)
        student = await ProtoClient(f"ws://127.0.0.1:{port + 2}/").start()
        await student.wait_for("Run", 60)
        await student.wait_for("Check my answer", 60)
        await asyncio.sleep(1.0)  # the page's own inputs are in (its token read too)
        await student.set("Assignment", TASK, 0.3)
        await until(
            lambda: any("al-assignment-task" in h for h in student.html.values()),
            90,
            "the assignment opened",
        )
        await student.set("Join code", JOIN, 0.1)
        await student.set("Your name", "Dana", 0.1)
        box = await _student_checks(student, 0)
        assert "al-check" in box, box
        t0 = time.monotonic()
        await until(lambda: any("Dana" in h for h in _rows(inst)), 2.0, "the row on worker 1")
        print(
            f"\n[record] worker 2's attempt on worker 1's table after {time.monotonic() - t0:.2f} s"
        )
        # the database goes down: not recorded, and said so; lessons are still served
        postgres.stop()
        try:
            box = await _student_checks(student, 1)
            assert "could not be recorded" in box and "al-check" not in box, box
            other = await ProtoClient(f"ws://127.0.0.1:{port + 2}/").start()
            await other.wait_for("Run", 60)
            await other.close()
        finally:
            postgres.start()
        box = await _student_checks(student, 2)
        assert "al-check" in box, box
        await until(lambda: any(">2</td>" in h for h in _rows(inst)), 10, "two attempts shown")
        await inst.close()
        await student.close()

    try:
        _run_in_thread(go())
        store = SqlStore(postgres.url)
        info = store.get_class("two-workers")
        assert info is not None
        assert len(store.attempts(info.id)) == 2  # the one refused while down is not there
        store.close()
    finally:
        door.stop()


# ------------------------------------------------------------------ a store that is full


def _fill_up(store: SqlStore) -> None:
    """Write a filler class's attempts until SQLite itself says the file is full (even
    for the smallest row)."""
    from analyzer_lab.classroom.store.records import NewAttempt, StoreError

    other = store.open_class("filler", join_code="FILL42")
    filler = store.enrol(other.id, "filler")
    for size in (2000, 400, 80, 16, 0):  # large rows first, then the pages' last gaps
        for _ in range(10_000):
            pad = {"pad": "x" * size}
            try:
                store.record(NewAttempt(filler.id, "pad", pad, (), False, time.time()))
            except StoreError as exc:
                assert "database or disk is full" in str(exc), exc
                break
        else:
            raise AssertionError("the database never became full")


def test_a_full_store_refuses_attempts_clearly_and_changes_nothing(
    make_lab: Any, tmp_path: Path
) -> None:
    """SQLite made full (``PRAGMA max_page_count`` on every connection the store uses): a
    check is told its attempt was NOT recorded (no verdict), so is a new student's first
    check, nothing stored changes, lessons are still served; with space back the next attempt is
    recorded."""
    import sqlalchemy as sa
    from analyzer_lab.classroom.course import Course
    from analyzer_lab.lessons.catalog import get_lesson

    store = SqlStore(f"sqlite:///{tmp_path / 'record.sqlite3'}")
    limit = [0]  # pages the file may have (0: no limit)

    @sa.event.listens_for(store.engine, "checkout")
    def _limit(dbapi_connection: Any, record: Any, proxy: Any) -> None:
        cur = dbapi_connection.cursor()
        cur.execute(f"PRAGMA max_page_count = {limit[0] or 1_073_741_823}")
        cur.close()

    course = Course(store, store.open_class("full", join_code=JOIN), b"f" * 32)
    lab = make_lab(
        lesson="circle",
        lessons=[get_lesson("circle")],
        instructor_code=CODE,
        warm_up=False,
        course=course,
    )
    url = f"ws://127.0.0.1:{lab.port}/"

    def pages() -> int:
        with store.engine.connect() as conn:
            return int(conn.execute(sa.text("PRAGMA page_count")).scalar_one())

    async def go() -> None:
        student = await _student_joins(url, "Ann")
        box = await _student_checks(student, 0)
        assert "al-check" in box, box
        stored = course.attempts()
        assert len(stored) == 1
        # the file may not grow: filled up to its last page
        limit[0] = pages()
        _fill_up(store)
        students_before = list(course.students())
        attempts_before = course.attempts()
        assert attempts_before == stored
        box = await _student_checks(student, 1)
        assert "could not be recorded" in box and "course record is full" in box, box
        assert "al-check" not in box and "pass" not in box, box
        # a new student's first check is not recorded either, and they are told so
        newcomer = await _student_joins(url, "Bob")
        box = await _student_checks(newcomer, 0)
        assert "could not be recorded" in box and "al-check" not in box, box
        # (the newcomer's own row may fit where an attempt does not: then they joined)
        assert list(course.students())[: len(students_before)] == students_before
        assert course.attempts() == attempts_before
        # the server keeps serving lessons: a new page plays the lesson
        viewer = await ProtoClient(url).start()
        await viewer.wait_for("Run", 60)
        viewer.measuring = True
        await viewer.set("Run", "Play", 0.1)
        await until(lambda: viewer.point_updates >= 5, 60, "a new page's lesson playing")
        # space is back: the next attempt is recorded and its verdict shown
        limit[0] = 0
        box = await _student_checks(student, 2)
        assert "al-check" in box, box
        after = course.attempts()
        assert after[:1] == attempts_before and len(after) == 2
        assert after[1].student_id == stored[0].student_id
        for c in (student, newcomer, viewer):
            await c.close()

    try:
        _run_in_thread(go())
        with store.engine.connect() as conn:
            assert conn.execute(sa.text("PRAGMA integrity_check")).scalar_one() == "ok"
    finally:
        store.close()


# ------------------------------------------------------------------ a join code that expired


async def _open_task(page: ProtoClient) -> None:
    await page.wait_for("Check my answer", 60)
    await page.set("Assignment", TASK, 0.3)
    await until(
        lambda: any("al-assignment-task" in h for h in page.html.values()),
        90,
        "the assignment opened",
    )


def test_an_expired_join_code_is_refused_but_joined_students_go_on(
    make_lab: Any, tmp_path: Path
) -> None:
    """A page typing the class's code after its lifetime is told it expired (another code:
    unknown); a student who joined before comes back with the token their browser kept and
    their attempt is recorded."""
    from analyzer_lab.classroom.course import EXPIRED, TOKEN_KEY, Course
    from analyzer_lab.classroom.store.records import RosterEntry
    from analyzer_lab.lessons.catalog import get_lesson

    store = SqlStore(f"sqlite:///{tmp_path / 'record.sqlite3'}")
    secret = b"e" * 32
    roster = [RosterEntry("s1", "Ann Lee"), RosterEntry("s2", "Bob")]
    before = Course(store, store.open_class("expiring", roster, join_code=JOIN), secret)
    ann = before.join(JOIN, "s1")  # Ann joined while the code was good
    token = before.token(ann)
    info = store.open_class("expiring", code_lifetime=0.5)
    expires = info.join_code_expires
    assert expires is not None
    wait_until(lambda: time.time() > expires, 10, "the code's lifetime to pass")
    course = Course(store, info, secret)
    lab = make_lab(
        lesson="circle",
        lessons=[get_lesson("circle")],
        instructor_code=CODE,
        warm_up=False,
        course=course,
    )
    url = f"ws://127.0.0.1:{lab.port}/"

    async def go() -> None:
        bob = await ProtoClient(url).start()
        await _open_task(bob)
        await bob.set("Join code", "WRONG9", 0.1)
        await bob.set("Your name", "s2", 0.1)
        box = await _student_checks(bob, 0)
        assert "unknown join code" in box and "al-check" not in box, box
        await bob.set("Join code", JOIN.lower(), 0.1)
        box = await _student_checks(bob, 1)
        assert EXPIRED in box and "al-check" not in box, box
        back = await ProtoClient(url, storage={TOKEN_KEY: token}).start()
        await _open_task(back)
        await until(
            lambda: any("Ann Lee" in h for h in back.html.values() if "al-student-who" in h),
            60,
            "Ann recorded from her saved token",
        )
        box = await _student_checks(back, 0)
        assert "al-check" in box, box
        for c in (bob, back):
            await c.close()

    try:
        _run_in_thread(go())
        got = course.attempts()
        assert [a.student_id for a in got] == [ann.id]  # nothing recorded for Bob
    finally:
        store.close()
