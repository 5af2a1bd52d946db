"""``analyzer-lab``: the command line (``serve``, ``lessons``, ``run``, ``check``,
``assignments``, ``grade``).

Headless commands import no view code; ``serve`` imports the viser app lazily.
"""

from __future__ import annotations

import argparse
import errno
import json
import logging
import os
import sys
import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from analyzer_lab.i18n import ENGLISH, N_, Language, resolve
from analyzer_lab.lessons.kit.message import Message
from analyzer_lab.serve.cli_help import LabParser, lang_option

if TYPE_CHECKING:
    from analyzer_lab.classroom.store.grades import Feedback

log = logging.getLogger(__name__)

EXIT_USAGE = 2
#: When the command started (``serve`` reports its start-up from here).
STARTED = time.perf_counter()


#: The environment variables that name the user's language, the first set one wins (as
#: gettext reads them).
LANGUAGE_VARIABLES = ("LC_ALL", "LC_MESSAGES", "LANG")
#: The language of the command's messages (:func:`command_language`); set by :func:`main`.
LANGUAGE: Language = ENGLISH


def command_language(lang: str | None, environ: dict[str, str]) -> tuple[Language, str | None]:
    """The language of the command line: ``--lang`` (an unknown code: English, with a
    notice), else the environment's (``LC_ALL``, ``LC_MESSAGES``, ``LANG``; one the lab
    does not speak: English, without a notice), English by default."""
    if lang:
        return resolve(lang)
    code = next((environ[k] for k in LANGUAGE_VARIABLES if environ.get(k)), None)
    return resolve(code)[0], None


def say(text: object) -> str:
    """A message (or an error's) in the command's language."""
    return LANGUAGE.message(text)


def _fail(message: object) -> int:
    text = LANGUAGE.gettext("analyzer-lab: error: {message}").format(message=say(message))
    print(text, file=sys.stderr)
    return EXIT_USAGE


def cmd_lessons(args: argparse.Namespace) -> int:
    from analyzer_lab.lessons.catalog import all_lessons

    items = all_lessons()
    if args.json:
        print(json.dumps([l.describe() for l in items], indent=1, default=str))
        return 0
    tr = LANGUAGE.gettext
    for l in items:
        print(f"{l.id:28s} {l.problem:18s} {LANGUAGE.lesson_text(l.title)}")
        print(f"{'':28s} {l.source}")
        params = tr("params: {names}").format(names=", ".join(p.name for p in l.params))
        print(f"{'':28s} {params}")
        if l.presets:
            presets = tr("presets: {names}").format(names=", ".join(p.name for p in l.presets))
            print(f"{'':28s} {presets}")
    return 0


def _parse_sets(items: Sequence[str]) -> dict[str, str]:
    out: dict[str, str] = {}
    for item in items:
        if "=" not in item:
            raise ValueError(f"--set expects NAME=VALUE, got {item[:60]!r}")
        name, value = item.split("=", 1)
        out[name.strip()] = value.strip()
    return out


def cmd_run(args: argparse.Namespace) -> int:
    from analyzer_lab.serve.headless import AnalyzerLabError, find_lesson, run_lesson

    if args.out and os.path.islink(args.out):
        return _fail(
            Message(
                N_("--out {path}: is a symbolic link; refused (name the file itself)"),
                path=args.out,
            )
        )
    try:
        lesson = find_lesson(args.lesson)
        result = run_lesson(lesson, args.preset, _parse_sets(args.set or []), args.t_end)
    except (AnalyzerLabError, ValueError) as exc:
        return _fail(exc)
    text = json.dumps(result.to_json_dict()) if args.format == "json" else result.to_csv()
    for m in result.messages:
        print(LANGUAGE.gettext("note: {message}").format(message=say(m)), file=sys.stderr)
    if args.out:
        try:  # a link put there since the check is not followed either
            fd = os.open(args.out, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_NOFOLLOW, 0o644)
        except OSError as exc:
            reason = "is a symbolic link" if exc.errno == errno.ELOOP else exc.strerror
            return _fail(
                Message(N_("--out {path}: {reason}; refused"), path=args.out, reason=reason)
            )
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
    else:
        sys.stdout.write(text)
        if not text.endswith("\n"):
            sys.stdout.write("\n")
    return 0


