"""``analyzer-lab assignments`` and ``analyzer-lab grade``: assignments headless.

``grade ASSIGNMENT ANSWER.json`` prints the per-check verdict as JSON and exits 0 when
every check passes, 1 when one fails, 2 on bad input (one line on stderr saying what is
wrong and where).  ``ASSIGNMENT`` is the id of a ready assignment (or of one in
``--dir``) or the path of an assignment file.

``grade ASSIGNMENT FOLDER_OR_FILES...`` (more than one file, or a folder of ``*.json``)
grades them all in one process and prints JSON lines, one per file in the order given
(a folder's files sorted by name): the verdict with ``"file"``, or ``{"file", "error"}``
for a file refused as bad input.  The exit code follows the same rule over the batch: 2
when a file was refused, else 1 when one failed a check, else 0.

A varied assignment grades each file against the variant of its student: ``--student``,
else the file's name without ``.json``, in ``--class``; only variants that passed the
release check are graded against.  Each answer's run is held to the run limits of
``analyzer-lab run`` (:mod:`analyzer_lab.serve.run_limits`) before it starts.  No view
code is imported.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from analyzer_lab.i18n import ENGLISH, N_, Language
from analyzer_lab.lessons.kit.message import Message

if TYPE_CHECKING:
    from analyzer_lab.lessons.assignments import Assignment, AssignmentError

EXIT_FAIL = 1
EXIT_USAGE = 2
#: answer files one ``grade`` call takes at most
MAX_BATCH = 10_000
#: the class of variants when none is named (``variants.DEFAULT_CLASS``, read without
#: importing the model; the classroom's board draws for it too)
DEFAULT_CLASS = "class"
#: where ``serve --assignments DIR`` tells the view (and any worker process) its folder
ENV_FOLDER = "ANALYZER_LAB_ASSIGNMENTS"


def _language(args: argparse.Namespace) -> Language:
    """The command's language (``main`` puts it on ``args``; English otherwise)."""
    return getattr(args, "language", ENGLISH)


def _error(exc: AssignmentError, language: Language) -> str:
    """A refusal in ``language``: its file and field, then its words (its
    :class:`Message` translated)."""
    return language.message(exc).replace("\n", " ")


def _fail(message: str, language: Language = ENGLISH) -> int:
    tr = language.gettext
    text = tr("analyzer-lab: error: {message}").format(message=message)
    print(text, file=sys.stderr)
    return EXIT_USAGE


def _folder(folder: str | None) -> list[Assignment]:
    from analyzer_lab.lessons.assignments import load_folder, ready_assignments

    return load_folder(folder) if folder else ready_assignments()


def cmd_assignments(args: argparse.Namespace) -> int:
    from analyzer_lab.lessons.assignments import AssignmentError

    language = _language(args)
    tr = language.gettext
    try:
        items = _folder(getattr(args, "dir", None))
    except AssignmentError as exc:
        return _fail(_error(exc, language), language)
    if args.json:
        print(json.dumps([a.summary() for a in items], indent=1, ensure_ascii=False))
        return 0
    for a in items:
        print(f"{a.id:32s} {a.lesson:26s} {a.title_in(language.code)}")
        line = tr("you set: {unlocked}; checks: {checks}").format(
            unlocked=", ".join(a.unlocked), checks=", ".join(c.id for c in a.checks)
        )
        print(f"{'':32s} {line}")
    print(tr("{count} assignments").format(count=len(items)))
    return 0


def find_assignment(target: str, folder: str | None = None) -> Assignment:
    """The assignment ``target`` names.

    Parameters
    ----------
    target : str
        A file (``*.json`` or a path), else the id of a ready assignment (or of one in
        ``folder``).
    folder : str, optional
        A folder of assignment files to look the id up in.

    Returns
    -------
    Assignment
        The assignment, validated.

    Raises
    ------
    AssignmentError
        One line naming the file, the field and the problem, or the unknown id.
    """
    from analyzer_lab.lessons.assignments import AssignmentError, load_assignment

    if target.endswith(".json") or os.sep in target:
        return load_assignment(target)
    found = [a for a in _folder(folder) if a.id == target]
    if not found:
        raise AssignmentError(
            "",
            "",
            Message(
                N_("{target}: no such assignment ('analyzer-lab assignments' lists them)"),
                target=repr(target[:60]),
            ),
        )
    return found[0]


def read_answer(path: str | Path, assignment: Assignment) -> dict[str, Any]:
    """The values of an answer file, checked against the assignment.

    Parameters
    ----------
    path : str or pathlib.Path
        The answer file: one JSON object of parameter values.
    assignment : Assignment
        The assignment it answers (what it unlocks).

    Returns
    -------
    dict of str to Any
        The values.

    Raises
    ------
    AssignmentError
        One line naming the file, the field and the problem.
    """
    from analyzer_lab.lessons.assignments import AssignmentError, load_answer
    from analyzer_lab.lessons.assignments.spec import MAX_ANSWER_BYTES

    path = Path(path)
    try:
        raw = path.read_bytes()[: MAX_ANSWER_BYTES + 1]
    except OSError as exc:
        raise AssignmentError(
            str(path), "", Message(N_("cannot be read ({why})"), why=exc.strerror or str(exc))
        ) from None
    return load_answer(raw, assignment, str(path))


def answer_files(targets: list[str]) -> list[Path]:
    """The answer files ``targets`` name: files as given, a folder's ``*.json`` sorted."""
    from analyzer_lab.lessons.assignments import AssignmentError

    out: list[Path] = []
    for t in targets:
        p = Path(t)
        out.extend(sorted(p.glob("*.json")) if p.is_dir() else [p])
        if len(out) > MAX_BATCH:
            raise AssignmentError(
                t, "", Message(N_("makes more than {count} answer files to grade"), count=MAX_BATCH)
            )
    return out


