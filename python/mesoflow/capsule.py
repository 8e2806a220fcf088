"""The SPH + mass-spring capsule (sph-microcapsules-constriction) in a periodic box, from Python.

    from mesoflow import capsule, analysis
    c = capsule.scene(sites=(20, 16, 16), radius=4.0, level=2, capsule_velocity=(0.05, 0, 0))
    c.advance(200)
    print(analysis.shear_plane_shape(c.outer_layer()))

Keywords are CapsuleSceneParameters' fields (sites, spacing, support, rho0, mu_outer, mu_inner, u_max,
body_force, radius, thickness, level, k_b, clearance, stretch, capsule_velocity, velocity_noise, seed,
dt, force_dt), checked by the C++ validate() (ValueError naming the value). The constriction channel
and the Ca/η sweeps are the `capsule` driver's.
"""
from . import _mesoflow
from ._params import fill

_core = _mesoflow.capsule
CapsuleSceneParameters = _core.CapsuleSceneParameters
_KEYS = ("sites", "spacing", "support", "rho0", "mu_outer", "mu_inner", "u_max", "body_force", "radius", "thickness",
         "level", "k_b", "clearance", "stretch", "capsule_velocity", "velocity_noise", "seed", "dt", "force_dt")


def scene(**kw):
    p = fill("capsule scene", CapsuleSceneParameters(), kw, _KEYS, lambda k, v: tuple(v) if isinstance(v, list) else v)
    p.validate()
    return _core.CapsuleScene(p)
