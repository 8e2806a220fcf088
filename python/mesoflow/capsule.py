"""The SPH + mass-spring capsule (sph-microcapsules-constriction) in a periodic box, from Python.

    from mesoflow import capsule, analysis
    c = capsule.scene(sites=(20, 16, 16), radius=4.0, level=2, capsule_velocity=(0.05, 0, 0))
    c.advance(200)
    print(analysis.shear_plane_shape(c.outer_layer()))

Keywords are CapsuleSceneParameters' fields (sites, spacing, support, rho0, mu_outer, mu_inner, u_max,
body_force, radius, thickness, level, k_b, clearance, stretch, capsule_velocity, velocity_noise, seed,
dt, force_dt), checked by the C++ validate() (ValueError naming the value).

The `capsule` driver's runs, from Python: `shear(ca, **kw)` (simple shear, D_xy and θ/π),
`constriction(ca, eta, **kw)` (the passage through the constriction) and `sweep(cas, etas, mode=...)`
(resumable, with Pearson's r per η), kw the driver's options in snake_case (run_parameters).

    r = capsule.shear(0.05, resolution=8, t_max=10)
    print(r["D_xy"], r["theta_over_pi"])
"""
from . import _mesoflow
from ._checkpoint import run_indexed
from ._params import fill

_core = _mesoflow.capsule
CapsuleSceneParameters = _core.CapsuleSceneParameters
_KEYS = ("sites", "spacing", "support", "rho0", "mu_outer", "mu_inner", "u_max", "body_force", "radius", "thickness",
         "level", "k_b", "clearance", "stretch", "capsule_velocity", "velocity_noise", "seed", "dt", "force_dt")


def scene(**kw):
    p = fill("capsule scene", CapsuleSceneParameters(), kw, _KEYS, lambda k, v: tuple(v) if isinstance(v, list) else v)
    p.validate()
    return _core.CapsuleScene(p)


# --- the `capsule` driver's runs and sweeps (scenes/capsule/capsule_runs.hpp) ----------------------------
CapsuleRunParameters = _core.CapsuleRunParameters
_RUN_KEYS = ("resolution", "reynolds", "thickness", "level", "diagonals", "shear_modulus", "support", "walls",
             "viscosity_ratio", "c0", "membrane_strain", "density_variation", "t_max", "sample_every", "frame_every",
             "stall_window", "shear_box_x", "shear_box_y", "shear_box_z", "dt", "force_dt", "check_every",
             "deterministic")
# The columns whose Pearson r against Ca the driver reports per η (eq. 17, Table 1).
PEARSON_COLUMNS = ("inverse_passage_time", "Dx_at_4", "Dy_at_4", "Dz_at_4")


def run_parameters(**kw):
    """CapsuleRunParameters from the driver's options as keywords (snake_case: resolution, reynolds,
    thickness, level, diagonals, shear_modulus, support, walls, viscosity_ratio, c0, membrane_strain,
    density_variation, t_max, sample_every, frame_every, stall_window, shear_box_x/y/z, dt, force_dt,
    check_every, deterministic), defaults the driver's, checked by the C++ validate() (ValueError
    naming the parameter and its range)."""
    p = fill("capsule run", CapsuleRunParameters(), kw, _RUN_KEYS)
    p.validate()
    return p


def shear(ca, callback=None, **kw):
    """One simple-shear run at Ca, as `capsule --mode shear --ca CA` with the same options: a dict with
    the series (shear_time, taylor_deformation, inclination_over_pi, ...), the steady D_xy and θ/π over
    the last 30% of t_max (D_xy, D_xy_std, theta_over_pi, theta_over_pi_std), dt_gamma, particles,
    the scene's physical parameters and the driver's scene signature. callback(shear_time, D_xy,
    theta_over_pi) per sample; returning False stops the run ("stopped": True)."""
    return _core.run_shear(run_parameters(**kw), float(ca), callback)


def constriction(ca, eta, callback=None, **kw):
    """One run through the constriction at (Ca, η), as `capsule --ca CA --eta ETA`: a dict with the
    status (passed, blocked (stalled), blocked (t-max), or stopped), passage_time and its inverse,
    Dx/Dy/Dz_at_4 and the tip curvatures at x_c = 3.5, 4, 4.5 d, the series per sample (time in d/U,
    x_c in d, Dx, Dy, Dz, Cf, Cr, body_force, flux_ratio, density_deviation). callback(time, x_c) per
    sample; returning False stops the run."""
    return _core.run_constriction(run_parameters(**kw), float(ca), float(eta), callback)


def _jsonable(record):
    """A run's dict as the checkpoint stores it (arrays and tuples as lists), so that a reused run and a
    fresh one look the same."""
    def plain(v):
        if hasattr(v, "tolist"):
            return v.tolist()
        if isinstance(v, tuple):
            return list(v)
        if isinstance(v, dict):
            return {k: plain(x) for k, x in v.items()}
        return v
    return {k: plain(v) for k, v in record.items()}


def sweep(cas, etas=(0.5,), mode="constriction", checkpoint=None, progress=False, callback=None, **kw):
    """The driver's sweeps: mode "constriction" runs every (η, Ca) in the driver's order (η outer) and
    adds Pearson's r against Ca per η (eq. 17, Table 1); mode "shear" runs every Ca (etas unused).
    kw: run_parameters' keywords. checkpoint: a JSON-lines file (mesoflow._checkpoint) holding each
    finished run at once; a later call with the same file and parameters reuses them (another sweep
    raises ValueError). callback(k, record) as each run finishes. Returns {"runs": [...],
    "pearson_r": [{"eta": η, column: r, ...}, ...]} (pearson_r only in constriction mode)."""
    if mode not in ("constriction", "shear"):
        raise ValueError("mode must be constriction or shear, got %r" % (mode,))
    params = run_parameters(**kw)
    cas = [float(c) for c in cas]
    etas = [float(e) for e in etas]
    if not cas:
        raise ValueError("cas must not be empty")
    points = [(None, c) for c in cas] if mode == "shear" else [(e, c) for e in etas for c in cas]
    signature = {"mode": mode, "cas": cas, "etas": etas if mode == "constriction" else [],
                 "run": {k: getattr(params, k) for k in _RUN_KEYS}}

    def run_one(k):
        eta, ca = points[k]
        r = _core.run_shear(params, ca, None) if mode == "shear" else _core.run_constriction(params, ca, eta, None)
        return _jsonable(r)

    runs = run_indexed(len(points), run_one, checkpoint, signature, "runs", progress, callback)
    out = {"runs": runs}
    if mode == "constriction":
        table = []
        for eta in etas:
            at = [r for r in runs if r["eta"] == eta]
            row = {"eta": eta}
            for col in PEARSON_COLUMNS:
                row[col] = _core.pearson_r([r[col] for r in at], [r["ca"] for r in at])
            for name in ("Cf", "Cr"):
                for i, x in enumerate(("3.5", "4", "4.5")):
                    row["%s_at_%s" % (name, x)] = _core.pearson_r([r[name + "_at_3.5_4_4.5"][i] for r in at],
                                                                   [r["ca"] for r in at])
            table.append(row)
        out["pearson_r"] = table
    return out
