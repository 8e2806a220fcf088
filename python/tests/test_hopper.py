"""The soft-particle hopper scene from Python (mesoflow.hopper)."""
import numpy as np
import pytest

import mesoflow
from mesoflow import hopper


def test_bad_parameters_raise_value_errors_naming_parameter_and_range():
    with pytest.raises(ValueError, match=r"orifice w must be in \(0, W\)"):
        hopper.scene(orifice=25.0, hopper_width=20.0)
    with pytest.raises(ValueError, match="particles N must be >= 2"):
        hopper.scene(particles=1)
    with pytest.raises(ValueError, match="dimension must be 2 or 3"):
        hopper.scene(dimension=4)
    with pytest.raises(TypeError, match="unknown parameter orifce"):
        hopper.scene(orifce=6.0)


def test_a_wide_orifice_flows_and_recycles():
    h = hopper.scene(particles=200, orifice=6.0, hopper_width=20.0, friction=1.0, seed=3)
    assert h.relax()["converged"]
    q = h.flow_rate(steps=20000)
    assert h.crossings > 0 and q > 0
    assert 0 < h.insertions <= h.crossings  # those that left come back in (some may still wait)
    x = h.positions
    assert x.shape == (200, 2) and np.all(np.isfinite(x))
    assert sorted(np.array(h.ids)) == list(range(200))


def test_runs_are_bitwise_reproducible_and_positions_are_views():
    a = hopper.scene(particles=120, orifice=5.0, seed=7)
    b = hopper.scene(particles=120, orifice=5.0, seed=7)
    for s in (a, b):
        s.relax()
        s.advance(3000)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.velocities, b.velocities)
    if mesoflow.host_backend():
        x = a.positions
        assert not x.flags["OWNDATA"]
        before = x.copy()
        a.advance(10)
        assert not np.array_equal(x, before)


def test_the_three_dimensional_hopper_steps():
    h = hopper.scene(dimension=3, particles=100, hopper_width=8.0, orifice=4.0, seed=2)
    h.relax()
    h.advance(500)
    assert h.positions.shape == (100, 3) and np.all(np.isfinite(h.positions))
    assert h.time == pytest.approx(500 * h.dt)


def test_the_generic_run_calls_back_and_stops_when_told():
    h = hopper.scene(particles=100, orifice=5.0, seed=1)
    h.relax()
    seen = []
    done = mesoflow.run(h, 1000, every=100, callback=lambda s: seen.append(s.steps) or len(seen) < 3)
    assert done == 300 and seen == [100, 200, 300] and h.steps == 300
    assert mesoflow.run(h, 250, every=100) == 250 and h.steps == 550
    with pytest.raises(ValueError):
        mesoflow.run(h, 10, every=0)


def test_the_deformable_polygon_hopper_refuses_bad_values_naming_them():
    with pytest.raises(ValueError, match="vertices N_v must be >= 8"):
        hopper.dp_scene(vertices=4)
    with pytest.raises(ValueError, match=r"time step dt must be <= .* \(stability limit set by"):
        hopper.dp_scene(smooth=True, friction=31.6, dt=1e-3)  # smooth with friction, above its step limit
    with pytest.raises(ValueError, match=r"orifice w must be in \(0, W\)"):
        hopper.dp_scene(orifice=-1.0)
    with pytest.raises(TypeError, match="unknown parameter pair_energy"):
        hopper.dp_scene(pair_energy=100.0)  # an SP keyword
    assert hopper.dp_scene(particles=20, smooth=True, friction=1.0, dt=0).dt < 1e-3  # smooth with friction runs


def test_the_deformable_polygon_hopper_flows_with_vertices_as_views():
    d = hopper.dp_scene(particles=60, vertices=12, hopper_width=12.0, orifice=5.0, friction=1.0, seed=4)
    assert d.relax()["converged"]
    assert d.model == "dp" and d.vertices_per_polygon == 12
    x = d.positions
    assert x.shape == (60 * 12, 2)
    np.testing.assert_array_equal(np.array(d.bodies), np.repeat(np.arange(60), 12))
    types = np.array(d.types)
    np.testing.assert_array_equal(types, np.repeat(np.arange(60) % 2, 12))  # half small, half large
    q = d.flow_rate(steps=8000)
    assert d.crossings > 0 and q > 0
    st = d.body_state()
    assert st["centroid"].shape == (60, 2)
    # each centroid is the mean of its polygon's vertices (equal vertex masses)
    np.testing.assert_allclose(st["centroid"], np.array(d.positions).reshape(60, 12, 2).mean(axis=1), atol=1e-9)
    # the polygons keep their area within 1% (K_a = 10⁴); small (a0 = π/4 (1/1.2)²) and large
    a0 = np.pi / 4 * np.array([1 / 1.2, 1.4 / 1.2]) ** 2
    assert np.all(np.abs(st["area"] / a0[np.arange(60) % 2] - 1) < 0.01)
    if mesoflow.host_backend():
        assert not x.flags["OWNDATA"]


