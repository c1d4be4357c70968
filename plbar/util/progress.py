"""Progress bars (tqdm on stderr) that cost nothing when switched off."""

from __future__ import annotations

__all__ = ["progress_bar"]


class _Null:
    def update(self, *_):
        pass

    def close(self):
        pass

    def set_description(self, *_):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def progress_bar(total, enabled: bool, desc: str, unit: str = "it", delay: float = 1.0):
    """A tqdm bar on stderr (shown after ``delay`` s) if ``enabled``, else a no-op with the same methods."""
    if not enabled:
        return _Null()
    from tqdm.auto import tqdm

    return tqdm(total=total, desc=desc, unit=unit, leave=False, delay=delay)
