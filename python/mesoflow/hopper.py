"""Hopper flows (hopper-flows §2): the soft-particle scene in 2D or 3D and the deformable-polygon
scene in 2D, from Python.

    from mesoflow import hopper
    h = hopper.scene(dimension=2, particles=300, orifice=6.0, friction=31.6)
    h.relax(); h.advance(20000)
    print(h.crossings, h.flow_rate(steps=20000))

    d = hopper.dp_scene(particles=100, vertices=16, orifice=5.0, friction=3.16)
    d.relax(); d.advance(5000)
    d.positions          # vertices (N N_v, 2); d.bodies their polygon; d.body_state()["centroid"]

scene(): keywords are HopperParameters' fields (particles, hopper_width, orifice, wall_angle,
pair_energy, wall_energy, drag, friction, friction_component, dt, seed, force_dt), checked by the
C++ validate(dimension). dp_scene(): DpHopperParameters' fields (particles, vertices, hopper_width,
orifice, wall_angle, area_stiffness, perimeter_stiffness, bending_stiffness, contact_energy,
wall_energy, drag, friction, friction_component, smooth, dt, seed, force_dt), checked by the C++
validate(). A value out of range raises ValueError naming it.
"""
from . import _mesoflow
from ._params import fill

_core = _mesoflow.hopper
HopperParameters = _core.HopperParameters
DpHopperParameters = _core.DpHopperParameters
FrictionComponent = _core.FrictionComponent
_KEYS = ("particles", "hopper_width", "orifice", "wall_angle", "pair_energy", "wall_energy", "drag", "friction",
         "friction_component", "dt", "seed", "force_dt")
_DP_KEYS = ("particles", "vertices", "hopper_width", "orifice", "wall_angle", "area_stiffness", "perimeter_stiffness",
            "bending_stiffness", "contact_energy", "wall_energy", "drag", "friction", "friction_component", "smooth",
            "dt", "seed", "force_dt")


def _friction_component(k, v):
    return getattr(FrictionComponent, v) if k == "friction_component" and isinstance(v, str) else v


class Hopper:
    """A HopperScene2D/3D or DpHopperScene with a flow-rate helper; attributes are the scene's
    (positions, crossings, ...). `model` is "sp" or "dp"."""

    def __init__(self, parameters, dimension, model="sp"):
        self.parameters, self.dimension, self.model = parameters, dimension, model
        if model == "dp":
            self._scene = _core.DpHopperScene(parameters)
        else:
            self._scene = (_core.HopperScene2D if dimension == 2 else _core.HopperScene3D)(parameters)

    def __getattr__(self, name):
        return getattr(self._scene, name)

    def flow_rate(self, steps):
        """Runs `steps` steps and returns the crossed area (2D) or volume (3D) per unit time over them:
        the flow rate Q of eq. 13 before the paper's Appendix B correction."""
        before, t0 = self._scene.crossed_measure, self._scene.time
        self._scene.advance(steps)
        return (self._scene.crossed_measure - before) / (self._scene.time - t0)


def scene(dimension=2, **kw):
    if dimension not in (2, 3):
        raise ValueError("dimension must be 2 or 3, got %r" % (dimension,))
    p = fill("hopper scene", HopperParameters(), kw, _KEYS, _friction_component)
    p.validate(dimension)
    return Hopper(p, dimension)


def dp_scene(**kw):
    """The 2D deformable-polygon hopper (rough vertex disks, or smooth=True circulo-lines)."""
    p = fill("dp hopper scene", DpHopperParameters(), kw, _DP_KEYS, _friction_component)
    p.validate()
    return Hopper(p, 2, model="dp")
