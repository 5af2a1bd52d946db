"""Assignments in the browser: a student opens one, answers with the allowed controls
and presses "Check my answer"; the instructor pushes one to every page, follows the
class in a live table (CSV download) and authors new ones from the current state.

One :class:`AssignmentBoard` per classroom (``room.board``) holds the assignments
(the ready ones plus ``serve --assignments DIR``), the pushed one and the
:class:`~analyzer_lab.classroom.course.Course` (the course record: who each page is,
every attempt written before its verdict is shown); it knows the classroom as a
:class:`~analyzer_lab.classroom.ports.RoomForBoard`.  Each page gets a :class:`StudentPanel`;
the instructor's page also a :class:`TeacherPanel` (with the authoring fields).  The
classroom tells the board of its pages with four calls (:meth:`~AssignmentBoard.attach`,
:meth:`~AssignmentBoard.detach`, :meth:`~AssignmentBoard.grant`,
:meth:`~AssignmentBoard.released`).  Checks run the lesson's own model on the session's
values of the unlocked parameters (the locked ones come from the assignment), so a
locked field cannot change a verdict even if a hand-made client sends it.
"""

from __future__ import annotations

import html
import json
import logging
import os
import sys
import threading
import time
from collections.abc import Set
from typing import TYPE_CHECKING, Any

from analyzer_lab.classroom.course import TOKEN_KEY, Course
from analyzer_lab.classroom.grader import GradeOutcome, Grader, GraderBusy
from analyzer_lab.classroom.ports import RoomForBoard
from analyzer_lab.classroom.roster import Progress, clean_name, head_html, row_html
from analyzer_lab.classroom.store.grades import export as export_grades
from analyzer_lab.classroom.store.records import JoinError, StoreError, Student
from analyzer_lab.classroom.table_rows import RowTable
from analyzer_lab.i18n import ENGLISH, N_, Language
from analyzer_lab.lessons.assignments import (
    Assignment,
    AssignmentError,
    Grade,
    Release,
    Variant,
    load_folder,
    ready_assignments,
    release,
)
from analyzer_lab.lessons.assignments import draft as draft_assignment
from analyzer_lab.lessons.assignments.spec import said
from analyzer_lab.lessons.assignments.variants import DEFAULT_CLASS
from analyzer_lab.lessons.kit.message import Message
from analyzer_lab.session.session import LabError
from analyzer_lab.viser_boundary import sent_value

if TYPE_CHECKING:
    from analyzer_lab.view.page import SessionView

log = logging.getLogger(__name__)

NONE = N_("(none)")  # the picker's "no assignment", shown in the page's language
#: What the instructor's authoring folder says it does.
AUTHORING = N_(
    "The current lesson and values become the assignment; its goal:"
    " the chosen series end where they end now and stay as small as"
    " now, the chosen metrics (e.g. A0, T, deviation_max_um) stay at"
    " their values."
)
#: Seconds between two reads of the course record for the instructor's table (the
#: attempts of pages on other workers arrive within this).
POLL_SECONDS = 1.0
#: Seconds a page waits for its browser's saved student token (in a thread of its own; a
#: check meanwhile waits for it rather than joining a second time).
TOKEN_WAIT = 3.0
TOKEN_TRIES = 5
#: Seconds a check waits for that token (then the page joins with what it typed).
CHECK_WAIT = 3.0
NOT_RECORDED = N_(
    "Your attempt could not be recorded: {why}. It is not in the course record and does "
    "not count yet; check again in a moment."
)
#: The task of an assignment authored from a run, when the instructor types none.
REPRODUCE = N_("Reproduce this run of {title}.")
ENV_FOLDER = "ANALYZER_LAB_ASSIGNMENTS"  # analyzer_lab.serve.cli_assignments.ENV_FOLDER
esc = html.escape


def _box(body: str, colour: str = "#333", cls: str = "") -> str:
    return (
        f'<div class="{cls}" style="font-size:0.88em;color:{colour};line-height:1.35">{body}</div>'
    )


