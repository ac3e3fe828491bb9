"""spectrace.cluster and the distributed pass loop, on a LocalCluster of two worker processes.

Oracles: the local pass loop (spectrace.passes.render_passes) with the same seed, and the
machine's core count.
"""

from __future__ import annotations

import os
import signal
from pathlib import Path

import numpy as np

from spectrace import cluster
from spectrace.cluster import SceneSpec, render_passes_distributed
from spectrace.passes import render_passes

ROOT = Path(__file__).resolve().parents[1]
SHOWCASE = ROOT / "scenes" / "showcase.xml"
PARAMS = {"res": "16", "max_depth": "3"}
VARIANT = "llvm_ad_rgb"
#: The film accumulates samples with parallel atomic adds: equal seeds agree up to the
#: order of float additions.
SAME_SEED_ATOL = 1e-5
SAME_SEED_RTOL = 1e-5


def local_render(spp, seed, spp_per_pass):
    import spectrace
    from spectrace.scene import load_scene

    spectrace.set_variant(VARIANT)
    return render_passes(load_scene(SHOWCASE, PARAMS), spp, seed=seed, spp_per_pass=spp_per_pass)


def test_thread_share_never_oversubscribes():
    """Workers on one host get cores // workers Dr.Jit threads each (at least one)."""
    assert cluster.dr_thread_share(2, cores=16) == 8
    assert cluster.dr_thread_share(3, cores=16) == 5
    assert cluster.dr_thread_share(4, cores=2) == 1


def test_workers_are_set_up_once_with_their_share_of_the_cores(client):
    """Each worker process set its variant once, runs cores // 2 Dr.Jit threads and uses
    the client's kernel cache folder."""
    info = client.run(cluster.worker_info)
    assert len(info) == 2 and len({i["pid"] for i in info.values()}) == 2
    for i in info.values():
        assert i["variant"] == VARIANT and i["setups"] == 1
        assert i["dr_threads"] == cluster.dr_thread_share(2)
        assert i["kernel_cache"] == str(Path.home() / ".drjit")


def test_distributed_passes_equal_the_local_loop(client):
    """The same pass seeds, summed with sample weights in pass order: the local image."""
    spec = SceneSpec.make(SHOWCASE, PARAMS, VARIANT)
    remote = render_passes_distributed(client, spec, 24, seed=7, spp_per_pass=4)
    local = local_render(24, 7, 4)
    assert (remote.spp, remote.passes, remote.interrupted) == (24, 6, False)
    np.testing.assert_allclose(remote.image, local.image, rtol=SAME_SEED_RTOL,
                               atol=SAME_SEED_ATOL)


def test_distributed_passes_weigh_what_the_sampler_took(client):
    """The showcase's ldsampler makes passes of 8 spp ones of 16: the workers report it,
    and the image and sample count are the local loop's (48 spp for 24 asked)."""
    spec = SceneSpec.make(SHOWCASE, PARAMS, VARIANT)
    remote = render_passes_distributed(client, spec, 24, seed=3, spp_per_pass=8)
    local = local_render(24, 3, 8)
    assert remote.spp == local.spp == 48 and remote.passes == local.passes == 3
    np.testing.assert_allclose(remote.image, local.image, rtol=SAME_SEED_RTOL,
                               atol=SAME_SEED_ATOL)


def test_a_worker_killed_mid_render_loses_nothing(client):
    """SIGKILL one worker process after the first pass: its passes run again elsewhere and
    the image is still the local loop's, with every sample."""
    pids = list(client.run(os.getpid).values())
    killed = []

    def on_pass(done, total):
        if not killed:
            os.kill(pids[0], signal.SIGKILL)
            killed.append(pids[0])

    spec = SceneSpec.make(SHOWCASE, PARAMS, VARIANT)
    remote = render_passes_distributed(client, spec, 32, seed=11, spp_per_pass=4,
                                       on_pass=on_pass)
    assert killed and remote.spp == 32 and not remote.interrupted
    assert pids[0] not in client.run(os.getpid).values()  # it did die
    np.testing.assert_allclose(remote.image, local_render(32, 11, 4).image,
                               rtol=SAME_SEED_RTOL, atol=SAME_SEED_ATOL)


#: A plain script (no ``if __name__ == "__main__":``), as in the README: it starts a cluster of
#: two workers at its top level and prints what it rendered and its own ``__file__``.
PLAIN_SCRIPT = """
import spectrace
print("top level ran", flush=True)
da = spectrace.sweep({scene!r}, params={{"res": 8, "max_depth": [1, 2]}}, variants={variant!r},
                     spp=1, workers=2)
print("shape", da.shape, "file", __file__)
"""
#: Seconds a plain script's sweep of two 8 x 8 images may take (start-up of two workers).
PLAIN_SCRIPT_LIMIT_S = 240


def test_a_plain_script_sweeps_without_a_main_guard(tmp_path):
    """Worker processes are spawned without running the user's main script: a script that
    calls spectrace.sweep at its top level runs it once (it ran three times and failed with
    'Nanny failed to start'), gets its images and keeps its __file__."""
    import subprocess
    import sys

    script = tmp_path / "plain.py"
    script.write_text(PLAIN_SCRIPT.format(scene=str(SHOWCASE), variant=VARIANT))
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          cwd=tmp_path, timeout=PLAIN_SCRIPT_LIMIT_S)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.count("top level ran") == 1, done.stdout
    assert f"shape (2, 8, 8, 3) file {script}" in done.stdout, done.stdout
    assert "Traceback" not in done.stderr, done.stderr[-3000:]