class Grader:
    """Grades answer files against one assignment (its variants released once)."""

    def __init__(self, assignment: Assignment, class_id: str, student: str | None) -> None:
        from analyzer_lab.lessons.assignments import release

        self.assignment = assignment
        self.class_id = class_id
        self.student = student
        self.released = release(assignment) if assignment.varied else None

    def grade_file(self, path: Path) -> dict[str, Any]:
        """The verdict on one file as JSON data (raises :class:`AssignmentError` when the
        file is refused)."""
        from analyzer_lab.lessons.assignments import grade

        a = self.assignment
        values = read_answer(path, a)
        doc: dict[str, Any] = {"file": str(path)}
        if self.released is not None:
            student = self.student or path.stem
            a = self.released.for_student(self.class_id, student).assignment
            doc["student"] = student
        check_run_limits(a, values, str(path))
        doc.update(grade(a, values, str(path)).to_json_dict())
        return doc


def check_run_limits(a: Assignment, values: dict[str, Any], where: str) -> None:
    """Refuse (before it starts) an answer whose run is over the limits of ``run``."""
    from analyzer_lab.lessons.assignments import AssignmentError
    from analyzer_lab.lessons.catalog import get_lesson
    from analyzer_lab.lessons.kit.contract import ParamError
    from analyzer_lab.serve.run_limits import refusal

    try:
        setup = get_lesson(a.lesson).open({**a.start, **values}, a.preset)
    except (ParamError, ValueError):  # grading names the value
        return
    why = refusal(setup, a.t_end, Message(N_("the assignment's t_end")))
    if why is not None:
        raise AssignmentError(where, "", why)


def cmd_grade(args: argparse.Namespace) -> int:
    from analyzer_lab.lessons.assignments import AssignmentError

    language = _language(args)
    try:
        assignment = find_assignment(args.assignment, getattr(args, "dir", None))
        files = answer_files(args.answers)
        grader = Grader(assignment, args.class_id, args.student)
    except AssignmentError as exc:
        return _fail(_error(exc, language), language)
    if len(args.answers) == 1 and len(files) == 1 and not Path(args.answers[0]).is_dir():
        try:
            doc = grader.grade_file(files[0])
        except AssignmentError as exc:
            return _fail(_error(exc, language), language)
        print(json.dumps(doc, indent=1, ensure_ascii=False))
        failed = [c for c in doc["checks"] if not c["pass"]]
        for c in failed:
            line = language.gettext("FAIL {id}: {message}").format(
                id=c["id"], message=language.message(c["message"])
            )
            print(line, file=sys.stderr)
        return 0 if doc["pass"] else EXIT_FAIL
    refused = failed = 0
    for f in files:
        try:
            doc = grader.grade_file(f)
        except AssignmentError as exc:
            refused += 1
            print(json.dumps({"file": str(f), "error": str(exc)}, ensure_ascii=False), flush=True)
            _fail(_error(exc, language), language)
            continue
        failed += not doc["pass"]
        print(json.dumps(doc, ensure_ascii=False), flush=True)
    tr = language.gettext
    summary = tr("graded {files} file(s): {passed} pass, {failed} fail, {refused} refused").format(
        files=len(files), passed=len(files) - failed - refused, failed=failed, refused=refused
    )
    print(summary, file=sys.stderr)
    return EXIT_USAGE if refused else EXIT_FAIL if failed else 0


def use_folder_for_serve(folder: str | None) -> str | None:
    """Validate ``serve --assignments DIR`` before the server starts; ``None`` when fine."""
    if not folder:
        return None
    from analyzer_lab.lessons.assignments import AssignmentError, load_folder

    try:
        load_folder(folder)
    except AssignmentError as exc:
        return str(exc)
    os.environ[ENV_FOLDER] = str(Path(folder).resolve())
    return None


def add_parsers(sub: argparse._SubParsersAction, language: Language = ENGLISH) -> None:
    """Register ``assignments`` and ``grade`` on the main parser, their help in ``language``."""
    tr = language.gettext
    s = sub.add_parser("assignments", help=tr("list the assignments"), language=language)
    s.add_argument("--json", action="store_true", help=tr("print the assignments as JSON"))
    s.add_argument("--dir", help=tr("a folder of assignment files (default: the ready ones)"))
    s.set_defaults(func=cmd_assignments)

    s = sub.add_parser(
        "grade",
        language=language,
        help=tr("check answer files against an assignment"),
        description=tr(
            "Grade one answer file (an indented JSON verdict) or many, or folders of them,"
            " in one process (JSON lines, one per file). Exit 0 when all pass, 1 when one"
            " fails a check, 2 when one is refused as bad input. Each answer's run is held"
            " to the limits of 'run'."
        ),
    )
    s.add_argument("assignment", help=tr("an assignment id or an assignment file"))
    s.add_argument(
        "answers",
        nargs="+",
        metavar="FOLDER_OR_FILES",
        help=tr(
            "answer files (JSON objects of the unlocked parameters' values) or folders of them"
        ),
    )
    s.add_argument("--dir", help=tr("a folder of assignment files (default: the ready ones)"))
    s.add_argument(
        "--class",
        dest="class_id",
        metavar="CLASS",
        default=DEFAULT_CLASS,
        help=tr("the class whose variants are graded (default {default})").format(
            default=repr(DEFAULT_CLASS)
        ),
    )
    s.add_argument(
        "--student",
        metavar="KEY",
        help=tr("the student whose variant is graded (default: each file's name without .json)"),
    )
    s.set_defaults(func=cmd_grade)
