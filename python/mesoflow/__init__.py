"""mesoflow — mesoscale soft-matter flows in microfluidic geometries, from Python (docs/python.md).

    import mesoflow
    mesoflow.initialize(threads=2)          # optional: Kokkos starts on first use otherwise
    from mesoflow import droplets
    run = droplets.orifice(width=0.4, line_tension=0.16)
    profile = run.run(progress=True)

The compiled core (`mesoflow._mesoflow`, pybind11) binds the C++ scenes and analysis; nothing of
the physics is re-implemented here. Kokkos is initialised once per process and finalised at exit.
"""
from . import _mesoflow
from ._mesoflow import finalize, host_backend, is_initialized, kokkos_configuration

__version__ = _mesoflow.version


def initialize(threads=0):
    """Starts Kokkos with `threads` host threads (0: OMP_NUM_THREADS or all cores).

    Once per process: called again with the same or no thread count it does nothing; with another
    thread count it raises RuntimeError. Scenes start Kokkos themselves with the default when it
    has not been started.
    """
    _mesoflow.initialize(int(threads))


def run(scene, steps, every=100, callback=None, progress=False):
    """Advances any stepped scene (hopper, crystal, capsule, pillar flow after equilibrate()) by `steps`
    steps, `every` at a time; after each chunk callback(scene) is called, and False from it stops the
    run there. progress=True shows a bar (tqdm where installed) in steps. Returns the steps done."""
    if steps < 0 or every < 1:
        raise ValueError("steps must be >= 0 and every >= 1, got %r and %r" % (steps, every))
    from .droplets import _progress_bar
    bar = _progress_bar(steps, "steps", progress)
    done = 0
    try:
        while done < steps:
            k = min(every, steps - done)
            scene.advance(k)
            done += k
            if bar is not None:
                bar.update(k)
            if callback is not None and callback(scene) is False:
                break
    finally:
        if bar is not None:
            bar.close()
    return done


from . import droplets  # noqa: E402  (after initialize, which it uses)
from . import hopper  # noqa: E402
from . import crystal  # noqa: E402
from . import capsule  # noqa: E402
from . import pillars  # noqa: E402
from ._mesoflow import analysis  # noqa: E402  (host analysis on arrays; no Kokkos needed)

__all__ = ["initialize", "finalize", "is_initialized", "kokkos_configuration", "host_backend", "run", "droplets",
           "hopper", "crystal", "capsule", "pillars",
           "analysis"]
