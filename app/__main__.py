"""``python -m analyzer_lab`` is ``analyzer-lab``."""

from analyzer_lab.serve.cli import main

raise SystemExit(main())
