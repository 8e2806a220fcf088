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


from . import droplets  # noqa: E402  (after initialize, which it uses)
from . import hopper  # noqa: E402
from . import crystal  # noqa: E402
from . import capsule  # noqa: E402
from . import pillars  # noqa: E402
from ._mesoflow import analysis  # noqa: E402  (host analysis on arrays; no Kokkos needed)

__all__ = ["initialize", "finalize", "is_initialized", "kokkos_configuration", "host_backend", "droplets",
           "hopper", "crystal", "capsule", "pillars",
           "analysis"]
