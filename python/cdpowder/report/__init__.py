"""cdpowder.report: a sweep folder's figures and report.md (`python -m cdpowder.report DIR`;
tools/report.py runs it from the source tree). The pieces: a sweep's runs as pandas tables
(data), the paper's stated values (paper), the figures (figures, packing_figure) and the
report's markdown (sections)."""
