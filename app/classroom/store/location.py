"""Where the course record lives: the data folder (the SQLite file and the server's
secret) and the database URL, from the command line or the environment (the workers of
``serve --workers N`` inherit the environment)."""

from __future__ import annotations

import os
import secrets
from pathlib import Path

ENV_DATA = "ANALYZER_LAB_DATA"
ENV_DB = "ANALYZER_LAB_DB"
ENV_CLASS = "ANALYZER_LAB_CLASS"
DB_FILE = "analyzer-lab.sqlite3"
SECRET_FILE = "secret.key"
DEFAULT_CLASS = "default"


def default_data_dir() -> Path:
    """``$XDG_DATA_HOME/analyzer-lab``, else ``~/.local/share/analyzer-lab``."""
    base = os.environ.get("XDG_DATA_HOME") or str(Path.home() / ".local" / "share")
    return Path(base) / "analyzer-lab"


def data_dir(given: str | None = None) -> Path:
    """The data folder: ``given``, else ``$ANALYZER_LAB_DATA``, else the default; made if
    missing (only its owner may read it)."""
    path = Path(given or os.environ.get(ENV_DATA) or default_data_dir()).expanduser()
    path.mkdir(parents=True, exist_ok=True, mode=0o700)
    return path


def database_url(data: Path, given: str | None = None) -> str:
    """``given`` (``postgresql://...`` or ``sqlite:///...``), else ``$ANALYZER_LAB_DB``,
    else the SQLite file in ``data``."""
    url = given or os.environ.get(ENV_DB)
    if url:
        if not url.startswith(("postgresql://", "postgresql+psycopg://", "sqlite://")):
            raise ValueError(
                f"--db must be postgresql://USER@HOST:PORT/NAME or sqlite:///PATH, got {url[:60]!r}"
            )
        return url
    return f"sqlite:///{data / DB_FILE}"


def server_secret(data: Path) -> bytes:
    """The secret that signs the students' tokens, kept in the data folder (made once;
    several machines of one class share it by sharing this file)."""
    path = data / SECRET_FILE
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except FileExistsError:
        text = path.read_text(encoding="ascii").strip()
        if len(text) < 32:
            raise ValueError(
                f"{path}: the secret is too short (delete the file to make a new one)"
            ) from None
        return text.encode("ascii")
    with os.fdopen(fd, "w", encoding="ascii") as fh:
        fh.write(secrets.token_hex(32) + "\n")
    return server_secret(data)


__all__ = [
    "DEFAULT_CLASS",
    "ENV_CLASS",
    "ENV_DATA",
    "ENV_DB",
    "data_dir",
    "database_url",
    "default_data_dir",
    "server_secret",
]
