"""MDPD flow through pillar arrays (mdpd-pillar-array-permeability), from Python.

    from mesoflow import pillars
    f = pillars.flow(dimension=2, layout="square", porosity=0.8, cells_x=3, cells_y=1)
    f.equilibrate(1000)
    f.run(warmup=2000, steps=20000, sample_every=10)
    print(f.record["mean_velocity_x"])

Keywords are the `pillars` driver's scene parameters (PillarRunParameters: layout 'square',
'rotated-square', 'hexagonal', 'irregular', 'none'; porosity, diameter, cells_x, cells_y, pillars,
aspect, exclusion, mc_sweeps, height (3D walls; 0: periodic), lz, box, fb (driving force, −1: the
paper's), driving_length, bin_width, density, A, B, r_B, R, dt, k_S, density_kernel, list,
density_self_term, seed); the C++ layout and scene check them (ValueError).

The `pillars` driver's flow run as one call, and a resumable sweep of such runs:

    r = pillars.run(dimension=2, layout="square", porosity=0.7, fb=0.6, equilibrate=500, warmup=3000,
                    steps=100000)
    print(r["kappa_darcy_box"], r["kappa_darcy_box_relative_error"])
    s = pillars.sweep([dict(porosity=e) for e in (0.6, 0.7, 0.8)], checkpoint="sweep.jsonl", layout="square")
"""
from . import _mesoflow
from ._checkpoint import run_indexed
from ._params import fill

_core = _mesoflow.pillars
PillarRunParameters = _core.PillarRunParameters
_KEYS = ("layout", "porosity", "diameter", "cells_x", "cells_y", "pillars", "aspect", "exclusion", "mc_sweeps",
         "height", "lz", "box", "fb", "driving_length", "bin_width", "density", "A", "B", "r_B", "R", "dt", "k_S",
         "density_kernel", "list", "density_self_term", "seed")


def flow(dimension=2, **kw):
    if dimension not in (2, 3):
        raise ValueError("dimension must be 2 or 3, got %r" % (dimension,))
    p = fill("pillar flow", PillarRunParameters(), kw, _KEYS)
    return (_core.PillarFlow2D if dimension == 2 else _core.PillarFlow3D)(p)


def run(dimension=2, equilibrate=1000, warmup=5000, steps=20000, sample_every=10, kappa_p=0.0, viscosity=0.0,
        on_sample=None, **kw):
    """One flow run, as `pillars --dimension D --equilibrate-steps E --warmup-steps W --steps S` with the
    same scene keywords (flow()'s): builds the scene, equilibrates and carves, runs, and returns the
    driver's estimates (permeability(viscosity, kappa_p): Darcy over the box with its block error,
    the drag estimates, and between walls 'brinkman' with μ_eff/μ when kappa_p > 0) together with the
    scene's porosity, particles, solid_particles, box, height and dimension. on_sample(dict) per sample."""
    for name, value in (("equilibrate", equilibrate), ("warmup", warmup), ("steps", steps)):
        if not isinstance(value, int) or value < 0:
            raise ValueError("%s must be an integer >= 0, got %r" % (name, value))
    if not isinstance(sample_every, int) or sample_every < 1 or steps < sample_every:
        raise ValueError("sample_every must be an integer in [1, steps], got %r" % (sample_every,))
    f = flow(dimension=dimension, **kw)
    f.equilibrate(equilibrate)
    f.run(warmup=warmup, steps=steps, sample_every=sample_every, on_sample=on_sample)
    out = dict(f.permeability(viscosity=viscosity, kappa_p=kappa_p))
    out.update(dimension=dimension, porosity=f.porosity, particles=len(f.types), solid_particles=f.solid_particles,
               box=list(f.box), height=f.height, samples=f.record["samples"])
    return out


def sweep(points, checkpoint=None, progress=False, callback=None, **common):
    """run() at every point: points is a list of keyword dicts (what differs per run, e.g.
    dict(porosity=0.6)), each merged over `common` (what all share; a point's keys win). checkpoint:
    a JSON-lines file (mesoflow._checkpoint) holding each finished run at once, so an interrupted sweep
    loses no finished run; the same call again reuses them (another sweep raises ValueError).
    callback(k, record) as each run finishes. Returns the records in the points' order, each with its
    point's keywords under "point"."""
    points = [dict(p) for p in points]
    if not points:
        raise ValueError("points must not be empty")
    for p in points:  # bad keywords and values fail before anything runs
        merged = dict(common, **p)
        for key in ("dimension", "equilibrate", "warmup", "steps", "sample_every", "kappa_p", "viscosity"):
            merged.pop(key, None)
        fill("pillar flow", PillarRunParameters(), merged, _KEYS)
    signature = {"points": points, "common": common}

    def run_one(k):
        record = run(**dict(common, **points[k]))
        record["point"] = points[k]
        return record

    return run_indexed(len(points), run_one, checkpoint, signature, "runs", progress, callback)
