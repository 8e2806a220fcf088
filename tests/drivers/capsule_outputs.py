#!/usr/bin/python3
"""Runs small `capsule` scenes and checks what a user gets.
  constriction sweep, Π = 8, Ca = 0.5 and 2, t_max 0.2 d/U: one sweep row per Ca with the effective
    η, a per-run series whose first sample has the capsule at x_c = 1.5 with D_x = D_y = D_z ≈ 1 and
    C_f ≈ C_r ≈ 1 within 10% (a sphere, level-3 mesh), the run's HDF5 file with the observables and membrane frames, the
    JSON's Pearson table (one entry per η), the plots; a second invocation with --restart reuses
    both finished runs (same rows, no new run) and a changed scene is not reused.
  shear, Π = 8, box 2.5d × 2d × 2d, γ̇t = 0.2: the table has D_xy ≥ 0 and θ/π in (−½, ½].

usage: capsule_outputs.py <capsule executable> <work dir>
"""
import csv
import json
import math
import os
import subprocess
import sys

import h5py

exe, work = sys.argv[1], sys.argv[2]
os.makedirs(work, exist_ok=True)
out = os.path.join(work, "sweep.h5")
base = [exe, "--threads", "2", "--output", out, "--resolution", "8", "--level", "3", "--ca", "0.5,2",
        "--t-max", "0.2", "--sample-every", "0.04", "--frame-every", "0.05"]


def sweep_rows():
    with open(os.path.join(work, "sweep_sweep.csv")) as f:
        return list(csv.DictReader(f))


first = subprocess.run(base + ["--quiet"], check=True, capture_output=True, text=True)
rows = sweep_rows()
assert [float(r["ca"]) for r in rows] == [0.5, 2.0], rows
for r in rows:
    assert float(r["eta_effective"]) == 0.5, r
    assert r["status"].startswith("blocked (t-max)"), r  # 0.2 d/U: still in the inlet
    series = list(csv.DictReader(open(r["series_csv"])))
    assert len(series) >= 5, len(series)
    s0 = series[0]
    assert abs(float(s0["x_c"]) - 1.5) < 1e-9, s0
    for key in ("Dx", "Dy", "Dz"):
        assert abs(float(s0[key]) - 1) < 0.02, s0
    for key in ("Cf", "Cr"):
        assert abs(float(s0[key]) - 1) < 0.1, s0
    assert all(math.isfinite(float(s[k])) for s in series for k in ("x_c", "Dx", "max_density_deviation"))
    h5 = r["series_csv"].replace("_series.csv", ".h5")
    with h5py.File(h5) as f:
        assert f["observables/x_c/value"].shape[0] == len(series)
        assert f["observables/deformation_index/value"].shape[1:] == (3,)
        assert f["particles/membrane/position/value"].shape[0] >= 3
        assert f["parameters"].attrs["ca_run"] == float(r["ca"])
    assert os.path.exists(h5.replace(".h5", ".xdmf"))
summary = json.load(open(os.path.join(work, "sweep.json")))
assert len(summary["pearson_r"]) == 1 and summary["pearson_r"][0]["eta"] == 0.5, summary
for png in ("sweep.png", "sweep_snapshot.png"):
    assert os.path.getsize(os.path.join(work, png)) > 1000, png

again = subprocess.run(base + ["--restart"], check=True, capture_output=True, text=True)
assert again.stderr.count("reusing the finished run") == 2, again.stderr
assert sweep_rows() == rows
changed = subprocess.run([a if a != "0.5,2" else "2" for a in base] + ["--restart", "--reynolds", "2"], check=True,
                         capture_output=True, text=True)
assert "reusing" not in changed.stderr, changed.stderr

shear_out = os.path.join(work, "shear.h5")
subprocess.run([exe, "--threads", "2", "--quiet", "--mode", "shear", "--output", shear_out, "--resolution", "8",
                "--level", "2", "--ca", "0.3", "--shear-box-x", "2.5", "--shear-box-y", "2", "--shear-box-z", "2",
                "--t-max", "0.2", "--sample-every", "0.05"], check=True)
table = list(csv.DictReader(open(os.path.join(work, "shear_shear.csv"))))
assert len(table) == 1, table
D, theta = float(table[0]["taylor_deformation"]), float(table[0]["inclination_over_pi"])
assert 0 <= D < 0.2 and -0.5 < theta <= 0.5, table
assert os.path.getsize(os.path.join(work, "shear_shear.png")) > 1000
print("capsule outputs: ok;", rows[0]["particles"], "particles, shear D_xy", D)
