"""Progress bars for long work: one tqdm bar on stderr, shown only to a person watching.

A bar appears only when stderr is a terminal, not under continuous
integration (``CI`` set), and only once the work has lasted a second, so
short runs and logs stay clean. tqdm is imported only when a bar is shown.
"""

from __future__ import annotations

import os
import sys

__all__ = ["show_progress", "progress_bar"]


def show_progress():
    """Whether progress bars are shown: stderr is a terminal and ``CI`` is not set."""
    return bool(sys.stderr.isatty()) and not os.environ.get("CI")


class _NoBar:
    """What :func:`progress_bar` returns when no bar is shown: the same methods, doing nothing."""

    def update(self, count=1):
        pass

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exception):
        self.close()
        return False


def progress_bar(total, description, unit="configuration", shown=None):
    """A progress bar over `total` units of work.

    Parameters
    ----------
    total : int
    description : str
        Shown before the bar.
    unit : str
    shown : bool, optional
        Force the bar on or off; default :func:`show_progress`.

    Returns
    -------
    tqdm.tqdm or a do-nothing bar
        Either has ``update(count)``, ``close()`` and is a context manager.
    """
    if not (show_progress() if shown is None else shown) or total <= 0:
        return _NoBar()
    from tqdm import tqdm
    return tqdm(total=total, desc=description, unit=unit, file=sys.stderr, leave=False, delay=1.0)
