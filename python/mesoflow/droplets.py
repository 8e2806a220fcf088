"""Capillary droplets (capillary-droplets-clogging): the orifice passage and clogging in obstacle arrays.

Scenes take the C++ scenes' parameters as keyword arguments and are checked by the same C++ code
(`validate()`, `ObstacleSweep.check`): a value out of range raises ValueError naming the parameter
and its range; an unknown keyword raises TypeError. Units: σ (droplet diameter), g, ρ; t0 = √(σ/g).
"""
import math

import numpy as np

from . import _mesoflow
from ._checkpoint import Checkpoint
from ._params import check_keywords as _unknown

_core = _mesoflow.droplets

DropletParameters = _core.DropletParameters
OrificeScene = _core.OrificeScene
ObstacleSweep = _core.ObstacleSweep
ClogTest = _core.ClogTest
decay_length = _core.decay_length
survival_curve = _core.survival_curve
replica_seed = _core.replica_seed


def obstacle_centres(strength, gap, seed, replica, **kw):
    """The obstacle centres (n, 2) of replica `replica` of a clogging_sweep with these keywords."""
    return _core.obstacle_centres(obstacle_sweep(**kw), float(strength), float(gap), seed, replica)

_DROPLET_KEYS = ("vertices", "line_tension", "area_stiffness", "bending_stiffness", "wall_energy",
                 "vertex_diameter", "near_wall_drag", "terminal_speed", "drag_exponent", "drag_floor", "dt",
                 "drag", "force_dt", "gravity_angle")
_ORIFICE_KEYS = ("width", "start_h", "end_h", "max_time", "sample_interval", "clog_threshold", "check_interval")
_EARLY_KEYS = {"clog_sample_interval": "sample_interval", "clog_window": "window", "clog_tolerance": "tolerance",
               "clog_max_scatter": "max_scatter", "clog_min_rate": "min_rate"}
_SWEEP_KEYS = ("soft_particles", "vertices", "area_stiffness", "perimeter_ratio", "dp_wall_energy", "edge_contacts",
               "near_wall_drag", "terminal_speed", "dt", "force_dt", "shape_dt_target", "box_length", "obstacle_diameter",
               "obstacle_fraction", "time_limit", "clog_threshold", "relax_iterations", "batch")


def orifice_scene(perimeter_ratio=1e-3, **kw):
    """The orifice scene of Fig. 1a with the `orifice` driver's defaults (the paper's Fig. 2).

    Keywords: the OrificeScene fields (width, start_h, end_h, max_time, sample_interval,
    clog_threshold, check_interval), the droplet's (vertices, line_tension, ...), and
    perimeter_ratio K_l/Γ (the perimeter stiffness follows the line tension, as in the driver).
    """
    _unknown("orifice scene", kw, _DROPLET_KEYS + _ORIFICE_KEYS)
    scene = OrificeScene()
    for k, v in kw.items():
        setattr(scene.droplet if k in _DROPLET_KEYS else scene, k, v)
    if not (isinstance(perimeter_ratio, (int, float)) and math.isfinite(perimeter_ratio) and perimeter_ratio >= 0):
        raise ValueError("perimeter ratio K_l/Γ must be finite and >= 0, got %r" % (perimeter_ratio,))
    scene.droplet.perimeter_stiffness = perimeter_ratio * scene.droplet.line_tension
    scene.validate()
    return scene


def _progress_bar(total, unit, enabled):
    if not enabled:
        return None
    try:
        from tqdm import tqdm
    except ImportError:  # a plain line when tqdm is not installed
        class _Line:
            def __init__(self):
                self.n = 0

            def update(self, k):
                self.n += k
                print("\r%.4g / %.4g %s" % (self.n, total, unit), end="", flush=True)

            def close(self):
                print()
        return _Line()
    return tqdm(total=total, unit=unit)


class Orifice:
    """One passage through the orifice (OrificeRun in C++): built, relaxed and sampled once on creation.

    `positions`, `velocities` and `forces` are (N_v, 2) NumPy arrays over the scene's own memory on
    host backends (no copy: they see every later step, and are valid while this object lives),
    copies on device backends (`mesoflow.host_backend()` tells which).
    """

    def __init__(self, scene=None, **kw):
        self.scene = scene if scene is not None else orifice_scene(**kw)
        if scene is not None and kw:
            raise TypeError("Orifice: pass a scene or keywords, not both")
        self._run = _core.OrificeRun(self.scene)

    def __getattr__(self, name):  # done, outcome, time, steps, dt, samples, positions, velocities, forces
        return getattr(self._run, name)

    def advance(self):
        """Steps to the next profile sample; False once the run has ended."""
        return self._run.advance()

    def stop(self):
        self._run.stop()

    def profile(self):
        """The profiles so far: dict of arrays t, h, vg, shape_parameter, area_over_a0, kinetic_over_terminal."""
        return self._run.profile()

    def run(self, callback=None, progress=False):
        """Runs to the end: passed, clogged, the time limit, or a callback returning False (outcome 'stopped').

        callback(orifice) is called after every sample; progress=True shows a bar (tqdm where installed)
        in simulated time. Returns profile().
        """
        bar = _progress_bar(self.scene.max_time, "t0", progress)
        shown = self.time
        try:
            while self._run.advance():
                if bar is not None:
                    bar.update(self.time - shown)
                    shown = self.time
                if callback is not None and callback(self) is False:
                    self._run.stop()
                    break
        finally:
            if bar is not None:
                bar.close()
        return self.profile()


