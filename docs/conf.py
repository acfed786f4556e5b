"""Sphinx configuration of flexbed's documentation site.

Build it (offline; warnings are errors, as the tests build it)::

    sphinx-build -W -b html docs build/docs

then open ``build/docs/index.html``. The pages are Markdown (MyST); the
command-line reference is generated from flexbed's own argument parsers
(sphinx-argparse) and the API reference from the docstrings (autodoc with
napoleon reading their numpydoc sections).
"""

from importlib import metadata

project = "flexbed"
author = "the flexbed developers"
copyright = "2026, the flexbed developers"
try:
    release = metadata.version("flexbed")
except metadata.PackageNotFoundError:      # a source tree not installed
    release = "0+unknown"
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinxarg.ext",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "**/.ipynb_checkpoints", "README.md"]

myst_enable_extensions = ["dollarmath", "deflist"]
myst_heading_anchors = 4          # [text](page.md#a-heading) links resolve

napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
autodoc_typehints = "none"         # the docstrings say the types, with shapes and units
autodoc_member_order = "bysource"

html_theme = "alabaster"
html_title = f"flexbed {release}"
html_theme_options = {"description": "mount systems with flexible common beds",
                      "page_width": "1200px", "sidebar_width": "240px"}
html_static_path: list[str] = []
html_show_sourcelink = False
