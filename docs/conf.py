"""Sphinx configuration of the fricctl book (``make book``; ``docs/book_authoring.md``).

Sphinx + myst-nb + sphinx-book-theme (the Jupyter Book stack), all from PyPI (``.[book]``),
nothing fetched at build or reading time: MathJax is served from the site itself
(``sphinx-mathjax-offline``), no widget JavaScript is loaded from a CDN.

* ``chapters/`` (a symbolic link to the repository's ``chapters/``): the jupytext chapters,
  read by ``_ext/fricctl_book.read_chapter`` and executed in a fresh kernel each build
  (``FRICCTL_FAST=1`` in the environment gives their short version), several at a time
  beside ``fricctl reproduce`` (``fricctl_book_jobs``, ``_ext/fricctl_book.start_execution``);
* ``reproduction.md``: the README's tables (included from README.md) and the output of
  ``fricctl reproduce``, run into ``fricctl_reproduce_dir`` at the start of the build (and on
  every other bench beside it, whose verdicts are columns of the page's summary table);
* ``api/``: the reference, from the numpydoc docstrings.

A cell error or any Sphinx warning fails the build (``-W --keep-going`` in the Makefile).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))

import fricctl  # noqa: E402

# the chapters' plt.show() must reach the kernel's inline backend: a MPLBACKEND=Agg inherited
# from `make test` or a CI job would make every figure of the book silently disappear
os.environ.pop("MPLBACKEND", None)

project = "fricctl"
author = "the fricctl contributors"
copyright = "2026, the fricctl contributors (MIT License)"
release = version = fricctl.__version__

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "numpydoc",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # MathJax 3 copied into _static/mathjax: no CDN
    "sphinxcontrib.bibtex",    # the one bibliography, docs/references.bib (bibliography.md)
    "fricctl_book",
]

root_doc = "index"
exclude_patterns = [
    "conf.py", "_ext", "_build",
    "chapters/__pycache__", "**/.ipynb_checkpoints",
]

# -- MyST -----------------------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_heading_anchors = 3

# an undefined macro is a TeX error (shown as such, and caught by tests/test_book.py), as in LaTeX,
# not red text
# every display equation numbered, so that a teacher can cite "Eq. (5.3)" (issue 24 item 5)
math_number_all = True
# captioned figures numbered as the equations are: the chapters are numbered sections (the
# `:numbered: 1` toctree of index.md) and numbers restart in each, prefixed by the chapter's,
# "Fig. 5.2", "Eq. (5.3)" (numfig_secnum_depth 1: the chapter's number only, not a section's;
# math_numfig: equations as figures); the PDF numbers them the same way (LaTeX's chapters, made
# to agree with the toctree by fricctl_book.latex_numbering).  A page outside the numbered
# toctree (notation, API) has no section number: its numbers run on, "Eq. (3)".
numfig = True
numfig_secnum_depth = 1
math_numfig = True
numfig_format = {"figure": "Fig. %s", "table": "Table %s", "code-block": "Listing %s",
                 "section": "Section %s"}
math_eqref_format = "Eq. ({number})"
mathjax3_config = {"tex": {"packages": {"[-]": ["noundefined"]}}}

# -- the bibliography ------------------------------------------------------------------------
# one file, listed whole on bibliography.md; a chapter cites an entry with a Markdown link to its
# key, [Gervini, Gomes & da Rosa 2003](#gervini2003), which Jupyter shows as its text and MyST
# resolves (like the `any` role) to a citation, "(Gervini et al., 2003)", linked to the entry
bibtex_bibfiles = ["references.bib"]
bibtex_default_style = "plain"
bibtex_reference_style = "author_year"

# -- myst-nb: execution and rendering -------------------------------------------------------
nb_custom_formats = {".py": ["fricctl_book.read_chapter", {}, False]}
nb_execution_mode = "force"           # the book shows what today's code does
nb_execution_raise_on_error = True    # a cell error fails the build
nb_execution_show_tb = True
nb_execution_in_temp = True           # chapters must not depend on the working directory
# a hang guard only (seconds per cell): full-mode cells take up to a minute or two
nb_execution_timeout = int(os.environ.get("FRICCTL_BOOK_CELL_TIMEOUT", "1800"))
nb_merge_streams = True
nb_ipywidgets_js = {}                 # widgets are Jupyter-only; the book shows static fallbacks
nb_render_markdown_format = "myst"

# -- API reference ---------------------------------------------------------------------------
autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "none"            # numpydoc's Parameters sections carry types and units
numpydoc_show_class_members = False   # no autosummary stubs
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# -- HTML ------------------------------------------------------------------------------------
# code that scrolls on screen and wraps on paper, solutions opened for printing, figures that
# open at full size on a click (issue 24): docs/_static/fricctl.css and fricctl.js
html_static_path = ["_static"]
html_css_files = ["fricctl.css"]
html_js_files = ["fricctl.js"]
html_theme = "sphinx_book_theme"
html_title = "fricctl"
html_theme_options = {
    "home_page_in_toc": True,
    "show_toc_level": 2,
    "use_download_button": True,
    "use_fullscreen_button": False,
    "navigation_with_keys": False,
}
html_show_sourcelink = True
html_last_updated_fmt = None

# -- PDF (`make book-pdf`) ---------------------------------------------------------------------
# Sphinx's LaTeX builder and latexmk, with XeLaTeX for the Unicode of the outputs and prose
# (ω, ≤, ±, ², Å) in Debian's FreeFont; the chapters are not executed again: `make book-pdf`
# gives the notebooks the HTML build executed (fricctl_executed_notebooks, fricctl_book.py)
latex_engine = "xelatex"
latex_documents = [(root_doc, "fricctl.tex",
                    "fricctl: friction in a robot drive joint, learned and compensated",
                    author, "manual")]
latex_elements = {
    "papersize": "a4paper",
    "pointsize": "10pt",
    # long code and output lines wrap (as on the printed HTML page) instead of running off
    "sphinxsetup": "verbatimwrapslines=true, verbatimforcewraps=true",
}
# the index holds the API's names (ASCII): makeindex, not xindy (one Debian package less)
latex_use_xindy = False
latex_show_urls = "no"
latex_show_pagerefs = False