def task_html(a: Assignment, language: Language = ENGLISH) -> str:
    """The task as the student sees it in ``language`` (the file's text in that language
    when it gives one; every text escaped)."""
    tr = language.gettext
    checks = "".join(f"<li>{esc(language.message(c.describe()))}</li>" for c in a.checks)
    hint = a.hint_in(language.code)
    may, locked, goal = tr("You may change:"), tr("(the other fields are locked)"), tr("Goal:")
    hint_head = tr("Hint:")
    numbers = tr("Your numbers: {numbers}").format(numbers=_numbers(a)) if a.variant else ""
    return _box(
        f"<b>{esc(a.title_in(language.code))}</b> <span style='color:#555'>({esc(a.lesson)})</span><br>"
        f"{esc(a.task_in(language.code))}<br><b>{esc(may)}</b> "
        f"{esc(', '.join(a.unlocked))} {esc(locked)}<br><b>{esc(goal)}</b>"
        f"<ul style='margin:2px 0 2px 1.1em;padding:0'>{checks}</ul>"
        + (f"<i>{esc(hint_head)}</i> {esc(hint)}<br>" if hint else "")
        + (
            f"<span class='al-variant' style='color:#555'>{esc(numbers)}</span><br>"
            if numbers
            else ""
        )
        + (f"<span style='color:#555'>{esc(a.reference)}</span>" if a.reference else ""),
        cls="al-assignment-task",
    )


def _numbers(a: Assignment) -> str:
    return ", ".join(f"{k} = {v:.12g}" for k, v in a.variant.items())


def verdict_html(g: Grade, language: Language = ENGLISH, a: Assignment | None = None) -> str:
    """Which checks pass and by how much the others miss, in ``language``: each check
    described from ``a``'s own check and its feedback in that language when the file gives
    it; a grade that came back as plain text (from the store or the bus) shows its text."""
    tr = language.gettext
    checks = {c.id: c for c in a.checks} if a is not None else {}
    items = []
    for c in g.checks:
        check = checks.get(c.id)
        feedback = check.feedback_in(language.code, c.passed) if check else c.feedback
        text = language.message(check.describe() if check else c.text)
        mark, colour = (
            ("✓ " + tr("pass"), "#1b7a2e") if c.passed else ("✗ " + tr("fail"), "#a61b1b")
        )
        items.append(
            f"<li class='al-check' data-check='{esc(c.id)}' data-pass='{'yes' if c.passed else 'no'}'>"
            f"<b style='color:{colour}'>{esc(mark)}</b> {esc(text)}<br>"
            f"<span style='color:#555'>{esc(language.message(c.message))}</span>"
            + (
                f"<br><span class='al-check-feedback' style='color:#1a4d8f'>{esc(feedback)}</span>"
                if feedback
                else ""
            )
            + "</li>"
        )
    failing = language.ngettext(
        "{failed} of {total} check fails.", "{failed} of {total} checks fail.", len(g.checks)
    ).format(failed=len(g.failed), total=len(g.checks))
    passing = tr("All checks pass.")
    head = (
        f"<b style='color:#1b7a2e'>{esc(passing)}</b>"
        if g.passed
        else f"<b style='color:#a61b1b'>{esc(failing)}</b>"
    )
    return _box(
        f"{head}<ul style='margin:2px 0 0 1.1em;padding:0'>{''.join(items)}</ul>",
        cls="al-assignment-result",
    )


def error_html(message: str) -> str:
    return _box(esc(message), "#a61b1b", "al-field-error al-assignment-error")


def load_assignments(lesson_ids: Set[str]) -> dict[str, Assignment]:
    """The ready assignments and those of ``serve --assignments DIR`` (the folder wins on
    a shared id) that are about one of ``lesson_ids``; a folder that cannot be read is
    reported and left out."""
    found: dict[str, Assignment] = {}
    folder = os.environ.get(ENV_FOLDER)
    for load in (ready_assignments, lambda: load_folder(folder) if folder else []):
        try:
            for a in load():
                found[a.id] = a
        except AssignmentError as exc:  # a page must open even without them
            print(f"analyzer-lab: assignments ignored: {exc}", file=sys.stderr)
    return {k: a for k, a in found.items() if a.lesson in lesson_ids}


