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

sweep(): the `hopper` driver's Q(w) sweep (width index k runs at orifice w_k with seed + k, FIRE, flow
to a steady state, Q over the measuring windows with its block error, the axis profile), width by
width with a resume file, and Beverloo's eq. 1 fitted as the driver does:

    r = hopper.sweep([4, 5, 6, 7], particles=400, hopper_width=25, friction=3.16,
                     flow=dict(measure_windows=20), checkpoint="q_w.jsonl")
    r["Q"], r["Q_error"], r["beverloo"]["beta"]
"""
from . import _mesoflow
from ._checkpoint import run_indexed
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


FlowSettings = _core.FlowSettings
_FLOW_KEYS = ("window", "steady_windows", "measure_windows", "clog_time", "max_time", "check_interval")


def _flow_settings(flow):
    f = fill("flow measurement", FlowSettings(), dict(flow or {}), _FLOW_KEYS)
    f.validate()
    return f


def sweep(widths, dimension=2, model="sp", flow=None, checkpoint=None, progress=False, callback=None, **kw):
    """Q(w) as the `hopper` driver measures it (--widths, same order and seeds), one width at a time.

    kw: the scene's keywords (scene() or, with model="dp", dp_scene()); flow: FlowSettings' fields
    (window, steady_windows, measure_windows, clog_time, max_time, check_interval).
    checkpoint: a file (JSON lines): its first line the sweep's parameters, then one line per finished
    width, written at once (fsync); a later call with the same file and parameters skips the widths
    it holds (other parameters raise ValueError). callback(k, w, record) as each width finishes.
    A width's run is not interruptible from Python (Ctrl-C acts after it).
    Returns a dict: widths, records (per width: Q, Q_error, Q_corrected, clogged, steady, ..., the
    window rates and the axis profile), Q, Q_error, and beverloo (eq. 1 over the flowing, steady
    widths with a rate and an error, as the driver; None below 4 such widths).
    """
    if model not in ("sp", "dp"):
        raise ValueError("model must be sp or dp, got %r" % (model,))
    if model == "dp":
        if dimension != 2:
            raise ValueError("dimension: the dp model is 2D only, got %r" % (dimension,))
        params = fill("dp hopper scene", DpHopperParameters(), kw, _DP_KEYS, _friction_component)
    else:
        if dimension not in (2, 3):
            raise ValueError("dimension must be 2 or 3, got %r" % (dimension,))
        params = fill("hopper scene", HopperParameters(), kw, _KEYS, _friction_component)
    widths = [float(w) for w in widths]
    if not widths:
        raise ValueError("widths must not be empty")
    for w in widths:
        if not (0 < w < params.hopper_width):
            raise ValueError("widths: each in (0, W = %g), got %g" % (params.hopper_width, w))
    settings = _flow_settings(flow)
    signature = {"model": model, "dimension": dimension, "widths": widths,
                 "scene": {k: str(v) for k, v in sorted(kw.items())},
                 "flow": {k: getattr(settings, k) for k in _FLOW_KEYS}}

    def run_one(k):
        return dict(_core.measure_width(params, dimension, widths[k], k, settings), w=widths[k])

    records = run_indexed(len(widths), run_one, checkpoint, signature, "widths", progress,
                          None if callback is None else lambda k, record: callback(k, widths[k], record))
    fit_rows = [(r["w"], r["Q"], r["Q_error"]) for r in records
                if not r["clogged"] and r["steady"] and r["Q"] > 0 and r["Q_error"] > 0]
    beverloo = None
    if len(fit_rows) >= 4:
        beverloo = _mesoflow.analysis.fit_beverloo(*(list(c) for c in zip(*fit_rows)))
    return {"widths": widths, "records": records, "Q": [r["Q"] for r in records],
            "Q_error": [r["Q_error"] for r in records], "beverloo": beverloo}
