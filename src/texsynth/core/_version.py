"""texsynth's version, in the core so that any layer (``texsynth.io``'s provenance attributes) can read it;
``texsynth.__version__`` re-exports it (keep it equal to ``version`` in pyproject.toml)."""

__version__ = "0.1.0"
