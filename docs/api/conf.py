# Sphinx's configuration of the Python API reference (docs/api): the docstrings of the package
# cdpowder, with the module built on PYTHONPATH (ctest docs_api_test builds it with -W):
#   PYTHONPATH=build/release/python python3 -m sphinx -W -b html docs/api build/docs/api
project = "cdpowder"
extensions = ["sphinx.ext.autodoc", "myst_parser"]
source_suffix = {".md": "markdown"}
autodoc_member_order = "bysource"
autodoc_default_options = {"members": True, "undoc-members": True, "special-members": "__getitem__, __len__"}
html_theme = "alabaster"
exclude_patterns = ["_build"]
