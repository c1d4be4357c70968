"""The paper's figure families (Sec. 4, Figs. 2-9) for our numbers.

Every ``fig*`` function computes what it needs with the public API, draws one
figure family and writes PNG and PDF files (atomically) into ``out``; it
returns the written paths.  matplotlib is imported lazily with the Agg
backend.  :func:`make_all` draws them all (``plbar figures``).

The sample points of the paper (Fig. 2b) are four-digit roundings; each figure
uses the nearest point of the computed paths (:func:`nearest_point`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .families import FAMILIES, assign_families
from .io import atomic_path

__all__ = ["RED", "GREEN", "nearest_point", "families_of", "fig2_paths", "fig3_time_histories",
           "fig4_energies", "fig5_loss_damping", "fig6_damping_paths", "fig7_load_responses",
           "fig8_xi_per_load", "fig9_xi_position", "make_all", "FIGURES", "frequency_response", "paths_plane",
           "contact_amplitude"]

#: The paper's sample points (T1, T2, phi): red on path 1, green on path 2 (Fig. 2b).
RED = (1.7748, 8.1525, 3.5495)
GREEN = (2.3876, 9.8894, 4.8050)
FAM_STYLE = {"T0_I": ("tab:blue", "path 1 (near $T_0^I$)"), "T0_II/2": ("tab:orange", "path 2 (near $T_0^{II}/2$)"),
             "other": ("0.65", "other branches")}
DOF_COLORS = ["tab:blue", "tab:red", "tab:orange", "tab:purple", "tab:green", "tab:brown", "tab:pink", "tab:cyan"]


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"figure.dpi": 110, "savefig.dpi": 150, "axes.grid": True, "grid.alpha": 0.3,
                         "font.size": 9, "axes.titlesize": 10, "legend.fontsize": 8})
    return plt


def _save(fig, out, name: str) -> list[Path]:
    out = Path(out)
    files = []
    for ext in ("png", "pdf"):
        path = out / f"{name}.{ext}"
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format=ext, bbox_inches="tight")
        files.append(path)
    import matplotlib.pyplot as plt

    plt.close(fig)
    return files


def families_of(res) -> list[str]:
    """Family label of each branch of a :class:`plbar.Result`."""
    T0I, T0II = res.paths.prob.system.T0
    return assign_families([(b.T.min(), b.T.max()) for b in res.branches], [len(b) for b in res.branches],
                           T0I, T0II)


def nearest_point(res, target, family: str | None = None):
    """The path point nearest to ``target = (T1, T2, phi)`` in the ``(T1, T2)`` plane.

    Returns
    -------
    (Orbits, Branch, int, float)
        The single orbit, its branch, its index on the branch and the distance.
    """
    fams = families_of(res)
    best = None
    for b, f in zip(res.branches, fams):
        if family is not None and f != family:
            continue
        d = np.hypot(b.T1 - target[0], b.T2 - target[1])
        i = int(np.argmin(d))
        if best is None or d[i] < best[3]:
            best = (b.orbits.take([i]), b, i, float(d[i]))
    if best is None:
        raise ValueError(f"no branch of family {family!r}")
    return best


def _solve(grid, **case):
    from .case import Case
    from .run import solve

    return solve(Case(grid=tuple(grid), **case))


def fig2_paths(out, res=None, grid=(200, 200)) -> list[Path]:
    """Fig. 2: the periodic paths in ``(T1, T2, phi)`` and in the ``T1-T2`` plane."""
    plt = _plt()
    res = res or _solve(grid)
    fams = families_of(res)
    fig = plt.figure(figsize=(11, 4.6))
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    ax2 = fig.add_subplot(1, 2, 2)
    seen = set()
    for b, f in zip(res.branches, fams):
        c, lab = FAM_STYLE[f]
        lab = lab if f not in seen else None
        seen.add(f)
        phi = np.mod(b.phi, 2 * np.pi)
        ax3.plot(b.T1, b.T2, phi, ".-", color=c, ms=2, lw=0.8, label=lab)
        ax2.plot(b.T1, b.T2, ".-", color=c, ms=2.5, lw=0.8, label=lab)
    for tgt, col, nm in ((RED, "red", "red point"), (GREEN, "green", "green point")):
        o, _, _, d = nearest_point(res, tgt)
        ax3.scatter(o.T1, o.T2, np.mod(o.phi, 2 * np.pi), color=col, s=40, depthshade=False, zorder=5)
        ax2.plot(o.T1, o.T2, "o", color=col, ms=7, mec="k",
                 label=f"{nm}: $T^I$={o.T1[0]:.4f}, $T^{{II}}$={o.T2[0]:.4f}")
    ax3.set(xlabel="$T^I$", ylabel="$T^{II}$", zlabel=r"$\phi$ [rad]", title="a) parameter space")
    ax2.set(xlabel="$T^I$", ylabel="$T^{II}$", title="b) $T^I$-$T^{II}$ plane")
    ax2.legend(loc="best")
    s = res.paths.prob.system
    fig.suptitle(f"Periodic paths, chain N = {s.n}, unit force on DOF 1 "
                 f"($T_0^I$ = {s.T0[0]:.3f}, $T_0^{{II}}$ = {s.T0[1]:.3f})")
    return _save(fig, out, "fig2_paths")


def _two_periods(o, k=1200):
    T = float(o.T[0])
    t = np.linspace(0.0, 2 * T, 2 * k, endpoint=False)
    return t, np.mod(t, T), T


def fig3_time_histories(out, res=None, grid=(200, 200)) -> list[Path]:
    """Fig. 3: displacement of every DOF over two periods at the red and green points."""
    plt = _plt()
    res = res or _solve(grid)
    n = res.paths.prob.system.n
    fig, axes = plt.subplots(n, 2, figsize=(10, 1.5 * n + 1), sharex="col")
    for col, (tgt, nm) in enumerate(((RED, "red"), (GREEN, "green"))):
        o, _, _, _ = nearest_point(res, tgt)
        t, tm, T = _two_periods(o)
        x, _, _ = o.response(tm)
        for k in range(n):
            ax = axes[k, col]
            ax.plot(t, x[0, :, k], color=DOF_COLORS[k % len(DOF_COLORS)], lw=1.2)
            for m in (1, 2):
                ax.axvline(m * T, color="red", ls="--", lw=0.8)
            ax.axvline(float(o.T1[0]), color="0.5", ls=":", lw=0.8)
            ax.set_ylabel(f"$x_{k + 1}$")
        axes[0, col].set_title(f"{'ab'[col]}) {nm} point: $T^I$={o.T1[0]:.4f}, $T^{{II}}$={o.T2[0]:.4f}, "
                               rf"$\phi$={np.mod(o.phi[0], 2 * np.pi):.4f}, T={T:.4f}")
        axes[-1, col].set_xlabel("t")
    fig.suptitle("Periodic responses of every DOF (dashed: period ends, dotted: gap opens at $T^I$)")
    fig.tight_layout()
    return _save(fig, out, "fig3_time_histories")


def fig4_energies(out, res=None, grid=(200, 200)) -> list[Path]:
    """Fig. 4: kinetic, potential and total energy over two periods; the drop at the impact."""
    plt = _plt()
    res = res or _solve(grid)
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
    for ax, (tgt, nm), lab in zip(axes, ((RED, "red"), (GREEN, "green")), "ab"):
        o, b, i, _ = nearest_point(res, tgt)
        t, tm, T = _two_periods(o, 2000)
        ek, ep = o.energies(tm)
        ax.plot(t, ek[0], label="kinetic $E_K$", color="tab:blue")
        ax.plot(t, ep[0], label="potential $E_P$", color="tab:green")
        ax.plot(t, ek[0] + ep[0], label="total", color="k", lw=1.5)
        for m in (1, 2):
            ax.axvline(m * T, color="red", ls="--", lw=0.8)
        ax.set(xlabel="t", ylabel="energy", title=f"{lab}) {nm} point, T = {T:.4f}: "
                                                 rf"$\Delta_{{PL}}$ = {b.dPL[i]:.4f}, $\xi_{{eq}}$ = {b.xi[i]:.4f}")
        ax.legend(loc="upper left")
    fig.suptitle("Mechanical energy over two periods (drop of $E_K$ at the plastic impact, t = T)")
    fig.tight_layout()
    return _save(fig, out, "fig4_energies")


def fig5_loss_damping(out, res=None, grid=(200, 200)) -> list[Path]:
    """Fig. 5: ``Delta_PL`` and ``xi_eq`` against ``T`` and ``phi`` (all branches)."""
    plt = _plt()
    res = res or _solve(grid)
    fams = families_of(res)
    fig = plt.figure(figsize=(11, 4.6))
    for k, (attr, zl, title) in enumerate((("dPL", r"$\Delta_{PL}$", "a) impact loss"),
                                           ("xi", r"$\xi_{eq}$", "b) equivalent viscous damping ratio"))):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        seen = set()
        for b, f in zip(res.branches, fams):
            c, lab = FAM_STYLE[f]
            ax.plot(b.T, np.mod(b.phi, 2 * np.pi), getattr(b, attr), ".-", color=c, ms=2, lw=0.8,
                    label=lab if f not in seen else None)
            seen.add(f)
        ax.set(xlabel="T", ylabel=r"$\phi$ [rad]", zlabel=zl, title=title)
        if k == 0:
            ax.legend(loc="upper left")
    fig.suptitle("Impact loss and $\\xi_{eq}$ (Eq. 22) along the periodic paths, chain N = 5, DOF 1 forced")
    return _save(fig, out, "fig5_loss_damping")


def fig6_damping_paths(out, res=None, grid=(200, 200)) -> list[Path]:
    """Fig. 6: ``xi_eq`` against ``T`` separately for path 1 and path 2."""
    plt = _plt()
    res = res or _solve(grid)
    fams = families_of(res)
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
    for ax, fam, lab in zip(axes, FAMILIES, "ab"):
        for b, f in zip(res.branches, fams):
            if f == fam:
                ax.plot(b.T, b.xi, ".-", color=FAM_STYLE[fam][0], ms=3, lw=1)
        ax.set(xlabel="T", ylabel=r"$\xi_{eq}$", title=f"{lab}) {FAM_STYLE[fam][1]}")
    for tgt, col in ((RED, "red"), (GREEN, "green")):
        o, b, i, _ = nearest_point(res, tgt)
        ax = axes[0] if col == "red" else axes[1]
        ax.plot(b.T[i], b.xi[i], "o", color=col, mec="k", ms=7, label=f"{col} point: {b.xi[i]:.4f}")
        ax.legend()
    T0 = res.paths.prob.system.T0
    axes[0].axvline(T0[0], color="k", ls=":", lw=0.8)
    axes[1].axvline(T0[1] / 2, color="k", ls=":", lw=0.8)
    fig.tight_layout()
    return _save(fig, out, "fig6_damping_paths")


def _dof_cases(n_dofs, grid):
    return [_solve(grid, load_nodes=((k, 1.0),)) for k in range(1, n_dofs)]


def fig7_load_responses(out, grid=(200, 200), cases=None) -> list[Path]:
    """Fig. 7: responses of every DOF at the red/green points for loads on DOF 1..N-1."""
    plt = _plt()
    cases = cases or _dof_cases(5, grid)
    n = cases[0].paths.prob.system.n
    fig, axes = plt.subplots(n, 2, figsize=(10, 1.5 * n + 1), sharex="col")
    for col, (tgt, nm) in enumerate(((RED, "red"), (GREEN, "green"))):
        for li, res in enumerate(cases):
            o, _, _, _ = nearest_point(res, tgt)
            T = float(o.T[0])
            t = np.linspace(0, T, 800)
            x, _, _ = o.response(t)
            for k in range(n):
                axes[k, col].plot(t, x[0, :, k], color=DOF_COLORS[li], lw=2.4 if k == li else 1.0,
                                  label=f"$q_{{0{li + 1}}}$ = 1" if k == 0 else None)
        for k in range(n):
            axes[k, col].set_ylabel(f"$x_{k + 1}$")
        axes[0, col].set_title(f"{'ab'[col]}) {nm} point, T = {T:.4f}")
        axes[-1, col].set_xlabel("t")
    fig.suptitle("Responses over one period for different loaded DOFs (thick: the loaded DOF)")
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    h, lab = axes[0, 0].get_legend_handles_labels()
    fig.legend(h, lab, ncol=len(cases), loc="upper center", bbox_to_anchor=(0.5, 0.965))
    return _save(fig, out, "fig7_load_responses")


def fig8_xi_per_load(out, grid=(200, 200), cases=None) -> list[Path]:
    """Fig. 8: ``xi_eq`` along path 1 and path 2 for a unit force on each DOF."""
    plt = _plt()
    cases = cases or _dof_cases(5, grid)
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
    for li, res in enumerate(cases):
        fams = families_of(res)
        for ax, fam in zip(axes, FAMILIES):
            first = True
            for b, f in zip(res.branches, fams):
                if f == fam:
                    ax.plot(b.T, b.xi, ".-", color=DOF_COLORS[li], ms=2.5, lw=1,
                            label=f"DOF {li + 1} forced (max {max(x.xi.max() for x, g in zip(res.branches, fams) if g == fam):.4f})"
                            if first else None)
                    first = False
    for ax, fam, lab in zip(axes, FAMILIES, "ab"):
        ax.set(xlabel="T", ylabel=r"$\xi_{eq}$", title=f"{lab}) {FAM_STYLE[fam][1]}")
        ax.legend()
    fig.suptitle("Equivalent viscous damping ratio for unit forces on different DOFs, chain N = 5")
    fig.tight_layout()
    return _save(fig, out, "fig8_xi_per_load")


def fig9_xi_position(out, grid=(200, 200), ns=(3, 4, 5, 6), per_element=4, executor=None) -> list[Path]:
    """Fig. 9: ``xi_eq`` on the family near ``T0^II/2`` against ``T`` and the load position, N = 3..6."""
    plt = _plt()
    from .sweep import default_positions
    from .tasks import solve_task

    fig, axes = plt.subplots(1, len(ns), figsize=(3.8 * len(ns), 4.0), squeeze=False)
    axes = axes[0]
    sc = None
    allres = []
    for n in ns:
        pos = default_positions(n, per_element)
        tasks = [{"case": {"model": "chain", "n": n, "grid": list(grid), "load_points": [[s, 1.0]]}} for s in pos]
        rs = list(executor.map(solve_task, tasks)) if executor else [solve_task(t) for t in tasks]
        allres.append((n, pos, rs))
    vmax = 0.0
    pts = []
    for n, pos, rs in allres:
        P = []
        for s, r in zip(pos, rs):
            rng = [(min(np.add(b["T1"], b["T2"])), max(np.add(b["T1"], b["T2"]))) for b in r["branches"]]
            lab = assign_families(rng, [len(b["T1"]) for b in r["branches"]], r["T0_I"], r["T0_II"])
            for b, f in zip(r["branches"], lab):
                if f == "T0_II/2":
                    T = np.add(b["T1"], b["T2"])
                    P.append(np.c_[T, np.full(T.size, s), b["xi"]])
        P = np.concatenate(P) if P else np.zeros((0, 3))
        pts.append((n, pos, P, rs[0]["T0_II"]))
        if P.size:
            vmax = max(vmax, float(np.quantile(P[:, 2], 0.99)))
    for ax, (n, pos, P, T0II), lab in zip(axes, pts, "abcd"):
        if P.size:
            sc = ax.scatter(P[:, 0], P[:, 1], c=P[:, 2], s=6, cmap="viridis", vmin=0, vmax=vmax)
            j = int(np.argmax(P[:, 2]))
            ax.plot(P[j, 0], P[j, 1], "*", color="red", ms=12, mec="k",
                    label=rf"max $\xi_{{eq}}$ = {P[j, 2]:.4f} at s = {P[j, 1]:.3g}")
            ax.legend(loc="lower right")
        ax.axvline(T0II / 2, color="k", ls=":", lw=0.8)
        ax.set(xlabel="T", title=f"{lab}) N = {n}")
    axes[0].set_ylabel("load position s (0 = clamp, DOF k at s = k)")
    if sc is not None:
        fig.colorbar(sc, ax=list(axes), label=r"$\xi_{eq}$", shrink=0.9)
    fig.suptitle(r"$\xi_{eq}$ on the path near $T_0^{II}/2$ against T and load position (dotted: $T_0^{II}/2$)")
    return _save(fig, out, "fig9_xi_position")


FIGURES = ("fig2", "fig3", "fig4", "fig56", "fig7", "fig8", "fig9")


def make_all(out, grid=(200, 200), which=None) -> list[Path]:
    """Draw the figure families ``which`` (default all of :data:`FIGURES`) into ``out``."""
    which = list(which or FIGURES)
    bad = [w for w in which if w not in FIGURES]
    if bad:
        from .errors import InputError

        raise InputError(f"unknown figure(s) {bad}; choose from {', '.join(FIGURES)}")
    files: list[Path] = []
    res = _solve(grid) if {"fig2", "fig3", "fig4", "fig56"} & set(which) else None
    cases = _dof_cases(5, grid) if {"fig7", "fig8"} & set(which) else None
    for w in which:
        if w == "fig2":
            files += fig2_paths(out, res)
        elif w == "fig3":
            files += fig3_time_histories(out, res)
        elif w == "fig4":
            files += fig4_energies(out, res)
        elif w == "fig56":
            files += fig5_loss_damping(out, res) + fig6_damping_paths(out, res)
        elif w == "fig7":
            files += fig7_load_responses(out, cases=cases)
        elif w == "fig8":
            files += fig8_xi_per_load(out, cases=cases)
        elif w == "fig9":
            files += fig9_xi_position(out, grid)
    return files


def contact_amplitude(orb, samples: int = 400) -> np.ndarray:
    """``max_t |x_c(t)|`` of each orbit (the contact node moves in state II only)."""
    u = np.linspace(0.0, 1.0, samples)
    return np.abs(orb.gap(orb.T2[:, None] * u)).max(axis=1)


def frequency_response(res, out, name: str = "frequency_response") -> Path:
    """Frequency-response view: ``max |x_c|`` and ``xi_eq`` against ``T``, coloured by stability.

    Solid dark points are stable orbits (all Floquet multipliers inside the
    unit circle), light crosses unstable ones; events along the branches
    (folds, grazing, stability changes) are marked.
    """
    plt = _plt()
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7.5, 6.2), sharex=True)
    for b in res.branches:
        amp = contact_amplitude(b.orbits)
        st = b.stable
        for ax, y in ((ax1, amp), (ax2, b.xi)):
            ax.plot(b.T, y, "-", color="0.75", lw=0.8, zorder=1)
            ax.plot(b.T[st], y[st], "o", ms=2.6, color="tab:blue", zorder=3)
            ax.plot(b.T[~st], y[~st], "x", ms=2.6, color="tab:red", alpha=0.6, zorder=2)
        for e in b.events:
            i = e["index"]
            ax2.annotate(e["kind"].split(" ")[0], (b.T[i], b.xi[i]), fontsize=6, color="0.3",
                         xytext=(2, 4), textcoords="offset points")
    T0I, T0II = res.paths.prob.system.T0
    for ax in (ax1, ax2):
        for x, lab in ((T0I, "$T_0^I$"), (T0II / 2, "$T_0^{II}/2$")):
            ax.axvline(x, color="0.5", ls="--", lw=0.7)
            ax.text(x, 1.0, lab, transform=ax.get_xaxis_transform(), ha="center", va="bottom", fontsize=8)
    ax1.set_ylabel(r"max $|x_c|$ (contact node)")
    ax2.set_ylabel(r"$\xi_{eq}$ (Eq. 22)")
    ax2.set_xlabel("forcing period $T$")
    ax1.plot([], [], "o", color="tab:blue", label="stable")
    ax1.plot([], [], "x", color="tab:red", label="unstable")
    ax1.legend(loc="upper left")
    ax1.set_yscale("log")
    fig.suptitle(f"{res.paths.prob.bar.describe() if res.paths.prob.bar else ''}; load "
                 f"{res.paths.prob.load.describe() if res.paths.prob.load else ''}", fontsize=8)
    return _save(fig, out, name)[0]


def paths_plane(res, out, name: str = "paths_T1_T2") -> Path:
    """Branches in the ``(T^I, T^II)`` plane (paper Fig. 2b) with their events and ends."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.5, 5.2))
    marks = {"fold in T": ("s", "k"), "grazing": ("v", "tab:purple"), "Neimark-Sacker": ("D", "tab:green"),
             "period doubling": ("^", "tab:orange"), "fold (mu = +1)": ("P", "tab:brown")}
    for b in res.branches:
        ax.plot(b.T1, b.T2, "-", lw=1.2)
        ax.text(b.T1[len(b) // 2], b.T2[len(b) // 2], str(b.id), fontsize=7)
        for e in b.events:
            m, c = marks.get(e["kind"], ("o", "k"))
            ax.plot(e["T1"], e["T2"], m, color=c, ms=5, mfc="none")
    for kind, (m, c) in marks.items():
        ax.plot([], [], m, color=c, mfc="none", label=kind)
    ax.set_xlabel("$T^I$")
    ax.set_ylabel("$T^{II}$")
    d = res.paths.domain
    ax.set_xlim(*d.T1)
    ax.set_ylim(*d.T2)
    ax.legend(fontsize=7, loc="best")
    ax.set_title("periodic paths and events (numbers: branch id)")
    return _save(fig, out, name)[0]
