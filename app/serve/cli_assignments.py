"""``analyzer-lab assignments`` and ``analyzer-lab grade``: assignments headless.

``grade ASSIGNMENT ANSWER.json`` prints the per-check verdict as JSON and exits 0 when
every check passes, 1 when one fails, 2 on bad input (one line on stderr saying what is
wrong and where).  ``ASSIGNMENT`` is the id of a ready assignment (or of one in
``--dir``) or the path of an assignment file.  No view code is imported.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from analyzer_lab.lessons.assignments import Assignment

EXIT_FAIL = 1
EXIT_USAGE = 2
#: where ``serve --assignments DIR`` tells the view (and any worker process) its folder
ENV_FOLDER = "ANALYZER_LAB_ASSIGNMENTS"


def _fail(message: str) -> int:
    print(f"analyzer-lab: error: {message}", file=sys.stderr)
    return EXIT_USAGE


def _folder(folder: str | None) -> list[Assignment]:
    from analyzer_lab.lessons.assignments import load_folder, ready_assignments

    return load_folder(folder) if folder else ready_assignments()


def cmd_assignments(args: argparse.Namespace) -> int:
    from analyzer_lab.lessons.assignments import AssignmentError

    try:
        items = _folder(getattr(args, "dir", None))
    except AssignmentError as exc:
        return _fail(str(exc))
    if args.json:
        print(json.dumps([a.summary() for a in items], indent=1, ensure_ascii=False))
        return 0
    for a in items:
        print(f"{a.id:32s} {a.lesson:26s} {a.title}")
        print(
            f"{'':32s} you set: {', '.join(a.unlocked)}; checks: {', '.join(c.id for c in a.checks)}"
        )
    print(f"{len(items)} assignments")
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
            "", "", f"{target[:60]!r}: no such assignment ('analyzer-lab assignments' lists them)"
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
        raise AssignmentError(str(path), "", f"cannot be read ({exc.strerror})") from None
    return load_answer(raw, assignment, str(path))


def cmd_grade(args: argparse.Namespace) -> int:
    from analyzer_lab.lessons.assignments import AssignmentError, grade

    try:
        assignment = find_assignment(args.assignment, getattr(args, "dir", None))
        values = read_answer(args.answer, assignment)
        verdict = grade(assignment, values, str(Path(args.answer)))
    except AssignmentError as exc:
        return _fail(str(exc))
    print(json.dumps(verdict.to_json_dict(), indent=1, ensure_ascii=False))
    for c in verdict.failed:
        print(f"FAIL {c.id}: {c.message}", file=sys.stderr)
    return 0 if verdict.passed else EXIT_FAIL


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


def add_parsers(sub: argparse._SubParsersAction) -> None:
    """Register ``assignments`` and ``grade`` on the main parser."""
    s = sub.add_parser("assignments", help="list the assignments")
    s.add_argument("--json", action="store_true")
    s.add_argument("--dir", help="a folder of assignment files (default: the ready ones)")
    s.set_defaults(func=cmd_assignments)

    s = sub.add_parser("grade", help="check an answer file against an assignment")
    s.add_argument("assignment", help="an assignment id or an assignment file")
    s.add_argument("answer", help="a JSON object of the unlocked parameters' values")
    s.add_argument("--dir", help="a folder of assignment files (default: the ready ones)")
    s.set_defaults(func=cmd_grade)
