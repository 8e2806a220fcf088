"""The pillar-array flow from Python (mesoflow.pillars): the `pillars` driver's samples bit for bit."""
import os
import subprocess

import h5py
import numpy as np
import pytest

from mesoflow import pillars

SCENE = dict(layout="square", porosity=0.8, cells_x=3, cells_y=1)
FLAGS = ["--dimension", "2", "--layout", "square", "--porosity", "0.8", "--cells-x", "3", "--cells-y", "1",
         "--equilibrate-steps", "100", "--warmup-steps", "200", "--steps", "1000", "--sample-every", "10"]


def test_bad_parameters_raise_value_errors():
    with pytest.raises(ValueError):
        pillars.flow(layout="pentagonal")
    with pytest.raises(ValueError, match="dimension must be 2 or 3"):
        pillars.flow(dimension=1)
    with pytest.raises(TypeError, match="unknown parameter porosty"):
        pillars.flow(porosty=0.5)


def test_the_samples_are_the_pillars_drivers_bit_for_bit(bin_dir, tmp_path):
    out = tmp_path / "p.h5"
    subprocess.run([os.path.join(bin_dir, "pillars"), "--quiet", "--threads", "1", *FLAGS, "--output", str(out)],
                   check=True)
    f = pillars.flow(**SCENE)
    f.equilibrate(100)
    samples = []
    f.run(warmup=200, steps=1000, sample_every=10, on_sample=samples.append)
    assert len(samples) == 100 and f.record["samples"] == 100
    assert f.solid_particles > 0 and 0.75 < f.porosity < 0.85
    with h5py.File(out, "r") as h5:
        for key in ("mean_velocity_x", "pillar_force_x"):
            assert np.array_equal(h5["observables/%s/value" % key][()], [s[key] for s in samples]), key
    assert np.mean([s["mean_velocity_x"] for s in samples[50:]]) > 0  # driven along +x
    types = np.array(f.types)
    assert set(np.unique(types)) == {0, 1, 2} and f.positions.shape == (len(types), 2)  # fluid, solid, core
    assert np.count_nonzero(types) == f.solid_particles


def test_the_permeability_estimates_are_the_drivers_bit_for_bit(bin_dir, tmp_path):
    import json
    out = tmp_path / "k.h5"
    subprocess.run([os.path.join(bin_dir, "pillars"), "--quiet", "--threads", "1", *FLAGS, "--output", str(out)],
                   check=True)
    with open(tmp_path / "k.json") as f:
        driver = json.load(f)
    f = pillars.flow(**SCENE)
    with pytest.raises(ValueError, match="no samples yet"):
        f.permeability()
    f.equilibrate(100)
    f.run(warmup=200, steps=1000, sample_every=10)
    e = f.permeability()
    for key in ("kappa_darcy", "kappa_drag_tether", "kappa_drag_pair", "kappa_darcy_box", "superficial_velocity",
                "mean_ux_block_error", "pressure_difference", "viscosity_used"):
        assert e[key] == driver[key], key
    assert e["viscosity_used"] == 26.1 and e["kappa_darcy"] > 0
    assert f.permeability(viscosity=13.05)["kappa_darcy"] == pytest.approx(e["kappa_darcy"] / 2, rel=1e-12)
    with pytest.raises(ValueError, match="viscosity must be finite and >= 0"):
        f.permeability(viscosity=-1.0)


WALLS = dict(layout="square", porosity=0.6, cells_x=2, cells_y=1, height=5.0, fb=2.0)
WALLS_FLAGS = ["--dimension", "3", "--layout", "square", "--porosity", "0.6", "--cells-x", "2", "--cells-y", "1",
               "--height", "5", "--fb", "2", "--equilibrate-steps", "50", "--warmup-steps", "50", "--steps", "200",
               "--sample-every", "2", "--kappa-p", "0.4"]


def test_one_call_run_between_walls_is_the_drivers_bit_for_bit(bin_dir, tmp_path):
    """pillars.run() is the driver's run: the box Darcy estimate with its block error, and the
    Brinkman fit with its jackknife error and μ_eff/μ (issue 28 items 3-4, issue 30)."""
    import json
    out = tmp_path / "w.h5"
    subprocess.run([os.path.join(bin_dir, "pillars"), "--quiet", "--threads", "1", *WALLS_FLAGS, "--output", str(out)],
                   check=True)
    with open(tmp_path / "w.json") as f:
        driver = json.load(f)
    r = pillars.run(dimension=3, equilibrate=50, warmup=50, steps=200, sample_every=2, kappa_p=0.4, **WALLS)
    assert r["samples"] == 100 and r["particles"] == driver["particles"] and r["height"] == 5.0
    for key in ("kappa_darcy_box", "kappa_darcy_box_relative_error", "kappa_drag_tether", "pressure_difference"):
        assert r[key] == driver[key], key
    b, db = r["brinkman"], driver["brinkman"]
    assert b["jackknife_blocks"] == 10 and not b["alpha_at_bound"] and b["alpha_error"] > 0 and b["B_error"] > 0
    for key in ("alpha", "B", "alpha_error", "B_error", "mu_eff_over_mu", "mu_eff_over_mu_error_alpha",
                "kappa_eff_eq7", "B_theory"):
        assert b[key] == db[key], key
    assert b["mu_eff_over_mu_error_alpha"] == pytest.approx(2 * b["mu_eff_over_mu"] * b["alpha_error"] / b["alpha"])
    with pytest.raises(ValueError, match="kappa_p must be finite and >= 0"):
        pillars.run(dimension=3, equilibrate=0, warmup=0, steps=10, kappa_p=-1.0, **WALLS)
    with pytest.raises(ValueError, match="steps must be an integer >= 0"):
        pillars.run(steps=-5, **SCENE)


def test_a_sweep_resumes_from_its_checkpoint(tmp_path):
    ck = str(tmp_path / "s.jsonl")
    common = dict(equilibrate=20, warmup=20, steps=100, sample_every=10, layout="square", cells_x=3, cells_y=1)
    points = [dict(porosity=0.8), dict(porosity=0.85)]
    first = pillars.sweep(points, checkpoint=ck, **common)
    assert [r["point"]["porosity"] for r in first] == [0.8, 0.85]
    assert first[0]["porosity"] < first[1]["porosity"] and all(r["samples"] == 10 for r in first)
    calls = []
    again = pillars.sweep(points, checkpoint=ck, callback=lambda k, r: calls.append(k), **common)
    assert calls == [] and again == first  # every run reused, nothing rerun
    with pytest.raises(ValueError, match="holds another sweep"):
        pillars.sweep(points, checkpoint=ck, **dict(common, steps=200))
    with pytest.raises(TypeError, match="unknown parameter porosty"):
        pillars.sweep([dict(porosty=0.8)], **common)
