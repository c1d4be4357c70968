"""The reference of ``tests/motion/test_precursor.py``: the discrete P2 bar's contact from rest in 40 digits (issue 29).

FE bar, 32 P2 elements, consistent mass, end mass 0.5, unit point force at s = 0.37, T = 2.5, undamped, from rest
against the wall.  Before the load's front arrives (t ~ 0.63) the contact reaction of the consistent-mass P2 bar is
real but tiny (2e-16 at t = 0, growing ~15-fold per flight): the contact leaves and comes back in flights that grow
from 1e-35 of loss to 1e-4.  This script integrates the discrete two-state model independently of the kernel: the
modes of both states in mpmath (``eigsy`` at 40 digits, from the double ``M, K``), each segment in closed form
(undamped modes under ``cos W t``), the margin (``-R`` stuck, ``-x_c`` free) scanned on a grid of 2e-4 and each crossing
bisected to 1e-32; an opening keeps ``x, v`` (``x_c = v_c = 0``), a plastic impact keeps the momenta of the DOFs
other than the contact (``M_rr v_r+ = (M v-)_r``); a stuck segment that starts with a tensile reaction opens at once
(zero dwell), a flight starts with ``x_c = 0`` exactly (its margin is taken relative to its start value, round-off of
the 40-digit modes).  It prints the events up to t = 0.7 (needs mpmath; a few minutes):
``python tests/bench/p2_precursor_reference.py``.
"""

import mpmath as mp

import plbar

mp.mp.dps = 40
T, TEND, H = 2.5, mp.mpf("0.7"), mp.mpf("2e-4")


def modes(Mm, Km):
    L = mp.cholesky(Mm)
    Li = mp.inverse(L)
    A = Li * Km * Li.T
    E, Q = mp.eigsy((A + A.T) / 2)
    return [mp.sqrt(E[i]) for i in range(len(E))], Li.T * Q          # x = V eta, V^T M V = I


def main():
    case = plbar.Case(model="fe", n=32, element="P2", mass="consistent", end_mass=0.5, load_points=((0.37, 1.0),))
    prob = case.problem()
    s = prob.system
    M, K, q = mp.matrix(s.M.tolist()), mp.matrix(s.K.tolist()), mp.matrix(prob.q.tolist())
    N = M.rows
    W = 2 * mp.pi / mp.mpf(T)
    Mrr = M[0:N - 1, 0:N - 1]
    w1, V1 = modes(Mrr, K[0:N - 1, 0:N - 1])
    w2, V2 = modes(M, K)
    Mrr_inv = mp.inverse(Mrr)
    f1, f2 = V1.T * q[0:N - 1], V2.T * q
    Kc, Mc = K[N - 1, 0:N - 1], M[N - 1, 0:N - 1]
    r1 = [(Kc * V1[:, j])[0] - (Mc * V1[:, j])[0] * w1[j] ** 2 for j in range(N - 1)]    # R = r1 . eta + rq cos
    rq = (Mc * V1 * f1)[0] - q[N - 1]
    gap = [V2[N - 1, j] for j in range(N)]

    class Segment:
        def __init__(self, st, t0, x, v):
            self.st, self.t0 = st, t0
            V, w, f, Mm = (V1, w1, f1, Mrr) if st == 0 else (V2, w2, f2, M)
            if st == 0:
                x, v = x[0:N - 1], v[0:N - 1]
            eta, vel = V.T * Mm * x, V.T * Mm * v
            self.V, self.w = V, w
            self.p = [f[j] / (w[j] ** 2 - W ** 2) for j in range(len(w))]
            self.h0 = [eta[j] - self.p[j] * mp.cos(W * t0) for j in range(len(w))]
            self.h1 = [vel[j] + self.p[j] * W * mp.sin(W * t0) for j in range(len(w))]
            self.c = r1 if st == 0 else gap
            self.g0 = 0
            if st == 1:
                self.g0 = self.raw(t0)

        def modal(self, t):
            tau, cW, sW = t - self.t0, mp.cos(W * t), mp.sin(W * t)
            e, v = [], []
            for j, w in enumerate(self.w):
                c, sn = mp.cos(w * tau), mp.sin(w * tau)
                e.append(self.h0[j] * c + self.h1[j] / w * sn + self.p[j] * cW)
                v.append(-self.h0[j] * w * sn + self.h1[j] * c - self.p[j] * W * sW)
            return e, v

        def raw(self, t):
            e, _ = self.modal(t)
            val = mp.fsum(self.c[j] * e[j] for j in range(len(e)))
            return -(val + rq * mp.cos(W * t)) if self.st == 0 else -val

        def g(self, t):
            return self.raw(t) - self.g0

        def phys(self, t):
            e, v = self.modal(t)
            x, vv = self.V * mp.matrix(e), self.V * mp.matrix(v)
            if self.st == 0:
                x, vv = mp.matrix(list(x) + [0]), mp.matrix(list(vv) + [0])
            return x, vv

    def bisect(seg, a, b):
        for _ in range(140):
            m = (a + b) / 2
            if seg.g(m) > 0:
                a = m
            else:
                b = m
            if b - a < mp.mpf(10) ** -32:
                break
        return b

    t, st, tol = mp.mpf(0), 0, mp.mpf(10) ** -34
    x, v = mp.matrix(N, 1), mp.matrix(N, 1)
    while t < TEND:
        seg = Segment(st, t, x, v)
        if st == 0 and seg.g(t) < -tol:
            tev = t
        else:
            tev, a = None, t + (H / 100 if st == 1 else 0)
            while a < TEND:
                b = a + H
                if seg.g(b) < -tol:
                    tev = bisect(seg, a, b)
                    break
                a = b
            if tev is None:
                break
        x, v = seg.phys(tev)
        loss = 0
        if st == 0:
            x[N - 1], v[N - 1] = 0, 0
        else:
            ke0 = (v.T * M * v)[0] / 2
            v = mp.matrix(list(Mrr_inv * (M * v)[0:N - 1, 0]) + [0])
            x[N - 1] = 0
            loss = ke0 - (v.T * M * v)[0] / 2
        print(f"({mp.nstr(tev, 17)}, {1 if st == 0 else 2}, {mp.nstr(loss, 6)}),", flush=True)
        t, st = tev, 1 - st


if __name__ == "__main__":
    main()