def cmd_check(args: argparse.Namespace) -> int:
    from analyzer_lab.lessons.catalog import all_lessons
    from analyzer_lab.serve.headless import AnalyzerLabError, check_claim, claim_jobs, find_lesson

    try:
        chosen = [find_lesson(i) for i in args.lessons] if args.lessons else list(all_lessons())
    except AnalyzerLabError as exc:
        return _fail(exc)
    rows = []
    failed = 0
    jobs = claim_jobs(chosen)
    for k, (lesson, claim) in enumerate(jobs, 1):
        print(f"[{k}/{len(jobs)}] {lesson.id}: {claim.id} ...", end="", file=sys.stderr, flush=True)
        t0 = time.perf_counter()
        row = check_claim(lesson, claim)
        dt = time.perf_counter() - t0
        print(f" {'pass' if row['pass'] else 'FAIL'} ({dt:.1f} s)", file=sys.stderr, flush=True)
        failed += not row["pass"]
        rows.append(row)
    if args.json:
        print(json.dumps(rows, indent=1))
    else:
        for r in rows:
            print(
                f"{'PASS' if r['pass'] else 'FAIL'}  {r['lesson']}: {r['statement']}  [{r['source']}]"
            )
            print(f"      expected {r['expected']}; got {r['got']}")
        print(
            LANGUAGE.gettext("{passed}/{total} claims pass").format(
                passed=len(rows) - failed, total=len(rows)
            )
        )
    return 1 if failed else 0


#: The server's log: what the edges caught, one line each (level from the environment).
LOG_FORMAT = "%(asctime)s %(levelname)s %(name)s: %(message)s"


def cmd_serve(args: argparse.Namespace) -> int:
    from analyzer_lab.serve.threads import one_math_thread

    level = os.environ.get("ANALYZER_LAB_LOG_LEVEL", "WARNING").upper()
    logging.basicConfig(level=getattr(logging, level, logging.WARNING), format=LOG_FORMAT)

    one_math_thread()  # before numpy loads; the workers inherit it
    from analyzer_lab.serve.cli_assignments import use_folder_for_serve

    problem = use_folder_for_serve(getattr(args, "assignments", None))
    if problem:
        return _fail(problem)
    from analyzer_lab.i18n import LANGUAGE_ENV
    from analyzer_lab.i18n import resolve as resolve_language

    # the language of new pages: --lang, else the one a front door gave its workers
    language, notice = resolve_language(getattr(args, "lang", None) or os.environ.get(LANGUAGE_ENV))
    if notice:
        print(
            LANGUAGE.gettext("analyzer-lab: note: {message}").format(message=notice),
            file=sys.stderr,
            flush=True,
        )
    os.environ[LANGUAGE_ENV] = language.code  # the workers inherit it
    workers = getattr(args, "workers", 1)  # the workers inherit the assignments folder
    bus = getattr(args, "bus", None)
    if not 1 <= workers <= 64:
        return _fail(Message(N_("--workers must be in 1..64, got {workers}"), workers=workers))
    if bus is not None and bus != "local":
        from analyzer_lab.classroom.bus import BusError, parse_redis_url

        try:
            parse_redis_url(bus)
        except BusError as exc:
            return _fail(str(exc))
    early = None
    if workers == 1 and 0 <= args.port <= 65535:
        # the page is served at once, before the lessons and the course record load (a
        # browser opened now waits on the page until the lab takes it)
        from analyzer_lab.viser_boundary import make_viser_server

        try:
            early = make_viser_server(args.host, args.port, False)
        except OSError as exc:
            return _fail(
                Message(
                    N_("cannot listen on {host}:{port}: {error}"),
                    host=args.host,
                    port=str(args.port),
                    error=str(exc),
                )
            )
        served = time.perf_counter() - STARTED
    from analyzer_lab.serve.course_record import (
        CourseRecordError,
        export_environment,
        open_course,
        resolve,
    )

    try:  # opened (made, upgraded, the roster imported) once, before any worker starts
        where = resolve(args.data, args.db, args.class_name)
        if workers > 1:
            open_course(
                where, args.roster, args.join_code, code_hours=args.join_code_hours
            ).store.close()
    except CourseRecordError as exc:
        if early is not None:
            early.stop()
        return _fail(str(exc))
    export_environment(where)
    if workers > 1:
        if bus is None or bus == "local":
            return _fail(
                Message(
                    N_(
                        "several workers share the classroom through Redis: add --bus"
                        " redis://HOST:PORT (Debian: apt-get install redis-server, then --bus"
                        " redis://127.0.0.1:6379)"
                    )
                )
            )
        from analyzer_lab.serve.frontdoor import serve_workers

        return serve_workers(
            args.host,
            args.port,
            workers,
            bus,
            args.instructor_code,
            args.lesson,
            args.fps,
            not args.no_browser,
            public_hosts=args.public_host,
            code_file=args.instructor_code_file,
        )
    from analyzer_lab.serve.server import serve

    return serve(
        host=args.host,
        port=args.port,
        lesson=args.lesson,
        instructor_code=getattr(args, "instructor_code", None),
        open_browser=not args.no_browser,
        fps=getattr(args, "fps", 36.0),
        bus_url=bus,
        worker_name=getattr(args, "worker_name", None),
        instructor_code_file=getattr(args, "instructor_code_file", None),
        roster=args.roster,
        join_code=args.join_code,
        join_code_hours=args.join_code_hours,
        server=early,
        started=(STARTED, served) if early is not None else None,
        lang=language.code,
    )  # fps: classroom hook