def orifice(**kw):
    """An Orifice from orifice_scene's keywords."""
    return Orifice(orifice_scene(**kw))


def obstacle_sweep(clog_test="full", **kw):
    """The ObstacleSweep with the `obstacles` driver's defaults; keywords are its fields, clog_test
    ('full', 'early', 'both') and the early test's clog_sample_interval, clog_window, clog_tolerance,
    clog_max_scatter, clog_min_rate."""
    _unknown("obstacle sweep", kw, _SWEEP_KEYS + tuple(_EARLY_KEYS))
    sweep = ObstacleSweep()
    for k, v in kw.items():
        if k in _EARLY_KEYS:
            early = sweep.early
            setattr(early, _EARLY_KEYS[k], v)
            sweep.early = early
        else:
            setattr(sweep, k, v)
    if clog_test not in ("full", "early", "both"):
        raise ValueError("clog_test must be one of full, early, both, got %r" % (clog_test,))
    sweep.clog_test = getattr(ClogTest, clog_test)
    if sweep.soft_particles and sweep.shape_dt_target > 0:
        raise ValueError("shape_dt_target: needs the DP model (an SP droplet has no shape), got %r"
                         % (sweep.shape_dt_target,))
    return sweep


_RECORD_KEYS = ("clogged", "distance", "time", "final_x", "final_y", "steady_speed", "early_decision",
                "early_clogged", "early_distance", "early_time", "early_rate", "early_crossing")


def _sweep_signature(sweep, points, replicas, seed, clog_test):
    fields = {k: getattr(sweep, k) for k in _SWEEP_KEYS}
    fields.update({k: getattr(sweep.early, v) for k, v in _EARLY_KEYS.items()})
    fields.update(points=[list(p) for p in points], replicas=replicas, seed=seed, clog_test=clog_test)
    fields.pop("batch")  # the batch size changes no replica's record
    return fields


def clogging_sweep(strengths, gaps, replicas, seed=1, checkpoint=None, progress=False, callback=None,
                   schedule="sweep", confidence=0.95, clog_test="full", **kw):
    """λ(strength, gap) as the `obstacles` driver computes it: `replicas` replicas per point, replica j
    in the obstacle array of replica_seed(seed, j), points strengths × gaps (strength Γ for DP, E_w
    for SP with soft_particles=True).

    checkpoint: a file (JSON lines) to which every finished replica is appended at once; a later
    call with the same file and parameters resumes, skipping the replicas it holds (other
    parameters raise ValueError). callback(point, replica, record) as each finishes.
    Returns a dict: points, records (per point, a list of record dicts by replica), and per point
    decay_length, lower, upper, clogged, censored (decay_length()).
    """
    sweep = obstacle_sweep(clog_test=clog_test, **kw)
    if not isinstance(replicas, int) or replicas < 1:
        raise ValueError("replicas must be an integer >= 1, got %r" % (replicas,))
    if not (0 <= seed <= 2**64 - 1):
        raise ValueError("seed must be in [0, 2^64), got %r" % (seed,))
    points = [(float(s), float(g)) for s in strengths for g in gaps]
    if not points:
        raise ValueError("strengths and gaps must not be empty")
    for s, g in points:
        sweep.check(s, g)
    signature = _sweep_signature(sweep, points, replicas, seed, clog_test)  # the schedule changes no record
    ck = Checkpoint(checkpoint, signature)
    done = {(r["point"], r["replica"]): r for r in ck.records}
    todo = [[j for j in range(replicas) if (p, j) not in done] for p in range(len(points))]
    pending = sum(len(t) for t in todo)
    bar = _progress_bar(pending, "replicas", progress and pending > 0)

    def finished(p, j, s, record):
        r = dict(record, point=p, replica=j, seed=s)
        done[(p, j)] = r
        ck.append(r)
        if bar is not None:
            bar.update(1)
        if callback is not None:
            callback(p, j, record)

    try:
        if pending:
            _core.run_sweep(sweep, points, todo, seed, schedule, finished)
    finally:
        ck.close()
        if bar is not None:
            bar.close()
    result = {"points": points, "records": [], "decay_length": [], "lower": [], "upper": [], "clogged": [],
              "censored": []}
    for p in range(len(points)):
        records = [done[(p, j)] for j in range(replicas)]
        result["records"].append(records)
        # as the driver: a replica's distance along g can be slightly negative at a clog right at the start
        e = decay_length([max(0.0, r["distance"]) for r in records], [bool(r["clogged"]) for r in records],
                         confidence)
        for k in ("decay_length", "lower", "upper", "clogged", "censored"):
            result[k].append(e[k])
    for k in ("decay_length", "lower", "upper"):
        result[k] = np.array(result[k])
    return result
