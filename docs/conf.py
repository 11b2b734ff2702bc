"""Sphinx configuration of the contact_sim docs.

    sphinx-build -W --keep-going -b html docs docs/_build/html      # the site
    sphinx-build -W -b doctest docs docs/_build/doctest             # run every example

The pages are Markdown (myst-parser); the API reference is autosummary over
``contact_sim.__all__`` and the node's modules, from numpydoc docstrings. docs/_ext/
contact_sim_docs.py writes the generated parts (the node's tables, console transcripts,
pictures) into docs/_generated/ before the pages are read.
"""
import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / '_ext'))
sys.path.insert(0, str(DOCS.parent))
os.environ.setdefault('MPLBACKEND', 'Agg')

project = 'contact_sim'
author = 'the contact_sim developers'
copyright = '2026, the contact_sim developers'

extensions = [
    'myst_parser',
    'sphinx.ext.autodoc',
    'sphinx.ext.autosummary',
    'sphinx.ext.doctest',
    'sphinx.ext.mathjax',
    'numpydoc',
    'contact_sim_docs',
]

source_suffix = {'.md': 'markdown', '.rst': 'restructuredtext'}
root_doc = 'index'
exclude_patterns = ['_build', '_generated', 'bench_results', 'README.md', 'Thumbs.db', '.DS_Store']
templates_path = []

# Markdown: ::: fences for directives, and `{math}` blocks for the paper's equations
myst_enable_extensions = ['colon_fence']
myst_heading_anchors = 3

# the API reference
autosummary_generate = True
autosummary_imported_members = False   # module pages: their own members, not rclpy's
autodoc_default_options = {'members': True, 'show-inheritance': False}
autodoc_typehints = 'none'
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# every example in the pages and in the docstrings the reference includes
doctest_global_setup = '''
import numpy as np
import contact_sim as cs
np.set_printoptions(precision=6, suppress=True)
'''
doctest_test_doctest_blocks = 'default'

html_theme = 'alabaster'
html_title = 'contact_sim'
html_static_path = []
html_theme_options = {'description': 'Compliant contact, Azad–Featherstone model', 'fixed_sidebar': True,
                      'page_width': '1280px', 'body_max_width': 'none'}   # room for the tables
