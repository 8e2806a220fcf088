"""Soft-particle hopper flows (hopper-flows §2): the scene from Python, in 2D or 3D.

    from mesoflow import hopper
    h = hopper.scene(dimension=2, particles=300, orifice=6.0, friction=31.6)
    h.relax(); h.advance(20000)
    print(h.crossings, h.flow_rate(steps=20000))

Keywords are HopperParameters' fields (particles, hopper_width, orifice, wall_angle, pair_energy,
wall_energy, drag, friction, friction_component, dt, seed, force_dt), checked by the C++
validate(dimension): a value out of range raises ValueError naming it.
"""
from . import _mesoflow
from ._params import fill

_core = _mesoflow.hopper
HopperParameters = _core.HopperParameters
FrictionComponent = _core.FrictionComponent
_KEYS = ("particles", "hopper_width", "orifice", "wall_angle", "pair_energy", "wall_energy", "drag", "friction",
         "friction_component", "dt", "seed", "force_dt")


class Hopper:
    """A HopperScene2D/3D with a flow-rate helper; attributes are the scene's (positions, crossings, ...)."""

    def __init__(self, parameters, dimension):
        self.parameters, self.dimension = parameters, dimension
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
    p = fill("hopper scene", HopperParameters(), kw, _KEYS,
             lambda k, v: getattr(FrictionComponent, v) if k == "friction_component" and isinstance(v, str) else v)
    p.validate(dimension)
    return Hopper(p, dimension)
