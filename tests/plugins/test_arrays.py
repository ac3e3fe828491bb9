"""plugins/arrays.py: numpy arrays handed to Dr.Jit's LLVM backend stay inside their
memory (Dr.Jit 1.5 reads the last packet of a zero-copy input whole)."""

from __future__ import annotations

import numpy as np

#: Length of the host arrays of the guard-page test: not a multiple of Dr.Jit's packet
#: (16 lanes with AVX-512, 8 with AVX2), as 9 points x 233016 samples were not.
GUARDED_LENGTH = 524280
GUARD_SCRIPT = r"""
import ctypes, mmap, sys
import numpy as np, spectrace
spectrace.set_variant("llvm_ad_rgb")
import drjit as dr, mitsuba as mi
from spectrace.plugins.arrays import host_array
n, padded = int(sys.argv[1]), sys.argv[2] == "padded"
libc = ctypes.CDLL(None, use_errno=True)
# the array (with host_array's padding, or as numpy's mmap allocations leave it: ending
# 16 bytes before the end of its pages) right before a page that may not be read
data = host_array(np.full(n, 0.5)).base if padded else np.full(n, 0.5, np.float32)
nbytes = data.nbytes + (0 if padded else 16)
pages = -(-nbytes // mmap.PAGESIZE)
memory = mmap.mmap(-1, (pages + 1) * mmap.PAGESIZE)
base = ctypes.addressof(ctypes.c_char.from_buffer(memory))
assert libc.mprotect(ctypes.c_void_p(base + pages * mmap.PAGESIZE), mmap.PAGESIZE, 0) == 0
x = np.frombuffer(memory, np.float32, data.size, pages * mmap.PAGESIZE - nbytes)
x[:] = data
x = x[:n]
scene = mi.load_dict({"type": "scene", "floor": {"type": "rectangle"}})
o = mi.Point3f(mi.Float(x), dr.zeros(mi.Float, n), dr.full(mi.Float, -1.0, n))
hit = scene.ray_test(mi.Ray3f(o, mi.Vector3f(0.0, 0.0, 1.0)))
print(dr.sum(dr.select(hit, 1, 0))[0], dr.max(dr.abs(o.x - 0.5))[0])
"""


def run_guarded(padded: bool):
    import subprocess
    import sys

    return subprocess.run([sys.executable, "-c", GUARD_SCRIPT, str(GUARDED_LENGTH),
                           "padded" if padded else "plain"], capture_output=True, text=True,
                          timeout=120)


def test_host_array_keeps_kernels_inside_its_memory(variant_rgb):
    """Dr.Jit's LLVM kernels load the last packet of a zero-copy numpy input whole, past
    its end: an array of GUARDED_LENGTH floats ending 16 bytes before an unreadable page
    (as a large numpy allocation may) kills the process (SIGSEGV), while the same values
    through host_array, its padding ending at that page, are read in bounds and right
    (every ray from x = 0.5 meets the unit square). (Run in subprocesses: a crash is a
    failure here, not the end of pytest.)"""
    from spectrace.plugins.arrays import PACKET_PADDING, host_array

    values = np.arange(GUARDED_LENGTH, dtype=np.float64)
    view = host_array(values)
    assert view.dtype == np.float32 and view.flags.c_contiguous
    assert np.array_equal(view, values.astype(np.float32))
    assert view.base.size % PACKET_PADDING == 0 and not np.any(view.base[GUARDED_LENGTH:])
    padded = run_guarded(True)
    assert padded.returncode == 0, padded.stderr[-2000:]
    hits, error = padded.stdout.split()
    assert int(hits) == GUARDED_LENGTH and float(error) == 0.0  # every ray hits the square
    plain = run_guarded(False)
    assert plain.returncode == -11, (
        "Dr.Jit no longer reads past a mapped array's end (host_array's padding may go): "
        f"rc {plain.returncode}")
