"""Plots of a solved case: the frequency response (amplitude and ``xi_eq`` against ``T``) and the paths plane.

Drawing only: every function takes results and writes files (atomically);
matplotlib is imported lazily with the Agg backend.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..paths import FOLD_MU, FOLD_T, GRAZING, NEIMARK_SACKER, PERIOD_DOUBLING
from ..util.files import atomic_path
from .style import PAPER_SIGNATURE, signature_styles, unit_note, with_units

__all__ = ["frequency_response", "paths_plane", "xi_load_map", "FAM_STYLE", "DOF_COLORS",
           "FAMILIES"]

FAMILIES = ("T0_I", "T0_II/2")      #: the branch families drawn in their own colours
FAM_STYLE = {"T0_I": ("tab:blue", "path 1 (near $T_0^I$)"), "T0_II/2": ("tab:orange", "path 2 (near $T_0^{II}/2$)"),
             "other": ("0.65", "other branches")}
DOF_COLORS = ["tab:blue", "tab:red", "tab:orange", "tab:purple", "tab:green", "tab:brown", "tab:pink", "tab:cyan"]
EVENT_MARKS = {FOLD_T: ("s", "k"), GRAZING: ("v", "tab:purple"), NEIMARK_SACKER: ("D", "tab:green"),
               PERIOD_DOUBLING: ("^", "tab:orange"), FOLD_MU: ("P", "tab:brown")}


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"figure.dpi": 110, "savefig.dpi": 150, "axes.grid": True, "grid.alpha": 0.3,
                         "font.size": 9, "axes.titlesize": 10, "legend.fontsize": 8})
    return plt


def _save(fig, out, name: str) -> list[Path]:
    import matplotlib as mpl

    out = Path(out)
    files = []
    fig.canvas.draw()                                   # the tight box once for both files (a draw saved)
    box = fig.get_tightbbox(fig.canvas.get_renderer()).padded(mpl.rcParams["savefig.pad_inches"])
    for ext in ("png", "pdf"):
        path = out / f"{name}.{ext}"
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format=ext, bbox_inches=box)
        files.append(path)
    import matplotlib.pyplot as plt

    plt.close(fig)
    return files


def _joined(xs, ys):
    """The curves ``(xs[i], ys[i])`` as one line broken by NaN between them (one artist for many branches)."""
    if not xs:
        return np.empty(0), np.empty(0)
    gap = [np.array([np.nan])]
    return (np.concatenate([v for x in xs for v in (np.asarray(x, float), *gap)]),
            np.concatenate([v for y in ys for v in (np.asarray(y, float), *gap)]))


def _picked(xs, ys, masks):
    """The points of every curve where its mask holds, in one array pair (one artist)."""
    if not xs:
        return np.empty(0), np.empty(0)
    return (np.concatenate([np.asarray(x)[m] for x, m in zip(xs, masks)]),
            np.concatenate([np.asarray(y)[m] for y, m in zip(ys, masks)]))


def _event_points(branches, y=None) -> dict:
    """Event kind -> ``(T1, T2, T, y)`` rows of its events (``y``: per-branch values, default ``xi``)."""
    pts: dict = {}
    for j, b in enumerate(branches):
        yy = b.xi if y is None else y[j]
        T1, T2 = b.T1, b.T2
        for e in b.events:
            i = e["index"]
            pts.setdefault(e["kind"], []).append((T1[i], T2[i], e["T"], float(yy[i])))
    order = [k for k in EVENT_MARKS if k in pts] + sorted(set(pts) - set(EVENT_MARKS))
    return {k: np.array(pts[k], float).reshape(-1, 4) for k in order}


def _draw_events(ax, pts: dict, cols: tuple[int, int], label: bool = True) -> None:
    """One marker series per event kind (``cols`` of the point arrays as x, y), labelled once per kind."""
    for kind, P in pts.items():
        m, c = EVENT_MARKS.get(kind, ("o", "k"))
        ax.plot(P[:, cols[0]], P[:, cols[1]], m, color=c, ms=5, mfc="none", mew=1.0, ls="none", zorder=4,
                label=kind if label else None)


#: anchor lines closer than this fraction of the axis span share one label
ANCHOR_GAP = 0.03


def _anchors(ax, T0I: float, T0II: float, label: bool = True) -> list:
    """Dashed lines at ``T0^I`` and ``T0^II/2``, labelled above the axes on one line.

    Lines closer than :data:`ANCHOR_GAP` of the axis span share one label, ``T0^I = T0^II/2`` (a uniform bar
    without an end mass: ``T0^II = 2 T0^I``) or ``T0^I ~ T0^II/2``, instead of two labels stacked or overlapping.
    """
    lo, hi = ax.get_xlim()
    span = max(hi - lo, 1e-300)
    gap = abs(T0I - T0II / 2)
    if gap < ANCHOR_GAP * span:
        sign = "=" if gap <= 1e-9 * span else r"\approx"
        marks = [(0.5 * (T0I + T0II / 2), f"$T_0^I {sign} T_0^{{II}}/2$")]
    else:
        marks = [(T0I, "$T_0^I$"), (T0II / 2, "$T_0^{II}/2$")]
    for x in (T0I, T0II / 2):
        ax.axvline(x, color="0.5", ls="--", lw=0.7)
    texts = []
    for x, lab in marks:
        if label:
            texts.append(ax.annotate(lab, (x, 1.0), xycoords=ax.get_xaxis_transform(), ha="center", va="bottom",
                                     xytext=(0, 2), textcoords="offset points", fontsize=8))
    return texts


def _plain_log_ticks(ax) -> None:
    """Tick labels of a log axis as plain numbers (``0.6``, ``6``, ``60``), never ``6x10^0``."""
    from matplotlib.ticker import FuncFormatter

    fmt = FuncFormatter(lambda v, _: f"{v:g}")
    ax.yaxis.set_major_formatter(fmt)
    ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: f"{v:g}" if _few_decades(ax) else ""))


def _few_decades(ax) -> bool:
    lo, hi = ax.get_ylim()
    return lo > 0 and hi / lo < 100


def frequency_response(res, out, name: str = "frequency_response", xi: str = "eq") -> Path:
    """Frequency-response view: ``max |x_c|`` and ``xi_eq`` against ``T``, coloured by stability.

    Solid dark points are stable orbits (all Floquet multipliers inside the
    unit circle), light crosses unstable ones; events along the branches
    (folds, grazing, stability changes) are markers, one legend entry per kind
    present (no per-event text, so hundreds of branches stay readable).
    """
    plt = _plt()
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9.0, 6.2), sharex=True)
    paper = list(res.paper)
    others = [b for b in res.branches if not b.paper]
    amps = [b.amplitude for b in paper]
    st = [np.asarray(b.stable, bool) for b in paper]
    for ax, ys in ((ax1, amps), (ax2, [b.xi if xi == "eq" else b.xi_w for b in paper])):
        Ts = [b.T for b in paper]
        ax.plot(*_joined(Ts, ys), "-", color="0.75", lw=0.8, zorder=1)
        ax.plot(*_picked(Ts, ys, st), "o", ms=2.6, color="tab:blue", ls="none", zorder=3)
        ax.plot(*_picked(Ts, ys, [~s for s in st]), "x", ms=2.6, color="tab:red", alpha=0.6, ls="none", zorder=2)
    _draw_events(ax1, _event_points(paper, amps), (2, 3), label=False)
    ev = _event_points(paper, None if xi == "eq" else [b.xi_w for b in paper])
    _draw_events(ax2, ev, (2, 3))
    _draw_signatures(ax1, ax2, others, xi)
    found = bool(res.branches)
    if found:                       # (without a response, T0's labels would lie far outside the range asked)
        T0I, T0II = res.prob.system.T0
        _anchors(ax1, T0I, T0II)
        _anchors(ax2, T0I, T0II, label=False)
    units = unit_note(res.prob.bar)
    ax1.set_ylabel(with_units(r"max $|x_c|$ (contact node)", units))
    ax2.set_ylabel(with_units(r"$\xi_{eq}$ (Eq. 22)" if xi == "eq" else r"$\xi_\omega$ (one frequency, the forcing's)",
                              "dimensionless"))
    ax2.set_xlabel(with_units("forcing period $T$", units))
    kinds = [(np.any(b.stable), np.any(~np.asarray(b.stable, bool))) for b in paper]
    hollow = " (other signatures: hollow)" if others else ""
    if any(k[0] for k in kinds):                                   # only the kinds present
        ax1.plot([], [], "o", color="tab:blue", label="1P (paper's class), stable")
    if any(k[1] for k in kinds):
        ax1.plot([], [], "x", color="tab:red", label="1P, unstable" + hollow)
    if ax1.get_legend_handles_labels()[1]:
        ax1.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False)
    if ev:
        ax2.legend(loc="best", framealpha=0.8, title="events")
    if found:
        ax1.set_yscale("log")
        _plain_log_ticks(ax1)
    else:                                   # nothing found: say so over the range asked (no log axis of nothing)
        d = res.domain
        ax2.set_xlim(d.T1[0] + d.T2[0], d.T1[1] + d.T2[1])
        ax1.text(0.5, 0.5, "no admissible periodic response in this range", transform=ax1.transAxes, ha="center")
    p = res.prob
    fig.suptitle(f"{p.bar.describe() if p.bar else ''}; load {p.load.describe() if p.load else ''}", fontsize=8)
    return _save(fig, out, name)[0]


#: the signatures (other than ``1P``) with the most points keep their colour and a legend entry each; the rest are
#: drawn grey (their markers kept) under one entry, so the legend stays at most this + 3 entries
MAX_SIGNATURE_ENTRIES = 5
#: the colour of the signatures beyond :data:`MAX_SIGNATURE_ENTRIES`
OTHER_COLOR = "0.45"


def _draw_signatures(ax1, ax2, branches, xi: str = "eq") -> None:
    """The branches the signature search found, one colour and marker per signature (:func:`signature_styles`):
    filled stable, hollow unstable; those of the paper's class (``1P``) as the paper's (blue, red crosses).

    The :data:`MAX_SIGNATURE_ENTRIES` signatures with the most points have a legend entry each; the others
    keep their markers in grey (:data:`OTHER_COLOR`) under one entry that names them."""
    styles = signature_styles(b.label for b in branches)
    size = {lab: sum(len(b.T) for b in branches if b.label == lab) for lab in styles if lab != PAPER_SIGNATURE}
    named = sorted(size, key=lambda lab: -size[lab])[:MAX_SIGNATURE_ENTRIES]
    rest = [lab for lab in styles if lab in size and lab not in named]
    styles = {lab: (col if lab == PAPER_SIGNATURE or lab in named else OTHER_COLOR, mk)
              for lab, (col, mk) in styles.items()}
    for lab, (col, mk) in styles.items():            # one artist per signature and stability: a fast savefig
        bs = [b for b in branches if b.label == lab]
        Ts, st = [b.T for b in bs], [np.asarray(b.stable, bool) for b in bs]
        amps = [np.array([o.amplitude for o in b.orbits]) for b in bs]
        for ax, ys in ((ax1, amps), (ax2, [b.xi if xi == "eq" else b.xi_w for b in bs])):
            if lab == PAPER_SIGNATURE:
                ax.plot(*_picked(Ts, ys, st), mk, ms=2.6, color=col, ls="none", zorder=3)
                ax.plot(*_picked(Ts, ys, [~s for s in st]), "x", ms=2.6, color="tab:red", alpha=0.6, ls="none",
                        zorder=2)
                continue
            ax.plot(*_picked(Ts, ys, st), mk, ms=3.2, color=col, ls="none", zorder=3)
            ax.plot(*_picked(Ts, ys, [~s for s in st]), mk, ms=3.2, color=col, mfc="none", alpha=0.5, ls="none",
                    zorder=2)
    for lab in named:
        col, mk = styles[lab]
        ax1.plot([], [], mk, color=col, ls="none", label=f"signature {lab}")
    if rest:
        ax1.plot([], [], "o", color=OTHER_COLOR, ls="none",
                 label=f"{len(rest)} other signature{'s' if len(rest) > 1 else ''} (grey):\n"
                       + _wrap(", ".join(rest), 28))


def _wrap(text: str, width: int) -> str:
    """``text`` broken at ", " into lines of about ``width`` characters."""
    import textwrap

    return "\n".join(textwrap.wrap(text, width, break_long_words=False))


#: at most this many branches (those with the largest ``xi_eq``) get their id written in :func:`paths_plane`
MAX_BRANCH_LABELS = 8


def paths_plane(res, out, name: str = "paths_T1_T2") -> Path:
    """Branches in the ``(T^I, T^II)`` plane (paper Fig. 2b) with their events.

    Events are markers with one legend entry per kind present; only the
    :data:`MAX_BRANCH_LABELS` branches with the largest ``xi_eq`` carry their id.
    """
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.5, 5.2))
    paper = list(res.paper)
    top = sorted(paper, key=lambda b: -float(b.xi.max()) if len(b) else 0.0)[:MAX_BRANCH_LABELS]
    for b in paper:
        ax.plot(b.T1, b.T2, "-", lw=1.2)
    ev = _event_points(paper)
    _draw_events(ax, ev, (0, 1))
    units = unit_note(res.prob.bar)
    ax.set_xlabel(with_units("$T^I$", units))
    ax.set_ylabel(with_units("$T^{II}$", units))
    d = res.domain
    ax.set_xlim(*d.T1)
    ax.set_ylim(*d.T2)
    _branch_labels(ax, fig, top)                      # after the limits: positions in points are final
    if ev:
        ax.legend(fontsize=7, loc="best", framealpha=0.8)
    more = len(paper) > len(top)
    ax.set_title("periodic paths and events (#: branch id" +
                 (f", the {len(top)} with the largest $\\xi_{{eq}}$)" if more else ")"))
    return _save(fig, out, name)[0]


#: branch labels closer than this (points) are moved apart, so "1" and "0" never read as "10"
LABEL_GAP = 11.0


def _branch_labels(ax, fig, branches) -> list:
    """``#id`` at each branch's largest ``xi_eq``; a label that would touch an earlier one is moved up."""
    to_pt = 72.0 / fig.dpi
    placed, texts = [], []
    for b in branches:
        j = int(np.argmax(b.xi))
        x, y = (v * to_pt for v in ax.transData.transform((b.T1[j], b.T2[j])))
        dy = 3.0
        while any(abs(x - px) < 2.5 * LABEL_GAP and abs(y + dy - py) < LABEL_GAP for px, py in placed):
            dy += LABEL_GAP
        placed.append((x, y + dy))
        texts.append(ax.annotate(f"#{b.id}", (b.T1[j], b.T2[j]), xytext=(3, dy), textcoords="offset points",
                                 fontsize=7, arrowprops=dict(arrowstyle="-", lw=0.4, color="0.5") if dy > 3 else None))
    return texts


