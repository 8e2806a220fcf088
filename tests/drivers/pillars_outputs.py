#!/usr/bin/python3
"""Runs two small `pillars` scenes and checks what a user gets.
  2D square lattice, porosity 0.8 (3 x 1 cells, 400 τ): the JSON's Darcy permeability is positive
    and within a factor 1.5 of the Drummond–Tahir square-array value (0.0773 d²; short run, about
    10% noise), the tether-drag permeability within 30% of the Darcy one, the layout CSV has 3
    pillars, the HDF5 file has the observables and the final frame with species.
  3D, the same lattice between walls H = 5: the elevation profile has H / 0.5 = 10 bins, u_s is
    larger in the mid-plane than at the walls, the Brinkman fit (eq. 5) and the PNG exist.
  viscosity mode (2D, 6000 steps): η within 20% of the paper's 26.1 (the documented runs, longer,
    give 1%).

usage: pillars_outputs.py <pillars executable> <work dir>
"""
import csv
import json
import os
import subprocess
import sys

import h5py

exe, work = sys.argv[1], sys.argv[2]
os.makedirs(work, exist_ok=True)


def run(name, *args):
    out = os.path.join(work, name + ".h5")
    subprocess.run([exe, "--threads", "2", "--quiet", "--output", out, *args], check=True)
    return out[:-3]


stem = run("square2d", "--dimension", "2", "--layout", "square", "--porosity", "0.8", "--cells-x", "3",
           "--cells-y", "1", "--equilibrate-steps", "200", "--warmup-steps", "2000", "--steps", "40000")
summary = json.load(open(stem + ".json"))
kappa = summary["kappa_darcy_over_d2"]
assert 0.0773 / 1.5 < kappa < 0.0773 * 1.5, summary
assert abs(summary["kappa_drag_tether"] / summary["kappa_darcy"] - 1) < 0.3, summary
layout = [line for line in open(stem + "_layout.csv") if not line.startswith("#")]
assert len(layout) == 1 + 3, layout  # header + 3 pillars
with h5py.File(stem + ".h5") as f:
    assert "mean_velocity_x" in f["observables"], list(f["observables"])
    species = f["particles/all/species/value"][-1]
    assert set(species.ravel()) == {0, 1, 2}, set(species.ravel())
assert os.path.exists(stem + ".xdmf")

stem = run("square3d", "--dimension", "3", "--layout", "square", "--porosity", "0.8", "--cells-x", "2",
           "--cells-y", "1", "--height", "5", "--equilibrate-steps", "200", "--warmup-steps", "1000",
           "--steps", "3000")
rows = list(csv.DictReader(open(stem + "_profile.csv")))
assert len(rows) == 10, len(rows)
u = [float(r["u_s"]) for r in rows]
assert u[4] > u[0] and u[5] > u[-1], u
summary = json.load(open(stem + ".json"))
assert "brinkman" in summary and summary["brinkman"]["alpha"] > 0, summary
assert os.path.exists(stem + ".png")

stem = run("viscosity", "--mode", "viscosity", "--dimension", "2", "--box", "10", "--lz", "20", "--fb", "0.2",
           "--equilibrate-steps", "200", "--warmup-steps", "1000", "--steps", "6000")
summary = json.load(open(stem + ".json"))
assert abs(summary["viscosity"] / 26.1 - 1) < 0.2, summary
assert abs(summary["temperature"] - 1) < 0.03, summary
print("pillars outputs OK")
