"""Nearest-neighbour search: the one place a neighbour is chosen."""

from ._index import METHODS, PatchIndex, exact_chunk_rows, nearest

__all__ = ["PatchIndex", "nearest", "METHODS", "exact_chunk_rows"]
