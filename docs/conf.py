"""Sphinx configuration of the kbm documentation (built with warnings as errors)."""

import os
import sys

sys.path.insert(0, os.path.abspath(".."))
sys.path.insert(0, os.path.abspath("_ext"))

project = "kbm"
author = "the kbm developers"
copyright = "2026, the kbm developers"
release = "0.1.0"

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinx.ext.doctest",
    "numpydoc",
    "cli_help",
]
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validation_checks = set()
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_type_aliases = {}
templates_path = []
exclude_patterns = ["_build"]
html_theme = "furo" if __import__("importlib").util.find_spec("furo") else "alabaster"
html_static_path = ["_static"]
html_title = "kbm: KBM averaging, checked numerically"
nitpicky = False
suppress_warnings = ["autodoc.import_object"]
doctest_global_setup = "import numpy as np\nimport sympy as sp\n"
# the >>> examples of the docstrings run under pytest --doctest-modules; here only the
# pages' explicit ``.. doctest::`` blocks run
doctest_test_doctest_blocks = ""
