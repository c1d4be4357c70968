"""Log-log plots of mesh-refinement convergence: one panel per quantity.

Drawing only: the items carry the numbers (``plbar.studies.refine.convergence.Convergence``
or anything with ``name, h, q, limit, rate, fitted``); nothing is computed here
beyond the differences that are drawn.  matplotlib is imported lazily (Agg).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .plots import _plt, _save

__all__ = ["MAX_COLUMNS", "convergence_plot"]

MAX_COLUMNS = 3     #: panels per row
MAX_TICKS = 6       #: at most this many mesh sizes are written on an x axis


def _number(x) -> float | None:
    """``x`` as a finite float, or None (None, nan and inf alike)."""
    if x is None:
        return None
    x = float(x)
    return x if math.isfinite(x) else None


def _points(item) -> tuple[np.ndarray, np.ndarray, bool]:
    """``(x, y, against_limit)``: ``|q - limit|`` against ``h``, or ``|q_i - q_{i+1}|`` against ``h_{i+1}``.

    Only the points a log axis can show (finite, positive) are kept.
    """
    h, q = np.asarray(item.h, float).ravel(), np.asarray(item.q, float).ravel()
    keep = np.isfinite(h) & np.isfinite(q)
    h, q = h[keep], q[keep]
    limit = _number(item.limit)
    if limit is not None:
        x, y = h, np.abs(q - limit)
    else:
        x, y = h[1:], np.abs(q[:-1] - q[1:])
    show = (x > 0) & (y > 0)
    return x[show], y[show], limit is not None


def _reference(ax, x: np.ndarray, y: np.ndarray, slope: float | None) -> None:
    """Dashed line of ``slope`` through the centroid of the points in log-log (labelled)."""
    if slope is None or x.size == 0:
        ax.plot([], [], " ", label="fitted slope: none")
        return
    lx, ly = np.log(x), np.log(y)
    xs = np.array([x.min(), x.max()]) if x.size > 1 else np.array([x[0] / 2, x[0] * 2])
    ys = np.exp(ly.mean() + slope * (np.log(xs) - lx.mean()))
    ax.plot(xs, ys, "--", color="0.35", lw=1.0, label=f"fitted slope p = {slope:.3g}")


def _size_ticks(ax, x: np.ndarray) -> None:
    """x ticks at the mesh sizes drawn (at most :data:`MAX_TICKS`), as ``1/N`` where ``1/h`` is an integer."""
    from matplotlib.ticker import FixedLocator, NullFormatter

    ticks = np.unique(x)[::-1]
    ticks = ticks[::math.ceil(ticks.size / MAX_TICKS)]
    n = 1.0 / ticks
    labels = [f"1/{round(v)}" if abs(v - round(v)) <= 1e-9 * v else f"{t:.3g}" for t, v in zip(ticks, n)]
    ax.xaxis.set_major_locator(FixedLocator(ticks))
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xticklabels(labels)


def _panel(ax, item, always: bool = False) -> None:
    """One item: markers, the fitted-slope reference, the final observed rate in the legend.

    An item with a ``caution`` (too few meshes, wandering values) shows its points only, and says why no
    rate or limit is stated (unless ``always``).
    """
    why = (getattr(item, "caution", "") or "") if not always else ""
    hidden = bool(why) and _number(item.rate) is not None
    if why:
        item = _Unstated(item.name, item.h, item.q)
    x, y, against_limit = _points(item)
    if x.size:
        ax.plot(x, y, "o-", color="tab:blue", ms=4, lw=1.0,
                label=r"$|q - q_\infty|$" if against_limit else r"$|q_i - q_{i+1}|$")
        ax.set_xscale("log")
        ax.set_yscale("log")
        _size_ticks(ax, x)
    else:
        ax.text(0.5, 0.5, "no nonzero values to show", ha="center", va="center", transform=ax.transAxes)
    _reference(ax, x, y, _number(item.fitted))
    rate = _number(item.rate)
    if hidden:
        ax.plot([], [], " ", label="no rate stated: " + ("too few meshes" if "mesh" in why else "values wander"))
    else:
        ax.plot([], [], " ", label=f"final observed rate {rate:.3g}" if rate is not None else "final rate: none")
    ax.legend(loc="best", framealpha=0.8, fontsize=7)
    ax.set_xlabel(("mesh size $h$" if against_limit else "mesh size $h_{i+1}$") + " (in units of L)")
    title = str(item.name)
    if against_limit:
        ax.set_title(f"{title}\n|q(h) - {_number(item.limit):.6g}|", fontsize=8)
    else:
        ax.set_title(f"{title}\nno limit stated: successive differences", fontsize=8)


class _Unstated:
    """An item drawn without its rate and limit (successive differences only)."""

    def __init__(self, name, h, q):
        self.name, self.h, self.q = name, h, q
        self.limit = self.rate = self.fitted = None


def convergence_plot(items, out, name: str = "refine_convergence", title: str = "", always: bool = False) -> list[Path]:
    """Log-log convergence panels (at most :data:`MAX_COLUMNS` per row), written as PNG and PDF.

    Parameters
    ----------
    items : sequence
        Objects with ``name, h, q, limit, rate, fitted`` (e.g. ``Convergence``). With a finite ``limit``
        a panel shows ``|q(h) - limit|`` against ``h``; without one (None or nan) ``|q_i - q_{i+1}|``
        against ``h_{i+1}`` (said in the title).  Zero differences are left out (a log axis cannot show
        them).  A dashed line has the ``fitted`` slope; the legend gives it and the final observed ``rate``.
    out : path
        Folder of the files (created if needed).
    name : str
        File stem: ``<out>/<name>.png`` and ``.pdf`` (written atomically).
    title : str
        Figure title.
    always : bool
        State the rate and limit of items with a ``caution`` too (by default they show their values only).

    Returns
    -------
    list of Path
        The PNG and the PDF.
    """
    items = list(items)
    plt = _plt()
    ncol = max(1, min(MAX_COLUMNS, len(items)))
    nrow = max(1, math.ceil(len(items) / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 3.4 * nrow), squeeze=False)
    for ax, item in zip(axes.flat, items):
        _panel(ax, item, always)
    for ax in list(axes.flat)[len(items):]:
        ax.set_visible(False)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return _save(fig, out, name)
