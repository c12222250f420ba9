"""Sphinx configuration: the API reference is generated from the docstrings (autosummary +
numpydoc); the tutorial and the architecture page are the Markdown files beside this one.

Build: ``python -m sphinx -W -b html docs docs/_build/html`` (``pip install -e ".[docs]"``).
"""

project = "slosh_bif"
author = "the slosh_bif developers"
copyright = "2026, the slosh_bif developers"

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "bench", "compare", "figures", "regimes_fig13", "trust"]
templates_path = ["_templates"]

autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "undoc-members": False}
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_validation_checks = set()  # the docstrings' prose is checked by reading, not by rule
myst_heading_anchors = 3
suppress_warnings = ["myst.header"]
html_theme = "alabaster"


def _plain_bars(app, what, name, obj, options, lines):
    # The docstrings write absolute values as |x|, which reStructuredText reads as substitutions.
    for i, line in enumerate(lines):
        lines[i] = line.replace("|", "\\|")


def setup(app):
    app.connect("autodoc-process-docstring", _plain_bars, priority=100)
