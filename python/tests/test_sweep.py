"""The clogging sweep from Python: the `obstacles` driver's replicas bit for bit, and a resume that
loses no finished replica."""
import json
import os
import subprocess

import h5py
import numpy as np
import pytest

from mesoflow import droplets

# Two points, three replicas each, small droplets in a small box, a short time limit.
SWEEP = dict(strengths=[0.5, 2.0], gaps=[0.3], replicas=3, seed=5, vertices=16, box_length=10.0,
             time_limit=15.0, relax_iterations=2000, batch=4)
DRIVER_FLAGS = ["--model", "dp", "--line-tension", "0.5,2", "--gap", "0.3", "--replicas", "3", "--seed", "5",
                "--vertices", "16", "--box-length", "10", "--time-limit", "15", "--relax-iterations", "2000",
                "--batch", "4", "--threads", "1", "--quiet"]


def test_replicas_are_the_obstacles_drivers_bit_for_bit(bin_dir, tmp_path):
    out = tmp_path / "sweep.h5"
    subprocess.run([os.path.join(bin_dir, "obstacles"), *DRIVER_FLAGS, "--output", str(out)], check=True)
    result = droplets.clogging_sweep(**SWEEP)
    records = [r for point in result["records"] for r in point]  # point-major, replica order: the driver's
    with h5py.File(out, "r") as f:
        rep = f["results/replicas"]
        assert list(rep["point"][()]) == [r["point"] for r in records]
        assert list(rep["replica"][()]) == [r["replica"] for r in records]
        assert list(rep["clogged"][()]) == [int(r["clogged"]) for r in records]
        for key in ("distance", "time", "steady_speed"):
            assert np.array_equal(rep[key][()], [r[key] for r in records]), key
        assert np.array_equal(rep["final_position"][()], [[r["final_x"], r["final_y"]] for r in records])
    assert all(np.isfinite(result["lower"]))


def test_an_interrupted_sweep_resumes_without_losing_a_finished_replica(tmp_path):
    ckpt = str(tmp_path / "sweep.jsonl")
    finished = []

    def interrupt(point, replica, record):
        finished.append((point, replica))
        if len(finished) == 2:
            raise KeyboardInterrupt  # as Ctrl-C would, between two replicas

    with pytest.raises(KeyboardInterrupt):
        droplets.clogging_sweep(**SWEEP, checkpoint=ckpt, callback=interrupt)
    with open(ckpt) as f:
        assert len([line for line in f.read().splitlines()[1:] if line]) == 2
    again = []
    resumed = droplets.clogging_sweep(**SWEEP, checkpoint=ckpt, callback=lambda p, j, r: again.append((p, j)))
    assert len(again) == 4 and not set(again) & set(finished), "only the unfinished replicas run again"
    fresh = droplets.clogging_sweep(**SWEEP)
    assert json.dumps(resumed["records"]) == json.dumps(fresh["records"])
    assert np.array_equal(resumed["decay_length"], fresh["decay_length"])
    # a third call finds everything done and runs nothing
    none = []
    droplets.clogging_sweep(**SWEEP, checkpoint=ckpt, callback=lambda p, j, r: none.append(j))
    assert none == []
    # other parameters are refused
    with pytest.raises(ValueError, match="differs in time_limit"):
        droplets.clogging_sweep(**dict(SWEEP, time_limit=20.0), checkpoint=ckpt)


def test_shape_following_steps_match_the_driver_and_are_checked(bin_dir, tmp_path):
    """shape_dt_target is the driver's --shape-dt: the same records bit for bit; out of range or
    with SP droplets it raises ValueError naming it."""
    out = tmp_path / "shape.h5"
    subprocess.run([os.path.join(bin_dir, "obstacles"), *DRIVER_FLAGS, "--shape-dt", "0.1", "--output", str(out)],
                   check=True)
    result = droplets.clogging_sweep(**SWEEP, shape_dt_target=0.1)
    records = [r for point in result["records"] for r in point]
    with h5py.File(out, "r") as f:
        rep = f["results/replicas"]
        for key in ("distance", "time", "steady_speed"):
            assert np.array_equal(rep[key][()], [r[key] for r in records]), key
    with pytest.raises(ValueError, match="shape time-step target"):
        droplets.clogging_sweep(**dict(SWEEP, shape_dt_target=2.0))
    with pytest.raises(ValueError, match="shape_dt_target"):
        droplets.clogging_sweep(**dict(SWEEP, soft_particles=True, shape_dt_target=0.5))
