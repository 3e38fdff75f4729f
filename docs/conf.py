# Sphinx configuration of the sphib documentation (scripts/run_docs.sh builds it with warnings as
# errors). Markdown pages through MyST; every docs/*.md page is picked up by index.md's toctrees.
# The scene-key reference comes from `sphib keys --json` and the Python reference from the module
# itself: SPHIB_BINARY names the command (default ../build/sphib) and SPHIB_PYTHONPATH the
# directory of the module (default ../build/python).
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "_ext"))
sys.path.insert(0, os.environ.get("SPHIB_PYTHONPATH", os.path.join(HERE, "..", "build", "python")))

project = "sphib"
author = "the sphib authors"
copyright = "the sphib authors"
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphib_docs"]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store"]
myst_enable_extensions = ["deflist"]  # equations are written in plain text: the pages need no script
myst_heading_anchors = 3
# Pages written by others slot in through index.md's glob; a heading that skips a level is theirs to
# tidy, not a reason to fail the build. Every other warning fails it (scripts/run_docs.sh: -W).
suppress_warnings = ["myst.header"]
html_theme = "alabaster"
html_title = "sphib"
html_theme_options = {"page_width": "1100px", "sidebar_width": "240px", "fixed_sidebar": True}
html_static_path = []
autodoc_member_order = "bysource"
sphib_binary = os.environ.get("SPHIB_BINARY", os.path.join(HERE, "..", "build", "sphib"))
