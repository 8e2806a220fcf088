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


def test_crystal_frames_hold_the_solvent_and_the_discs_in_a_centred_box(tmp_path):
    import mesoflow
    from mesoflow import crystal
    from mesoflow.gsd_output import CrystalGsd
    path = str(tmp_path / "crystal.gsd")
    c = crystal.channel(length=20.0, width=10.0, density=5.0, disc_radius=2.0, seed=4,
                        disc_centres=[(5.0, 5.0), (15.0, 5.0)], body_acceleration=0.05)
    with CrystalGsd(path, c, every=2) as out:
        mesoflow.run(c, 300, every=50, callback=out)  # 6 calls: frames at 2, 4, 6
    f = gsd.hoomd.open(path, "rb")
    assert len(f) == 4 and f[-1].configuration.step == 300
    frame = f[-1]
    n = c.positions.shape[0]
    assert frame.particles.N == n + 2 and list(frame.particles.types) == ["solvent", "disc"]
    np.testing.assert_array_equal(frame.particles.typeid[n:], [1, 1])
    assert frame.particles.type_shapes[1] == {"type": "Disk", "diameter": 4.0}
    box = frame.configuration.box
    assert box[0] == 20.0 and box[1] == 10.0
    # positions shifted by (−L/2, −W/2) and inside the box
    np.testing.assert_allclose(frame.particles.position[n:, :2], np.array(c.disc_positions) - [10.0, 5.0],
                               atol=1e-5)
    assert np.all(np.abs(frame.particles.position[:, 0]) <= 10.0)
    assert np.all(np.abs(frame.particles.position[:, 1]) <= 5.0)
    np.testing.assert_allclose(np.sort(frame.particles.position[:n, 0]),
                               np.sort(np.array(c.positions)[:, 0] % 20.0 - 10.0), atol=1e-5)


def test_capsule_frames_keep_particle_ids_through_sorts_and_hold_the_springs(tmp_path):
    from mesoflow import capsule
    from mesoflow.gsd_output import CapsuleGsd
    c = capsule.scene(sites=(16, 16, 16), radius=4.0, level=1, capsule_velocity=(0.02, 0.0, 0.0), seed=3)
    slot0 = np.array(c.particle_slot)
    first = np.array(c.positions)[slot0]
    path = str(tmp_path / "capsule.gsd")
    with CapsuleGsd(path, c) as out:
        c.advance(120)
    f = gsd.hoomd.open(path, "rb")
    assert len(f) == 2
    frame = f[-1]
    n = c.positions.shape[0]
    nf, nw, nm = c.num_fluid, c.num_walls, c.num_membrane
    assert frame.particles.N == n == nf + nw + nm
    assert list(frame.particles.types) == ["outer_fluid", "inner_fluid", "wall", "membrane"]
    assert np.count_nonzero(frame.particles.typeid == 3) == nm
    assert np.count_nonzero(frame.particles.typeid == 1) == nf - c.num_outer_fluid > 0
    # ids fixed: a membrane particle moved by less than a spacing between the frames (the scene may
    # have sorted its memory in between; then the stored order differs from the ids)
    lo, length, _ = c.box
    shift = np.array(lo) + np.array(length) / 2
    now = np.array(c.positions)[np.array(c.particle_slot)]
    disp = now[nf + nw:] - first[nf + nw:]
    assert np.all(np.linalg.norm(disp, axis=1) < 0.5)
    got = frame.particles.position[nf + nw:].astype(float) + shift
    L = np.array(length)
    np.testing.assert_allclose(np.mod(got - now[nf + nw:] + L / 2, L) - L / 2, 0.0, atol=1e-4)
    # the springs: every bond joins two membrane particles and is a spring of the mesh
    bonds = frame.bonds.group
    assert frame.bonds.N == len(c.membrane_bonds) > nm and list(frame.bonds.types) == ["spring"]
    assert bonds.min() >= nf + nw and bonds.max() < n
    ends = np.array(c.positions)[np.array(c.particle_slot)][bonds]
    assert np.max(np.linalg.norm(ends[:, 0] - ends[:, 1], axis=1)) < 4.0  # shorter than the radius
    tri = np.array(c.membrane_triangles)
    assert tri.shape == (80, 3) and tri.min() >= nf + nw  # level-1 icosphere, outer layer
    # without the fluid: walls and membrane, bonds renumbered
    path2 = str(tmp_path / "shell.gsd")
    CapsuleGsd(path2, c, fluid=False).close()
    shell = gsd.hoomd.open(path2, "rb")[0]
    assert shell.particles.N == nw + nm and shell.bonds.group.min() >= nw


def test_pillar_frames_hold_fluid_and_solid_with_their_types(tmp_path):
    from mesoflow import pillars
    from mesoflow.gsd_output import PillarsGsd
    f = pillars.flow(layout="square", porosity=0.8, cells_x=3, cells_y=1)
    f.equilibrate(100)
    path = str(tmp_path / "pillars.gsd")
    with PillarsGsd(path, f, every=5) as out:
        f.run(warmup=0, steps=200, sample_every=10, on_sample=out)  # 20 samples: frames at 5, 10, 15, 20
    g = gsd.hoomd.open(path, "rb")
    assert len(g) == 5
    frame = g[-1]
    assert frame.configuration.step == f.steps and frame.configuration.dimensions == 2
    np.testing.assert_array_equal(frame.particles.typeid, np.array(f.types))
    assert list(frame.particles.types) == ["fluid", "solid_surface", "solid_core"]
    Lx, Ly, Lz = f.box
    assert Lz == 0.0
    np.testing.assert_allclose(frame.configuration.box[:2], [Lx, Ly], rtol=1e-6)
    np.testing.assert_allclose(frame.particles.position[:, 0] + Lx / 2, np.array(f.positions)[:, 0] % Lx, atol=1e-4)

    # the same particles in every frame: as many of each kind (the solid ones tethered, not fixed)
    np.testing.assert_array_equal(np.bincount(g[0].particles.typeid, minlength=3),
                                  np.bincount(frame.particles.typeid, minlength=3))
    assert np.count_nonzero(frame.particles.typeid) == f.solid_particles
