"""Optional dependencies: imported when a call needs them, or a one-line error naming the
extra that installs them."""

from __future__ import annotations

import importlib
from types import ModuleType

from analyzer_lab.serve.headless import AnalyzerLabError

#: The distribution's name on the package index.
DISTRIBUTION = "analyzer-lab"


def optional(module: str, extra: str, what: str) -> ModuleType:
    """Import ``module`` for ``what``.

    Parameters
    ----------
    module : str
        The module to import, e.g. ``"pandas"``.
    extra : str
        The extra of the distribution that installs it, e.g. ``"pandas"``.
    what : str
        The call that needs it, named in the message, e.g. ``"Run.to_pandas()"``.

    Returns
    -------
    types.ModuleType
        The imported module.

    Raises
    ------
    AnalyzerLabError
        When the module is not installed: the message says which extra to install.
    """
    try:
        return importlib.import_module(module)
    except ImportError:
        package = module.split(".")[0]
        raise AnalyzerLabError(
            f"{what} needs {package}, which is not installed: pip install '{DISTRIBUTION}[{extra}]'"
        ) from None


__all__ = ["DISTRIBUTION", "optional"]