def test_deformable_polygon_runs_are_bitwise_reproducible():
    a, b = (hopper.dp_scene(particles=40, vertices=10, hopper_width=10.0, orifice=4.0, drag=0.3, seed=9)
            for _ in range(2))
    for s in (a, b):
        s.relax()
        s.advance(1500)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.velocities, b.velocities)


SWEEP = dict(particles=150, hopper_width=15.0, friction=3.16, seed=3)
SWEEP_FLOW = dict(steady_windows=2, measure_windows=4, max_time=40.0)
SWEEP_FLAGS = ["--particles", "150", "--hopper-width", "15", "--friction", "3.16", "--seed", "3", "--widths", "4,5",
               "--steady-windows", "2", "--measure-windows", "4", "--max-time", "40"]


def test_the_width_sweep_is_the_drivers_bit_for_bit_and_resumes(bin_dir, tmp_path):
    import json
    import os
    import subprocess
    out = tmp_path / "q.h5"
    subprocess.run([os.path.join(bin_dir, "hopper"), "--quiet", "--no-plot", "--threads", "1", *SWEEP_FLAGS,
                    "--output", str(out)], check=True)
    with open(tmp_path / "q.json") as f:
        driver = json.load(f)["results"]
    ck = str(tmp_path / "q.jsonl")
    seen = []
    r = hopper.sweep([4, 5], flow=SWEEP_FLOW, checkpoint=ck, callback=lambda k, w, rec: seen.append(k), **SWEEP)
    assert seen == [0, 1] and r["widths"] == [4.0, 5.0]
    for rec, d in zip(r["records"], driver):
        assert rec["Q"] == d["Q"] and rec["Q_error"] == d["Q_error"]  # bit for bit, one thread each
        assert rec["clogged"] == d["clogged"] and rec["steady"] == d["steady"]
        assert rec["steady_time"] == d["steady_time"] and rec["end_time"] == d["end_time"]
        assert len(rec["profile_h"]) == len(rec["profile_vg"]) == 96
    assert r["beverloo"] is None  # two widths: no fit (the driver's rule: at least 4)
    # killed after the first width: the resume runs only the second, to the same result
    with open(ck) as f:
        lines = f.read().split("\n")
    with open(ck, "w") as f:
        f.write("\n".join(lines[:2]) + "\n" + lines[2][:20])  # a torn last line
    seen.clear()
    again = hopper.sweep([4, 5], flow=SWEEP_FLOW, checkpoint=ck, callback=lambda k, w, rec: seen.append(k), **SWEEP)
    assert seen == [1] and again["Q"] == r["Q"] and again["Q_error"] == r["Q_error"]
    with pytest.raises(ValueError, match="holds another sweep"):
        hopper.sweep([4, 5], flow=dict(SWEEP_FLOW, max_time=50.0), checkpoint=ck, **SWEEP)


def test_the_width_sweep_refuses_bad_input():
    with pytest.raises(ValueError, match=r"widths: each in \(0, W = 15\)"):
        hopper.sweep([4, 16], **SWEEP)
    with pytest.raises(ValueError, match="measure windows must be >= 4"):
        hopper.sweep([4], flow=dict(measure_windows=2), **SWEEP)
    with pytest.raises(TypeError, match="unknown parameter windows"):
        hopper.sweep([4], flow=dict(windows=3), **SWEEP)
    with pytest.raises(ValueError, match="dp model is 2D only"):
        hopper.sweep([4], model="dp", dimension=3)


def test_the_polygon_width_sweep_is_the_drivers_bit_for_bit(bin_dir, tmp_path):
    import json
    import os
    import subprocess
    subprocess.run([os.path.join(bin_dir, "hopper"), "--quiet", "--no-plot", "--threads", "1", "--model", "dp",
                    "--particles", "20", "--vertices", "10", "--hopper-width", "10", "--friction", "3.16", "--seed", "5",
                    "--widths", "4", "--steady-windows", "2", "--measure-windows", "4", "--max-time", "20",
                    "--output", str(tmp_path / "dp.h5")], check=True)
    with open(tmp_path / "dp.json") as f:
        driver = json.load(f)["results"][0]
    r = hopper.sweep([4.0], model="dp", particles=20, vertices=10, hopper_width=10.0, friction=3.16, seed=5,
                     flow=dict(steady_windows=2, measure_windows=4, max_time=20.0))
    rec = r["records"][0]
    assert rec["Q"] == driver["Q"] and rec["Q_error"] == driver["Q_error"] and rec["end_time"] == driver["end_time"]
    assert not rec["clogged"] and rec["Q"] > 0