def _record_options(s: argparse.ArgumentParser, tr: Callable[[str], str]) -> None:
    s.add_argument(
        "--data",
        metavar="DIR",
        default=None,
        help=tr(
            "the data folder: the SQLite course record and the secret that signs students' "
            "tokens (default $XDG_DATA_HOME/analyzer-lab or ~/.local/share/analyzer-lab)"
        ),
    )
    s.add_argument(
        "--db",
        metavar="URL",
        default=None,
        help=tr(
            "the course record in a database server: postgresql://USER:PASS@HOST:PORT/NAME "
            "(default: the SQLite file in the data folder)"
        ),
    )
    s.add_argument(
        "--class",
        dest="class_name",
        metavar="NAME",
        default=None,
        help=tr("the class (default 'default')"),
    )


def _feedback_texts(folder: str | None) -> Feedback:
    """The checks' feedback texts of the ready assignments and those in ``folder``."""
    from analyzer_lab.classroom.store.grades import feedback_from
    from analyzer_lab.lessons.assignments import load_folder, ready_assignments

    found = {a.id: a for a in ready_assignments()}
    if folder:
        found.update({a.id: a for a in load_folder(folder)})
    return feedback_from(found)


def cmd_grades(args: argparse.Namespace) -> int:
    from analyzer_lab.classroom.store.grades import export
    from analyzer_lab.classroom.store.records import StoreError
    from analyzer_lab.lessons.assignments import AssignmentError
    from analyzer_lab.serve.course_record import CourseRecordError, open_course, resolve

    if args.feedback and args.format != "moodle":
        return _fail(
            Message(N_("--feedback adds Moodle's feedback columns: use it with --format moodle"))
        )
    try:
        feedback = _feedback_texts(args.assignments) if args.feedback else None
        course = open_course(resolve(args.data, args.db, args.class_name), create=False)
        text = export(
            args.format, list(course.students()), course.attempts(), args.assignment, feedback
        )
    except AssignmentError as exc:
        return _fail(f"--assignments: {exc}")
    except (CourseRecordError, StoreError, ValueError) as exc:
        return _fail(str(exc))
    if args.out:
        try:
            with open(args.out, "w", encoding="utf-8", newline="") as fh:
                fh.write(text)
        except OSError as exc:
            return _fail(
                Message(N_("cannot write {path}: {reason}"), path=args.out, reason=exc.strerror)
            )
    else:
        sys.stdout.write(text)
    return 0


