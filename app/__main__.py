"""``python -m app`` is ``analyzer-lab``."""

from app.cli import main

raise SystemExit(main())
