"""GSD trajectories of droplet and hopper scenes with their shapes (issue 30; docs/python.md), for OVITO.

GSD (Debian's python3-gsd, HOOMD-blue's format) stores per frame the particles and, per particle
type, a shape (`particles/type_shapes`, JSON). Here every droplet is one particle at its polygon's
centroid whose type carries the current polygon (a "Polygon" shape: the vertices relative to the
centroid, rounded by half the vertex diameter), and every wall or obstacle is a particle with its
own shape ("Polygon" for the orifice's wedges, "Disk" for obstacles). OVITO then draws the
droplets and obstacles as they are. The droplet's shape changes every frame, so its type is
written into every frame (GSD keeps per-frame type_shapes).

    from mesoflow import droplets
    from mesoflow.gsd_output import OrificeGsd
    run = droplets.orifice(vertices=64)
    with OrificeGsd("orifice.gsd", run, every=20) as gsd:
        run.run(callback=gsd)

Hopper scenes (`HopperGsd`): every soft particle a 'Disk' (2D) or 'Sphere' (3D) of its diameter;
for the deformable-polygon hopper every vertex a 'Disk' of the vertex diameter δ — the rough DP
model's contact shape itself — with `particles/body` its polygon.

    h = hopper.dp_scene(particles=100); h.relax()
    with HopperGsd("hopper.gsd", h) as gsd:
        mesoflow.run(h, 20000, every=500, callback=gsd)

The other studies' scenes (`CrystalGsd`, `CapsuleGsd`, `PillarsGsd`) write every particle with its
kind as the type, drawn at the spacing of the fluid ((volume/N)^(1/d), the lattice spacing Δx of
the SPH fluid), the crystal's discs as 'Disk's of 2R, and the capsule's springs as GSD bonds, so
OVITO shows the membrane as its mesh. Positions are shifted into GSD's box centred on the origin.

    c = crystal.channel(disc_centres=[(5, 7.5)])
    with CrystalGsd("crystal.gsd", c) as gsd:
        mesoflow.run(c, 2000, every=100, callback=gsd)
    f = pillars.flow(porosity=0.8); f.equilibrate(500)
    with PillarsGsd("pillars.gsd", f, every=10) as gsd:
        f.run(warmup=0, steps=2000, sample_every=10, on_sample=gsd)
"""
import numpy as np

try:
    import gsd.hoomd
except ImportError as error:  # pragma: no cover - python3-gsd is a bootstrap package
    raise ImportError("mesoflow.gsd_output needs the gsd module (Debian: python3-gsd)") from error


def _snapshot():
    # gsd 2.x calls a frame Snapshot, gsd 3 Frame
    return gsd.hoomd.Frame() if hasattr(gsd.hoomd, "Frame") else gsd.hoomd.Snapshot()


def _open_for_writing(path):
    # gsd 2.x writes with mode "wb", gsd 3 with "w"
    return gsd.hoomd.open(path, "w") if hasattr(gsd.hoomd, "Frame") else gsd.hoomd.open(path, "wb")