class AssignmentBoard:
    """The classroom's assignments, the pushed one, the course record and every page's
    panel."""

    def __init__(
        self, room: RoomForBoard, lesson_ids: Set[str], course: Course | None = None
    ) -> None:
        self.room = room
        self.lesson_ids = frozenset(lesson_ids)
        self.lock = threading.RLock()
        self._assignments: dict[str, Assignment] | None = None
        self.pushed: str | None = None
        #: the class's course record (an in-memory one when the server was given none)
        self.course = course if course is not None else Course.in_memory()
        #: the instructor's table, folded from the course record
        self.progress = Progress()
        self.store_problem: str | None = None  # why the last read of the record failed
        self.students: dict[int, StudentPanel] = {}
        self.teachers: dict[int, TeacherPanel] = {}
        #: the class the students' variants are drawn for
        self.class_id = self.course.info.name if course is not None else DEFAULT_CLASS
        self._released: dict[str, Release] = {}
        self._stop = threading.Event()
        self._poke = threading.Event()
        self._poller: threading.Thread | None = None
        #: the class's answers are checked in a worker process, in line
        self.grader = Grader()

    @property
    def assignments(self) -> dict[str, Assignment]:
        """The assignments by id, read when the first page asks (not at server start)."""
        with self.lock:
            if self._assignments is None:
                self._assignments = load_assignments(self.lesson_ids)
            return self._assignments

    # -- the classroom's pages

    def attach(self, view: SessionView) -> None:
        """A page connected (after the classroom set its gate): its Assignment folder."""
        self.students[view.client.client_id] = StudentPanel(self, view)

    def detach(self, client_id: int) -> None:
        """A page left (its answer waiting in line goes)."""
        self.grader.cancel(client_id)
        self.students.pop(client_id, None)
        self.teachers.pop(client_id, None)

    def grant(self, view: SessionView) -> None:
        """The page became the instructor: the class's folder replaces its own."""
        cid = view.client.client_id
        student = self.students.get(cid)
        if student is not None:
            student.close()
        self.teachers[cid] = TeacherPanel(self, view)
        with self.lock:
            if self._poller is None:
                self._poller = threading.Thread(
                    target=self._poll, name="analyzer-lab-course-record", daemon=True
                )
                self._poller.start()
        self._poke.set()

    def released(self, view: SessionView) -> None:
        """A follower has its own session again (caller holds its lock)."""
        panel = self.students.get(view.client.client_id)
        if panel is not None:
            panel.resume()

    # -- variants: each student's numbers, from the variants checked at release

    def release(self, aid: str) -> Release:
        """The variants of ``aid`` that passed the release check (checked once, on first
        use); raises :class:`AssignmentError` naming the variant that failed."""
        done = self._released.get(aid)
        if done is None:
            a = self.assignments[aid]
            # the ready and served files are checked by their tests; a varied one here
            done = release(a) if a.varied else Release(a, (Variant(0, {}, a),), 0, 0.0)
            self._released[aid] = done
            log.info("assignment %s released: %d variant(s)", aid, len(done.variants))
        return done

    def variant(self, aid: str, class_id: str, student: str) -> Variant:
        """The variant of ``aid`` for ``student`` (the typed name, else the page) in
        ``class_id``: the same every time."""
        return self.release(aid).for_student(class_id, student)

    # -- the class

    def choices(self, none: str = NONE) -> tuple[str, ...]:
        """The picker's options: ``none`` (no assignment, in the page's language), then
        the assignments' ids."""
        return (none, *self.assignments)

    def push(self, aid: str) -> int:
        """Open ``aid`` on every student page (not the instructors'); returns how many.
        Pages following a demo show the instructor's session: they get it on release."""
        if aid not in self.assignments:
            raise LabError("choose one of the assignments")
        self.release(aid)  # a variant space that fails its check is never pushed
        self.pushed = aid
        reached = 0
        for cid, panel in list(self.students.items()):
            if self.room.is_instructor(cid) or panel.view.closed:
                continue
            if self.room.is_following(cid):
                panel.pending = aid
                continue
            try:
                with panel.view.session.lock:
                    panel.open(aid, pushed=True)
                    panel.view.refresh(heavy=True)
                reached += 1
            except Exception:  # one page's fault does not stop the push to the others
                log.exception("page %s: the pushed assignment failed", cid)
        self.changed()
        return reached

    def changed(self) -> None:
        """Something the table shows changed here: read the record now."""
        self._poke.set()

    def refresh(self) -> bool:
        """Fold the record's new attempts into the table (any worker's); True if any."""
        try:
            new = self.course.attempts(self.progress.last_id)
            names = {}
            if any(a.student_id not in self.progress.names for a in new):
                names = {st.id: st.name for st in self.course.students()}
        except StoreError as exc:
            if self.store_problem is None:
                log.warning("the course record cannot be read: %s", exc)
            self.store_problem = str(exc)
            return False
        self.store_problem = None
        self.progress.names.update(names)
        return self.progress.fold(new, self.progress.names) > 0

    def _poll(self) -> None:
        """Read the record every :data:`POLL_SECONDS` (at once when poked) while an
        instructor's table is open."""
        while not self._stop.is_set():
            self._poke.wait(POLL_SECONDS)
            self._poke.clear()
            if self._stop.is_set():
                break
            if not self.teachers:
                continue
            try:
                self.refresh()
                for t in list(self.teachers.values()):
                    t.update()
            except Exception:  # the table's thread goes on; the log says what failed
                log.exception("the instructor's table could not be updated")

    def grades(self, fmt: str) -> str:
        """The class's grades (:mod:`analyzer_lab.classroom.store.grades`)."""
        return export_grades(fmt, list(self.course.students()), self.course.attempts())

    def stop(self) -> None:
        self._stop.set()
        self._poke.set()
        self.grader.close()


