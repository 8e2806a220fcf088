"""GSD output (mesoflow.gsd_output): read back with the gsd module, as OVITO would read it."""
import gsd.hoomd
import numpy as np
import pytest

from mesoflow import droplets
from mesoflow.gsd_output import OrificeGsd, obstacle_array_gsd, polygon_centroid


def test_orifice_frames_hold_the_droplet_polygon_and_the_wedges(tmp_path):
    path = str(tmp_path / "orifice.gsd")
    run = droplets.orifice(vertices=32, start_h=-1.3, max_time=1.0, sample_interval=0.1)
    with OrificeGsd(path, run, every=5) as out:
        run.run(callback=out)
    last = np.array(run.positions)
    f = gsd.hoomd.open(path, "rb")
    assert len(f) == 4  # the first sample, samples 5 and 10, and the last (11, the time limit)
    frame = f[-1]
    assert frame.configuration.dimensions == 2
    assert list(frame.particles.types) == ["droplet", "wedge_left", "wedge_right"]
    shapes = frame.particles.type_shapes
    assert shapes[0]["type"] == "Polygon" and len(shapes[0]["vertices"]) == 32
    assert shapes[1]["type"] == "Polygon" and len(shapes[1]["vertices"]) == 3
    centre = frame.particles.position[0, :2].astype(float)
    np.testing.assert_allclose(centre, polygon_centroid(last), atol=1e-6)  # float32 positions
    np.testing.assert_allclose(np.array(shapes[0]["vertices"]) + polygon_centroid(last), last, atol=1e-12)
    assert frame.log["time"][0] == pytest.approx(run.time)
    # the droplet moved between the first and the last frame, the wedges did not
    assert f[0].particles.position[0, 1] > frame.particles.position[0, 1]
    np.testing.assert_array_equal(f[0].particles.position[1:], frame.particles.position[1:])
    tip = np.array(shapes[2]["vertices"][0]) + frame.particles.position[2, :2]
    np.testing.assert_allclose(tip, [0.2, 0.0], atol=1e-6)  # the right wedge's tip at (w/2, 0)


def test_an_obstacle_array_is_disks_of_the_obstacle_diameter(tmp_path):
    kw = dict(box_length=10.0, obstacle_fraction=0.05)
    centres = droplets.obstacle_centres(1.0, 0.2, seed=3, replica=2, **kw)
    assert centres.shape[1] == 2 and len(centres) > 10
    np.testing.assert_array_equal(centres, droplets.obstacle_centres(1.0, 0.2, seed=3, replica=2, **kw))
    assert not np.array_equal(centres, droplets.obstacle_centres(1.0, 0.2, seed=3, replica=1, **kw))
    path = str(tmp_path / "array.gsd")
    square = np.array([[4.5, 4.5], [5.5, 4.5], [5.5, 5.5], [4.5, 5.5]])
    obstacle_array_gsd(path, centres, 0.3, 10.0, droplets=[square])
    frame = gsd.hoomd.open(path, "rb")[0]
    assert frame.particles.N == len(centres) + 1
    assert frame.particles.type_shapes[0] == {"type": "Disk", "diameter": 0.3}
    assert np.all(np.abs(frame.particles.position[:, :2]) <= 5.0)
    np.testing.assert_allclose(frame.particles.position[-1, :2], [0.0, 0.0], atol=1e-6)  # (5, 5) − L/2


def test_hopper_frames_hold_every_particle_with_its_diameter(tmp_path):
    import mesoflow
    from mesoflow import hopper
    from mesoflow.gsd_output import HOPPER_DIAMETERS, HopperGsd
    path = str(tmp_path / "sp.gsd")
    h = hopper.scene(particles=80, orifice=5.0, seed=2)
    h.relax()
    with HopperGsd(path, h) as out:
        mesoflow.run(h, 600, every=200, callback=out)
    f = gsd.hoomd.open(path, "rb")
    assert len(f) == 4  # the start and three calls
    frame = f[-1]
    assert frame.configuration.step == 600 and frame.configuration.dimensions == 2
    assert list(frame.particles.types) == ["small", "large"]
    np.testing.assert_allclose(frame.particles.position[:, :2], np.array(h.positions), atol=1e-5)
    types = np.array(h.types)
    np.testing.assert_array_equal(frame.particles.typeid, types)
    np.testing.assert_allclose(frame.particles.diameter, np.array(HOPPER_DIAMETERS)[types], rtol=1e-6)
    assert [s["type"] for s in frame.particles.type_shapes] == ["Disk", "Disk"]
    box = frame.configuration.box
    assert np.all(np.abs(frame.particles.position[:, 0]) <= box[0] / 2)
    assert np.all(np.abs(frame.particles.position[:, 1]) <= box[1] / 2)
    assert frame.log["time"][0] == pytest.approx(h.time)


def test_deformable_polygon_hopper_frames_are_vertex_disks_with_their_polygon(tmp_path):
    from mesoflow import hopper
    from mesoflow.gsd_output import HopperGsd
    path = str(tmp_path / "dp.gsd")
    d = hopper.dp_scene(particles=20, vertices=10, hopper_width=10.0, orifice=4.0, seed=5)
    d.relax()
    with HopperGsd(path, d) as out:
        d.advance(300)
    f = gsd.hoomd.open(path, "rb")
    assert len(f) == 2  # the start and, at close, the last state
    frame = f[-1]
    assert frame.particles.N == 200
    np.testing.assert_array_equal(frame.particles.body, np.repeat(np.arange(20), 10))
    delta = d.vertex_diameters
    np.testing.assert_allclose([s["diameter"] for s in frame.particles.type_shapes], delta, rtol=1e-6)
    np.testing.assert_allclose(frame.particles.position[:, :2], np.array(d.positions), atol=1e-5)
