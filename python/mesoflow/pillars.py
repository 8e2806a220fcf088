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
"""
from . import _mesoflow
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
