"""The SPH + mass-spring capsule from Python (mesoflow.capsule)."""
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
