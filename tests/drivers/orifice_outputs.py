#!/usr/bin/python3
"""Runs the `orifice` driver on a small fast scene and checks what a user gets: the JSON outcome,
a profile CSV whose last row agrees with the HDF5 observables, an H5MD file with the vertex
positions and the parameters as attributes, an XDMF sidecar that names the HDF5 file, and the PNG.

usage: orifice_outputs.py <orifice executable> <work dir>
"""
import csv
import json
import os
import subprocess
import sys

import h5py

exe, work = sys.argv[1], sys.argv[2]
os.makedirs(work, exist_ok=True)
out = os.path.join(work, "stiff.h5")
# Γ = 10, N_v = 32 through w = 0.9σ: passes in ~60 t0 (well under a second).
subprocess.run([exe, "--quiet", "--threads", "1", "--gamma", "10", "--vertices", "32", "--width", "0.9",
                "--output", out], check=True)
stem = out[:-3]
summary = json.load(open(stem + ".json"))
assert summary["outcome"] == "passed", summary
assert summary["final_h"] >= 1.0, summary
rows = list(csv.DictReader(open(stem + ".csv")))
assert len(rows) > 100, len(rows)
assert float(rows[-1]["h"]) >= 1.0
with h5py.File(out, "r") as f:
    pos = f["particles/droplet/position/value"]
    assert pos.shape[1:] == (32, 2), pos.shape
    h = f["observables/h/value"][:]
    assert abs(h[-1] - float(rows[-1]["h"])) < 1e-9, (h[-1], rows[-1]["h"])
    params = dict(f["parameters"].attrs)
    assert float(params["gamma"]) == 10.0 and int(params["vertices"]) == 32, params
    assert params["outcome"] == "passed" and float(params["dt_used"]) > 0, params
xdmf = open(stem + ".xdmf").read()
assert os.path.basename(out) in xdmf
assert os.path.getsize(stem + ".png") > 1000
print("orifice outputs: passed at t =", summary["time"], "with", len(rows), "profile rows")
