"""The paper's figure families (Sec. 4, Figs. 2-9), drawn from computed results (no solving here).

Each ``draw_fig*`` takes results (and the family label of each branch, see
:mod:`plbar.studies.loads.families`), writes PNG and PDF files atomically into
``out`` and returns their paths; :mod:`plbar.studies.paper.figures` computes the
results and calls them (``plbar figures``).  The paper's sample points
(Fig. 2b) are four-digit roundings off its scan grid; Figs. 2-6 mark the exact
path points at the paper's ``T^I`` (``points``: the red and green
:class:`plbar.Orbits` of :func:`plbar.studies.paper.points.exact_point`, what
``examples/paper_sec41.py`` prints), or, without them, the nearest computed
path point (:func:`nearest_point`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .plots import DOF_COLORS, FAM_STYLE, FAMILIES, _plt, _save
from .style import with_units

__all__ = ["RED", "GREEN", "nearest_point", "draw_fig2", "draw_fig3", "draw_fig4", "draw_fig5", "draw_fig6",
           "draw_fig7", "draw_fig8", "draw_fig9"]

#: The paper's sample points (T1, T2, phi): red on path 1, green on path 2 (Fig. 2b).
RED = (1.7748, 8.1525, 3.5495)
GREEN = (2.3876, 9.8894, 4.8050)
#: the units of the paper's chain (masses and springs of one: time in units of sqrt(m/k))
UNITS = "m = k = 1"
#: axis labels of the paper's figures, with their units
TI, TII, T_, t_ = (with_units(x, UNITS) for x in ("$T^I$", "$T^{II}$", "T", "t"))
XI = with_units(r"$\xi_{eq}$", "dimensionless")


def nearest_point(res, fams, target, family: str | None = None):
    """The path point nearest to ``target = (T1, T2, phi)`` in the ``(T1, T2)`` plane (``fams``: branch labels).

    Returns
    -------
    (Orbits, Branch, int, float)
        The single orbit, its branch, its index on the branch and the distance.
    """
    best = None
    for b, f in zip(res.paths.branches, fams):
        if family is not None and f != family:
            continue
        d = np.hypot(b.T1 - target[0], b.T2 - target[1])
        i = int(np.argmin(d))
        if best is None or d[i] < best[3]:
            best = (b.orbits.take([i]), b, i, float(d[i]))
    if best is None:
        raise ValueError(f"no branch of family {family!r}")
    return best


def _sample(res, fams, points, name: str):
    """The red or green point: ``(orbit, xi, dPL)`` of the exact point of ``points``, else the nearest path point."""
    if points and name in points:
        from ..response import damping

        o = points[name]
        d = damping(o)
        return o, float(d.xi[0]), float(d.dPL[0])
    o, b, i, _ = nearest_point(res, fams, RED if name == "red" else GREEN)
    return o, float(b.xi[i]), float(b.dPL[i])


def draw_fig2(out, res, fams, points=None) -> list[Path]:
    """Fig. 2: the periodic paths in ``(T1, T2, phi)`` and in the ``T1-T2`` plane.

    ``points``: ``{"red": Orbits, "green": Orbits}``, the exact sample points to mark (default: the nearest
    computed path points).
    """
    plt = _plt()
    fig = plt.figure(figsize=(11, 4.6), layout="constrained")
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    ax2 = fig.add_subplot(1, 2, 2)
    seen = set()
    for b, f in zip(res.paths.branches, fams):
        c, lab = FAM_STYLE[f]
        lab = lab if f not in seen else None
        seen.add(f)
        phi = np.mod(b.phi, 2 * np.pi)
        ax3.plot(b.T1, b.T2, phi, ".-", color=c, ms=2, lw=0.8, label=lab)
        ax2.plot(b.T1, b.T2, ".-", color=c, ms=2.5, lw=0.8, label=lab)
    for col in ("red", "green"):
        o, _, _ = _sample(res, fams, points, col)
        ax3.scatter(o.T1, o.T2, np.mod(o.phi, 2 * np.pi), color=col, s=40, depthshade=False, zorder=5)
        ax2.plot(o.T1, o.T2, "o", color=col, ms=7, mec="k", gid=f"{col} point",
                 label=f"{col} point: $T^I$={o.T1[0]:.4f}, $T^{{II}}$={o.T2[0]:.4f}")
    ax3.set(xlabel=TI, ylabel=TII, zlabel=r"$\phi$ [rad]", title="a) parameter space")
    ax3.set_box_aspect(None, zoom=0.88)                   # the z label inside the 3D panel's box
    fig.get_layout_engine().set(wspace=0.08)
    ax2.set(xlabel=TI, ylabel=TII, title="b) $T^I$-$T^{II}$ plane")
    ax2.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), frameon=False)     # outside: never on a branch
    s = res.prob.system
    fig.suptitle(f"Periodic paths, chain N = {s.n}, unit force on DOF 1 "
                 f"($T_0^I$ = {s.T0[0]:.3f}, $T_0^{{II}}$ = {s.T0[1]:.3f})")
    return _save(fig, out, "fig2_paths")


def _two_periods(o, k=1200):
    T = float(o.T[0])
    t = np.linspace(0.0, 2 * T, 2 * k, endpoint=False)
    return t, np.mod(t, T), T


def draw_fig3(out, res, fams, points=None) -> list[Path]:
    """Fig. 3: displacement of every DOF over two periods at the red and green points (``points`` as in
    :func:`draw_fig2`)."""
    plt = _plt()
    n = res.prob.system.n
    fig, axes = plt.subplots(n, 2, figsize=(10, 1.5 * n + 1), sharex="col")
    for col, nm in enumerate(("red", "green")):
        o, _, _ = _sample(res, fams, points, nm)
        t, tm, T = _two_periods(o)
        x, _, _ = o.response(tm)
        for k in range(n):
            ax = axes[k, col]
            ax.plot(t, x[0, :, k], color=DOF_COLORS[k % len(DOF_COLORS)], lw=1.2, gid=f"{nm} x{k + 1}")
            for m in (1, 2):
                ax.axvline(m * T, color="red", ls="--", lw=0.8)
            ax.axvline(float(o.T1[0]), color="0.5", ls=":", lw=0.8)
            ax.set_ylabel(with_units(f"$x_{k + 1}$", UNITS))
        axes[0, col].set_title(f"{'ab'[col]}) {nm} point: $T^I$={o.T1[0]:.4f}, $T^{{II}}$={o.T2[0]:.4f}, "
                               rf"$\phi$={np.mod(o.phi[0], 2 * np.pi):.4f}, T={T:.4f}")
        axes[-1, col].set_xlabel(t_)
    fig.suptitle("Periodic responses of every DOF (dashed: period ends, dotted: gap opens at $T^I$)")
    fig.tight_layout()
    return _save(fig, out, "fig3_time_histories")


def draw_fig4(out, res, fams, points=None) -> list[Path]:
    """Fig. 4: kinetic, potential and total energy over two periods; the drop at the impact (``points`` as in
    :func:`draw_fig2`)."""
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
    for ax, nm, lab in zip(axes, ("red", "green"), "ab"):
        o, xi, dpl = _sample(res, fams, points, nm)
        t, tm, T = _two_periods(o, 2000)
        ek, ep = o.energies(tm)
        ax.plot(t, ek[0], label="kinetic $E_K$", color="tab:blue")
        ax.plot(t, ep[0], label="potential $E_P$", color="tab:green")
        ax.plot(t, ek[0] + ep[0], label="total", color="k", lw=1.5)
        for m in (1, 2):
            ax.axvline(m * T, color="red", ls="--", lw=0.8)
        ax.set(xlabel=t_, ylabel=with_units("energy", UNITS), title=f"{lab}) {nm} point, T = {T:.4f}: "
                                                 rf"$\Delta_{{PL}}$ = {dpl:.4f}, $\xi_{{eq}}$ = {xi:.4f}")
        ax.legend(loc="upper left")
    fig.suptitle("Mechanical energy over two periods (drop of $E_K$ at the plastic impact, t = T)")
    fig.tight_layout()
    return _save(fig, out, "fig4_energies")


def draw_fig5(out, res, fams) -> list[Path]:
    """Fig. 5: ``Delta_PL`` and ``xi_eq`` against ``T`` and ``phi`` (all branches)."""
    plt = _plt()
    fig = plt.figure(figsize=(11, 4.6))
    for k, (attr, zl, title) in enumerate((("dPL", r"$\Delta_{PL}$", "a) impact loss"),
                                           ("xi", r"$\xi_{eq}$", "b) equivalent viscous damping ratio"))):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        seen = set()
        for b, f in zip(res.paths.branches, fams):
            c, lab = FAM_STYLE[f]
            ax.plot(b.T, np.mod(b.phi, 2 * np.pi), getattr(b, attr), ".-", color=c, ms=2, lw=0.8,
                    label=lab if f not in seen else None)
            seen.add(f)
        ax.set(xlabel=T_, ylabel=r"$\phi$ [rad]", zlabel=with_units(zl, UNITS if attr == "dPL" else "dimensionless"),
               title=title)
        if k == 0:
            ax.legend(loc="upper left")
    fig.suptitle("Impact loss and $\\xi_{eq}$ (Eq. 22) along the periodic paths, chain N = 5, DOF 1 forced")
    return _save(fig, out, "fig5_loss_damping")


def draw_fig6(out, res, fams, points=None) -> list[Path]:
    """Fig. 6: ``xi_eq`` against ``T`` separately for path 1 and path 2 (``points`` as in :func:`draw_fig2`)."""
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
    for ax, fam, lab in zip(axes, FAMILIES, "ab"):
        for b, f in zip(res.paths.branches, fams):
            if f == fam:
                ax.plot(b.T, b.xi, ".-", color=FAM_STYLE[fam][0], ms=3, lw=1)
        ax.set(xlabel=T_, ylabel=XI, title=f"{lab}) {FAM_STYLE[fam][1]}")
    for col in ("red", "green"):
        o, xi, _ = _sample(res, fams, points, col)
        ax = axes[0] if col == "red" else axes[1]
        ax.plot(o.T[0], xi, "o", color=col, mec="k", ms=7, label=f"{col} point: {xi:.4f}")
        ax.legend()
    T0 = res.prob.system.T0
    axes[0].axvline(T0[0], color="k", ls=":", lw=0.8)
    axes[1].axvline(T0[1] / 2, color="k", ls=":", lw=0.8)
    fig.tight_layout()
    return _save(fig, out, "fig6_damping_paths")


def draw_fig7(out, cases, fams_list) -> list[Path]:
    """Fig. 7: responses of every DOF at the red/green points for loads on DOF 1..N-1."""
    plt = _plt()
    n = cases[0].prob.system.n
    fig, axes = plt.subplots(n, 2, figsize=(10, 1.5 * n + 1), sharex="col")
    for col, (tgt, nm) in enumerate(((RED, "red"), (GREEN, "green"))):
        for li, (res, fams) in enumerate(zip(cases, fams_list)):
            o, _, _, _ = nearest_point(res, fams, tgt)
            T = float(o.T[0])
            t = np.linspace(0, T, 800)
            x, _, _ = o.response(t)
            for k in range(n):
                axes[k, col].plot(t, x[0, :, k], color=DOF_COLORS[li], lw=2.4 if k == li else 1.0,
                                  label=f"$q_{{0{li + 1}}}$ = 1" if k == 0 else None)
        for k in range(n):
            axes[k, col].set_ylabel(with_units(f"$x_{k + 1}$", UNITS))
        axes[0, col].set_title(f"{'ab'[col]}) {nm} point, T = {T:.4f}")
        axes[-1, col].set_xlabel(t_)
    fig.suptitle("Responses over one period for different loaded DOFs (thick: the loaded DOF)")
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    h, lab = axes[0, 0].get_legend_handles_labels()
    fig.legend(h, lab, ncol=len(cases), loc="upper center", bbox_to_anchor=(0.5, 0.965))
    return _save(fig, out, "fig7_load_responses")


def draw_fig8(out, cases, fams_list) -> list[Path]:
    """Fig. 8: ``xi_eq`` along path 1 and path 2 for a unit force on each DOF."""
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
    for li, (res, fams) in enumerate(zip(cases, fams_list)):
        for ax, fam in zip(axes, FAMILIES):
            first = True
            for b, f in zip(res.paths.branches, fams):
                if f == fam:
                    ax.plot(b.T, b.xi, ".-", color=DOF_COLORS[li], ms=2.5, lw=1,
                            label=f"DOF {li + 1} forced (max "
                                  f"{max(x.xi.max() for x, g in zip(res.paths.branches, fams) if g == fam):.4f})"
                            if first else None)
                    first = False
    for ax, fam, lab in zip(axes, FAMILIES, "ab"):
        ax.set(xlabel=T_, ylabel=XI, title=f"{lab}) {FAM_STYLE[fam][1]}")
        ax.legend()
    fig.suptitle("Equivalent viscous damping ratio for unit forces on different DOFs, chain N = 5")
    fig.tight_layout()
    return _save(fig, out, "fig8_xi_per_load")


def draw_fig9(out, allres, families, optima=None) -> list[Path]:
    """Fig. 9: ``xi_eq`` on the family near ``T0^II/2`` against ``T`` and the load position.

    ``allres`` is a list of ``(N, positions, task results)`` (see
    :func:`plbar.studies.execution.tasks.solve_task`), ``families`` the family labels of
    each result's branches, in the same nesting.  ``optima`` (one per ``N``, or None):
    ``{"xi", "s", "T"}`` of the best single force, continuous in ``s``
    (:func:`plbar.studies.paper.figures.load_optima`, what ``plbar sweep-loads`` states),
    marked by a star (``gid="optimum"``); the best position of the grid is an open circle
    (``gid="grid best"``).  Without ``optima`` the star is the grid's best.
    """
    plt = _plt()
    fig, axes = plt.subplots(1, len(allres), figsize=(3.8 * len(allres), 4.4), squeeze=False, layout="constrained")
    axes = axes[0]
    optima = list(optima) if optima is not None else [None] * len(allres)
    sc = None
    vmax = 0.0
    pts = []
    for (n, pos, rs), labs in zip(allres, families):
        P = []
        for s, r, lab in zip(pos, rs, labs):
            for b, f in zip(r["branches"], lab):
                if f == "T0_II/2":
                    T = np.add(b["T1"], b["T2"])
                    P.append(np.c_[T, np.full(T.size, s), b["xi"]])
        P = np.concatenate(P) if P else np.zeros((0, 3))
        pts.append((n, pos, P, rs[0]["T0_II"]))
        if P.size:
            vmax = max(vmax, float(np.quantile(P[:, 2], 0.99)))
    for ax, (n, _pos, P, T0II), opt, lab in zip(axes, pts, optima, "abcdefgh"):
        lines = []
        if P.size:
            sc = ax.scatter(P[:, 0], P[:, 1], c=P[:, 2], s=6, cmap="viridis", vmin=0, vmax=vmax)
            j = int(np.argmax(P[:, 2]))
            grid = f"grid of s: max {P[j, 2]:.4f} at s = {P[j, 1]:.3g}"
            if opt is None:
                ax.plot(P[j, 0], P[j, 1], "*", color="red", ms=12, mec="k", gid="optimum")
                lines.append(f"(star) {grid}")
            else:
                ax.plot(P[j, 0], P[j, 1], "o", mfc="none", mec="red", ms=9, gid="grid best")
                lines.append(f"(circle) {grid}")
        if opt is not None:
            ax.plot(opt["T"], opt["s"], "*", color="red", ms=12, mec="k", gid="optimum")
            lines.insert(0, f"(star) max {opt['xi']:.4f} at s = {opt['s']:.4g}")
        ax.axvline(T0II / 2, color="k", ls=":", lw=0.8)
        ax.set(xlabel=T_)
        ax.set_title("\n".join([f"{lab}) N = {n}"] + lines), fontsize=8)
    axes[0].set_ylabel("load position s (0 = clamp, DOF k at s = k; m = k = 1)")
    if sc is not None:
        fig.colorbar(sc, ax=list(axes), label=r"$\xi_{eq}$", shrink=0.9)
    fig.suptitle(r"$\xi_{eq}$ on the path near $T_0^{II}/2$ against T and load position (dotted: $T_0^{II}/2$; "
                 "star: best single force, continuous in s, as plbar sweep-loads states it)", fontsize=9)
    return _save(fig, out, "fig9_xi_position")