class StudentPanel:
    """The "Assignment" folder of one page."""

    def __init__(self, board: AssignmentBoard, view: SessionView) -> None:
        self.board = board
        self.view = view
        self.active: Assignment | None = None
        self.variant: Variant | None = None
        self.pending: str | None = None
        gui = view.client.gui
        tr = view.language.gettext
        order = float(view.status.order) + 0.5
        self.none = tr(NONE)  # "no assignment" as the page's language writes it
        self.folder = gui.add_folder(tr("Assignment"), order=order, expand_by_default=True)
        with self.folder:
            self.picker = gui.add_dropdown(
                tr("Assignment"), board.choices(self.none), initial_value=self.none
            )
            self.task = gui.add_html("")
            self.who = gui.add_html("")
            self.code = gui.add_text(
                tr("Join code"),
                initial_value="",
                hint=tr("the class's join code from the instructor"),
            )
            self.name = gui.add_text(
                tr("Your name"),
                initial_value="",
                hint=tr("your student id or your name, shown to the instructor"),
            )
            self.check_btn = gui.add_button(tr("Check my answer"))
            self.result = gui.add_html("")
        #: the student this page records for (decided on the server: a signed token or a join)
        self.student: Student | None = None
        self._restored = threading.Event()  # set once the saved token was read (or not)
        self.picker.on_update(view.guard(self._on_pick))
        view.language_hooks.append(self._relabel)
        self.check_btn.on_click(view.guard(lambda e: self.check()))
        self.name.on_update(view.guard(lambda e: self._renumber()))
        inner = view.gate
        view.gate = lambda v, event, again: self._gate(v, event, again, inner)  # type: ignore[assignment]
        self._shown_visible(False)
        threading.Thread(
            target=self._restore, name="analyzer-lab-student-token", daemon=True
        ).start()

    def _relabel(self, view: SessionView) -> None:
        """The folder in the page's language now (after a switch of it; caller holds the
        session lock): its labels, "no assignment", the open task."""
        tr = view.language.gettext
        none, self.none = self.none, tr(NONE)
        self.folder.label = tr("Assignment")
        self.picker.label = tr("Assignment")
        chosen = self.picker.value
        self.picker.options = self.board.choices(self.none)
        self.picker.value = self.none if chosen == none else chosen
        self.code.label = tr("Join code")
        self.code.hint = tr("the class's join code from the instructor")
        self.name.label = tr("Your name")
        self.name.hint = tr("your student id or your name, shown to the instructor")
        self.check_btn.label = tr("Check my answer")
        if self.variant is not None and self.active is not None:
            self.task.content = task_html(self.variant.assignment, view.language)

    # -- opening and closing

    def _shown_visible(self, on: bool) -> None:
        for w in (self.task, self.who, self.check_btn, self.result):
            w.visible = on
        joined = self.student is not None
        self.name.visible = on and not joined
        self.code.visible = on and not joined and self.board.course.needs_code

    # -- who this page is

    def _restore(self) -> None:
        """A page that joined before (reload, another tab, the next lecture) brings back
        its student from the token its browser kept; a token this server did not sign
        is refused and the page is told why."""
        try:
            student = self._read_token()
        finally:
            self._restored.set()
        if student is not None:
            with self.view.session.lock:
                self._joined(student)

    def _read_token(self) -> Student | None:
        token = None
        for _ in range(TOKEN_TRIES):  # a busy browser answers late: ask again
            try:
                token = self.view.client.local_storage.get_item(TOKEN_KEY, timeout=TOKEN_WAIT)
                break
            except TimeoutError:
                log.warning(
                    "page %s: its browser did not answer for its student token",
                    self.view.client.client_id,
                )
            except RuntimeError:  # the page left or blocks its storage
                return None
            if self.view.closed:
                return None
        if token is None or token == "":
            return None
        try:
            student = self.board.course.restore(token)
        except JoinError as exc:
            text = self.view.language.gettext(
                "your saved student record was refused: {reason}; join again"
            ).format(reason=self.view.language.message(exc))
            self.who.content = _box(esc(text), "#a61b1b", "al-student-refused")
            self._tell(text, "red")
            try:
                self.view.client.local_storage.remove_item(TOKEN_KEY)
            except RuntimeError:  # the page left meanwhile
                pass
            return None
        except StoreError as exc:
            self._tell(
                self.view.language.gettext(
                    "your student record cannot be read now: {reason}"
                ).format(reason=exc),
                "yellow",
            )
            return None
        if self.student is not None:  # the page joined meanwhile: it stays who it joined as
            return None
        self.student = student
        return student

    def _tell(self, text: str, color: str) -> None:
        try:
            self.view.client.add_notification(
                self.view.language.gettext("Course record"),
                text,
                auto_close_seconds=8.0,
                color=color,
            )
        except RuntimeError:  # the page left meanwhile
            pass

    def _joined(self, student: Student) -> None:
        self.student = student
        ident = f" ({esc(student.roster_id)})" if student.roster_id else ""
        recorded = esc(self.view.language.gettext("Recorded as"))
        self.who.content = _box(
            f"{recorded} <b class='al-student'>{esc(student.name)}</b>{ident}",
            cls="al-student-who",
        )
        self._shown_visible(self.active is not None)
        self._renumber()

    def join(self) -> Student | None:
        """Join the class with the typed code and name or id (the result says why not)."""
        try:
            student = self.board.course.join(self.code.value, self.name.value)
        except JoinError as exc:
            self.result.content = error_html(self.view.language.message(exc))
            return None
        except StoreError as exc:
            self.result.content = error_html(
                self.view.language.gettext(NOT_RECORDED).format(why=exc)
            )
            return None
        try:
            self.view.client.local_storage.set_item(TOKEN_KEY, self.board.course.token(student))
        except RuntimeError:  # the page left meanwhile
            pass
        self._joined(student)
        return student

    def _on_pick(self, event: Any) -> None:
        value = sent_value(event)
        if value in (self.none, NONE):
            self.close()
            return
        if value not in self.board.assignments:
            raise LabError(f"unknown assignment {str(value)[:60]!r}")
        try:
            self.open(value)
        except AssignmentError as exc:
            self.close()
            raise LabError(said(exc)) from None

    def open(self, aid: str, pushed: bool = False) -> None:
        """Load the assignment's lesson, preset and start values, lock the other fields
        (caller holds the session lock); a varied one with this student's numbers."""
        self.variant = self.board.variant(aid, self.board.class_id, self.student_key())
        a = self.variant.assignment
        s = self.view.session
        self.active = None  # the lesson picker must not be refused while switching
        if s.lesson.id != a.lesson:
            s.select_lesson(a.lesson, a.preset)
        else:
            s.apply_preset(a.preset)
        if a.start:
            s.set_values(dict(a.start))
        self.active = a
        self.pending = None
        self.view.after_state_change()
        self.view.refresh(heavy=True)
        self.view.controls.set_locked(self.locked(), s.params)
        self._pickers_disabled(True)
        if self.picker.value != aid:
            self.picker.value = aid
        self.task.content = task_html(a, self.view.language)
        self.result.content = ""
        self._shown_visible(True)
        self.board.grader.warm()  # a check may follow: its worker is started now
        s.notify(
            Message(
                N_("the instructor pushed assignment {id}: {title}")
                if pushed
                else N_("opened assignment {id}: {title}"),
                id=a.id,
                title=a.title_in(self.view.language.code),
            )
        )
        if pushed:
            try:
                tr = self.view.language.gettext
                self.view.client.add_notification(
                    tr("Assignment"),
                    tr("the instructor gave you: {title}").format(
                        title=a.title_in(self.view.language.code)
                    ),
                    auto_close_seconds=6.0,
                )
            except RuntimeError:  # the page left meanwhile
                pass

    def resume(self) -> None:
        """The page has its own session again after a demo (caller holds its lock): an
        assignment pushed during the demo opens now; an open one keeps its locks."""
        if self.pending is not None and self.pending in self.board.assignments:
            self.open(self.pending, pushed=True)
        elif self.active is not None:
            self.view.controls.set_locked(self.locked(), self.view.session.params)
            self._pickers_disabled(True)

    def student_key(self) -> str:
        """Who the variant is drawn for: the student this page joined as (their roster
        id, else their name: the same on every page and worker, and the key ``grade
        --student`` takes), else the typed name, else this page."""
        if self.student is not None:  # a roster id as the university writes it, else the name
            return self.student.roster_id or self.student.name
        try:
            return clean_name(self.name.value)
        except ValueError:
            return f"page-{self.view.client.client_id}"

    def _renumber(self) -> bool:
        """The typed name changed: a varied assignment gets that student's numbers
        (caller holds the lock); True when they changed."""
        a, v = self.active, self.variant
        if a is None or v is None or not a.varied:
            return False
        now = self.board.variant(a.id, self.board.class_id, self.student_key())
        if now.index == v.index:
            return False
        self.open(a.id)
        self.result.content = error_html(
            self.view.language.gettext(
                "your numbers for this name: {numbers} (the start values are reset)"
            ).format(numbers=_numbers(now.assignment))
        )
        return True

    def close(self) -> None:
        self.active = None
        self.variant = None
        self.view.controls.set_locked(frozenset(), self.view.session.params)
        self._pickers_disabled(self.view.following)
        if self.picker.value != self.none:
            self.picker.value = self.none
        self.task.content = ""
        self.result.content = ""
        self._shown_visible(False)

    def _pickers_disabled(self, on: bool) -> None:
        """The lesson and preset pickers are off while an assignment is open."""
        for w in (self.view.lesson_dd, self.view.preset_dd):
            if w.disabled != on:
                w.disabled = on

    def locked(self) -> frozenset[str]:
        a = self.active
        if a is None:
            return frozenset()
        return frozenset(p.name for p in self.view.session.lesson.params) - set(a.unlocked)

    # -- refusing locked inputs

    def _gate(self, view: SessionView, event: Any, again: Any, inner: Any) -> bool:
        a = self.active
        if a is not None and view.session.lesson.id == a.lesson:
            target = getattr(event, "target", None)
            refused = None
            tr = view.language.gettext
            if target is view.lesson_dd or target is view.preset_dd:
                refused = tr("choose (none) under Assignment first to leave the assignment")
            elif target is None and hasattr(event, "ray_origin"):
                start = view.session.lesson.start_point or ()
                if any(n in self.locked() for n in start):
                    refused = tr("the start point is locked in this assignment")
            else:
                for name, widgets in view.controls.widgets.items():
                    if name in self.locked() and any(w is target for w in widgets):
                        refused = tr("{name} is locked in this assignment").format(name=name)
                        break
            if refused is not None:
                try:
                    view.client.add_notification(
                        tr("Assignment"), refused, auto_close_seconds=4.0, color="yellow"
                    )
                    with view.session.lock:
                        view.sync_widgets(force=True)
                except (RuntimeError, ValueError):  # the page left meanwhile
                    pass
                return False
        return True if inner is None else bool(inner(view, event, again))

    # -- checking

    def check(self) -> None:
        """Grade the session's values of the unlocked parameters (caller holds the lock)."""
        a = self.active
        if a is None:
            self.result.content = error_html(
                self.view.language.gettext("choose an assignment first")
            )
            return
        if self._renumber():  # who this page is changed without the update reaching us
            return
        if self.student is None:  # a token still on its way from the browser counts first
            self._restored.wait(CHECK_WAIT)
        variant = self.variant
        student = self.student or self.join()
        if student is None:
            return
        if self.variant is not variant:  # joined as a student with other numbers: theirs first
            return
        s = self.view.session
        if s.lesson.id != a.lesson:
            self.result.content = error_html(
                self.view.language.gettext("this assignment is about the lesson {lesson}").format(
                    lesson=a.lesson
                )
            )
            return
        raw = s.raw_values()
        values = {n: raw[n] for n in a.unlocked}
        variant = self.variant.label if self.variant is not None else ""
        try:
            place = self.board.grader.submit(
                f"student-{student.id}",
                a,
                values,
                lambda outcome: self._graded(student, a, values, variant, outcome),
                self._in_line,
                owner=self.view.client.client_id,
            )
        except GraderBusy as exc:
            self.result.content = error_html(self.view.language.message(exc))
            return
        self._in_line(place, locked=True)

    def _in_line(self, place: int, locked: bool = False) -> None:
        """Say where the answer waits (0: being checked); from the grader's thread
        unless ``locked``."""
        tr = self.view.language.gettext
        text = (
            tr("Your answer is being checked…")
            if place == 0
            else tr("Your answer is number {place} in line to be checked.").format(place=place)
        )
        box = _box(esc(text), "#555", "al-assignment-queue")
        if locked:
            self.result.content = box
            return
        with self.view.session.lock:
            if not self.view.closed:
                self.result.content = box

    def _graded(
        self, student: Student, a: Assignment, values: dict, variant: str, outcome: GradeOutcome
    ) -> None:
        """The grader's verdict: recorded first, then shown (from the grader's thread)."""
        g = outcome.grade
        if g is not None:
            try:  # recorded first: the page is told only what the record holds
                self.board.course.record(student, g, values, variant)
            except StoreError as exc:
                log.warning("page %s: an attempt not recorded: %s", self.view.client.client_id, exc)
                why = self.view.language.gettext(NOT_RECORDED).format(why=exc)
                g, outcome = None, GradeOutcome(None, why)
            else:
                self.board.changed()
        with self.view.session.lock:
            if self.view.closed:
                return
            if g is not None:
                self.result.content = verdict_html(g, self.view.language, a)
                return
            error = self.view.language.message(outcome.error)
            self.result.content = error_html(error)
            field = outcome.field if outcome.field in self.view.controls.widgets else None
            if field is not None:
                self.view.controls.show_error(field, error)


