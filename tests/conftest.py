"""Shared fixtures: Mitsuba variants, seeded generators and the tolerances used across tests."""

from __future__ import annotations

import numpy as np
import pytest

import spectrace

VARIANTS = ("llvm_ad_rgb", "llvm_ad_spectral")
#: Every LLVM variant of Mitsuba's wheel: RGB, mono, spectral and the polarized forms it has.
ALL_VARIANTS = ("llvm_ad_rgb", "llvm_ad_mono", "llvm_ad_mono_polarized", "llvm_ad_spectral",
                "llvm_ad_spectral_polarized")


@pytest.fixture(params=VARIANTS)
def variant(request):
    """Run the test once per LLVM variant (RGB and spectral), plugins registered."""
    spectrace.set_variant(request.param)
    return request.param


@pytest.fixture(params=ALL_VARIANTS)
def any_variant(request):
    """Run the test once per supported LLVM variant (ALL_VARIANTS), plugins registered."""
    spectrace.set_variant(request.param)
    return request.param


@pytest.fixture
def variant_rgb():
    spectrace.set_variant("llvm_ad_rgb")
    return "llvm_ad_rgb"


@pytest.fixture
def variant_spectral():
    spectrace.set_variant("llvm_ad_spectral")
    return "llvm_ad_spectral"


@pytest.fixture(scope="session")
def local_cluster():
    """One Dask LocalCluster of two worker processes for the whole session (cluster tests
    share it; a worker killed by a test is restarted by its nanny), closed at the end."""
    from spectrace import cluster

    local = cluster.start_local(2)
    yield local
    local.close()


@pytest.fixture(scope="module")
def client(local_cluster):
    """A Dask client of the session's cluster, workers set up for llvm_ad_rgb."""
    from distributed import Client

    from spectrace import cluster

    c = Client(local_cluster, set_as_default=False)
    cluster.setup_workers(c, variant="llvm_ad_rgb")
    yield c
    c.close()


@pytest.fixture
def rng():
    """A seeded numpy generator: every random test is reproducible."""
    return np.random.default_rng(20261122)


#: The fixtures that set a variant per test, and the variants' order in a module's run.
_VARIANT_FIXTURES = ("variant", "any_variant")
_VARIANT_RANK = {name: rank for rank, name in enumerate(ALL_VARIANTS)}


def pytest_collection_modifyitems(items):
    """Within each test file, the tests of one variant run together (a stable sort, so the
    order within a variant stays the file's): each switch of variant re-executes Mitsuba's
    Python integrators and every plugin (about 90 ms), and test by test the suite switched
    variants 201 times (91 now)."""
    files: dict[str, int] = {}
    for item in items:
        files.setdefault(str(item.path), len(files))

    def key(item):
        callspec = getattr(item, "callspec", None)
        params = callspec.params if callspec is not None else {}
        variant = next((params[f] for f in _VARIANT_FIXTURES if f in params), None)
        return files[str(item.path)], _VARIANT_RANK.get(variant, -1)

    items.sort(key=key)
