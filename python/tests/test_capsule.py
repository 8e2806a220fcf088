"""The SPH + mass-spring capsule from Python (mesoflow.capsule), and the `capsule` driver's runs from Python."""
import csv
import json
import os
import subprocess

import numpy as np
import pytest

from mesoflow import analysis, capsule


def test_bad_parameters_raise_value_errors():
    with pytest.raises(ValueError, match=r"thickness h_t must be in \(0, a\)"):
        capsule.scene(radius=4.0, thickness=5.0)
    with pytest.raises(ValueError, match="must exceed the capsule's extent"):
        capsule.scene(sites=(10, 16, 16), radius=4.0)
    with pytest.raises(TypeError, match="unknown parameter radus"):
        capsule.scene(radus=4.0)


def test_a_moving_capsule_keeps_the_total_momentum_and_its_shape_starts_round():
    c = capsule.scene(sites=(16, 16, 16), radius=4.0, level=2, capsule_velocity=(0.02, 0.0, 0.0), seed=3)
    y = c.outer_layer()
    assert y.shape == (162, 3)  # level-2 icosphere
    assert analysis.shear_plane_shape(y)["taylor"] < 0.02
    p0 = np.array(c.total_momentum)
    assert p0[0] > 0
    c.advance(40)
    p1 = np.array(c.total_momentum)
    assert np.all(np.abs(p1 - p0) < 1e-10 * max(1.0, abs(p0[0]) * 1e3))  # periodic box, no body force
    assert c.max_density_deviation < 0.05
    assert np.all(np.isfinite(c.positions))


def test_runs_repeat_bit_for_bit():
    a = capsule.scene(level=1, velocity_noise=0.01, seed=9)
    b = capsule.scene(level=1, velocity_noise=0.01, seed=9)
    a.advance(20)
    b.advance(20)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.velocities, b.velocities)


# The driver's runs at a tiny size: Π = 6, a level-1 membrane, a short run.
SHEAR = dict(resolution=6, level=1, t_max=0.4, sample_every=0.1, shear_box_x=2, shear_box_y=2, shear_box_z=2)
CONSTRICTION = dict(resolution=6, level=1, t_max=0.3, sample_every=0.1, frame_every=0.1)


def _flags(kw):
    return [a for k, v in kw.items() for a in ("--" + k.replace("_", "-"), str(v))]


def test_run_parameters_are_checked_with_their_ranges():
    with pytest.raises(ValueError, match=r"resolution must be in \[6, 128\], got 4"):
        capsule.run_parameters(resolution=4)
    with pytest.raises(ValueError, match=r"t_max must be in \(0, 10000\], got nan"):
        capsule.run_parameters(t_max=float("nan"))
    with pytest.raises(ValueError, match="walls must be one of morris, prescribed, got 'slip'"):
        capsule.run_parameters(walls="slip")
    with pytest.raises(ValueError, match=r"eta must be in \(0, 2\]"):
        capsule.constriction(0.1, 3.0, **CONSTRICTION)
    with pytest.raises(TypeError, match="unknown parameter resolutoin"):
        capsule.shear(0.1, resolutoin=8)


def test_a_shear_run_is_the_drivers_bit_for_bit(bin_dir, tmp_path):
    out = tmp_path / "cap.h5"
    subprocess.run([os.path.join(bin_dir, "capsule"), "--quiet", "--threads", "1", "--mode", "shear", "--ca", "0.1",
                    *_flags(SHEAR), "--output", str(out)], check=True)
    with open(tmp_path / "cap_shear_ca0.1_series.csv") as f:
        rows = list(csv.DictReader(f))
    r = capsule.shear(0.1, **SHEAR)
    assert len(rows) == len(r["shear_time"]) == 5
    for key in ("shear_time", "taylor_deformation", "inclination_over_pi"):
        np.testing.assert_allclose(r[key], [float(x[key]) for x in rows], rtol=1e-7, atol=1e-12)  # CSV: 8 digits
    with open(tmp_path / "cap_shear_ca0.1_result.csv") as f:
        row = next(csv.DictReader(f))
    assert r["signature"] == row["signature"]
    assert abs(r["D_xy"] - float(row["taylor_deformation"])) <= 1e-7 * abs(r["D_xy"])
    assert r["D_xy"] > 0 and not r["stopped"]


def test_a_constriction_run_is_the_drivers_bit_for_bit_and_a_callback_stops_it(bin_dir, tmp_path):
    out = tmp_path / "cap.h5"
    subprocess.run([os.path.join(bin_dir, "capsule"), "--quiet", "--threads", "1", "--ca", "0.2", "--eta", "1",
                    *_flags(CONSTRICTION), "--output", str(out)], check=True)
    with open(tmp_path / "cap_ca0.2_eta1_series.csv") as f:
        rows = list(csv.DictReader(f))
    r = capsule.constriction(0.2, 1.0, **CONSTRICTION)
    assert r["status"] == "blocked (t-max)"  # 0.3 d/U: the capsule has not reached the constriction
    assert len(r["time"]) == len(rows) >= 3
    for key, col in (("time", "time"), ("x_c", "x_c"), ("Dx", "Dx"), ("Dy", "Dy"), ("body_force", "body_force")):
        np.testing.assert_allclose(r[key], [float(x[col]) for x in rows], rtol=1e-7, atol=1e-12)
    seen = []
    stopped = capsule.constriction(0.2, 1.0, callback=lambda t, x: seen.append(t) or len(seen) < 2, **CONSTRICTION)
    assert stopped["status"] == "stopped" and len(stopped["time"]) == 2
    np.testing.assert_array_equal(stopped["x_c"], r["x_c"][:2])


def test_a_constriction_sweep_resumes_from_its_checkpoint(tmp_path):
    ck = str(tmp_path / "sweep.jsonl")
    kw = dict(CONSTRICTION, t_max=0.1)
    first = capsule.sweep([0.1, 0.2], etas=[1.0], checkpoint=ck, **kw)
    assert [r["ca"] for r in first["runs"]] == [0.1, 0.2]
    assert first["pearson_r"][0]["eta"] == 1.0
    calls = []
    again = capsule.sweep([0.1, 0.2], etas=[1.0], checkpoint=ck, callback=lambda k, r: calls.append(k), **kw)
    assert calls == []
    assert json.dumps(again["runs"]) == json.dumps(first["runs"])  # NaN (not passed) compares as text
    with pytest.raises(ValueError, match="differs in run"):
        capsule.sweep([0.1, 0.2], etas=[1.0], checkpoint=ck, **dict(kw, t_max=0.2))
