"""numpy arrays handed to Dr.Jit's LLVM backend without a fault.

Dr.Jit 1.5 maps a contiguous numpy array into an LLVM-backend array without copying it,
and its kernels load every packet of an input whole, the last one too. A large numpy
array (allocated with ``mmap``) can end just before an unmapped page, and the kernel's
read of its last packet then kills the process with SIGSEGV (measured: 9 x 233016 points
of ``spectrace lux --points``). :func:`host_array` gives such arrays a padded buffer; use
it for every numpy array of more than a few thousand elements that becomes a Dr.Jit array.
Strided numpy views (``a[:, i]`` of a C-ordered array) are copied by Dr.Jit and are safe.
"""

from __future__ import annotations

#: Elements a host array handed to Dr.Jit is padded to a multiple of (see
#: :func:`host_array`): a multiple of the widest packet of Dr.Jit's LLVM kernels (16 lanes
#: with AVX-512; 64 leaves room for wider targets).
PACKET_PADDING = 64


def host_array(values, dtype="float32"):
    """``values`` as a 1-D numpy array of ``dtype`` that Dr.Jit's LLVM backend may map
    without copying: a view of the first len(values) elements of a zero-padded buffer
    whose length is a multiple of PACKET_PADDING.

    Dr.Jit 1.5 maps a contiguous numpy array into an LLVM-backend array without a copy,
    and its kernels load every packet of an input whole (``vmovups`` of 16 lanes with
    AVX-512), the last one too: a kernel reads up to 15 elements past the end of a mapped
    array of a length that is no multiple of the packet. Dr.Jit's own allocations are
    padded for that; numpy's are not, and a large one (allocated with ``mmap``) may end
    16 bytes before an unmapped page: the over-read then kills the process (SIGSEGV),
    depending on the array's length and on what lies after it in memory. The padding
    keeps every packet inside memory the array owns (the extra lanes are masked)."""
    import numpy as np

    values = np.ascontiguousarray(values, dtype=dtype).reshape(-1)
    buffer = np.zeros(max(-(-len(values) // PACKET_PADDING), 1) * PACKET_PADDING, dtype)
    buffer[:len(values)] = values
    return buffer[:len(values)]
