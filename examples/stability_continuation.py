"""Stability and continuation of the paper's case: branches end to end, their ends and events.

Prints, per branch, its T range, how many points are stable, how each end is classified and the
events found along it (folds in T, grazing, multipliers crossing the unit circle), and draws the
frequency-response view (max |x_c| and xi_eq against T, coloured by stability) and the branches
with their events on the (T1, T2) plane.

Run:  python examples/stability_continuation.py [OUTDIR]
"""

import sys
from pathlib import Path

import numpy as np

import plbar

result = plbar.solve()          # continuation is the default method
rows = []
for b in result.branches:
    rows.append(dict(id=b.id, n=len(b), T=(float(b.T.min()), float(b.T.max())), stable=int(b.stable.sum()),
                     mu=(float(b.max_abs_multiplier.min()), float(b.max_abs_multiplier.max())), ends=b.ends,
                     events=[(e["kind"], round(e["T"], 5)) for e in b.events]))


def report() -> str:
    out = [f"{len(rows)} branches, {sum(r['n'] for r in rows)} points, solver time {result.solver_time:.2f} s"]
    for r in rows:
        out.append(f"branch {r['id']}: {r['n']} points, T in [{r['T'][0]:.5f}, {r['T'][1]:.5f}], "
                   f"{r['stable']} stable, max|mu| in [{r['mu'][0]:.4f}, {r['mu'][1]:.4f}]")
        out.append(f"   ends: {r['ends'][0]} | {r['ends'][1]}")
        for kind, T in r["events"]:
            out.append(f"   event: {kind} at T = {T}")
    return "\n".join(out)


if __name__ == "__main__":
    print(report())
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "plbar-examples")
    from plbar.visuals import frequency_response, paths_plane

    print("wrote", frequency_response(result, out), paths_plane(result, out))
    assert np.all([np.isfinite(b.xi).all() for b in result.branches])