def build_parser(language: Language = ENGLISH) -> argparse.ArgumentParser:
    """The command line's parser, its help and refusals in ``language``."""
    tr = language.gettext
    p = LabParser(
        prog="analyzer-lab",
        description=tr("Analyzer Lab: programmed motion of mechatronic systems."),
        language=language,
    )
    p.add_argument(
        "--lang",
        metavar="CODE",
        default=None,
        help=tr(
            "the language of the command's help and messages: en or ru (default: the "
            "environment's, LC_ALL, LC_MESSAGES or LANG; else English)"
        ),
    )
    sub = p.add_subparsers(dest="command", required=True)

    s = sub.add_parser("serve", help=tr("start the browser lab"), language=language)
    s.add_argument(
        "--host",
        default="127.0.0.1",
        help=tr("interface to bind (default loopback; 0.0.0.0 = every interface)"),
    )
    s.add_argument(
        "--port", type=int, default=8080, help=tr("the port to listen on (default 8080)")
    )
    s.add_argument("--lesson", default="sphere", help=tr("lesson shown first"))
    s.add_argument(
        "--lang",
        metavar="CODE",
        default=argparse.SUPPRESS,  # the main parser's --lang holds it when not given here
        help=tr(
            "the language of new pages and of the command's messages: en (default) or ru"
            " (pseudo: every text half as long again, a layout check); an unknown code:"
            " English, with a notice"
        ),
    )
    s.add_argument(
        "--instructor-code",
        default=None,
        help=tr(
            "code that makes a page the instructor (at least 12 letters or digits; generated "
            "if omitted); any local user can read it from the process list: prefer "
            "--instructor-code-file or ANALYZER_LAB_INSTRUCTOR_CODE"
        ),
    )
    s.add_argument(
        "--instructor-code-file",
        default=None,
        metavar="PATH",
        help=tr(
            "read the instructor code from the first line of PATH (not shown in the process "
            "list); the environment variable ANALYZER_LAB_INSTRUCTOR_CODE works too"
        ),
    )
    s.add_argument("--no-browser", action="store_true", help=tr("do not open a browser window"))
    s.add_argument(
        "--fps",
        type=float,
        default=36.0,
        help=tr(
            "frames per second of the live view (default 36: every page gets 30 updates/s or more)"
        ),
    )
    s.add_argument(
        "--workers",
        type=int,
        default=1,
        help=tr(
            "worker processes (default 1: this process serves every page); N > 1 starts N "
            "workers on the next ports and a front door on --port that sends each page to the "
            "least-loaded one (needs --bus redis://...)"
        ),
    )
    s.add_argument(
        "--public-host",
        action="append",
        default=[],
        metavar="NAME",
        help=tr(
            "with --workers: a host name or address the students' pages use to reach this "
            "machine (repeatable); the front door redirects only to these, the address it listens "
            "on and, for 0.0.0.0, this machine's own names"
        ),
    )
    s.add_argument(
        "--bus",
        default=None,
        metavar="URL",
        help=tr(
            "the class bus shared by the servers of a class: 'local' (default, in-process) "
            "or redis://HOST:PORT"
        ),
    )
    s.add_argument(
        "--worker-name",
        default=None,
        help=tr("this server's name on the bus (default: random; unique within a class)"),
    )
    s.add_argument(
        "--assignments", metavar="DIR", help=tr("also offer the assignment files in DIR")
    )
    _record_options(s, tr)
    s.add_argument(
        "--roster",
        metavar="CSV",
        help=tr(
            "open the class with this roster (columns: student id, name, email, group); "
            "only its students can join"
        ),
    )
    s.add_argument(
        "--join-code", metavar="CODE", help=tr("the class's join code (default: generated once)")
    )
    s.add_argument(
        "--join-code-hours",
        type=float,
        metavar="H",
        default=None,
        help=tr(
            "the join code expires H hours from now (students who joined keep their "
            "record; default: a code given with --join-code never expires)"
        ),
    )
    s.set_defaults(func=cmd_serve)

    s = sub.add_parser(
        "grades",
        language=language,
        help=tr("export the class's grades (Moodle, Canvas or long CSV)"),
        description=tr(
            "Export the class's grades from the course record. Score: 1 per "
            "assignment passed (every check of one attempt passed), 0 attempted and not "
            "passed, empty never attempted (Moodle, Canvas)."
        ),
    )
    _record_options(s, tr)
    s.add_argument(
        "--format",
        choices=("moodle", "canvas", "long"),
        default="moodle",
        help=tr("the export's layout (default moodle)"),
    )
    s.add_argument(
        "--assignment",
        action="append",
        default=[],
        metavar="ID",
        help=tr("a column for this assignment (repeatable; default: every assignment attempted)"),
    )
    s.add_argument(
        "--feedback",
        action="store_true",
        help=tr(
            "moodle: after each assignment's column a feedback column '<assignment> "
            "(Feedback)' (map it to 'Feedback for <assignment>' at import): the checks the best "
            "attempt missed, by how much, with the assignment's feedback texts"
        ),
    )
    s.add_argument(
        "--assignments",
        metavar="DIR",
        help=tr(
            "with --feedback: also read the feedback texts of the assignment files in DIR "
            "(those served with serve --assignments DIR)"
        ),
    )
    s.add_argument("--out", metavar="FILE", help=tr("write here (default: standard output)"))
    s.set_defaults(func=cmd_grades)

    s = sub.add_parser("lessons", help=tr("list the lessons"), language=language)
    s.add_argument("--json", action="store_true", help=tr("print the lessons as JSON"))
    s.set_defaults(func=cmd_lessons)

    from analyzer_lab.serve.run_limits import limits_text

    s = sub.add_parser(
        "run",
        help=tr("run one lesson headless"),
        description=tr("Run one lesson headless; {limits}.").format(limits=limits_text(language)),
        language=language,
    )
    s.add_argument("lesson", help=tr("the lesson's id ('analyzer-lab lessons' lists them)"))
    s.add_argument("--preset", help=tr("start from this preset (an example of the lesson)"))
    s.add_argument(
        "--set", action="append", metavar="NAME=VALUE", help=tr("set a parameter (repeatable)")
    )
    s.add_argument("--t-end", type=float, help=tr("the run's end time, s (default: the lesson's)"))
    s.add_argument(
        "--format", choices=("json", "csv"), default="json", help=tr("the output (default json)")
    )
    s.add_argument("--out", help=tr("write here (default: standard output)"))
    s.set_defaults(func=cmd_run)

    s = sub.add_parser(
        "check", help=tr("check the lessons against the textbook's claims"), language=language
    )
    s.add_argument("lessons", nargs="*", help=tr("the lessons to check (default: every lesson)"))
    s.add_argument("--json", action="store_true", help=tr("print the verdicts as JSON"))
    s.set_defaults(func=cmd_check)

    from analyzer_lab.serve.cli_assignments import add_parsers

    add_parsers(sub, language)
    return p


def main(argv: Sequence[str] | None = None) -> int:
    global LANGUAGE
    argv = list(sys.argv[1:] if argv is None else argv)
    # the help's language too: read before the parser is built
    LANGUAGE = command_language(lang_option(argv), dict(os.environ))[0]
    parser = build_parser(LANGUAGE)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0)
    # the command's own messages: --lang (serve), else the environment's language; an
    # unknown --lang is said once, by serve
    LANGUAGE = command_language(getattr(args, "lang", None), dict(os.environ))[0]
    args.language = LANGUAGE  # the commands of other modules say their words in it
    try:
        return int(args.func(args))
    except BrokenPipeError:  # the reader stopped early (``| head``): nothing more to say
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    raise SystemExit(main())
