"""A choice among each query's own candidates by a cost the caller computed: distance plus an extra term."""

from __future__ import annotations

import numpy as np

from .._validate import check_choice

__all__ = ["lowest_cost"]


def lowest_cost(distances, extra=None, *, ties="first"):
    """For each query (a row), the candidate (a column) of least ``distances + extra``: a re-scoring query.

    The search layer's answer when a method ranks candidates by more than their distance: Kwatra et
    al.'s Algorithm 2 (the distance plus the soft constraint's cost), a tileable synthesis's wrap
    search, a mixture's alternation (Wei 2002, eq. 1). The candidates and their costs come from the
    method; the choice, and how ties break, is made here.

    Parameters
    ----------
    distances : array_like
        ``(M, K)`` squared distances of each query to its ``K`` candidates.
    extra : array_like, optional
        ``(M, K)`` cost added to each (another energy term); None: the distances alone.
    ties : {"first", "last"}
        Which of equal costs wins: the first column, or the last (e.g. the current match, placed
        last, keeps its place against an equally good candidate).

    Returns
    -------
    choice : numpy.ndarray
        ``(M,)`` int, the column chosen for every row.
    cost : numpy.ndarray
        ``(M,)`` its cost.

    Examples
    --------
    >>> import numpy as np
    >>> d = np.array([[1.0, 0.5, 0.5], [2.0, 3.0, 1.0]])
    >>> lowest_cost(d, ties="last")[0].tolist(), lowest_cost(d, extra=[[0.0, 1.0, 1.0], [0.0, 0.0, 0.0]])[0].tolist()
    ([2, 2], [0, 2])
    """
    ties = check_choice(ties, "ties", ("first", "last"))
    cost = np.asarray(distances) if extra is None else np.asarray(distances) + np.asarray(extra)
    if ties == "last":
        choice = cost.shape[1] - 1 - np.argmin(cost[:, ::-1], axis=1)
    else:
        choice = np.argmin(cost, axis=1)
    return choice, cost[np.arange(cost.shape[0]), choice]
