"""Rigid discs in an MPC channel flow (mpc-microfluidic-crystal-phonons): the scene from Python.

    from mesoflow import crystal, analysis
    c = crystal.channel(length=60, width=15, density=10, disc_centres=[(5, 7.5), (17, 7.5)])
    c.advance(1000)
    print(c.disc_positions, c.total_momentum)

Keywords are ChannelFlowParameters' fields (length, width, walls, cell_size, density, kT, mass, h,
rule ('srd', 'at_minus_a', 'at_plus_a'), srd_angle, body_acceleration, disc_radius, friction,
wca_epsilon, wca_r0, seed, sort_interval, deterministic); the C++ scene checks them (ValueError).

The `crystal` driver's run as one call: the discs on the driver's zigzag, the results file (H5MD +
XDMF), K = u_d/u_oil and, with two or more discs, the phonon analysis and theory files:

    r = crystal.run("crystal.h5", discs=27, length=300.0, time=2000.0, warmup=200.0)
    print(r["K"], r["B"], r["beta"]); y = r["y"]  # (frames, discs) transverse positions
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


# The run's own keywords (CrystalRunParameters; rule as the driver's --collision: 'at+a', 'at-a', 'srd')
# and the channel's (ChannelFlowParameters) that a run takes; walls are always on.
_RUN_KEYS = ("rule", "wall_virtual", "discs", "wavelength", "amplitude", "warmup", "time", "frame_interval",
             "checkpoint_interval", "check_every", "calibrated_ratio", "seed", "force_dt")
_RUN_FLOW_KEYS = ("length", "width", "cell_size", "density", "kT", "mass", "h", "srd_angle", "body_acceleration",
                  "disc_radius", "friction", "wca_epsilon", "wca_r0", "sort_interval", "deterministic")
CrystalRunParameters = _core.CrystalRunParameters


def run_parameters(**kw):
    """CrystalRunParameters from keywords (the run's: rule, wall_virtual, discs, wavelength, amplitude,
    warmup, time, frame_interval, checkpoint_interval, check_every, calibrated_ratio, seed, force_dt;
    the channel's: length, width, cell_size, density, kT, mass, h, srd_angle, body_acceleration,
    disc_radius, friction, wca_epsilon, wca_r0, sort_interval, deterministic), defaults the driver's
    (the paper's scene), checked by the C++ validate() (ValueError naming the parameter and its range)."""
    from ._params import check_keywords
    check_keywords("crystal run", kw, _RUN_KEYS + _RUN_FLOW_KEYS)
    p = CrystalRunParameters()
    fp = p.flow
    fill("crystal run", fp, {k: v for k, v in kw.items() if k in _RUN_FLOW_KEYS}, _RUN_FLOW_KEYS)
    p.flow = fp
    fill("crystal run", p, {k: v for k, v in kw.items() if k in _RUN_KEYS}, _RUN_KEYS)
    p.validate()
    return p


def run(output="crystal.h5", callback=None, restart=False, **kw):
    """One run of the `crystal` driver with the same scene (kw: run_parameters' keywords), its files at
    `output` (.h5; the checkpoint, XDMF and the phonon files beside it). Returns a dict with what the
    driver's JSON has (K, u_d, u_oil, Re, Pe, η of eq. B.3; with two or more discs the theory's K, B,
    β, phase velocity and spacing; with one disc the far field) and the frames: frame_time,
    u_d_series, u_oil_series, x and y (frames × discs, unwrapped along x). callback(step, time) at
    every frame; returning False stops the run ("stopped": True, no analysis) and writes a checkpoint
    there. restart=True continues from `output`'s checkpoint as the driver's --restart does: the same
    scene (ValueError otherwise), `time` may grow; "resumed_from_step" says where it began."""
    p = run_parameters(**kw)
    resolved = [(k, str(getattr(p, k))) for k in _RUN_KEYS if k != "force_dt"]
    resolved += [(k, str(getattr(p.flow, k))) for k in _RUN_FLOW_KEYS]
    return _core.run_crystal(p, str(output), callback, resolved, bool(restart))