def polygon_centroid(vertices):
    """Area centroid of a simple polygon (N, 2)."""
    x, y = vertices[:, 0], vertices[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2
    return np.array([((x + xn) * cross).sum() / (6 * area), ((y + yn) * cross).sum() / (6 * area)])


def orifice_wedges(width, size=3.0):
    """The two 45-degree wedges of the orifice scene (scenes/droplets/orifice_run.hpp): their tips at
    (±w/2, 0), faces rising at 45 degrees; drawn as triangles `size` σ tall (centroid, vertices)."""
    shapes = []
    for side in (-1, 1):
        tip = np.array([side * width / 2, 0.0])
        corner_up = tip + np.array([side * size, size])
        corner_out = tip + np.array([side * size, 0.0])
        tri = np.array([tip, corner_up, corner_out])
        c = tri.mean(axis=0)
        shapes.append((c, tri - c))
    return shapes


class _GsdWriter:
    """close() appends the last state if _stale() says it is not written yet, then closes the file;
    a context manager closes it on exit."""

    def close(self):
        if self.file is not None:
            if self._stale():
                self._append()
            self.file.close()
            self.file = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


class OrificeGsd(_GsdWriter):
    """A callback for Orifice.run() that appends a GSD frame every `every` samples (and at the first
    and last one): particle 0 the droplet (type 'droplet', its polygon), particles 1 and 2 the wedges
    (type 'wedge_left', 'wedge_right'). Positions are 3D with z = 0, the box 2D."""

    def __init__(self, path, run, every=20):
        if not isinstance(every, int) or every < 1:
            raise ValueError("every must be an integer >= 1, got %r" % (every,))
        self.run, self.every = run, every
        self.file = _open_for_writing(path)
        self.wedges = orifice_wedges(run.scene.width)
        n_v = run.scene.droplet.vertices
        edge = np.pi / n_v  # l0 ≈ the circumference πσ over N_v
        self.rounding = 0.5 * run.scene.droplet.vertex_diameter * edge
        self.frames = 0
        self._append()

    def _append(self):
        x = np.array(self.run.positions)  # a copy: the view changes with the next step
        c = polygon_centroid(x)
        s = _snapshot()
        s.configuration.step = int(self.run.steps)
        s.configuration.dimensions = 2
        s.configuration.box = [20.0, 20.0, 0.0, 0.0, 0.0, 0.0]
        s.particles.N = 3
        s.particles.types = ["droplet", "wedge_left", "wedge_right"]
        s.particles.typeid = np.array([0, 1, 2], dtype=np.uint32)
        pos = [c] + [w[0] for w in self.wedges]
        s.particles.position = np.array([[p[0], p[1], 0.0] for p in pos], dtype=np.float32)
        shapes = [{"type": "Polygon", "rounding_radius": float(self.rounding), "vertices": (x - c).tolist()}]
        shapes += [{"type": "Polygon", "rounding_radius": 0.0, "vertices": w[1].tolist()} for w in self.wedges]
        s.particles.type_shapes = shapes
        s.log["time"] = np.array([self.run.time])
        s.log["h"] = np.array([-c[1]])
        self.file.append(s)
        self.frames += 1
        self._last_sample = self.run.samples

    def __call__(self, run):
        if run.samples % self.every == 0 or run.done:
            self._append()
        return True

    def _stale(self):
        return self.run.samples != self._last_sample


def obstacle_array_gsd(path, centres, obstacle_diameter, box_length, droplets=()):
    """One GSD frame of an obstacle array: each obstacle a 'Disk' of diameter σ_ob, each droplet
    (an (N, 2) vertex array) one 'Polygon' particle. The sweep's box is [0, L)²; GSD boxes are
    centred on the origin, so positions are folded into [0, L) and shifted by −L/2."""
    centres = np.asarray(centres, dtype=float).reshape(-1, 2)
    s = _snapshot()
    s.configuration.dimensions = 2
    s.configuration.box = [box_length, box_length, 0.0, 0.0, 0.0, 0.0]
    n_d = len(droplets)
    s.particles.N = len(centres) + n_d
    s.particles.types = ["obstacle"] + ["droplet%d" % k for k in range(n_d)]
    s.particles.typeid = np.array([0] * len(centres) + list(range(1, n_d + 1)), dtype=np.uint32)
    pos = [p for p in centres]
    shapes = [{"type": "Disk", "diameter": float(obstacle_diameter)}]
    for x in droplets:
        x = np.asarray(x, dtype=float)
        c = polygon_centroid(x)
        pos.append(c)
        shapes.append({"type": "Polygon", "rounding_radius": 0.0, "vertices": (x - c).tolist()})
    p = np.array(pos, dtype=float).reshape(-1, 2)
    p = p % box_length - box_length / 2
    s.particles.position = np.array([[a, b, 0.0] for a, b in p], dtype=np.float32)
    s.particles.type_shapes = shapes
    f = _open_for_writing(path)
    f.append(s)
    f.close()


# Particle diameters of the hopper study (scenes/hopper/hopper_scene.hpp: σ_s = 1/1.2, σ_l = 1.4/1.2 σ_avg).
HOPPER_DIAMETERS = (1.0 / 1.2, 1.4 / 1.2)


class _SteppedGsd(_GsdWriter):
    """A callback for mesoflow.run(scene, ...) (or a pillar flow's on_sample) that appends a frame at
    construction and then every `every`-th call; a subclass fills the frame (_fill). Frames log the
    scene's time."""

    def __init__(self, path, scene, every=1):
        if not isinstance(every, int) or every < 1:
            raise ValueError("every must be an integer >= 1, got %r" % (every,))
        self.scene, self.every, self.calls = scene, every, 0
        self.file = _open_for_writing(path)
        self.frames = 0
        self._append()

    def _append(self):
        s = _snapshot()
        s.configuration.step = int(self.scene.steps)
        self._fill(s)
        s.log["time"] = np.array([float(self.scene.time)])
        self.file.append(s)
        self.frames += 1
        self._last_step = self.scene.steps

    def __call__(self, *_):
        self.calls += 1
        if self.calls % self.every == 0:
            self._append()
        return True

    def _stale(self):
        return self.scene.steps != self._last_step


def _centred(x, lo, length):
    """Positions folded into the periodic box [lo, lo + L) and shifted so that it is centred on the
    origin, as GSD boxes are; axes with L = 0 are left as they are."""
    x = np.array(x, dtype=float)
    for a, (l0, L) in enumerate(zip(lo, length)):
        if L > 0:
            x[:, a] = (x[:, a] - l0) % L + l0 - (l0 + L / 2)
    return x


def _spacing(volume, n, d):
    return float((volume / max(n, 1)) ** (1.0 / d))


class CrystalGsd(_SteppedGsd):
    """The crystal's channel flow (mesoflow.crystal.channel): types 'solvent' (Disks at the solvent's
    spacing) and 'disc' (Disks of diameter 2R), the channel [0, L) × [0, W) centred on the origin."""

    def _fill(self, s):
        c = self.scene
        p = c.parameters
        L, W = float(p.length), float(p.width)
        x = _centred(c.positions, (0.0, 0.0), (L, W))
        discs = _centred(np.array(c.disc_positions, dtype=float).reshape(-1, 2), (0.0, 0.0), (L, W))
        s.configuration.dimensions = 2
        s.configuration.box = [L, W, 0.0, 0.0, 0.0, 0.0]
        n, m = len(x), len(discs)
        s.particles.N = n + m
        s.particles.types = ["solvent", "disc"]
        s.particles.typeid = np.array([0] * n + [1] * m, dtype=np.uint32)
        pos = np.zeros((n + m, 3), dtype=np.float32)
        pos[:n, :2], pos[n:, :2] = x, discs
        s.particles.position = pos
        d_solvent, d_disc = 0.5 * _spacing(L * W, n, 2), 2.0 * float(p.disc_radius)
        s.particles.diameter = np.array([d_solvent] * n + [d_disc] * m, dtype=np.float32)
        s.particles.type_shapes = [{"type": "Disk", "diameter": d_solvent}, {"type": "Disk", "diameter": d_disc}]


class CapsuleGsd(_SteppedGsd):
    """The SPH capsule scene (mesoflow.capsule.scene): every particle in its initial order (positions
    through particle_slot, so that ids stay fixed through memory sorts), types 'outer_fluid',
    'inner_fluid', 'wall', 'membrane' (Spheres of the lattice spacing), the membrane's springs as
    bonds of type 'spring'. fluid=False leaves the fluid out (walls and membrane only)."""

    def __init__(self, path, scene, every=1, fluid=True):
        self.fluid = fluid
        self.bonds = np.array(scene.membrane_bonds, dtype=np.uint32)
        super().__init__(path, scene, every)

    def _fill(self, s):
        c = self.scene
        lo, length, periodic = c.box
        x = np.array(c.positions, dtype=float)[np.array(c.particle_slot)]
        x = _centred(x, lo, [L if per else 0.0 for L, per in zip(length, periodic)])
        for a in range(3):  # walled axes: shift only
            if not periodic[a]:
                x[:, a] -= lo[a] + length[a] / 2
        outer, fluid, walls = c.num_outer_fluid, c.num_fluid, c.num_walls
        kind = np.concatenate([np.zeros(outer), np.ones(fluid - outer), np.full(walls, 2),
                               np.full(c.num_membrane, 3)]).astype(np.uint32)
        first = 0 if self.fluid else fluid
        spacing = _spacing(float(np.prod(length)), len(x), 3)
        s.configuration.dimensions = 3
        s.configuration.box = [float(length[0]), float(length[1]), float(length[2]), 0.0, 0.0, 0.0]
        s.particles.N = len(x) - first
        s.particles.types = ["outer_fluid", "inner_fluid", "wall", "membrane"]
        s.particles.typeid = kind[first:]
        s.particles.position = x[first:].astype(np.float32)
        s.particles.diameter = np.full(len(x) - first, spacing, dtype=np.float32)
        s.particles.type_shapes = [{"type": "Sphere", "diameter": spacing}] * 4
        s.bonds.N = len(self.bonds)
        s.bonds.types = ["spring"]
        s.bonds.typeid = np.zeros(len(self.bonds), dtype=np.uint32)
        s.bonds.group = self.bonds - first


class PillarsGsd(_SteppedGsd):
    """An MDPD pillar flow (mesoflow.pillars.flow, after equilibrate()): types 'fluid',
    'solid_surface', 'solid_core' (mdpd::particle_type), Disks (2D) or Spheres (3D) at the fluid's
    spacing; in 3D with walls the wall particles are the solid ones above z = H. Pass it as the
    run's on_sample: a frame every `every` samples."""

    def _fill(self, s):
        f = self.scene
        box = [float(v) for v in f.box]
        x = np.array(f.positions, dtype=float)
        d = x.shape[1]
        x = _centred(x, (0.0,) * d, box[:d])
        spacing = _spacing(float(np.prod(box[:d])), len(x), d)
        s.configuration.dimensions = d
        s.configuration.box = [box[0], box[1], box[2] if d == 3 else 0.0, 0.0, 0.0, 0.0]
        s.particles.N = len(x)
        s.particles.types = ["fluid", "solid_surface", "solid_core"]
        s.particles.typeid = np.array(f.types, dtype=np.uint32)
        pos = np.zeros((len(x), 3), dtype=np.float32)
        pos[:, :d] = x
        s.particles.position = pos
        s.particles.diameter = np.full(len(x), spacing, dtype=np.float32)
        kind = "Disk" if d == 2 else "Sphere"
        s.particles.type_shapes = [{"type": kind, "diameter": spacing}] * 3


class HopperGsd(_SteppedGsd):
    """A callback for mesoflow.run(hopper scene, ...) that appends a GSD frame at every call (and one
    at the start): types 'small' and 'large'. Soft particles are Disks (2D, z = 0) or Spheres (3D)
    of the particle diameter; the deformable-polygon scene's vertices are Disks of the vertex
    diameter δ, `particles/body` their polygon. The box is centred on the origin, as the hopper is
    in x; its height covers every particle. Frames log time and crossings."""

    def _fill(self, s):
        h = self.scene
        x = np.array(h.positions, dtype=float)  # a copy: the view changes with the next step
        types = np.array(h.types, dtype=np.uint32)
        d = h.dimension
        s.configuration.dimensions = d
        width = float(h.parameters.hopper_width) + 2.0
        reach = 2.0 * float(np.abs(x).max()) + 2.0
        s.configuration.box = [width if d == 2 else reach, reach, 0.0 if d == 2 else reach, 0.0, 0.0, 0.0]
        s.particles.N = len(x)
        s.particles.types = ["small", "large"]
        s.particles.typeid = types
        pos = np.zeros((len(x), 3), dtype=np.float32)
        pos[:, :d] = x
        s.particles.position = pos
        if getattr(h, "model", "sp") == "dp":
            diameters = tuple(h.vertex_diameters)
            s.particles.body = np.array(h.bodies, dtype=np.int32)
        else:
            diameters = HOPPER_DIAMETERS
        s.particles.diameter = np.array([diameters[t] for t in types], dtype=np.float32)
        kind = "Disk" if d == 2 else "Sphere"
        s.particles.type_shapes = [{"type": kind, "diameter": float(di)} for di in diameters]
        s.log["crossings"] = np.array([h.crossings])
