#!/usr/bin/env python3
"""ParaView opens the XDMF sidecar of every driver that writes one and reads the particle positions
(issue 30 item 4; docs/python.md, "ParaView").

    paraview_reads_xdmf.py BIN_DIR WORK_DIR

Runs orifice, lj_fluid, crystal, pillars and capsule at tiny sizes into WORK_DIR, then ParaView's
pvpython opens each <out>.xdmf with ParaView's XDMF reader ("XDMF Reader", vtkXdmfReader) at its first
and last time step; the points it reads must equal the H5MD positions of those frames (z = 0 for 2D
drivers), bit for bit. Exit status 77 (ctest: skipped) with the reason printed when pvpython is not
installed (Debian: paraview and python3-paraview).
"""
import json
import os
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np

SKIP = 77
bin_dir, work = sys.argv[1], sys.argv[2]
pvpython = shutil.which("pvpython")
if pvpython is None:
    print("skipped: ParaView's pvpython is not on PATH (Debian: apt install paraview python3-paraview)")
    sys.exit(SKIP)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)

RUNS = {
    "orifice": ["--quiet", "--threads", "1", "--gamma", "10", "--vertices", "32", "--width", "0.9", "--max-time", "3",
                "--no-plot"],
    "lj_fluid": ["--quiet", "--particles", "256", "--steps", "100", "--dt", "0.01", "--fire-iterations", "50"],
    "crystal": ["--quiet", "--length", "60", "--discs", "5", "--wavelength", "5", "--density", "10", "--dt", "0.1",
                "--friction", "2000", "--body-force", "0.05", "--warmup", "10", "--time", "2", "--frame-interval", "1",
                "--no-plot"],
    "pillars": ["--quiet", "--threads", "1", "--dimension", "2", "--layout", "square", "--porosity", "0.8", "--cells-x", "3",
                "--cells-y", "1", "--equilibrate-steps", "50", "--warmup-steps", "50", "--steps", "200"],
    "capsule": ["--quiet", "--threads", "1", "--resolution", "8", "--level", "2", "--ca", "0.5", "--t-max", "0.02",
                "--sample-every", "0.01", "--frame-every", "0.01"],
}
xdmf_files = []
for driver, args in RUNS.items():
    out = os.path.join(work, driver + ".h5")
    subprocess.run([os.path.join(bin_dir, driver), *args, "--output", out], check=True, stdout=subprocess.DEVNULL)
    found = sorted(os.path.join(work, f) for f in os.listdir(work) if f.endswith(".xdmf") and f.startswith(driver))
    if not found:
        sys.exit("%s wrote no XDMF sidecar into %s" % (driver, work))
    xdmf_files += found

READER = r'''
import json, sys
from paraview.simple import XDMFReader, UpdatePipeline
from paraview import servermanager
from vtk.util.numpy_support import vtk_to_numpy
out = {}
for path in sys.argv[1:]:
    r = XDMFReader(FileNames=[path])
    times = list(r.TimestepValues) if hasattr(r.TimestepValues, "__len__") else [r.TimestepValues]
    frames = []
    for t in (times[0], times[-1]) if times else (None,):
        UpdatePipeline(time=t, proxy=r) if t is not None else UpdatePipeline(proxy=r)
        d = servermanager.Fetch(r)
        sets = []
        def walk(o):
            if o is None:
                return
            if o.IsA("vtkDataSet"):
                sets.append(vtk_to_numpy(o.GetPoints().GetData()).tolist() if o.GetPoints() else [])
            elif o.IsA("vtkCompositeDataSet"):
                for i in range(o.GetNumberOfBlocks()):
                    walk(o.GetBlock(i))
        walk(d)
        frames.append(sets)
    out[path] = {"times": len(times), "frames": frames}
print("PVJSON" + json.dumps(out))
'''
script = os.path.join(work, "read.py")
open(script, "w").write(READER)
run = subprocess.run([pvpython, script, *xdmf_files], capture_output=True, text=True, timeout=600)
line = next((l for l in run.stdout.splitlines() if l.startswith("PVJSON")), None)
if run.returncode != 0 or line is None:
    sys.exit("pvpython failed (exit %d):\n%s\n%s" % (run.returncode, run.stdout[-2000:], run.stderr[-2000:]))
seen = json.loads(line[len("PVJSON"):])
failures = []
for path in xdmf_files:
    text = open(path).read()
    # the first grid's geometry: <file>.h5:/particles/<group>/position/value, frames along axis 0
    m = re.search(r'Format="HDF">([^:<]+):(/particles/[^<]+/position/value)<', text)
    with h5py.File(os.path.join(os.path.dirname(path), m.group(1)), "r") as f:
        value = f[m.group(2)][()]
    r = seen[path]
    ok = r["times"] == value.shape[0]
    for frame, sets in zip((0, value.shape[0] - 1), r["frames"]):
        points = np.array(sets[0]) if sets else np.zeros((0, 3))
        expected = value[frame]
        if expected.shape[1] == 2:
            expected = np.c_[expected, np.zeros(len(expected))]
        ok = ok and points.shape == expected.shape and np.array_equal(points, expected)
    print("%-60s %s: %d frames, %d points%s" % (os.path.basename(path), "ok" if ok else "DIFFERS", r["times"],
                                               len(r["frames"][0][0]) if r["frames"][0] else 0,
                                               "" if ok else " (H5: %s)" % (value.shape,)))
    if not ok:
        failures.append(path)
if failures:
    sys.exit("ParaView did not read the positions of: " + ", ".join(failures))
print("ParaView %s read %d XDMF files from %d drivers: positions equal the H5MD frames" %
      (subprocess.run([pvpython, "--version"], capture_output=True, text=True).stdout.strip(), len(xdmf_files), len(RUNS)))
