#!/usr/bin/env python3
"""How compressed is the MPC solvent around a single disc? (docs/mpc.md, "K of a single disc")

Reads a one-disc `crystal` run: its trajectory <out>.h5 (disc position and velocity, u_oil per
frame) and its checkpoint <out>.ckpt.h5 (the solvent at the end of the run). Writes a JSON with
  - K = u_d/u_oil, u_d, u_oil and the disc's mean height y over the measured frames (time ≥ warmup),
    and the same in `blocks` equal blocks of those frames; where the run recorded the oil speed far
    from the disc (observables u_far_mean, u_far_axis), also K against those, overall and per block;
  - the solvent number density n(x) at the end of the run in strips of `strip` Δx along the channel,
    x measured from the disc centre (upstream < 0), normalised by the mean density;
  - the largest and smallest strip density over the mean, and the disc's gap to the nearer wall.

    crystal_single_disc_check.py RUN.h5 OUT.json [--warmup T] [--blocks B] [--strip S]
"""
import argparse
import json
import os

import h5py
import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run")
    ap.add_argument("out")
    ap.add_argument("--warmup", type=float, default=0.0, help="time before the measured frames, tau")
    ap.add_argument("--blocks", type=int, default=5)
    ap.add_argument("--strip", type=float, default=5.0, help="strip width along the channel, Δx")
    a = ap.parse_args()

    with h5py.File(a.run, "r") as f:
        t = f["particles/discs/position/time"][:]
        y = f["particles/discs/position/value"][:, 0, 1]
        ud = f["particles/discs/velocity/value"][:, 0, 0]
        uoil = f["observables/u_oil/value"][:]
        far_mean = f["observables/u_far_mean/value"][:] if "u_far_mean" in f["observables"] else None
        far_axis = f["observables/u_far_axis/value"][:] if "u_far_axis" in f["observables"] else None
        edges = f["particles/discs/box/edges"][:]
        if f["particles/discs/position/value"].shape[1] != 1:
            raise SystemExit("crystal_single_disc_check: the run must have exactly one disc")
    length, width = float(edges[0]), float(edges[1])
    ckpt = a.run[: -len(".h5")] + ".ckpt.h5" if a.run.endswith(".h5") else a.run + ".ckpt.h5"
    with h5py.File(ckpt, "r") as f:
        xs = f["solvent/x"][:]
        xd = f["discs/x"][0]
        # The checkpoint's scene line, "L=60 W=15 R=5 ...": the disc radius.
        scene = f["scene"][()].decode() if "scene" in f else ""
    radius = next((float(item[2:]) for item in scene.split() if item.startswith("R=")), None)
    if radius is None:
        raise SystemExit("crystal_single_disc_check: no disc radius R= in the checkpoint's scene line")

    m = t >= a.warmup
    if m.sum() < a.blocks:
        raise SystemExit("crystal_single_disc_check: fewer measured frames than blocks")
    blocks = []
    for idx in np.array_split(np.flatnonzero(m), a.blocks):
        block = {"t0": float(t[idx[0]]), "t1": float(t[idx[-1]]), "u_d": float(ud[idx].mean()),
                 "u_oil": float(uoil[idx].mean()), "K": float(ud[idx].mean() / uoil[idx].mean()),
                 "disc_y": float(y[idx].mean())}
        if far_axis is not None:
            block["K_far_mean"] = float(ud[idx].mean() / far_mean[idx].mean())
            block["K_axis"] = float(ud[idx].mean() / far_axis[idx].mean())
        blocks.append(block)
    rel = np.mod(xs[:, 0] - xd[0] + length / 2, length) - length / 2
    nstrip = int(round(length / a.strip))
    counts, bounds = np.histogram(rel, bins=nstrip, range=(-length / 2, length / 2))
    mean_density = len(xs) / (length * width)
    density = counts / ((bounds[1] - bounds[0]) * width) / mean_density
    # Strips that the disc itself covers hold less solvent for geometric reasons; leave them out of
    # the extremes (|x| < R + half a strip).
    r = radius
    centres = 0.5 * (bounds[1:] + bounds[:-1])
    outside = np.abs(centres) > r + a.strip / 2
    out = {
        "run": os.path.basename(a.run),
        "length": length,
        "width": width,
        "warmup": a.warmup,
        "K": float(ud[m].mean() / uoil[m].mean()),
        "u_d": float(ud[m].mean()),
        "u_oil": float(uoil[m].mean()),
        "disc_y_mean": float(y[m].mean()),
        "K_far_mean": float(ud[m].mean() / far_mean[m].mean()) if far_mean is not None else None,
        "K_axis": float(ud[m].mean() / far_axis[m].mean()) if far_axis is not None else None,
        "disc_y_end": float(xd[1]),
        "wall_gap_end": float(min(xd[1], width - xd[1]) - r),
        "blocks": blocks,
        "strip": a.strip,
        "density_over_mean": [round(float(v), 4) for v in density],
        "strip_centres": [round(float(v), 3) for v in centres],
        "density_max_over_mean": float(density[outside].max()),
        "density_min_over_mean": float(density[outside].min()),
    }
    with open(a.out, "w") as fo:
        json.dump(out, fo, indent=1)
    print(f"{a.run}: K = {out['K']:.3f} (u_d {out['u_d']:.4g}, u_oil {out['u_oil']:.4g}), blocks "
          + " ".join(f"{b['K']:.3f}" for b in blocks)
          + (f"; K against the far oil speed, mean {out['K_far_mean']:.3f}, axis {out['K_axis']:.3f} (blocks "
             + " ".join(f"{b['K_axis']:.3f}" for b in blocks) + ")" if far_axis is not None else "")
          + f"; disc y {out['disc_y_mean']:.2f} of W = {width:g} (gap to wall at the end {out['wall_gap_end']:.2f});"
          f" solvent density {out['density_min_over_mean']:.2f}-{out['density_max_over_mean']:.2f} x mean")


if __name__ == "__main__":
    main()
