#!/usr/bin/python3
"""The shear table of the capsule study in the network's capillary number (issue 29 item 1).

The documented shear runs (scripts/reproduce_capsule shear) set k_b from §4's formula
G_s = E h_t/(2(1 + ν)), E = 5 k_b/(√3 δ_ave), ν = 1/4 (--shear-modulus paper). The network's own shear
modulus at the same k_b, measured on a patch (capsule --mode moduli), is R = G_network/G_formula
times that, so the same run has Ca_network = μ γ̇ a/G_network = Ca_formula / R. This script rewrites
the table in Ca_network and reads D_xy off it (linear interpolation) at the capillary numbers of
the neo-Hookean reference values, whose Ca is defined with the shear modulus too (their
Ca_E = μ γ̇ a/E_s with E_s = 3 G_s: Ca_E = 0.1, 0.2 are Ca = 0.3, 0.6):
  Ramanujan & Pozrikidis (1998, J. Fluid Mech. 361, 117): D = 0.385 at Ca = 0.3;
  Doddi & Bagchi (2008, Int. J. Multiphase Flow 34, 966): D = 0.39 at Ca = 0.3, 0.495 at Ca = 0.6;
(plateaus digitized from the curves in comphy-lab/basilisk-C, sandbox/huet/tests/lagrangian_caps/
data/nh_shear_3d/, ±0.005; docs/sph-capsules.md).

usage: capsule_ca_network.py <moduli.json> <shear.csv> <out.csv> [<out.png>]
"""
import csv
import json
import sys

REFERENCES = [  # (Ca with G_s, D, source)
    (0.3, 0.385, "Ramanujan & Pozrikidis 1998"),
    (0.3, 0.39, "Doddi & Bagchi 2008"),
    (0.6, 0.495, "Doddi & Bagchi 2008"),
]


def interpolate(xs, ys, x):
    for (x0, y0), (x1, y1) in zip(zip(xs, ys), zip(xs[1:], ys[1:])):
        if x0 <= x <= x1:
            return y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    return None


def main():
    moduli_json, shear_csv, out_csv = sys.argv[1:4]
    membrane = json.load(open(moduli_json))["membrane"]
    ratio = membrane["ca_paper_formula_over_ca_network"]  # = G_network / G_formula at one k_b
    rows = list(csv.DictReader(open(shear_csv)))
    ca_formula = [float(r["ca"]) for r in rows]
    ca_network = [c / ratio for c in ca_formula]
    d = [float(r["taylor_deformation"]) for r in rows]
    d_std = [float(r["taylor_deformation_std"]) for r in rows]
    theta = [float(r["inclination_over_pi"]) for r in rows]
    with open(out_csv, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["# G_network/G_formula", f"{ratio:.6g}", "h_t/delta_ave", f"{membrane['thickness_over_spacing']:.6g}"])
        w.writerow(["ca_formula", "ca_network", "taylor_deformation", "taylor_deformation_std", "inclination_over_pi",
                    "reference_ca", "reference_d", "reference_source", "ours_at_reference_ca", "ours_over_reference"])
        for cf, cn, dd, ds, th in zip(ca_formula, ca_network, d, d_std, theta):
            w.writerow([f"{cf:.6g}", f"{cn:.6g}", f"{dd:.6g}", f"{ds:.3g}", f"{th:.6g}", "", "", "", "", ""])
        for ca, ref, source in REFERENCES:
            ours = interpolate(ca_network, d, ca)
            w.writerow(["", "", "", "", "", ca, ref, source, "" if ours is None else f"{ours:.4g}",
                        "" if ours is None else f"{ours / ref:.4g}"])
    for ca, ref, source in REFERENCES:
        ours = interpolate(ca_network, d, ca)
        print(f"Ca = {ca} (network G_s): ours D_xy = {ours:.3f}, {source} {ref} (ratio {ours / ref:.2f})")
    if len(sys.argv) > 4:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5, 3.6))
        ax.errorbar(ca_formula, d, yerr=d_std, fmt="s", mfc="none", color="0.6", label="ours, Ca of §4's formula")
        ax.errorbar(ca_network, d, yerr=d_std, fmt="o-", color="C0", label="ours, Ca of the network's G_s")
        for k, (ca, ref, source) in enumerate(REFERENCES):
            ax.plot([ca], [ref], "x^v"[k], color="C3", label=f"neo-Hookean, {source}")
        ax.set_xlabel("Ca = μ γ̇ a / G_s")
        ax.set_ylabel("D_xy")
        ax.set_title(f"capsule in shear, Π = 8: G_network = {ratio:.3f} G_formula", fontsize=9)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(sys.argv[4], dpi=120)


if __name__ == "__main__":
    main()
