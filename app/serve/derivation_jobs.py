"""Derivations built in child processes, each with limits, several pages at once.

A formula can make a derivation arbitrarily slow and large ((sin(t)+cos(t)+t)**64 in
u1, u2, u3 takes 35 s and gives 4.7 MB of MathML).  Each derivation is built in its own
child process (forked from a fork server that has the lessons loaded, at a lower CPU
priority): one job per page at a time, :data:`MAX_JOBS` pages at once, and a job that
runs longer than :data:`DERIVATION_SECONDS` is ended and its page says so, as does a
derivation over :data:`MAX_DERIVATION_BYTES`.  The frame loop and the other pages'
derivations are not held up.
"""

from __future__ import annotations

import html
import logging
import multiprocessing
import os
import time
from dataclasses import dataclass
from typing import Any

from analyzer_lab.i18n import DEFAULT, language_of
from analyzer_lab.lessons.catalog import all_lessons
from analyzer_lab.view.math import derivation_to_html

log = logging.getLogger(__name__)

#: A derivation's time limit (s), its largest HTML (bytes), and jobs at once.
DERIVATION_SECONDS = 15.0
MAX_DERIVATION_BYTES = 400_000
MAX_JOBS = 3
#: Lessons by id, loaded when the fork server imports this module.
LESSONS = {lesson.id: lesson for lesson in all_lessons()}


def too_large(reason: str) -> str:
    """The page's message for a derivation that is not shown."""
    return (
        '<div class="al-error">The derivation is too large to show: '
        f"{html.escape(reason)}. Simpler formulas give a derivation again.</div>"
    )


def build(lesson: Any, values: dict[str, Any], language: str = DEFAULT) -> str:
    """The derivation's HTML (or the too-large message) in the page's ``language`` (a
    code), in this process."""
    steps = lesson.derivation(lesson.open(values).params)
    lang = language_of(language)
    content = derivation_to_html(steps, text=lang.lesson_text, tr=lang.gettext)
    if len(content) > MAX_DERIVATION_BYTES:
        return too_large(
            f"{len(content) / 1e6:.1f} MB of formulas (at most {MAX_DERIVATION_BYTES / 1e6:.1f} MB)"
        )
    return content


def _child(conn: Any, lesson_id: str, values: dict[str, Any], language: str) -> None:
    try:
        os.nice(10)  # the server's frame loop first
    except OSError:
        pass
    try:
        conn.send(("ok", build(LESSONS[lesson_id], values, language)))
    except Exception as exc:  # any formula: the page says why
        log.warning("the derivation of %s failed", lesson_id, exc_info=True)
        conn.send(("error", f"{type(exc).__name__}: {exc}"[:300]))
    finally:
        conn.close()


@dataclass
class Job:
    """One derivation being built for one page."""

    proc: Any
    conn: Any
    started: float


class DerivationJobs:
    """The derivation jobs of a server, by page (any hashable owner key)."""

    def __init__(self, seconds: float = DERIVATION_SECONDS, max_jobs: int = MAX_JOBS) -> None:
        self.seconds = seconds
        self.max_jobs = max_jobs
        self.jobs: dict[Any, Job] = {}
        self.ctx = multiprocessing.get_context("forkserver")
        self.ctx.set_forkserver_preload(["analyzer_lab.serve.derivation_jobs"])

    def warm(self) -> None:
        """Start the fork server now (it loads the lessons once, about 3 s)."""
        from multiprocessing import forkserver

        forkserver.ensure_running()

    @staticmethod
    def can_run(lesson: Any) -> bool:
        """Only catalog lessons are rebuilt by id in a child process."""
        return LESSONS.get(getattr(lesson, "id", "")) is lesson

    def busy(self, owner: Any) -> bool:
        return owner in self.jobs

    def full(self) -> bool:
        return len(self.jobs) >= self.max_jobs

    def start(
        self, owner: Any, lesson_id: str, values: dict[str, Any], language: str = DEFAULT
    ) -> None:
        """Start building ``owner``'s derivation in its page's ``language`` (the caller
        checked :meth:`busy`/:meth:`full`)."""
        recv, send = self.ctx.Pipe(duplex=False)
        proc = self.ctx.Process(
            target=_child,
            args=(send, lesson_id, values, language),
            name="analyzer-lab-derivation",
            daemon=True,
        )
        proc.start()
        send.close()
        self.jobs[owner] = Job(proc, recv, time.monotonic())

    def poll(self, owner: Any) -> str | None:
        """``owner``'s derivation HTML when its job ended (a message if it failed or took
        too long), ``None`` while it runs or when there is none."""
        job = self.jobs.get(owner)
        if job is None:
            return None
        result: str | None = None
        try:
            if job.conn.poll():
                kind, text = job.conn.recv()
                result = (
                    text
                    if kind == "ok"
                    else f'<div class="al-error">The derivation could not be built: {html.escape(text)}</div>'
                )
            elif not job.proc.is_alive():
                result = '<div class="al-error">The derivation could not be built.</div>'
            elif time.monotonic() - job.started > self.seconds:
                result = too_large(f"it takes longer than {self.seconds:g} s to build")
        except (EOFError, OSError):
            result = '<div class="al-error">The derivation could not be built.</div>'
        if result is not None:
            self.cancel(owner)
        return result

    def cancel(self, owner: Any) -> None:
        """End ``owner``'s job (if any)."""
        job = self.jobs.pop(owner, None)
        if job is None:
            return
        if job.proc.is_alive():
            job.proc.kill()
        job.proc.join(timeout=2.0)
        job.conn.close()

    def stop(self) -> None:
        for owner in list(self.jobs):
            self.cancel(owner)
