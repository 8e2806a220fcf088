"""The crystal's MPC channel flow from Python (mesoflow.crystal)."""
import numpy as np
import pytest

import mesoflow
from mesoflow import crystal

SMALL = dict(length=20.0, width=10.0, density=5.0, disc_radius=2.0, seed=4)


def test_bad_parameters_raise_value_errors():
    with pytest.raises(ValueError, match="length must be finite and > 0"):
        crystal.channel(length=-1.0)
    with pytest.raises(ValueError, match="rule must be one of"):
        crystal.channel(rule="lbm")
    with pytest.raises(TypeError, match="unknown parameter lenght"):
        crystal.channel(lenght=3.0)
    # discs 0.01 apart at their surfaces: refused (they used to blow apart and crash the process)
    with pytest.raises(ValueError, match="closer than the .* the step limit assumes"):
        crystal.channel(length=60.0, width=15.0, density=5.0, disc_centres=[(5.0, 7.5), (15.01, 7.5)])


def test_a_periodic_solvent_without_forces_keeps_its_momentum():
    c = crystal.channel(walls=False, body_acceleration=0.0, **SMALL)
    p0 = np.array(c.total_momentum)
    c.advance(200)
    p1 = np.array(c.total_momentum)
    n = c.positions.shape[0]
    assert n == int(20 * 10 * 5)
    assert np.all(np.abs(p1 - p0) < 1e-9 * n)  # MPC-AT+a conserves momentum to round-off


def test_the_body_force_drives_the_solvent_and_the_discs_and_runs_repeat_bit_for_bit():
    runs = []
    for _ in range(2):
        c = crystal.channel(disc_centres=[(5.0, 5.0), (15.0, 5.0)], body_acceleration=0.05, **SMALL)
        c.advance(300)
        runs.append(c)
    a, b = runs
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.disc_positions, b.disc_positions)
    assert a.solvent_momentum[0] > 0 and np.all(a.disc_velocities[:, 0] > 0)  # pushed along +x
    if mesoflow.host_backend():
        assert not a.positions.flags["OWNDATA"]


RUN = dict(length=60.0, width=15.0, density=5.0, discs=3, warmup=0.5, time=2.0, frame_interval=0.5, seed=3)
RUN_FLAGS = ["--length", "60", "--width", "15", "--density", "5", "--discs", "3", "--warmup", "0.5", "--time", "2",
             "--frame-interval", "0.5", "--seed", "3"]


def test_one_call_run_is_the_drivers_bit_for_bit(bin_dir, tmp_path):
    """crystal.run() is the driver's run (issue 30): the same frames, K and phonon numbers, and its
    results file with the phonon files beside it."""
    import json
    import os
    import subprocess
    import h5py
    out = tmp_path / "drv.h5"
    subprocess.run([os.path.join(bin_dir, "crystal"), "--quiet", "--threads", "1", "--no-plot", *RUN_FLAGS,
                    "--output", str(out)], check=True)
    with open(tmp_path / "drv.json") as f:
        driver = json.load(f)
    frames = []
    r = crystal.run(str(tmp_path / "py.h5"), callback=lambda step, t: frames.append(step), **RUN)
    assert not r["stopped"] and r["discs"] == 3 and r["measured_frames"] == driver["measured_frames"]
    for key in ("u_d", "u_oil", "K", "reynolds", "peclet", "viscosity_b3", "theory_K", "spacing", "B", "beta",
                "phase_velocity", "frame_interval"):
        assert r[key] == driver[key], key
    assert r["x"].shape == (len(frames) + 1, 3) and np.all(np.diff(r["frame_time"]) > 0)  # + the first frame
    with h5py.File(out, "r") as a, h5py.File(tmp_path / "py.h5", "r") as b:
        assert np.array_equal(a["particles/discs/position/value"][()], b["particles/discs/position/value"][()])
    for suffix in ("_phonons.h5", "_theory.csv", ".xdmf", ".ckpt.h5"):
        assert (tmp_path / ("py" + suffix)).exists(), suffix


def test_a_run_refuses_bad_values_and_stops_on_request(tmp_path):
    with pytest.raises(ValueError, match="frame_interval must be in"):
        crystal.run(str(tmp_path / "a.h5"), **dict(RUN, frame_interval=0.0))
    with pytest.raises(ValueError, match="rule must be one of at\\+a, at-a, srd"):
        crystal.run(str(tmp_path / "a.h5"), **dict(RUN, rule="lbm"))
    with pytest.raises(ValueError, match="time step dt must be <="):
        crystal.run(str(tmp_path / "a.h5"), **dict(RUN, h=0.5))
    with pytest.raises(TypeError, match="unknown parameter tme"):
        crystal.run(str(tmp_path / "a.h5"), tme=3.0)
    r = crystal.run(str(tmp_path / "s.h5"), callback=lambda step, t: t < 1.0, **RUN)
    assert r["stopped"] and "K" not in r and r["frame_time"][-1] == pytest.approx(1.0)


def test_a_stopped_run_resumes_bit_for_bit(tmp_path):
    """A run stopped by its callback continues with restart=True to the uninterrupted run's frames, K
    and phonon numbers bit for bit (issue 30); a restart refuses another scene and a missing checkpoint."""
    import h5py
    full = crystal.run(str(tmp_path / "full.h5"), **RUN)
    part = crystal.run(str(tmp_path / "part.h5"), callback=lambda step, t: t < 1.0, **RUN)
    assert part["stopped"] and part["frame_time"][-1] == pytest.approx(1.0)
    with pytest.raises(ValueError, match="restart: .*part.ckpt.h5 was written by another scene"):
        crystal.run(str(tmp_path / "part.h5"), restart=True, **dict(RUN, seed=4))
    with pytest.raises(ValueError, match="restart=True needs the checkpoint .*none.ckpt.h5"):
        crystal.run(str(tmp_path / "none.h5"), restart=True, **RUN)
    rest = crystal.run(str(tmp_path / "part.h5"), restart=True, **RUN)
    assert not rest["stopped"] and rest["resumed_from_step"] == part["steps"] > 0
    assert full["resumed_from_step"] == 0 and rest["steps"] == full["steps"]
    for key in ("measured_frames", "u_d", "u_oil", "K", "theory_K", "spacing", "B", "beta", "phase_velocity"):
        assert rest[key] == full[key], key
    for key in ("frame_time", "u_d_series", "x", "y"):
        assert np.array_equal(rest[key], full[key]), key
    with h5py.File(tmp_path / "full.h5", "r") as a, h5py.File(tmp_path / "part.h5", "r") as b:
        for name in ("particles/discs/position/value", "particles/discs/velocity/value", "observables/u_d/value"):
            assert np.array_equal(a[name][()], b[name][()]), name
