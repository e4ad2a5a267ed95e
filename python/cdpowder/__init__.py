"""cdpowder: contact dynamics of cohesive powders of rigid spheres.

The engine (scenes, runs, a World stepped from Python) is the compiled module cdpowder._core;
its names are this package's (docs/python.md). The pure-Python modules read what a run writes:
cdpowder.summary (summary.json) and cdpowder.tables (the CSV files as pandas DataFrames). They
import without the compiled module, which loads at the first use of an engine name.
"""
import importlib

_ENGINE = ("Scene", "World", "Result", "StepDiagnostics", "ConfigError", "RunFailed", "deposit",
           "compact", "simulate", "load", "__version__", "git_commit")

__all__ = list(_ENGINE)


def __getattr__(name):
    if name in _ENGINE:
        value = getattr(importlib.import_module("._core", __name__), name)
        globals()[name] = value  # once: later reads find it here
        return value
    raise AttributeError(f"module 'cdpowder' has no attribute '{name}'")


def __dir__():
    return sorted(set(globals()) | set(_ENGINE))
