"""Export: the run as CSV or JSON (the lesson's declared series) or an HTML replay."""

from __future__ import annotations

import json

from app.session import LabError, Session


def export_run(s: Session, kind: str) -> tuple[str, bytes]:
    """The run as a CSV/JSON file or the scene as an HTML replay: (file name, bytes)."""
    stem = f"analyzer-lab-{s.lesson.id}" + (f"-{s.preset}" if s.preset else "")
    if kind == "csv":
        data = s.run_result().to_csv().encode()
        name = stem + ".csv"
    elif kind == "json":
        data = json.dumps(s.run_result().to_json_dict(), indent=1).encode()
        name = stem + ".json"
    elif kind == "html":
        from app.replay import replay_html

        data = replay_html(s).encode()
        name = stem + "-replay.html"
    else:
        raise LabError(f"unknown export {kind[:20]!r}")
    return name, data
