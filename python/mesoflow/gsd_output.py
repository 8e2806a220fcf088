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


class HopperGsd(_GsdWriter):
    """A callback for mesoflow.run(hopper scene, ...) that appends a GSD frame at every call (and one
    at the start): types 'small' and 'large'. Soft particles are Disks (2D, z = 0) or Spheres (3D)
    of the particle diameter; the deformable-polygon scene's vertices are Disks of the vertex
    diameter δ, `particles/body` their polygon. The box is centred on the origin, as the hopper is
    in x; its height covers every particle. Frames log time and crossings."""

    def __init__(self, path, hopper_scene):
        self.h = hopper_scene
        self.file = _open_for_writing(path)
        self.frames = 0
        self._append()

    def _append(self):
        h = self.h
        x = np.array(h.positions, dtype=float)  # a copy: the view changes with the next step
        types = np.array(h.types, dtype=np.uint32)
        d = h.dimension
        s = _snapshot()
        s.configuration.step = int(h.steps)
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
        s.log["time"] = np.array([h.time])
        s.log["crossings"] = np.array([h.crossings])
        self.file.append(s)
        self.frames += 1
        self._last_step = h.steps

    def __call__(self, scene):
        self._append()
        return True

    def _stale(self):
        return self.h.steps != self._last_step
