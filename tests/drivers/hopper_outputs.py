#!/usr/bin/python3
"""Runs a small `hopper` sweep (N = 300, W = 20, friction only, w = 4…7) and checks what a user
gets: the results CSV (Q > 0 at every width, rising with w; Q' of Appendix B within 25% of Q for
these nearly hard particles, E_sp = 100), the axis velocity profile CSV (96 heights per width, mean
speed positive and larger near the orifice than 10σ above it), the JSON with the Beverloo fit, the
HDF5 observables and parameters, and the PNG.

usage: hopper_outputs.py <hopper executable> <work dir>
"""
import csv
import json
import os
import subprocess
import sys

import h5py

exe, work = sys.argv[1], sys.argv[2]
os.makedirs(work, exist_ok=True)
out = os.path.join(work, "run.h5")
run = subprocess.run([exe, "--threads", "1", "--widths", "4,5,6,7", "--friction", "31.6", "--particles", "300",
                      "--hopper-width", "20", "--measure-windows", "8", "--output", out],
                     check=True, capture_output=True, text=True)
assert "Beverloo fit over 4 widths" in run.stdout, run.stdout
stem = out[:-3]
rows = list(csv.DictReader(open(stem + ".csv")))
assert [float(r["w"]) for r in rows] == [4, 5, 6, 7], rows
Q = [float(r["Q"]) for r in rows]
assert all(q > 0 for q in Q) and Q == sorted(Q), Q
for r in rows:
    assert r["steady"] == "1" and r["clogged"] == "0", r
    q, qc, rho = float(r["Q"]), float(r["Q_corrected"]), float(r["number_density_orifice"])
    assert 0.5 < rho < 1.6, r  # particles per σ_avg² near the orifice (a_avg = 0.81)
    assert abs(qc / q - 1) < 0.25, r
profile = list(csv.DictReader(open(stem + "_profile.csv")))
assert len(profile) == 4 * 96, len(profile)
for w in ("4", "5", "6", "7"):
    prof = [r for r in profile if r["w"] == w]
    assert [float(r["h"]) for r in prof[:3]] == [0, 0.25, 0.5], prof[:3]
    near, above = float(prof[0]["vg_mean"]), float(prof[40]["vg_mean"])  # h = 0 and 10σ
    assert near > above > 0, (w, near, above)
summary = json.load(open(stem + ".json"))
assert summary["beverloo"] is not None and summary["beverloo"]["points"] == 4, summary
assert len(summary["results"]) == 4 and all("Q_corrected" in r for r in summary["results"])
with h5py.File(out, "r") as f:
    for k in range(4):
        assert f[f"observables/window_flow_rate_{k}/value"].shape[0] > 8
        assert f[f"observables/profile_vg_{k}/value"].shape == (1, 96)
        assert f[f"observables/profile_number_density_{k}/value"].shape == (1, 96)
    attrs = f["parameters"].attrs
    assert abs(attrs["Q_0"] - Q[0]) < 1e-8 and "Q_corrected_3" in attrs, dict(attrs)
assert os.path.getsize(stem + ".png") > 10000
print("hopper outputs ok")
