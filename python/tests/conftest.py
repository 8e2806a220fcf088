"""pytest setup for the mesoflow bindings: the module from the build tree (PYTHONPATH=<build>/python,
set by ctest), Kokkos on one host thread so that runs are comparable bit for bit with a driver run
with --threads 1; MESOFLOW_BIN points at the drivers of the same build."""
import os

import pytest

import mesoflow

mesoflow.initialize(threads=1)


@pytest.fixture
def bin_dir():
    path = os.environ.get("MESOFLOW_BIN", "")
    if not os.path.isdir(path):
        pytest.fail("MESOFLOW_BIN must name the build's bin/ folder (ctest sets it), got %r" % path)
    return path
