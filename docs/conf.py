"""Sphinx configuration of dynlab's documentation.

Sphinx because the scientific Python projects this toolkit follows (numpy, scipy, pvlib,
python-control, scikit-rf) document with it: numpydoc reads our docstrings as they are
written, autosummary makes the API reference from them, and MyST reads the Markdown pages
that also read well on GitHub. Build it with warnings as errors, as CI does::

    pip install ".[docs]"
    sphinx-build -W --keep-going -b html docs docs/_build/html
"""
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))
sys.path.insert(0, str(HERE.parent))

from processing import __version__  # noqa: E402

project = "dynlab"
author = "dynlab developers"
copyright = "2026, dynlab developers"
version = release = __version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "dynlab_pages",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "gallery/README.md"]
root_doc = "index"

autosummary_generate = True
autodoc_default_options = {"members": True}
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_xref_param_type = False
myst_heading_anchors = 3
suppress_warnings = ["ref.citation", "myst.header"]

html_theme = "pydata_sphinx_theme"
html_title = "dynlab"
html_theme_options = {"navigation_with_keys": False, "show_toc_level": 2,
                      "header_links_before_dropdown": 3}
