"""Sphinx configuration of Analyzer Lab's documentation (``docs/``).

Built by ``sphinx-build -W docs docs/_build/html`` (warnings are errors); the notebooks are
executed at every build (nbclient with the ``python3`` ipykernel) and ``-b doctest`` runs
every example of the pages and docstrings (``tests/test_docs.py`` does both).
"""

from __future__ import annotations

project = "Analyzer Lab"
author = "Analyzer Lab"
copyright = "Analyzer Lab"

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.doctest",
    "myst_nb",
]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
exclude_patterns = ["_build", "**.ipynb_checkpoints", "jupyter_execute"]

# numpy-style docstrings
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_ivar = True
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_typehints_format = "short"

# every notebook runs at every build; a cell that raises fails the build
nb_execution_mode = "force"
nb_execution_raise_on_error = True
nb_execution_timeout = 300
nb_execution_show_tb = True
nb_merge_streams = True
nb_output_stderr = "remove-warn"
myst_enable_extensions = ["dollarmath"]

# doctest: the examples' expected output is compared as printed
doctest_global_setup = """
import matplotlib
matplotlib.use("Agg")
"""

html_theme = "alabaster"
html_title = "Analyzer Lab"
html_theme_options = {"description": "Programmed motion of mechatronic systems, from Python"}
