"""The pieces of tools/report.py: a sweep's runs as pandas tables (data), the paper's stated
values (paper), the figures (figures, packing_figure) and the report's markdown (sections)."""
