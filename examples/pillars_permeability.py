#!/usr/bin/env python3
"""Permeability of square pillar arrays (mdpd-pillar-array-permeability Fig. 7(b), docs/mdpd.md):
MDPD flow through 2D square lattices of pillars at a few porosities, κ_p/d² by Darcy's law and by
the pillars' drag, against the square-array theories.

    examples/pillars_permeability.py [--tiny] [--plot FILE.png]

Without --tiny: ε = 0.6, 0.7, 0.8, 0.9, 4 × 2 unit cells, f_b = 0.6, 1000 τ sampled per porosity
(as `scripts/reproduce_pillars square`; about 20 min per porosity on one core). --tiny runs one
short, small array (what CI runs).
"""
import argparse

import mesoflow
from mesoflow import analysis, pillars

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--tiny", action="store_true")
parser.add_argument("--plot", help="write κ_p/d² against ε to this PNG")
parser.add_argument("--threads", type=int, default=0)
args = parser.parse_args()
mesoflow.initialize(threads=args.threads)

if args.tiny:
    porosities, scene, steps = [0.8], dict(cells_x=3, cells_y=1, diameter=5.0), (100, 200, 1000)
else:
    porosities, scene, steps = [0.6, 0.7, 0.8, 0.9], dict(cells_x=4, cells_y=2, fb=0.6, diameter=5.0), (500, 3000, 100000)
equilibrate, warmup, sampled = steps
rows = []
print("  ε     κ_darcy/d²   ± rel. error   κ_drag/d²   Gebart      Drummond-Tahir")
for eps in porosities:
    f = pillars.flow(dimension=2, layout="square", porosity=eps, **scene)
    f.equilibrate(equilibrate)
    f.run(warmup=warmup, steps=sampled, sample_every=10)
    e = f.permeability()
    d2 = scene["diameter"] ** 2
    g, dt = analysis.kappa_gebart_square(f.porosity), analysis.kappa_drummond_tahir_square(f.porosity)
    rows.append((f.porosity, e["kappa_darcy"] / d2, e["kappa_darcy_relative_error"], e["kappa_drag_tether"] / d2, g, dt))
    print("%.3f   %9.4g    %8.2g      %9.4g    %9.4g   %9.4g" % rows[-1])
if args.plot:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    r = np.array(rows)
    plt.errorbar(r[:, 0], r[:, 1], yerr=r[:, 1] * r[:, 2], fmt="o", capsize=3, label="Darcy (flux)")
    plt.plot(r[:, 0], r[:, 3], "s", mfc="none", label="drag (tethers)")
    eps = np.linspace(0.55, 0.95, 60)
    plt.plot(eps, [analysis.kappa_drummond_tahir_square(x) for x in eps], label="Drummond–Tahir")
    plt.plot(eps, [analysis.kappa_gebart_square(x) for x in eps], "--", label="Gebart")
    plt.yscale("log"), plt.xlabel("ε"), plt.ylabel("κ_p/d²"), plt.legend()
    plt.savefig(args.plot, dpi=120)
