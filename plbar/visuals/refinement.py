"""The picture of a refinement study: each family's responses, period range and largest ``xi_eq`` against N.

Drawing only: takes the levels (plain data, as :mod:`plbar.studies.refine.track`
makes them) and writes PNG and PDF files atomically.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .plots import _plt, _save

__all__ = ["refine_family_plot"]


def _points(level: dict):
    """``T / T0^I``, ``xi`` of the admissible points of a level."""
    T, xi, good = [], [], []
    for p in level["pieces"]:
        T.append(np.add(np.asarray(p["T1"], float), np.asarray(p["T2"], float)))
        xi.append(np.asarray(p["xi"], float))
        good.append(np.asarray(p["good"], bool))
    if not T:
        return np.zeros(0), np.zeros(0)
    T, xi, good = (np.concatenate(v) for v in (T, xi, good))
    return T[good] / level["T0_I"], xi[good]


def _responses(ax, levels: list[dict], cmap) -> None:
    ns = [lv["n"] for lv in levels]
    for k, lv in enumerate(levels):
        T, xi = _points(lv)
        col = cmap(k / max(len(levels) - 1, 1))
        ax.plot(T, xi, ".", ms=3, color=col, label=f"N = {lv['n']}" if len(ns) <= 8 or k in (0, len(ns) - 1) else None)
    ax.set_xlabel("$T / T_0^I$ (dimensionless)")
    ax.set_ylabel(r"$\xi_{eq}$ (dimensionless)")
    ax.set_title("a) admissible responses (colour: N)")
    ax.legend(loc="best", ncol=2)


def _ranges(ax, levels: list[dict], cmap) -> None:
    for k, lv in enumerate(levels):
        T, _ = _points(lv)
        col = cmap(k / max(len(levels) - 1, 1))
        if T.size:
            ax.plot([lv["n"], lv["n"]], [T.min(), T.max()], "-", lw=4, color=col, solid_capstyle="butt")
        else:
            ax.plot(lv["n"], 1.0, "x", color="0.5")
        ax.plot(lv["n"], lv["A"] / lv["T0_I"], "_", ms=12, color="k")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("N (elements)")
    ax.set_ylabel("$T / T_0^I$ (dimensionless)")
    ax.set_title("b) period range (bar: admissible, dash: anchor)")


def _largest(ax, levels: list[dict]) -> None:
    n, xi = [], []
    for lv in levels:
        _, x = _points(lv)
        if x.size and x.max() > 0:
            n.append(lv["n"])
            xi.append(x.max())
    if n:
        ax.loglog(n, xi, "o-", color="tab:red")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("N (elements)")
    ax.set_ylabel(r"largest $\xi_{eq}$ of the family (dimensionless)")
    ax.set_title("c) largest " + r"$\xi_{eq}$")


def refine_family_plot(families, out, name: str = "refine_family") -> list[Path]:
    """One row of panels per family: responses (``xi`` vs ``T / T0^I``, colour = N), period range, largest ``xi``.

    Each row is a subfigure headed by the family's label (short panel titles under it: none runs into its
    neighbour), laid out by matplotlib's constrained layout.

    Parameters
    ----------
    families : sequence of (str, list of dict)
        A label and the family's levels, coarse to fine.
    out : path
        Folder; writes ``name.png`` and ``name.pdf``.
    """
    plt = _plt()
    families = list(families)
    rows = max(len(families), 1)
    fig = plt.figure(figsize=(13, 3.9 * rows), layout="constrained")
    subs = np.atleast_1d(fig.subfigures(rows, 1))
    cmap = plt.get_cmap("viridis")
    for sub, (label, levels) in zip(subs, families):
        ax = sub.subplots(1, 3)
        sub.suptitle(label, fontsize=10)
        _responses(ax[0], levels, cmap)
        _ranges(ax[1], levels, cmap)
        _largest(ax[2], levels)
    if not families:
        subs[0].subplots(1, 3)[0].set_title("no family")
    return _save(fig, out, name)
