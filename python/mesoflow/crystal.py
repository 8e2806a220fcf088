"""Rigid discs in an MPC channel flow (mpc-microfluidic-crystal-phonons): the scene from Python.

    from mesoflow import crystal, analysis
    c = crystal.channel(length=60, width=15, density=10, disc_centres=[(5, 7.5), (17, 7.5)])
    c.advance(1000)
    print(c.disc_positions, c.total_momentum)

Keywords are ChannelFlowParameters' fields (length, width, walls, cell_size, density, kT, mass, h,
rule ('srd', 'at_minus_a', 'at_plus_a'), srd_angle, body_acceleration, disc_radius, friction,
wca_epsilon, wca_r0, seed, sort_interval, deterministic); the C++ scene checks them (ValueError).
"""
from . import _mesoflow
from ._params import fill

_core = _mesoflow.crystal
ChannelFlowParameters = _core.ChannelFlowParameters
CollisionRule = _core.CollisionRule
_KEYS = ("length", "width", "walls", "cell_size", "density", "kT", "mass", "h", "rule", "srd_angle",
         "body_acceleration", "disc_radius", "friction", "wca_epsilon", "wca_r0", "seed", "sort_interval",
         "deterministic")


def channel(disc_centres=(), **kw):
    def rule(k, v):
        if k == "rule" and isinstance(v, str):
            if v not in ("srd", "at_minus_a", "at_plus_a"):
                raise ValueError("rule must be one of srd, at_minus_a, at_plus_a, got %r" % (v,))
            return getattr(CollisionRule, v)
        return v

    p = fill("channel flow", ChannelFlowParameters(), kw, _KEYS, rule)
    return _core.ChannelFlow(p, [tuple(map(float, c)) for c in disc_centres])