class TeacherPanel:
    """The instructor's "Assignments" folder: push, the live table, CSV, authoring."""

    def __init__(self, board: AssignmentBoard, view: SessionView) -> None:
        self.board = board
        self.view = view
        gui = view.client.gui
        tr = view.language.gettext
        self.folder = gui.add_folder(tr("Assignments (class)"), order=-999.0)
        with self.folder:
            self.picker = gui.add_dropdown(
                tr("Assignment for all"), board.choices(tr(NONE)), initial_value=tr(NONE)
            )
            self.push_btn = gui.add_button(tr("Push assignment to all"))
            self.table = gui.add_html("")
            self.csv_btn = gui.add_button(tr("Download results (CSV)"))
            self.grades_btn = gui.add_button(
                tr("Download grades (Moodle CSV)"),
                hint=tr("one row per student, one column per assignment: 1 passed, 0 not yet"),
            )
            self.author = gui.add_folder(tr("Author from this state"), expand_by_default=False)
            with self.author:
                self.a_intro = gui.add_html(_box(esc(tr(AUTHORING))))
                self.a_id = gui.add_text(tr("Id"), initial_value="my-assignment")
                self.a_title = gui.add_text(tr("Title"), initial_value="My assignment")
                self.a_task = gui.add_text(tr("Task"), initial_value="", multiline=True)
                self.a_unlocked = gui.add_text(tr("Unlocked"), initial_value="")
                self.a_series = gui.add_text(tr("Series to check"), initial_value="")
                self.a_metrics = gui.add_text(tr("Metrics to check"), initial_value="")
                self.a_btn = gui.add_button(tr("Download assignment"))
                self.a_error = gui.add_html("")
        #: the live table: its head in ``table``, one element per student below it
        self.lock = threading.Lock()
        self.rows = RowTable(self._add_row, float(self.table.order), float(self.csv_btn.order))
        self._rows_of: str | None = None
        self.push_btn.on_click(self._cb(self._push))
        self.csv_btn.on_click(self._cb(self._csv))
        self.grades_btn.on_click(self._cb(self._grades))
        self.a_btn.on_click(self._cb(self._draft))
        view.language_hooks.append(self._relabel)  # a switch after the role was granted
        self.suggest()
        self.update()

    def _relabel(self, view: SessionView) -> None:
        """The folder in the page's language now (after a switch of it; caller holds the
        session lock): its labels, "no assignment" in the picker, the live table."""
        tr = view.language.gettext
        none = tr(NONE)
        self.folder.label = tr("Assignments (class)")
        self.picker.label = tr("Assignment for all")
        chosen = self.picker.value
        self.picker.options = self.board.choices(none)
        self.picker.value = chosen if chosen in self.board.assignments else none
        self.push_btn.label = tr("Push assignment to all")
        self.csv_btn.label = tr("Download results (CSV)")
        self.grades_btn.label = tr("Download grades (Moodle CSV)")
        self.grades_btn.hint = tr(
            "one row per student, one column per assignment: 1 passed, 0 not yet"
        )
        self.author.label = tr("Author from this state")
        self.a_intro.content = _box(esc(tr(AUTHORING)))
        for widget, label in (
            (self.a_id, "Id"),
            (self.a_title, "Title"),
            (self.a_task, "Task"),
            (self.a_unlocked, "Unlocked"),
            (self.a_series, "Series to check"),
            (self.a_metrics, "Metrics to check"),
            (self.a_btn, "Download assignment"),
        ):
            widget.label = tr(label)
        self.a_error.content = ""
        self.update()

    def _cb(self, fn: Any) -> Any:
        def wrapped(event: Any) -> None:
            client = getattr(event, "client", None)
            if client is None or client.client_id != self.view.client.client_id:
                return
            if not self.board.room.is_instructor(client.client_id):
                return
            try:
                fn()
            except (LabError, AssignmentError, ValueError) as exc:
                self.view.client.add_notification(
                    self.view.language.gettext("Assignments"),
                    self.view.language.gettext("refused: {reason}").format(
                        reason=self.view.language.message(exc)
                    ),
                    auto_close_seconds=6.0,
                    color="red",
                )
            except Exception as exc:  # a page callback: the page says so, the log how
                log.exception("page %s: an assignments control failed", client.client_id)
                self.view.client.add_notification(
                    self.view.language.gettext("Assignments"),
                    self.view.language.gettext("internal error: {error}").format(error=exc),
                    auto_close_seconds=6.0,
                    color="red",
                )

        return wrapped

    def _push(self) -> None:
        aid = self.picker.value
        n = self.board.push(aid)
        language = self.view.language
        self.view.client.add_notification(
            language.gettext("Assignments"),
            language.ngettext("pushed {aid} to {n} page", "pushed {aid} to {n} pages", n).format(
                aid=aid, n=n
            ),
            auto_close_seconds=4.0,
            color="green",
        )

    def _csv(self) -> None:
        data = self.board.progress.to_csv(self.board.pushed).encode("utf-8")
        stamp = time.strftime("%Y%m%d-%H%M%S")
        self.view.client.send_file_download(
            f"assignment-results-{stamp}.csv", data, save_immediately=True
        )

    def _grades(self) -> None:
        try:
            data = self.board.grades("moodle").encode("utf-8")
        except StoreError as exc:
            raise LabError(
                self.view.language.gettext("the grades cannot be read: {reason}").format(reason=exc)
            ) from exc
        stamp = time.strftime("%Y%m%d-%H%M%S")
        self.view.client.send_file_download(
            f"grades-moodle-{stamp}.csv", data, save_immediately=True
        )

    def suggest(self) -> None:
        """Prefill the authoring fields from the instructor's lesson."""
        lesson = self.view.session.lesson
        controls = [p.name for p in lesson.params if p.group == "controls"]
        self.a_unlocked.value = ", ".join(controls or [lesson.params[0].name])
        self.a_series.value = ", ".join(lesson.readout[:2] or [s.name for s in lesson.series[:1]])

    def _draft(self) -> None:
        s = self.view.session

        def names(text: Any) -> list[str]:
            if not isinstance(text, str):
                return []
            return [n.strip() for n in text.split(",") if n.strip()][:24]

        try:
            with s.lock:
                lesson, values, preset = s.lesson, s.raw_values(), s.preset
            data = draft_assignment(
                lesson.id,
                values,
                names(self.a_unlocked.value),
                names(self.a_series.value),
                assignment_id=str(self.a_id.value).strip(),
                title=str(self.a_title.value).strip(),
                task=str(self.a_task.value).strip() or REPRODUCE.format(title=lesson.title),
                preset=preset,
                t_end=s.t_end,
                metrics=names(self.a_metrics.value),
            )
            language = self.view.language
            if not str(self.a_task.value).strip() and language.code == "ru":
                # the default task also in the page's language (the file's task stays English)
                data["task_ru"] = language.gettext(REPRODUCE).format(
                    title=language.lesson_text(lesson.title)
                )
        except (AssignmentError, LabError, ValueError) as exc:
            self.a_error.content = error_html(self.view.language.message(exc))
            return
        done = self.view.language.gettext("downloaded {name}").format(name=f"{data['id']}.json")
        self.a_error.content = _box(esc(done), "#1b7a2e")
        text = json.dumps(data, indent=1, ensure_ascii=False) + "\n"
        self.view.client.send_file_download(
            f"{data['id']}.json", text.encode("utf-8"), save_immediately=True
        )

    def _add_row(self, content: str, order: float) -> Any:
        with self.folder:
            return self.view.client.gui.add_html(content, order=order)

    def update(self) -> int:
        """Bring the live table up to date: the head when it changed and only the rows
        that changed (returns how many rows were sent)."""
        with self.lock:
            pushed = self.board.pushed
            if pushed != self._rows_of:  # another assignment: another set of rows
                self.rows.clear()
                self._rows_of = pushed
            records = self.board.progress.rows(pushed)
            tr = self.view.language.gettext
            pushed_head, code_head = tr("Pushed:"), tr("Join code:")
            title = (
                f"{esc(pushed_head)} <b>{esc(pushed)}</b>"
                if pushed
                else esc(tr("No assignment pushed: every answer checked"))
            )
            course = self.board.course
            if course.needs_code:
                title += (
                    f"<br>{esc(code_head)} "
                    f"<b class='al-join-code'>{esc(course.info.join_code)}</b>"
                    f"{esc(course.code_expiry())}"
                )
            if self.board.store_problem:
                down = tr("The course record cannot be read: {reason}").format(
                    reason=self.board.store_problem
                )
                title += f"<br><span class='al-store-down' style='color:#a61b1b'>{esc(down)}</span>"
            content = _box(title) + head_html(pushed, not records, self.view.language)
            if self.table.content != content:
                self.table.content = content
            return self.rows.show(
                [
                    ((r.student, r.assignment), row_html(r, pushed, self.view.language))
                    for r in records
                ]
            )
