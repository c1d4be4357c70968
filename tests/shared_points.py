"""Points shared by the simulator and stability tests (importable: tests/ is on sys.path via conftest)."""

import numpy as np

FE_POINT = dict(model="fe", n=8, element="P2", mass="consistent", load_points=((0.37, 1.0),), grid=(80, 80),
                T1=(0.255, 0.295), T2=(0.878, 0.918))


def good_points(res, per_branch=3, min_len=15):
    """(orbits, index) of well-separated, non-grazing points with a clear impact on the long branches.

    A slow impact (``v_c(T-)`` small against the largest one of the case) makes the impact time, hence the
    one-period map, strongly curved: finite differences and event times lose digits there, so such points
    are left out.
    """
    out = []
    vmax = max(np.abs(b.adm.v_impact).max() for b in res.paths.branches)
    for b in res.paths.branches:
        if len(b) < min_len:
            continue
        ok = np.flatnonzero(~b.grazing & (b.adm.v_impact > 0.05 * vmax) & (b.e1 < 1e-12) & (b.e2 < 1e-12))
        if ok.size == 0:
            continue
        for k in ok[np.linspace(0, ok.size - 1, per_branch).round().astype(int)]:
            out.append((b.orbits, int(k)))
    return out
