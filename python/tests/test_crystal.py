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
