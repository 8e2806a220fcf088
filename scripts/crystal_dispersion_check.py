#!/usr/bin/python3
"""Quantifies which dispersion relation a crystal run's spectra follow (issue 5, item 5).

usage: crystal_dispersion_check.py <run>_phonons.h5 [out.json]

For every wavenumber 0 < k < π/a of the power spectra (/spectra of drivers/crystal's analysis file)
it finds the frequency of largest power, restricted to |ω| below 3 × the largest theory frequency
(the Nyquist range may be far wider), and compares it with
  transverse |ỹ(k, ω)|²:   eq. (3) ω⊥(k), and, for reference, its negative;
  longitudinal |x̃(k, ω)|²: eq. (8) 2ω⊥(k/2) against eq. (4) ω∥(k).
It reports, per curve, the fraction of the spectral power within ±1/4 of the largest theory
frequency of the curve (robust to noise), the mean distance |ω_peak − ω_theory| in units of the frequency bin 2π/(TΔt)
and in units of the curve's range, and for the longitudinal spectrum the number of k columns whose
peak lies closer to eq. (8) than to eq. (4). It also gives, for the Pearson amplitude correlation
C(k∥, k⊥) (/correlation/amplitude_fluctuation), for every k⊥ > 0 the k∥ > 0 of the largest |C|
and whether it is 2k⊥ folded into the first Brillouin zone, counted separately for long
(k⊥ < π/(2a)) and short wavelengths.
"""
import json
import sys

import h5py
import numpy as np

path = sys.argv[1]
out = sys.argv[2] if len(sys.argv) > 2 else None
with h5py.File(path, "r") as f:
    a = float(f.attrs["a"])
    k = f["spectra/k"][()]
    omega = f["spectra/omega"][()]
    trans = f["spectra/transverse"][()]
    longi = f["spectra/longitudinal"][()]
    kt = f["theory/k"][()]
    w3 = f["theory/omega_transverse"][()]
    w4 = f["theory/omega_longitudinal"][()]
    w8 = f["theory/omega_coupled"][()]
    ck = f["correlation/k"][()]
    corr = f["correlation/amplitude_fluctuation"][()]

if trans.shape[0] != k.size:  # stored (T, N): transpose to (N, T)
    trans, longi = trans.T, longi.T
bin_width = omega[1] - omega[0]
scale = max(np.max(np.abs(w3)), np.max(np.abs(w8)), np.max(np.abs(w4)))
window = np.abs(omega) <= 3 * scale


def theory(curve, kk):
    return np.interp(kk, kt, curve)


def peaks(power):
    rows = []
    for i, kk in enumerate(k):
        if not (0 < kk < np.pi / a - 1e-12):
            continue
        p = np.where(window, power[i], -np.inf)
        rows.append((kk, omega[int(np.argmax(p))]))
    return np.array(rows)


def distance(rows, curve):
    d = np.abs(rows[:, 1] - theory(curve, rows[:, 0]))
    return {"mean_bins": float(np.mean(d) / bin_width), "mean_over_range": float(np.mean(d) / scale)}


def power_near(power, curve, half_width):
    """Fraction of the power in 0 < k < π/a, |ω| ≤ 3 × scale, lying within ±half_width of the curve."""
    total = near = 0.0
    for i, kk in enumerate(k):
        if not (0 < kk < np.pi / a - 1e-12):
            continue
        row = np.where(window, power[i], 0.0)
        total += row.sum()
        near += row[np.abs(omega - theory(curve, kk)) <= half_width].sum()
    return near / total


pt, pl = peaks(trans), peaks(longi)
result = {
    "file": path,
    "k_columns": int(len(pt)),
    "frequency_bin": float(bin_width),
    "largest_theory_frequency": float(scale),
    "transverse_vs_eq3": distance(pt, w3),
    "transverse_vs_minus_eq3": distance(pt, -w3),
    "longitudinal_vs_eq8": distance(pl, w8),
    "longitudinal_vs_eq4": distance(pl, w4),
    "longitudinal_columns_closer_to_eq8": int(np.sum(np.abs(pl[:, 1] - theory(w8, pl[:, 0])) <
                                                     np.abs(pl[:, 1] - theory(w4, pl[:, 0])))),
    "power_fraction_within_quarter_range": {
        "transverse_eq3": power_near(trans, w3, scale / 4),
        "transverse_minus_eq3": power_near(trans, -w3, scale / 4),
        "longitudinal_eq8": power_near(longi, w8, scale / 4),
        "longitudinal_eq4": power_near(longi, w4, scale / 4),
    },
    "transverse_peaks": [[float(x), float(y)] for x, y in pt],
    "longitudinal_peaks": [[float(x), float(y)] for x, y in pl],
}

# Correlation: for each k⊥ > 0, the k∥ > 0 with the largest |C| (C is even in each k), and whether it
# is the image of 2k⊥ in the first Brillouin zone, |2k⊥| folded into [0, π/a] (within one bin).
def fold(q):
    period = 2 * np.pi / a
    return abs((q + np.pi / a) % period - np.pi / a)


dk = ck[1] - ck[0] if ck.size > 1 else 1.0
ridge = {"long": [], "short": []}
for j, kp in enumerate(ck):
    if not (1e-12 < kp < np.pi / a - 1e-12):
        continue
    col = np.where(ck > 1e-12, np.abs(corr[:, j]), -np.inf)
    i = int(np.argmax(col))
    hit = abs(ck[i] - fold(2 * kp)) <= dk * 1.01
    ridge["short" if kp >= np.pi / (2 * a) - 1e-12 else "long"].append([float(kp), float(ck[i]), bool(hit)])
for half in ("long", "short"):
    rows = ridge[half]
    result[f"correlation_max_at_2k_{half}_wavelengths"] = f"{sum(r[2] for r in rows)} of {len(rows)}"
result["correlation_ridge"] = ridge

text = json.dumps(result, indent=1)
if out:
    with open(out, "w") as fo:
        fo.write(text + "\n")
summary = {key: result[key] for key in result if not key.endswith("peaks") and key != "correlation_ridge"}
print(json.dumps(summary, indent=1))