def _edges(v):
    """Cell edges around the values ``v`` (midpoints, ends extended by half a step)."""
    v = np.asarray(v, float)
    if v.size == 1:
        return np.r_[v - 1e-3 * max(abs(v[0]), 1.0), v + 1e-3 * max(abs(v[0]), 1.0)]
    mid = 0.5 * (v[1:] + v[:-1])
    return np.r_[2 * v[0] - mid[0], mid, 2 * v[-1] - mid[-1]]


def xi_load_map(path, T, branch, fam, s, xi, xi_worst, xi_best, fams, units: str = "") -> Path:
    """``xi_eq`` over (period ``T``, load position ``s``) per family, with the largest ``xi_eq`` of any load above it.

    ``T, branch, fam`` per path point (P,), ``xi`` (P, S) for unit forces at ``s`` (S,),
    ``xi_worst, xi_best`` (P,) the worst load distribution and the best single force; ``units`` the bar's
    (:func:`plbar.visuals.style.unit_note`), said on the axes.
    """
    plt = _plt()
    fig, ax = plt.subplots(2, len(fams), figsize=(4.5 * len(fams), 6), sharex="col", squeeze=False,
                           gridspec_kw={"height_ratios": [1, 2]})
    for c, f in enumerate(fams):
        m = fam == f
        for bid in np.unique(branch[m]):
            k = m & (branch == bid)
            ax[0, c].plot(T[k], xi_worst[k], "k-", lw=1)
            ax[0, c].plot(T[k], xi_best[k], "r--", lw=1)
        ax[0, c].set_title(f"family {f}")
        ax[0, c].legend(["largest $\\xi_{eq}$ of any load", "best single force"], fontsize=7)
        vmax = max(float(xi[m].max()), 1e-300)
        for bid in np.unique(branch[m]):
            k = np.flatnonzero(m & (branch == bid))
            sc = ax[1, c].pcolormesh(_edges(T[k]), _edges(s), xi[k].T, cmap="viridis", vmin=0.0,
                                     vmax=vmax, shading="flat")
        fig.colorbar(sc, ax=ax[1, c], label=with_units(r"$\xi_{eq}$ (unit force at s)", "dimensionless"))
        ax[1, c].set_xlabel(with_units("forcing period T", units))
    ax[0, 0].set_ylabel(with_units(r"$\xi_{eq}$", "dimensionless"))
    ax[1, 0].set_ylabel(with_units("load position s", units))
    fig.tight_layout()
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=110)
    plt.close(fig)
    return path
