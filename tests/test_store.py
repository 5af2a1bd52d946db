"""The course record against a real SQLite file and a real PostgreSQL server started here:
the schema, rosters, joining, tokens, attempts, and a database that goes down."""

from __future__ import annotations

import itertools
import math
import time
from pathlib import Path
from typing import Any

import pytest
from analyzer_lab.classroom.course import EXPIRED, Course
from analyzer_lab.classroom.store import tokens
from analyzer_lab.classroom.store.records import (
    CheckRecord,
    ClassInfo,
    JoinError,
    NewAttempt,
    RosterEntry,
    RosterError,
    StoreError,
)
from analyzer_lab.classroom.store.roster_csv import parse_roster, read_roster
from analyzer_lab.classroom.store.sql_store import SqlStore
from analyzer_lab.serve.course_record import CourseRecordError, Where, open_course

from tests.support.postgres import PostgresCluster

SECRET = b"k" * 32
ROSTER = [RosterEntry("s1", "Ann Lee", "ann@uni.example", "G1"), RosterEntry("s2", "Bob", "", "G2")]
_names = itertools.count()


@pytest.fixture(scope="module", params=["sqlite", "postgresql"])
def url(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Any:
    if request.param == "sqlite":
        return f"sqlite:///{tmp_path_factory.mktemp('store') / 'record.sqlite3'}"
    cluster: PostgresCluster = request.getfixturevalue("postgres")
    return cluster.url


@pytest.fixture(scope="module")
def store(url: str) -> Any:
    s = SqlStore(url)
    yield s
    s.close()


def _class_name() -> str:
    return f"class-{next(_names)}"


def _attempt(student: int, passed: bool, assignment: str = "a1") -> NewAttempt:
    checks = (CheckRecord("speed", passed, 10.0 if passed else 15.0, 0.0 if passed else 5.0),)
    return NewAttempt(student, assignment, {"u": "2", "k": 1.5}, checks, passed, time.time(), "v1")


def test_schema_is_at_the_newest_revision_and_reopening_changes_nothing(store: SqlStore) -> None:
    from analyzer_lab.classroom.ports import CourseStore

    assert isinstance(store, CourseStore)
    assert store.revision() == "0002"
    info = store.open_class(_class_name(), ROSTER)
    again = SqlStore(store.url)
    try:
        assert again.revision() == "0002"
        assert [s.roster_id for s in again.students(info.id)] == ["s1", "s2"]
    finally:
        again.close()


def test_roster_import_and_reimport_update(store: SqlStore) -> None:
    name = _class_name()
    info = store.open_class(name, ROSTER, join_code="ABCD12")
    assert info.closed and info.join_code == "ABCD12"
    info2 = store.open_class(name, [RosterEntry("s1", "Ann Lee-Smith", "a@x", "G3")])
    assert info2.id == info.id
    got = {(s.roster_id, s.name, s.group) for s in store.students(info.id)}
    assert got == {("s1", "Ann Lee-Smith", "G3"), ("s2", "Bob", "G2")}


def test_attempts_round_trip_with_checks_and_values(store: SqlStore) -> None:
    info = store.open_class(_class_name())
    st = store.enrol(info.id, "Ann")
    nan = NewAttempt(
        st.id, "a1", {"u": float("nan")}, (CheckRecord("c", False, math.inf, math.nan),), False, 5.0
    )
    a1 = store.record(_attempt(st.id, False))
    a2 = store.record(nan)
    got = store.attempts(info.id)
    assert [a.id for a in got] == [a1.id, a2.id]
    assert got[0].values == {"u": "2", "k": 1.5} and got[0].variant == "v1"
    assert got[0].checks == (CheckRecord("speed", False, 15.0, 5.0),)
    assert got[1].checks == (CheckRecord("c", False, None, None),) and got[1].values == {"u": "nan"}
    assert store.attempts(info.id, after=a1.id) == [got[1]]


def test_two_students_with_one_name_stay_two(store: SqlStore) -> None:
    course = Course(store, store.open_class(_class_name(), join_code="JOIN42"), SECRET)
    a = course.join("join42", "Ann")
    b = course.join("JOIN42", "Ann")
    assert a.id != b.id and a.name == b.name == "Ann"
    course.record(a, _grade(True), {"u": "2"})
    assert {x.student_id for x in course.attempts()} == {a.id}
    assert course.restore(course.token(a)).id == a.id
    assert course.restore(course.token(b)).id == b.id


def test_join_refusals_say_why(store: SqlStore) -> None:
    course = Course(store, store.open_class(_class_name(), ROSTER, join_code="JOIN42"), SECRET)
    with pytest.raises(JoinError, match="type the join code"):
        course.join("", "s1")
    with pytest.raises(JoinError, match="unknown join code"):
        course.join("WRONG1", "s1")
    with pytest.raises(JoinError, match="not on this class's roster"):
        course.join("JOIN42", "Mallory")
    ann = course.join("JOIN42", "s1")
    assert ann.roster_id == "s1"
    # another page cannot take Ann's id (or her name) once she joined
    with pytest.raises(JoinError, match="already joined"):
        course.join("JOIN42", "s1")
    with pytest.raises(JoinError, match="already joined"):
        course.join("JOIN42", "ann lee")
    assert course.join("JOIN42", "Bob").roster_id == "s2"  # a roster name joins too


def test_forged_and_foreign_tokens_are_refused(store: SqlStore) -> None:
    course = Course(store, store.open_class(_class_name(), join_code="JOIN42"), SECRET)
    ann = course.join("JOIN42", "Ann")
    bob = course.join("JOIN42", "Bob")
    good = course.token(ann)
    # another's id under Ann's signature
    parts = good.split(".")
    parts[2] = str(bob.id)
    with pytest.raises(JoinError, match="not signed by this server"):
        course.restore(".".join(parts))
    with pytest.raises(JoinError, match="not signed by this server"):
        course.restore(tokens.sign(b"x" * 32, course.info.id, bob.id))
    with pytest.raises(JoinError, match="malformed"):
        course.restore("s1.1.2")
    with pytest.raises(JoinError, match="not a token"):
        course.restore({"student": bob.id})
    other = Course(store, store.open_class(_class_name(), join_code="JOIN43"), SECRET)
    with pytest.raises(JoinError, match="another class"):
        other.restore(good)
    assert course.restore(good) == ann


# ------------------------------------------------------------------ join codes that expire


def _expire(store: SqlStore, name: str) -> ClassInfo:
    """The class's join code made one that expired a second ago (as if its lifetime passed)."""
    import sqlalchemy as sa
    from analyzer_lab.classroom.store.schema import classes

    with store.engine.begin() as conn:
        conn.execute(
            sa.update(classes)
            .where(classes.c.name == name)
            .values(join_code_expires=time.time() - 1.0)
        )
    info = store.get_class(name)
    assert info is not None
    return info


def test_a_join_code_with_a_lifetime_expires_and_joined_students_keep_their_tokens(
    store: SqlStore,
) -> None:
    name = _class_name()
    t0 = time.time()
    info = store.open_class(name, ROSTER, join_code="TERM42", code_lifetime=2 * 3600.0)
    assert info.join_code_expires is not None
    assert t0 + 7200.0 <= info.join_code_expires <= time.time() + 7200.0
    course = Course(store, info, SECRET)
    assert "(expires " in course.code_expiry() and " UTC)" in course.code_expiry()
    ann = course.join("TERM42", "s1")  # within its lifetime
    token = course.token(ann)
    course = Course(store, _expire(store, name), SECRET)
    assert "expired" in course.code_expiry()
    with pytest.raises(JoinError) as err:
        course.join("term42", "s2")
    assert str(err.value) == EXPIRED
    # an unknown code is still told apart from the expired one
    with pytest.raises(JoinError, match="unknown join code"):
        course.join("OTHER1", "s2")
    # Ann's page keeps working: her token brings her back and her attempts are recorded
    assert course.restore(token) == ann
    course.record(course.restore(token), _grade(True), {"u": "2"})
    assert [a.student_id for a in course.attempts()] == [ann.id]
    assert store.find_roster(info.id, "s2") is not None  # Bob was not claimed
    # a new code (without a lifetime) never expires; reopening without one keeps it so
    fresh = store.open_class(name, join_code="NEXT42")
    assert fresh.join_code == "NEXT42" and fresh.join_code_expires is None
    assert Course(store, fresh, SECRET).join("NEXT42", "s2").roster_id == "s2"
    assert store.open_class(name).join_code_expires is None


def test_a_lifetime_alone_applies_to_the_current_code_and_reopening_keeps_it(
    store: SqlStore,
) -> None:
    name = _class_name()
    first = store.open_class(name, join_code="KEEP42")
    assert first.join_code_expires is None
    timed = store.open_class(name, code_lifetime=60.0)
    assert timed.join_code == "KEEP42" and timed.join_code_expires is not None
    again = store.open_class(name)  # a worker opening the class changes nothing
    assert again.join_code_expires == timed.join_code_expires


def test_the_lifetime_migration_keeps_a_class_made_before_it(tmp_path: Path) -> None:
    """A record at revision 0001 (no lifetimes) is upgraded: its classes and students stay,
    their codes never expire."""
    import sqlalchemy as sa
    from alembic import command
    from alembic.config import Config
    from analyzer_lab.classroom.store.sql_store import MIGRATIONS

    url = f"sqlite:///{tmp_path / 'old.sqlite3'}"
    engine = sa.create_engine(url)
    cfg = Config()
    cfg.set_main_option("script_location", str(MIGRATIONS))
    with engine.begin() as conn:
        cfg.attributes["connection"] = conn
        command.upgrade(cfg, "0001")
        conn.execute(
            sa.text(
                "INSERT INTO classes (name, join_code, closed, created) "
                "VALUES ('old', 'OLD42', 0, 1.0)"
            )
        )
    engine.dispose()
    store = SqlStore(url)
    try:
        assert store.revision() == "0002"
        info = store.get_class("old")
        assert info is not None and info.join_code == "OLD42" and info.join_code_expires is None
        assert Course(store, info, SECRET).join("OLD42", "Zed").name == "Zed"
    finally:
        store.close()


def test_an_impossible_lifetime_is_refused_and_changes_nothing(tmp_path: Path) -> None:
    url = f"sqlite:///{tmp_path / 'record.sqlite3'}"
    where = Where(str(tmp_path), url, "life")
    course = open_course(where, join_code="LIFE42", code_hours=1.5)
    before = course.info
    assert before.join_code_expires is not None
    for bad in (0.0, -2.0, float("nan"), float("inf"), 9000.0):
        with pytest.raises(CourseRecordError, match="--join-code-hours must be a number of hours"):
            open_course(where, join_code="LIFE43", code_hours=bad)
    assert course.store.get_class("life") == before
    course.store.close()  # type: ignore[attr-defined]


def test_serve_refuses_a_bad_lifetime_before_it_starts(tmp_path: Path) -> None:
    import subprocess
    import sys

    out = subprocess.run(
        [sys.executable, "-m", "analyzer_lab", "serve", "--no-browser", "--port", "0"]
        + ["--data", str(tmp_path), "--join-code", "LIFE42", "--join-code-hours", "-1"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 2
    assert "--join-code-hours must be a number of hours above 0" in out.stderr


def _grade(passed: bool) -> Any:
    from analyzer_lab.lessons.assignments.grading import CheckOutcome, Grade

    check = CheckOutcome(
        "speed", "series", "speed = 10", passed, 10.0, 1e-6, 0.0 if passed else 5.0, ""
    )
    return Grade("a1", "circle", passed, [check])


# ------------------------------------------------------------------ rosters


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (b"name,email\nAnn,a@x\n", "roster.csv: row 1: missing column 'student id'"),
        (
            b"student id,name\ns1,Ann\ns1,Bob\n",
            "row 3: field 'student id': duplicate id 's1' (also on row 2)",
        ),
        (b"student id,name\ns1,Ann\n\xff\xfe,Bob\n", "roster.csv: row 3: not UTF-8 text"),
        (b"student id,name\ns1,\n", "row 2: field 'name' is empty"),
        (b"", "empty file"),
        (b"student id,name\n", "no students below the header row"),
    ],
)
def test_a_malformed_roster_is_refused_naming_file_row_and_field(data: bytes, message: str) -> None:
    with pytest.raises(RosterError) as err:
        parse_roster(data, "roster.csv")
    assert message in str(err.value)


def test_a_roster_with_a_bom_and_section_header() -> None:
    data = "\ufeffStudent ID,Full name,Email address,Section\n7,Zoë,z@x,B\n".encode()
    assert parse_roster(data) == [RosterEntry("7", "Zoë", "z@x", "B")]


def test_a_malformed_roster_changes_nothing_stored(url: str, tmp_path: Path) -> None:
    name = _class_name()
    good = tmp_path / "good.csv"
    good.write_text("student id,name,email,group\ns1,Ann,a@x,G1\n", encoding="utf-8")
    bad = tmp_path / "bad.csv"
    bad.write_text("student id,name\ns9,Zed\ns1,Bob\ns9,Eve\n", encoding="utf-8")
    where = Where(str(tmp_path), url, name)
    course = open_course(where, str(good))
    before = course.students()
    with pytest.raises(CourseRecordError, match=r"bad\.csv: row 4: field 'student id': duplicate"):
        open_course(where, str(bad))
    assert course.students() == before
    with pytest.raises(RosterError, match="missing.csv: cannot be read"):
        read_roster(tmp_path / "missing.csv")
    course.store.close()  # type: ignore[attr-defined]


# ------------------------------------------------------------------ a database that goes down


def test_postgres_down_refuses_writes_and_loses_nothing(postgres: PostgresCluster) -> None:
    store = SqlStore(postgres.url)
    course = Course(store, store.open_class(_class_name(), join_code="DOWN42"), SECRET)
    ann = course.join("DOWN42", "Ann")
    kept = course.record(ann, _grade(False), {"u": "1"})
    postgres.stop()
    try:
        t0 = time.monotonic()
        with pytest.raises(StoreError, match="unreachable"):
            course.record(ann, _grade(True), {"u": "2"})
        with pytest.raises(StoreError):
            course.attempts()
        assert time.monotonic() - t0 < 30
    finally:
        postgres.start()
    got = course.attempts()
    assert [a.id for a in got] == [kept.id] and not got[0].passed
    course.record(ann, _grade(True), {"u": "2"})
    assert [a.passed for a in course.attempts()] == [False, True]
    store.close()


# ------------------------------------------------------------------ the grades command


def test_the_grades_command_reads_the_record(tmp_path: Path) -> None:
    import csv
    import io
    import subprocess
    import sys

    store = SqlStore(f"sqlite:///{tmp_path / 'analyzer-lab.sqlite3'}")
    course = Course(store, store.open_class("default", ROSTER, join_code="JOIN42"), SECRET)
    ann = course.join("JOIN42", "s1")
    course.record(ann, _grade(False), {"u": "1"})
    course.record(ann, _grade(True), {"u": "2"})
    store.close()

    def grades(*args: str) -> subprocess.CompletedProcess:
        return subprocess.run(
            [sys.executable, "-m", "analyzer_lab", "grades", "--data", str(tmp_path), *args],
            capture_output=True,
            text=True,
            timeout=120,
        )

    out = grades("--format", "canvas")
    assert out.returncode == 0, out.stderr
    rows = list(csv.reader(io.StringIO(out.stdout)))
    assert rows == [
        ["Student", "ID", "SIS User ID", "SIS Login ID", "Section", "a1"],
        ["Ann Lee", "", "s1", "ann@uni.example", "G1", "1"],
        ["Bob", "", "s2", "", "G2", ""],
    ]
    out = grades("--format", "long", "--out", str(tmp_path / "long.csv"))
    assert out.returncode == 0 and out.stdout == ""
    long = list(csv.reader(open(tmp_path / "long.csv", encoding="utf-8")))
    assert long[1][:5] == ["s1", "Ann Lee", "a1", "1", "2"]
    out = grades("--format", "moodle", "--feedback")
    assert out.returncode == 0, out.stderr
    rows = list(csv.reader(io.StringIO(out.stdout)))
    assert rows[0] == ["ID number", "Email address", "Full name", "a1", "a1 (Feedback)"]
    assert rows[1] == ["s1", "ann@uni.example", "Ann Lee", "1", "all checks pass"]
    assert rows[2] == ["s2", "", "Bob", "", ""]
    out = grades("--feedback", "--assignments", str(tmp_path / "missing"))
    assert out.returncode == 2 and "--assignments: " in out.stderr and "missing" in out.stderr
    out = grades("--format", "canvas", "--feedback")
    assert out.returncode == 2 and "use it with --format moodle" in out.stderr
    out = grades("--class", "nope")
    assert out.returncode == 2 and "no class 'nope'" in out.stderr
    out = grades("--db", "mysql://x")
    assert out.returncode == 2 and "--db must be postgresql://" in out.stderr
