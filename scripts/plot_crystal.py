#!/usr/bin/python3
"""Plot a phonon analysis of the microfluidic crystal (microfluidic-crystal-phonons paper, Figs. 3c,d
and 4a) from the HDF5 file of mesoflow::crystal::write_phonon_analysis:
  (a) transverse power spectrum |y(k, omega)|^2, eq. (2), log colour scale, with eq. (3) (solid) and
      the nearest-neighbour continuum eq. (14) (dashed);
  (b) longitudinal power spectrum |x(k, omega)|^2, eq. (1), with eq. (4) (grey solid), eq. (13)
      (grey dashed) and the coupled branch 2 omega_perp(k/2), eq. (8) (white solid);
  (c) correlation strength C(k_par, k_perp) (default: the definition stored as /correlation@ridge,
      the Pearson correlation of the mode amplitudes) with the line k_par = 2 k_perp (dashed).
omega is in units of u_d/R (omega Delta T with the paper's Delta T = R/u_d), k in units of pi/a.
omega > 0 for k > 0 is a wave travelling forward (the file's `convention` attribute). The omega axis
of (a) and (b) shows the measured range, cut to 2.5 times the largest theory frequency of eqs. (3),
(4) and (8) where the Nyquist frequency is higher.

usage: plot_crystal.py ANALYSIS.h5 OUT.png [--correlation complex_literal|amplitude|amplitude_fluctuation]
"""
import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

DEFINITIONS = {
    "complex_literal": "|<x(k_par) y(k_perp)>_t| / norm, eq. (5)",
    "amplitude": "<|x| |y|>_t / norm",
    "amplitude_fluctuation": "Pearson correlation of |x| and |y|",
}


def attr(f, name):
    v = f.attrs[name]
    return v.decode() if isinstance(v, bytes) else v


def spectrum_panel(fig, ax, k, omega, power, title):
    with np.errstate(divide="ignore"):
        logp = np.where(power > 0, np.log10(np.where(power > 0, power, 1.0)), np.nan)
    top = np.nanmax(logp)
    bottom = max(np.nanmin(logp), top - 8)
    mesh = ax.pcolormesh(k, omega, logp.T, shading="nearest", cmap="viridis", vmin=bottom, vmax=top)
    fig.colorbar(mesh, ax=ax, label="log10 power")
    ax.set_xlabel("k a / π")
    ax.set_ylabel("ω R / u_d")
    ax.set_title(title, fontsize=9)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("analysis")
    parser.add_argument("out")
    parser.add_argument("--correlation", choices=sorted(DEFINITIONS), help="definition of C for panel (c)")
    args = parser.parse_args()

    with h5py.File(args.analysis, "r") as f:
        a, R, u_d = float(attr(f, "a")), float(attr(f, "R")), float(attr(f, "u_d"))
        N, T, dt = int(attr(f, "N")), int(attr(f, "T")), float(attr(f, "dt"))
        beta, B = float(attr(f, "beta")), float(attr(f, "B"))
        ks = f["spectra/k"][()] * a / np.pi
        ws = f["spectra/omega"][()] * R / u_d
        transverse = f["spectra/transverse"][()]
        longitudinal = f["spectra/longitudinal"][()]
        window = attr(f["spectra"], "window")
        theory = {name: f["theory"][name][()] for name in f["theory"]}
        kt = theory["k"] * a / np.pi
        definition = args.correlation or attr(f["correlation"], "ridge")
        kc = f["correlation/k"][()] * a / np.pi
        corr = f["correlation"][definition][()]

    scale = R / u_d
    w3, w4, w8 = (theory[n] * scale for n in ("omega_transverse", "omega_longitudinal", "omega_coupled"))
    w13, w14 = theory["omega_longitudinal_nn"] * scale, theory["omega_transverse_nn"] * scale
    limit = min(np.pi / dt * scale, 2.5 * max(np.abs(w3).max(), np.abs(w4).max(), np.abs(w8).max()))

    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8))
    spectrum_panel(fig, axes[0], ks, ws, transverse, f"transverse |y(k, ω)|², eq. (2) ({window} window)")
    axes[0].plot(kt, w3, "w-", lw=1.5, label="eq. (3)")
    axes[0].plot(kt, w14, "w--", lw=1.2, label="eq. (14)")
    spectrum_panel(fig, axes[1], ks, ws, longitudinal, f"longitudinal |x(k, ω)|², eq. (1) ({window} window)")
    axes[1].plot(kt, w4, "-", color="0.6", lw=1.5, label="eq. (4)")
    axes[1].plot(kt, w13, "--", color="0.6", lw=1.2, label="eq. (13)")
    axes[1].plot(kt, w8, "w-", lw=1.5, label="eq. (8): 2ω⊥(k/2)")
    for ax in axes[:2]:
        ax.set_xlim(-1, 1)
        ax.set_ylim(-limit, limit)
        ax.legend(fontsize=7, loc="lower right", facecolor="0.3", labelcolor="w")

    symmetric = definition == "amplitude_fluctuation"
    mesh = axes[2].pcolormesh(kc, kc, corr, shading="nearest", cmap="RdBu_r" if symmetric else "viridis",
                              vmin=-1 if symmetric else 0, vmax=1)
    fig.colorbar(mesh, ax=axes[2], label="C(k∥, k⊥)")
    kp = np.linspace(-0.5, 0.5, 2)
    axes[2].plot(kp, 2 * kp, "k--", lw=1.2, label="k∥ = 2k⊥")
    axes[2].set_xlabel("k⊥ a / π")
    axes[2].set_ylabel("k∥ a / π")
    axes[2].set_title(f"correlation: {DEFINITIONS[definition]}", fontsize=9)
    axes[2].legend(fontsize=7, loc="lower right")
    fig.suptitle(f"N = {N}, T = {T}, Δt = {dt:g}, β = a/W = {beta:.3g}, B = {B:.4g}, ΔT = R/u_d = {R / u_d:.4g}",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(args.out, dpi=130)


if __name__ == "__main__":
    main()
