"""Progress reporting shared by every long-running function.

``progress=True`` shows a ``tqdm.auto`` bar (a widget in notebooks), a callable
receives ``(step, total, info)`` after every step (for users' own UIs), and
``False``/``None`` reports nothing.
"""

from __future__ import annotations

__all__ = ["Progress"]


class Progress:
    """A progress reporter; use as a context manager so the bar always closes.

    Parameters
    ----------
    progress : bool, None or callable
        What the user passed as ``progress=``.
    total : int
        Number of steps.
    desc : str
        Label of the bar.

    Examples
    --------
    >>> seen = []
    >>> with Progress(lambda step, total, info: seen.append((step, total, info)), 2, "demo") as p:
    ...     p.advance({"energy": 1.0})
    ...     p.advance()
    >>> seen
    [(1, 2, {'energy': 1.0}), (2, 2, {})]
    >>> Progress("yes", 1, "demo")
    Traceback (most recent call last):
    ...
    TypeError: progress must be True, False or a callable (step, total, info), got 'yes'
    """

    def __init__(self, progress, total, desc):
        self.step, self.total = 0, int(total)
        self.callback, self.bar = None, None
        if callable(progress):
            self.callback = progress
        elif progress is True:
            from tqdm.auto import tqdm

            self.bar = tqdm(total=self.total, desc=desc, leave=False)
        elif progress not in (False, None):
            raise TypeError(f"progress must be True, False or a callable (step, total, info), got {progress!r}")

    def advance(self, info=None, n=1):
        """Record ``n`` finished steps; ``info`` is a dict shown on the bar and passed to the callback."""
        info = {} if info is None else info
        self.step += n
        if self.bar is not None:
            self.bar.update(n)
            if info:
                self.bar.set_postfix({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in info.items()},
                                     refresh=False)
        if self.callback is not None:
            self.callback(self.step, self.total, info)

    def close(self):
        """Close the bar (idempotent)."""
        if self.bar is not None:
            self.bar.close()
            self.bar = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False
