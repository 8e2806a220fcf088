"""The module itself: Kokkos started once per process, parameters checked by the C++ scenes."""
import pytest

import mesoflow
from mesoflow import droplets


def test_kokkos_starts_once_with_one_thread_count():
    assert mesoflow.is_initialized()
    assert "Kokkos" in mesoflow.kokkos_configuration()
    mesoflow.initialize(threads=1)  # the same count again: nothing happens
    mesoflow.initialize()           # no count: nothing happens
    with pytest.raises(RuntimeError, match="already runs with 1 threads"):
        mesoflow.initialize(threads=2)


def test_bad_orifice_parameters_raise_value_errors_naming_parameter_and_range():
    with pytest.raises(ValueError, match=r"orifice width w must be in \(0, 10\], got -1"):
        droplets.orifice_scene(width=-1.0)
    with pytest.raises(ValueError, match=r"vertices N_v must be >= 3, got 2"):
        droplets.orifice_scene(vertices=2)
    with pytest.raises(ValueError, match=r"line tension .* must be finite and >= 0"):
        droplets.orifice_scene(line_tension=float("nan"))
    with pytest.raises(ValueError, match=r"perimeter ratio K_l/.* must be finite and >= 0"):
        droplets.orifice_scene(perimeter_ratio=-1)
    with pytest.raises(TypeError, match="unknown parameter widht"):
        droplets.orifice_scene(widht=0.4)
    with pytest.raises(TypeError):
        droplets.orifice_scene(width="wide")


def test_bad_sweep_parameters_raise_value_errors():
    with pytest.raises(ValueError, match="box-length"):
        droplets.clogging_sweep([1.0], [0.2], replicas=1, box_length=1.0)
    with pytest.raises(ValueError, match="replicas must be an integer >= 1"):
        droplets.clogging_sweep([1.0], [0.2], replicas=0)
    with pytest.raises(ValueError, match="clog_test must be one of"):
        droplets.clogging_sweep([1.0], [0.2], replicas=1, clog_test="sometimes")
    with pytest.raises(ValueError, match="--clog-window"):
        droplets.clogging_sweep([1.0], [0.2], replicas=1, clog_test="early", clog_window=-1.0)


def test_decay_length_is_the_censored_maximum_likelihood_estimate():
    # λ̂ = (total distance) / (number clogged): 3 clogged at 1, 2, 3 and one censored at 6 → 12/3
    e = droplets.decay_length([1.0, 2.0, 3.0, 6.0], [True, True, True, False])
    assert e["decay_length"] == pytest.approx(4.0, rel=1e-15)
    assert e["clogged"] == 3 and e["censored"] == 1
    assert e["lower"] < 4.0 < e["upper"]
    with pytest.raises(ValueError):
        droplets.decay_length([1.0, -1.0], [True, True])
    with pytest.raises(ValueError, match="same length"):
        droplets.decay_length([1.0], [True, False])
    r, p = droplets.survival_curve([1.0, 2.0, 3.0, 6.0], [True, True, True, False])
    assert list(r) == [0.0, 1.0, 2.0, 3.0]
    assert list(p) == pytest.approx([1.0, 0.75, 0.5, 0.25])


def test_after_finalize_every_scene_is_released_and_says_so():
    # in a process of its own: Kokkos starts once per process
    import subprocess
    import sys
    code = """
import mesoflow
from mesoflow import droplets, hopper
mesoflow.initialize(threads=1)
run = droplets.orifice(vertices=16, max_time=1.0)
h = hopper.scene(particles=20, orifice=5.0)
mesoflow.finalize()
for f in (lambda: run.positions, lambda: h.advance(1)):
    try:
        f()
    except RuntimeError as e:
        assert "released when Kokkos was finalised" in str(e), e
    else:
        raise SystemExit("no error after finalize")
try:
    droplets.orifice(vertices=16)
except RuntimeError as e:
    assert "finalised" in str(e)
else:
    raise SystemExit("a new scene after finalize")
print("ok")
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stdout + out.stderr
