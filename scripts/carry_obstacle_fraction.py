#!/usr/bin/python3
"""Carry the calibrated obstacle area fraction over to another obstacle gap w_ob or diameter σ_ob.

The paper (capillary-droplets §4.2) builds its arrays by "a Poisson sampling procedure with separations
w > w_ob" and never states the density. We read that literally: a Poisson field of candidate centres
of one intensity ρ_c (per σ²), thinned sequentially — each candidate, in its random order, is kept
when it lies farther than σ_ob + w_ob from every centre kept before it (random sequential addition
with a fixed number of attempts). One ρ_c is the calibrated quantity: it is the one whose thinned
field has the calibrated φ = 0.0248 at the Fig. 13(b) geometry (σ_ob = 0.3σ, w_ob = 0.2σ). At another
(σ_ob, w_ob) the same ρ_c gives a different number density, printed here as the area fraction that
`obstacles --obstacle-fraction` takes (its arrays place that many centres by random sequential
addition, which at these coverages is the same ensemble up to the count's fluctuation).

usage: carry_obstacle_fraction.py SIGMA_OB W_OB [--anchor-phi 0.0248] [--box 200] [--seeds 8]
prints: phi  n_per_sigma2  rho_c
"""
import argparse
import math
import random


def thinned_count(rho_c, separation, box, seed):
    """Centres kept from round(rho_c box²) uniform candidates under sequential thinning (periodic box)."""
    rng = random.Random(seed)
    ncell = max(1, int(box / separation))
    width = box / ncell
    cells = {}
    kept = 0
    s2 = separation * separation
    for _ in range(int(round(rho_c * box * box))):
        x, y = rng.random() * box, rng.random() * box
        cx, cy = int(x / width) % ncell, int(y / width) % ncell
        ok = True
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for (px, py) in cells.get(((cx + dx) % ncell, (cy + dy) % ncell), ()):
                    ddx = x - px
                    ddy = y - py
                    ddx -= box * round(ddx / box)
                    ddy -= box * round(ddy / box)
                    if ddx * ddx + ddy * ddy < s2:
                        ok = False
                        break
                if not ok:
                    break
            if not ok:
                break
        if ok:
            cells.setdefault((cx, cy), []).append((x, y))
            kept += 1
    return kept


def density(rho_c, separation, box, seeds):
    return sum(thinned_count(rho_c, separation, box, 1000 + s) for s in range(seeds)) / (seeds * box * box)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sigma_ob", type=float)
    ap.add_argument("w_ob", type=float)
    ap.add_argument("--anchor-phi", type=float, default=0.0248)
    ap.add_argument("--anchor-sigma-ob", type=float, default=0.3)
    ap.add_argument("--anchor-w-ob", type=float, default=0.2)
    ap.add_argument("--box", type=float, default=200.0)
    ap.add_argument("--seeds", type=int, default=8)
    a = ap.parse_args()
    if not (a.sigma_ob > 0 and a.w_ob >= 0 and 0 < a.anchor_phi < 0.5):
        raise SystemExit("carry_obstacle_fraction: need sigma_ob > 0, w_ob >= 0, 0 < anchor-phi < 0.5")
    area = lambda s: math.pi * s * s / 4
    n_anchor = a.anchor_phi / area(a.anchor_sigma_ob)
    sep_anchor = a.anchor_sigma_ob + a.anchor_w_ob
    # ρ_c by bisection on the anchor's thinned density (monotonic in ρ_c below jamming)
    lo, hi = n_anchor, 20 * n_anchor
    if density(hi, sep_anchor, a.box, a.seeds) < n_anchor:
        raise SystemExit("carry_obstacle_fraction: the anchor density is beyond what thinning reaches")
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        if density(mid, sep_anchor, a.box, a.seeds) < n_anchor:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-4 * n_anchor:
            break
    rho_c = 0.5 * (lo + hi)
    n = density(rho_c, a.sigma_ob + a.w_ob, a.box, a.seeds)
    print(f"{n * area(a.sigma_ob):.6g} {n:.6g} {rho_c:.6g}")


if __name__ == "__main__":
    main()
