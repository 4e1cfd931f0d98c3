#!/usr/bin/env python3
"""Checks a conserved quantity of the intergranular strain's evolution (Niemunis & Herle 1997).

On the loading branch (h_dir : d > 0) under a fixed strain direction d, h stays in the plane of
h and d, and with rho = |h|/R and eta = |h - (h:d) d|/R the quantity

    K = eta^beta_R / (1 - rho^beta_R)

is constant (docs/performance.md, "Intergranular strain: one scalar equation"). The script
integrates dh = (I - rho^beta_R h_dir (x) h_dir) : d ds with classical RK4 in small steps from
random loading states and prints K, rho and cos(h, d) at a few points along the path: K keeps
its digits while rho and the direction change.

Usage: /usr/bin/python3 scripts/check_igs_invariant.py [--beta 0.08] [--trials 4]
"""
import argparse

import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--beta", type=float, default=0.08, help="beta_R (Karlsruhe sand: 0.08)")
    ap.add_argument("--trials", type=int, default=4)
    args = ap.parse_args()
    R, beta = 5.0e-5, args.beta
    rng = np.random.default_rng(1)
    worst = 0.0
    for _ in range(args.trials):
        d = rng.normal(size=6)
        d /= np.linalg.norm(d)
        h = rng.normal(size=6)
        h *= R * rng.uniform(0.01, 0.99) / np.linalg.norm(h)
        if h @ d < 0.0:
            h = -h  # start on the loading branch

        def rate(h):
            r = np.linalg.norm(h)
            n = h / r
            return d - (r / R) ** beta * (n @ d) * n

        def invariant(h):
            rho = np.linalg.norm(h) / R
            eta = np.linalg.norm(h - (h @ d) * d) / R
            return eta ** beta / (1.0 - rho ** beta), rho, (h @ d) / np.linalg.norm(h)

        ds = 1.0e-4 * R
        k0 = invariant(h)[0]
        rows = [invariant(h)]
        for k in range(30000):  # 3 R of strain
            k1 = rate(h)
            k2 = rate(h + 0.5 * ds * k1)
            k3 = rate(h + 0.5 * ds * k2)
            k4 = rate(h + ds * k3)
            h = h + ds / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
            if k % 10000 == 9999:
                rows.append(invariant(h))
        worst = max(worst, max(abs(r[0] / k0 - 1.0) for r in rows))
        print("  ".join(f"K={r[0]:.10f} rho={r[1]:.4f} cos={r[2]:.4f}" for r in rows))
    print(f"largest relative change of K: {worst:.2e}")


if __name__ == "__main__":
    main()
