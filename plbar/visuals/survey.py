"""The frequency response of the real motion: a survey over the forcing period on top of the exact branches.

Three panels against ``T``: the impact loss per forcing period, ``xi_eq`` (with
``xi_w``) and the contact amplitude.  Each survey point is the mean over the
recorded periods, with a band from the smallest to the largest period (the
spread of an irregular motion or of a subharmonic); its colour and marker tell the kind:
periodic, each signature its own (:func:`plbar.visuals.style.signature_styles`, as in ``plbar run``'s
figure); irregular (grey cross).  Loss and
amplitude axes end above the largest mean (a wild transient's band may go off the top).  Under them, the exact periodic
responses of the paper's class (``plbar run``): stable (blue) and unstable (red).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .plots import _edges, _plt, _save
from .style import signature_styles, with_units

__all__ = ["survey_plot", "survey_damping_plot", "survey_loads_plot", "survey_restitution_plot"]

_START = {"up": "^", "down": "v"}       #: markers of the sweeps up and down (from rest: the signature's own)


def _groups(table: dict):
    """``(label, mask, marker, colour)`` of each kind and signature present (:func:`signature_styles`)."""
    kind, start, sig = table["kind"], table["start"], table["signature"]
    styles = signature_styles(sorted(set(sig[kind == "periodic"].tolist())))
    out = []
    for s in dict.fromkeys(start):
        tag = "" if s == "rest" else f" ({s} sweep)"
        sel = start == s
        per = sel & (kind == "periodic")
        for lab in sorted(set(sig[per].tolist())):
            col, mark = styles[lab]
            out.append((f"periodic, signature {lab}{tag}", per & (sig == lab), _START.get(s, mark), col))
        if np.any(sel & (kind == "irregular")):
            out.append((f"irregular{tag}", sel & (kind == "irregular"), _START.get(s, "x"), "0.35"))
        if np.any(sel & (kind == "failed")):
            out.append((f"failed (chattering contact){tag}", sel & (kind == "failed"), "X", "tab:red"))
    return out


def _branches(axes, branches) -> None:
    for b in branches:
        amp = b.amplitude
        st = np.asarray(b.stable, bool)
        for ax, y in zip(axes, (b.dPL, b.xi, amp)):
            ax.plot(b.T[st], y[st], ".", ms=1.8, color="tab:blue", zorder=1)
            ax.plot(b.T[~st], y[~st], ".", ms=1.2, color="tab:red", alpha=0.35, zorder=1)
    axes[0].plot([], [], ".", color="tab:blue", label="exact periodic responses (paper's class), stable")
    axes[0].plot([], [], ".", color="tab:red", alpha=0.5, label="unstable")


def survey_plot(table: dict, out, name: str = "survey", paths=None, title: str = "", units: str = "") -> list[Path]:
    """Draw the survey (``table``: the columns of ``survey.csv``) into ``out/name.png`` and ``.pdf``.

    ``units``: the bar's units (:func:`plbar.visuals.style.unit_note`), said on the axes; ``paths`` (optional):
    branches (:class:`plbar.periodic.Branch`) drawn under the survey.
    """
    plt = _plt()
    fig, axes = plt.subplots(3, 1, figsize=(10.0, 8.6), sharex=True)
    if paths is not None:
        _branches(axes, paths)
    T = table["T"]
    rest = table["start"] == "rest"
    order = np.argsort(T[rest])
    Tr = T[rest][order]
    for ax, lo, hi in ((axes[0], "loss_min", "loss_max"), (axes[1], "xi_min", "xi_max")):
        ax.fill_between(Tr, table[lo][rest][order], table[hi][rest][order], color="0.85", lw=0, zorder=0,
                        label="spread over the recorded periods (min to max)" if ax is axes[0] else None)
    for label, sel, mark, col in _groups(table):
        filled = mark not in ("x",)
        kw = dict(ls="none", ms=4.0, color=col, mfc=col if filled else "none", zorder=3)
        axes[0].plot(T[sel], table["loss_per_T"][sel], mark, label=label, **kw)
        axes[1].plot(T[sel], table["xi_eq"][sel], mark, **kw)
        axes[2].plot(T[sel], table["amp_c"][sel], mark, **kw)
        axes[2].plot(T[sel], table["amp_c_max"][sel], "_", ms=5, color=col, zorder=2)
    axes[1].plot(Tr, table["xi_w"][rest][order], "-", color="k", lw=0.7, alpha=0.6, zorder=2,
                 label=r"$\xi_\omega$ (one frequency, the forcing's)")
    axes[0].set_ylabel("impact loss per forcing period" + (f"\n({units})" if units else ""))
    axes[1].set_ylabel(r"$\xi_{eq}$ of the motion" + "\n(Eq. 22; dimensionless)")
    axes[2].set_ylabel(r"contact amplitude $\max|x_c|$ per period" + "\n" +
                       with_units("(marker: mean, bar: largest)", units))
    axes[2].set_xlabel(with_units("forcing period T", units))
    axes[0].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False)
    axes[1].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False)
    axes[0].set_title(f"what the bar does from rest{': ' + title if title else ''}")
    for ax, cols in zip(axes, (("loss_per_T",), ("xi_eq", "xi_w"), ("amp_c_max",))):
        # the spread of a wild transient can dwarf the rest: the axis shows every mean (and largest amplitude)
        vals = np.concatenate([np.asarray(table[c], float) for c in cols])
        top = float(np.nanmax(vals)) if np.isfinite(vals).any() else 1.0
        ax.set_ylim(0, 1.1 * max(top, 1e-12))
    fig.tight_layout()
    return _save(fig, out, name)


def survey_damping_plot(levels: dict, out, name: str = "survey_damping", units: dict | None = None) -> list[Path]:
    """``xi_eq`` of the real motion against ``T`` for several inherent damping ratios, one panel per case.

    ``levels``: case title -> list of ``(ratio, T, xi_eq, settled fraction)``; ``units``: case title -> the
    bar's units (:func:`plbar.visuals.style.unit_note`).
    """
    units = units or {}
    plt = _plt()
    fig, axes = plt.subplots(1, len(levels), figsize=(5.2 * len(levels), 4.0), squeeze=False)
    for ax, (title, rows) in zip(axes[0], levels.items()):
        for ratio, T, xi, settled in rows:
            o = np.argsort(T)
            ax.plot(np.asarray(T)[o], np.asarray(xi)[o], "-", lw=1.0,
                    label=f"Rayleigh {100 * ratio:g} % ({100 * settled:.0f} % of the periods settle)")
        ax.set_title(title)
        ax.set_xlabel(with_units("forcing period T", units.get(title, "")))
        ax.set_ylabel(with_units(r"$\xi_{eq}$ of the impact (the motion from rest)", "dimensionless"))
        ax.set_ylim(bottom=0)
        ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    return _save(fig, out, name)


def _cells(table: dict, N, column: str, axis: str = "s"):
    sel = table["N"] == N
    s, T = np.unique(table[axis][sel]), np.unique(table["T"][sel])
    g = np.full((s.size, T.size), np.nan, dtype=object if column == "kind" else float)
    g[np.searchsorted(s, table[axis][sel]), np.searchsorted(T, table["T"][sel])] = table[column][sel]
    return s, T, g


def survey_loads_plot(table: dict, out, name: str = "survey_loads", title: str = "", units: str = "",
                      column: str = "s", label: str = "load position s") -> list[Path]:
    """``xi_eq`` and ``xi_w`` of the real motion over (forcing period, load position), one row per size ``N``; or
    over (forcing period, amplitude factor) with ``column = "A"``.

    ``table``: the columns of ``survey_loads.csv`` (``survey_amplitudes.csv``).  Colour: the value of the cell (the
    motion from rest under a unit force at ``s``, or the load times ``A``); white dots: the periodic cells; red
    crosses: failed ones (a chattering contact); the black line: the worst position (amplitude) of each forcing
    period (the largest value over the axis).  ``units``: the bar's units (:func:`plbar.visuals.style.unit_note`),
    said on the axes (an amplitude factor has none).
    """
    plt = _plt()
    sizes = np.unique(table["N"])
    fig, ax = plt.subplots(len(sizes), 2, figsize=(12.0, 3.6 * len(sizes) + 0.6), squeeze=False, sharex=True)
    for r, n in enumerate(sizes):
        for c, (col, cbar) in enumerate((("xi_eq", r"$\xi_{eq}$ of the motion (Eq. 22, dimensionless)"),
                                          ("xi_w", r"$\xi_\omega$ (the forcing's frequency, dimensionless)"))):
            s, T, g = _cells(table, n, col, column)
            _, _, kind = _cells(table, n, "kind", column)
            a = ax[r, c]
            vmax = float(np.nanquantile(g, 0.99)) if np.isfinite(g).any() else 1.0
            mesh = a.pcolormesh(_edges(T), _edges(s), g, cmap="viridis", vmin=0.0, vmax=max(vmax, 1e-12),
                                shading="flat", rasterized=True)
            fig.colorbar(mesh, ax=a, label=cbar, extend="max")
            ii, jj = np.nonzero(kind == "periodic")
            a.plot(T[jj], s[ii], ".", ms=1.6, color="w", alpha=0.8, label="periodic (settled) motion")
            ii, jj = np.nonzero(kind == "failed")
            if ii.size:
                a.plot(T[jj], s[ii], "x", ms=3, color="tab:red", label="failed (chattering contact)")
            worst = np.nanargmax(np.where(np.isfinite(g), g, -np.inf), axis=0)
            some = np.nanmax(np.where(np.isfinite(g), g, -np.inf), axis=0) > 0     # no line where every cell is 0
            word = "position" if column == "s" else "amplitude"
            a.plot(T, np.where(some, s[worst], np.nan), "-", color="k", lw=0.9, drawstyle="steps-mid",
                   label=f"{word} of the largest value per T")
            if column != "s":
                a.set_yscale("log" if s.size > 1 and s.min() > 0 and s.max() / s.min() > 10 else "linear")
            a.set_ylabel(with_units(f"{label} (N = {int(n)})", units if column == "s" else ""))
            if r == 0:
                what = "load at s" if column == "s" else "load times A"
                a.set_title((f"what the bar does from rest, {what}" + (f": {title}" if title else ""))
                            if c == 0 else "")
    ax[-1, 0].legend(loc="upper left", bbox_to_anchor=(0.0, -0.18), fontsize=7, ncol=3, frameon=False)
    for a in ax[-1]:
        a.set_xlabel(with_units("forcing period T", units))
    fig.tight_layout()
    return _save(fig, out, name)


#: colours and markers of the single forcing periods of :func:`survey_restitution_plot` (black and grey: the median)
_LINES = (("tab:blue", "s"), ("tab:orange", "^"), ("tab:green", "D"), ("tab:purple", "v"), ("tab:brown", "P"),
          ("tab:cyan", "X"))


def _by_e(table: dict, column: str):
    """``(e, T, grid)`` of ``column`` over (restitution, forcing period)."""
    e, T = np.unique(table["e"]), np.unique(table["T"])
    g = np.full((e.size, T.size), np.nan, dtype=object if column == "kind" else float)
    g[np.searchsorted(e, table["e"]), np.searchsorted(T, table["T"])] = table[column]
    return e, T, g


def _picked(T: np.ndarray, want) -> np.ndarray:
    """The forcing periods of the table nearest to ``want`` (default: four spread over the range)."""
    want = np.quantile(T, (0.125, 0.375, 0.625, 0.875)) if want is None else np.atleast_1d(np.asarray(want, float))
    return np.unique(np.abs(T[:, None] - want[None, :]).argmin(axis=0))[:len(_LINES)]


def _against_e(ax, table: dict, column: str, picks, plastic: bool) -> None:
    """Median over ``T`` with the 10-90 % band, the plastic bound, single forcing periods, against ``e``."""
    e, T, g = _by_e(table, column)
    lo, med, hi = (np.nanquantile(g, q, axis=1) for q in (0.1, 0.5, 0.9))
    ax.fill_between(e, lo, hi, color="0.85", lw=0, zorder=0, label="10-90 % of the forcing periods")
    for (col, mark), j in zip(_LINES, picks):
        ax.plot(e, g[:, j], "-", marker=mark, ms=3.5, lw=0.8, color=col, zorder=2, label=f"T = {T[j]:.4g}")
    ax.plot(e, med, "-o", color="k", lw=1.6, ms=4, zorder=3, label="median over the forcing periods")
    if e[0] == 0.0:
        ax.axhline(med[0], color="tab:red", ls="--", lw=0.9, zorder=1)
        ax.plot([0.0], [med[0]], "*", ms=12, color="tab:red", zorder=4,
                label=f"plastic impact e = 0 (the paper's upper limit): {med[0]:.3g}")
        if plastic:
            ee = np.linspace(0.0, 1.0, 101)
            ax.plot(ee, med[0] * (1 - ee ** 2), ":", color="tab:red", lw=1.0, zorder=1,
                    label=r"$(1 - e^2)\times$ plastic median (same motion, Eq. 14 $\times (1 - e^2)$)")
    ax.set_xlim(-0.02, 1.02)
    top = np.nanmax(np.r_[hi, g[:, picks].ravel()])
    ax.set_ylim(0, 1.45 * top if np.isfinite(top) and top > 0 else 1.0)      # room for the legend above the data
    handles, labels = ax.get_legend_handles_labels()
    mine = [i for i, lb in enumerate(labels) if lb.startswith("T = ") != plastic]     # (a): the summary, (b): the T
    ax.legend([handles[i] for i in mine], [labels[i] for i in mine], loc="upper right", fontsize=7,
              ncol=1 if plastic else 2)


def _e_map(fig, ax, table: dict, picks, units: str) -> None:
    e, T, g = _by_e(table, "xi_eq")
    _, _, kind = _by_e(table, "kind")
    vmax = float(np.nanquantile(g, 0.99)) if np.isfinite(g).any() else 1.0
    mesh = ax.pcolormesh(_edges(T), _edges(e), g, cmap="viridis", vmin=0.0, vmax=max(vmax, 1e-12), shading="flat",
                         rasterized=True)
    fig.colorbar(mesh, ax=ax, label=r"$\xi_{eq}$ of the motion (Eq. 22, dimensionless)", extend="max")
    ii, jj = np.nonzero(kind == "periodic")
    ax.plot(T[jj], e[ii], ".", ms=2.0, color="w", alpha=0.9)
    for (col, _), j in zip(_LINES, picks):
        ax.axvline(T[j], color=col, lw=0.9, ls="--")
    ax.set_xlabel(f"forcing period T{' (' + units + ')' if units else ''}")
    ax.set_ylabel("coefficient of restitution e")
    ax.set_title(r"(c) $\xi_{eq}$ over (T, e); white dots: periodic motions, dashed: the single T of (a), (b)",
                 loc="left", fontsize=8)


def survey_restitution_plot(tables, out, name: str = "restitution", periods=None, units=None) -> list[Path]:
    """``xi_eq`` and the loss per period of the real motion against the coefficient of restitution ``e``.

    One row per case: (a) ``xi_eq`` (Eq. 22) against ``e``: the median over the forcing periods with their
    10-90 % band, the plastic impact's median (``e = 0``, the paper's upper limit: red star and dashed line),
    ``1 - e^2`` times it (what the same motion with each impact losing ``1 - e^2`` of Eq. (14) would give),
    and a few single forcing periods; (b) the impact loss per forcing period, the same way; (c) ``xi_eq`` over
    ``(T, e)``, periodic cells dotted, the single periods dashed.

    Parameters
    ----------
    tables : dict or mapping
        A restitution table (the columns of :data:`plbar.studies.survey.RESTITUTION_COLUMNS`), or a mapping
        ``title -> table`` (one row of panels each).
    out, name : path, str
        Writes ``out/name.png`` and ``.pdf``.
    periods : array_like or mapping, optional
        The single forcing periods drawn (the nearest of each table's); a mapping ``title -> periods`` per case.
        Default: four spread over each table's range.
    units : str or mapping, optional
        The units of ``T`` and of the loss (``"m = k = 1"``), per title as a mapping.
    """
    plt = _plt()
    tables = {"": tables} if "e" in tables else dict(tables)
    pick = lambda v, t: v.get(t) if isinstance(v, dict) else v
    fig, ax = plt.subplots(len(tables), 3, figsize=(16.0, 4.2 * len(tables) + 0.8), squeeze=False,
                           gridspec_kw={"width_ratios": (1.0, 1.0, 1.25)})
    for r, (title, table) in enumerate(tables.items()):
        picks, u = _picked(np.unique(table["T"]), pick(periods, title)), pick(units, title) or ""
        _against_e(ax[r, 0], table, "xi_eq", picks, True)
        _against_e(ax[r, 1], table, "loss_per_T", picks, False)
        _e_map(fig, ax[r, 2], table, picks, u)
        ax[r, 0].set_ylabel(r"$\xi_{eq}$ of the motion (Eq. 22, dimensionless)")
        ax[r, 1].set_ylabel(f"impact loss per forcing period{' (' + u + ')' if u else ''}")
        for a in ax[r, :2]:
            a.set_xlabel("coefficient of restitution e (0: plastic, 1: elastic)")
        ax[r, 0].set_title(f"(a) {title or 'the motion from rest against e'}", loc="left")
        ax[r, 1].set_title("(b) the loss per forcing period against e", loc="left")
    fig.tight_layout()
    return _save(fig, out, name)
