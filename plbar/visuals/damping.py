"""``xi_eq`` of the impact against the forcing period for several inherent Rayleigh ratios (issue 21).

Drawing only: the runs come from :func:`plbar.studies.damping.inherent.with_rayleigh` (or anything with
``ratio``, ``rayleigh`` and ``branches``); matplotlib is imported lazily with the Agg backend.
"""

from __future__ import annotations

import numpy as np

from .plots import _plt, _save
from .style import with_units

__all__ = ["xi_rayleigh_plot", "RATIO_COLORS"]

RATIO_COLORS = ("0.35", "tab:blue", "tab:orange", "tab:red", "tab:green", "tab:purple")


def _panel(ax, runs, title: str, units: str = "") -> None:
    """One case: ``xi_eq(T)`` per ratio (stable points filled, unstable hollow), the ratio itself dotted."""
    for k, r in enumerate(runs):
        col = RATIO_COLORS[k % len(RATIO_COLORS)]
        lab = ("undamped (the paper)" if r.ratio == 0
               else f"Rayleigh {100 * r.ratio:g} % at T = {r.at[0]:.3g}, {r.at[1]:.3g}")
        first = True
        for b in r.branches:
            st = np.asarray(b.stable, bool)
            ax.plot(b.T, b.xi, "-", color=col, lw=0.8, alpha=0.7, label=lab if first else None)
            ax.plot(b.T[st], b.xi[st], ".", color=col, ms=2.5)
            ax.plot(b.T[~st], b.xi[~st], "o", color=col, ms=2.5, mfc="none", mew=0.5)
            first = False
        if r.ratio > 0 and r.branches:
            lo = min(float(b.T.min()) for b in r.branches)
            hi = max(float(b.T.max()) for b in r.branches)
            T = np.linspace(lo, hi, 200)
            W = 2 * np.pi / T
            a, bb = r.rayleigh
            ax.plot(T, a / (2 * W) + bb * W / 2, ":", color=col, lw=1.0)
    ax.set_xlabel(with_units("forcing period $T$", units))
    ax.set_ylabel(with_units(r"$\xi_{eq}$ of the impact (Eq. 22, damped velocities)", "dimensionless"))
    ax.set_title(title)
    ax.set_ylim(bottom=0)
    ax.legend(loc="upper left")


def xi_rayleigh_plot(panels, out, name: str = "xi_rayleigh", units: dict | None = None) -> list:
    """Draw ``xi_eq`` against ``T`` for each Rayleigh ratio, one panel per case; PNG and PDF.

    Parameters
    ----------
    panels : sequence of (str, sequence of runs)
        A title and the runs of one case (:class:`plbar.studies.damping.inherent.DampedRun`: ``ratio``,
        ``at``, ``rayleigh``, ``branches``).
    out : path
        Output folder.
    name : str
        File stem.
    units : dict, optional
        Title -> the case's units (:func:`plbar.visuals.style.unit_note`), said on the axes.

    Returns
    -------
    list of Path
        The PNG and the PDF.

    Notes
    -----
    Dots: stable responses, circles: unstable ones; the dotted line of each colour is the Rayleigh
    ratio at the forcing frequency, ``alpha / (2 W) + beta W / 2``: a linear analysis takes
    ``zeta(W) + xi_eq`` (README, "Inherent damping").
    """
    plt = _plt()
    panels = list(panels)
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 3.9), squeeze=False)
    for ax, (title, runs) in zip(axes[0], panels):
        _panel(ax, runs, title, (units or {}).get(title, ""))
    fig.tight_layout()
    return _save(fig, out, name)
