#!/usr/bin/env python3
"""Monte Carlo check of the two-temperature theory's algebra (docs/PHYSICS.md §6.6).

Pairs of equal rough grains are drawn from Maxwellians (translational temperature T, rotational R),
weighted by their normal approach speed, and collided with the law of §6.5; the mean energy changes
per collision are printed beside the closed forms of `theory::RoughCooling`. Agreement to the Monte
Carlo error (≈ 0.001 T) checks the derivation apart from the Maxwellian closure itself.

    .venv/bin/python scripts/rough-maxwell-mc.py [--samples 2000000]
"""

import argparse

import numpy as np


def monte_carlo(d, eps, beta, q, t, r, samples, rng):
    m, radius = 1.0, 0.5
    inertia = q * m * radius**2
    dr = 1 if d == 2 else 3
    v1, v2 = (rng.normal(0, np.sqrt(t / m), (samples, d)) for _ in range(2))
    w1, w2 = (rng.normal(0, np.sqrt(r / inertia), (samples, dr)) for _ in range(2))
    n = np.zeros(d)
    n[0] = 1.0  # from grain 2 to grain 1; they approach when (v1 - v2)·n < 0
    g = v1 - v2
    weight = np.maximum(-(g @ n), 0.0)
    w = w1 + w2
    w_cross_n = np.stack([-w[:, 0] * n[1], w[:, 0] * n[0]], 1) if d == 2 else np.cross(w, n)
    gc = g - radius * w_cross_n
    gcn = gc @ n
    gt = gc - gcn[:, None] * n
    mu, mu_t = m / 2, 1 / (2 / m + 2 * radius**2 / inertia)
    impulse = -(1 + eps) * mu * gcn[:, None] * n - (1 + beta) * mu_t * gt
    dv = impulse / m
    if d == 2:
        dw = ((-radius * n[0] * impulse[:, 1] + radius * n[1] * impulse[:, 0]) / inertia)[:, None]
    else:
        dw = np.cross(-radius * n, impulse) / inertia
    e_tr = m / 2 * (((v1 + dv) ** 2).sum(1) + ((v2 - dv) ** 2).sum(1) - (v1**2).sum(1) - (v2**2).sum(1))
    e_rot = inertia / 2 * (((w1 + dw) ** 2).sum(1) + ((w2 + dw) ** 2).sum(1) - (w1**2).sum(1) - (w2**2).sum(1))
    return (weight * e_tr).sum() / weight.sum(), (weight * e_rot).sum() / weight.sum()


def theory(d, eps, beta, q, t, r):
    eta = q * (1 + beta) / (2 * (1 + q))
    k = 2 * (d - 1)
    tr = -(1 - eps**2) * t - k * (eta * (1 - eta) * t - eta**2 / q * r)
    rot = k * (eta**2 / q * t - eta / q * (1 - eta / q) * r)
    return tr, rot


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=2_000_000)
    args = ap.parse_args()
    rng = np.random.default_rng(1)
    print("d  beta   <dE_tr> MC / theory     <dE_rot> MC / theory   (eps 0.9, T 1, R 0.5)")
    for d, q in [(2, 0.5), (3, 0.4)]:
        for beta in [-0.5, 0.0, 0.5]:
            mc = monte_carlo(d, 0.9, beta, q, 1.0, 0.5, args.samples, rng)
            th = theory(d, 0.9, beta, q, 1.0, 0.5)
            print(f"{d}  {beta:+.1f}   {mc[0]:.4f} / {th[0]:.4f}       {mc[1]:.4f} / {th[1]:.4f}")


if __name__ == "__main__":
    main()
