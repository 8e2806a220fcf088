"""The orifice passage from Python: the same loop as the `orifice` driver (OrificeRun), zero-copy
arrays, callbacks that stop a run."""
import os
import subprocess

import h5py
import numpy as np
import pytest

import mesoflow
from mesoflow import droplets

# A small passage that reaches the funnel: 32 vertices, 1.3σ above the orifice, 12 t0.
SMALL = dict(vertices=32, start_h=-1.3, max_time=12.0, sample_interval=0.1, width=0.4, line_tension=0.16)
DRIVER_FLAGS = ["--vertices", "32", "--start-h", "-1.3", "--max-time", "12", "--sample-interval", "0.1",
                "--width", "0.4", "--gamma", "0.16", "--threads", "1", "--no-plot", "--quiet"]


def test_a_run_is_the_orifice_drivers_run_bit_for_bit(bin_dir, tmp_path):
    out = tmp_path / "orifice.h5"
    subprocess.run([os.path.join(bin_dir, "orifice"), *DRIVER_FLAGS, "--output", str(out)], check=True)
    profile = droplets.orifice(**SMALL).run()
    with h5py.File(out, "r") as f:
        for name, key in (("h", "h"), ("vg", "vg"), ("shape_parameter", "shape_parameter"),
                          ("area_over_a0", "area_over_a0"), ("kinetic_over_terminal", "kinetic_over_terminal")):
            driver = f["observables/%s/value" % name][()]
            assert driver.shape == profile[key].shape, name
            assert np.array_equal(driver, profile[key]), "%s differs from the driver's" % name
        assert np.array_equal(f["observables/h/time"][()], profile["t"])
        assert f["parameters"].attrs["outcome"] in (profile["outcome"], profile["outcome"].encode())
    assert profile["steps"] > 0 and len(profile["t"]) > 10


def test_positions_are_views_of_the_scenes_memory():
    if not mesoflow.host_backend():
        pytest.skip("device backend: arrays are copies by design (docs/python.md)")
    run = droplets.orifice(**SMALL)
    x = run.positions
    assert x.shape == (32, 2) and x.dtype == np.float64
    assert not x.flags["OWNDATA"]
    before = x.copy()
    assert run.advance()
    assert not np.array_equal(x, before), "the view must see the step"
    assert np.array_equal(x, run.positions)
    assert x.__array_interface__["data"][0] == run.positions.__array_interface__["data"][0]
    # writing through the view moves the droplet in the scene
    com_y = run.positions[:, 1].mean()
    x[:, 1] += 0.25
    assert run.positions[:, 1].mean() == pytest.approx(com_y + 0.25, rel=1e-12)
    v = run.velocities
    assert v.shape == (32, 2) and np.all(np.isfinite(v))


def test_a_callback_returning_false_stops_the_run():
    run = droplets.orifice(**SMALL)
    seen = []

    def callback(r):
        seen.append(r.time)
        return len(seen) < 3

    profile = run.run(callback=callback)
    assert profile["outcome"] == "stopped"
    assert len(seen) == 3
    assert len(profile["t"]) == 4  # the first sample and three more
    assert not run.advance()
    assert run.done


def test_a_run_to_its_end_passes_and_keeps_its_area():
    profile = droplets.orifice(vertices=32, start_h=-1.3, max_time=400.0, sample_interval=0.5).run()
    assert profile["outcome"] == "passed"
    assert profile["h"][-1] >= 1.0
    assert profile["max_area_error"] < 0.05
