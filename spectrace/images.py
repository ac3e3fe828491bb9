"""Image files: float32 linear-sRGB EXR, sRGB PNG, atomic writes, reading back.

This module owns every image file of spectrace: the render's EXR and PNG
(:func:`write_exr`, :func:`write_png`), the PNGs of the display pipeline
(:func:`write_png_codes`, 8 or 16 bits, from :mod:`spectrace.display`), one-channel maps
(:func:`write_channel_exr`, :func:`read_channel_exr`: the lux maps), any RGB(A) EXR
(:func:`read_exr`) and the Fichet 2021 spectral EXRs through :mod:`spectrace.spectral.exr`,
which writes through :func:`write_exr_channels` here.

Every writer goes through :func:`atomic_path`: the file is written under a temporary name
in the destination folder and renamed over the target, so a reader never sees a
half-written file and a failed write leaves nothing behind.

The writers take a numpy array or a Dr.Jit tensor (``mi.TensorXf``, what
:func:`spectrace.render` makes). A tensor is converted and written by Mitsuba itself
(``mi.Bitmap``), so that ``spectrace render`` imports neither numpy, OpenEXR nor Pillow;
a numpy array goes through OpenEXR and Pillow. Both write the same pixels (the PNG's
8-bit codes are the same up to float64 rounding in the sRGB curve) and the same header.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

from spectrace.errors import FileAccessError, FileFormatError, ParameterError, first_line

if TYPE_CHECKING:
    import numpy as np

#: Mitsuba's EXR writer (its bundled OpenEXR 2.5) queues the lines of a file on the global
#: thread pool and waits for them: with a Dr.Jit pool of one thread
#: (``dr.set_thread_count(1)``, what ``-t 1`` asks) no thread runs them and the write hangs
#: (``Imf::OutputFile::writePixels`` waits on ``IlmThread::Semaphore``). :func:`_write_bitmap`
#: writes with at least this many threads.
WRITER_THREADS = 2


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike):
    """Yield a temporary path beside ``path``; rename it to ``path`` on success."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=f".tmp{path.suffix}",
                               dir=path.parent)
    os.close(fd)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual mode
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def check_writable(path: str | os.PathLike) -> Path:
    """Make the output's folder if needed and check a file can be created there."""
    path = Path(path)
    if path.exists() and path.is_dir():
        raise FileAccessError(f"output {path} is a directory")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path.parent, prefix=f".{path.stem}.probe"):
            pass
    except OSError as e:
        blocker = next((p for p in path.parents if p.exists() and not p.is_dir()), None)
        reason = f"{blocker} is a file, not a folder" if blocker else e.strerror or e
        raise FileAccessError(f"cannot write output {path}: {reason}") from None
    return path


def is_tensor(image) -> bool:
    """Whether ``image`` is a Dr.Jit array (a tensor from ``mi.render``), not numpy's."""
    return type(image).__module__.startswith("drjit")


def as_rgb(image):
    """The (H, W, 3) colour of a film's image: its first three channels, or, for the
    one-channel film of a mono variant (luminance, possibly with alpha: C = 1 or 2), that
    channel as grey (R = G = B = Y). A Dr.Jit tensor stays a tensor, anything else becomes
    a numpy array."""
    if is_tensor(image):
        import drjit as dr

        if len(image.shape) == 2:
            image = dr.reshape(type(image), image, (*image.shape, 1))
        if image.shape[-1] in (1, 2):
            grey = image[..., :1]
            return dr.concat([grey, grey, grey], axis=2)
        return image if image.shape[-1] == 3 else image[..., :3]
    import numpy as np

    image = np.asarray(image)
    if image.ndim == 2:
        image = image[..., None]
    if image.shape[-1] in (1, 2):
        return np.repeat(image[..., :1], 3, axis=-1)
    return image[..., :3]


def write_exr(path, rgb, header: dict | None = None) -> None:
    """Write (H, W, 3) linear sRGB as float32 channels R, G, B with extra header attributes
    (a one-channel mono image as grey, see :func:`as_rgb`).

    Header values may be int (32-bit), float or str (stored as EXR int, float and string
    attributes; from a Dr.Jit tensor, Mitsuba stores a float as a double attribute).
    """
    if is_tensor(rgb):
        _write_bitmap(path, _float32_tensor(as_rgb(rgb)), header, "OpenEXR")
        return
    import numpy as np

    write_exr_channels(path, {"RGB": np.asarray(as_rgb(rgb))}, header)


def _openexr():
    """The OpenEXR module, its thread pool (it compresses and decompresses the lines of a
    file in parallel) at one thread per core: 1024 x 1024 with 27 channels writes in 1.4 s
    instead of 2.3 s and reads in 0.25 s instead of 0.5 s on 2 cores. The pool is
    OpenEXR's own, not Dr.Jit's."""
    import OpenEXR

    if OpenEXR.global_thread_count() == 0:
        OpenEXR.set_global_thread_count(os.cpu_count() or 1)
    return OpenEXR


def exr_channel_names(path) -> list[str] | None:
    """The channel names of an OpenEXR file, None when it cannot be read as one."""
    try:
        with _openexr().File(str(path), separate_channels=True) as f:
            return list(f.channels())
    except Exception:  # OpenEXR raises RuntimeError/OSError on broken files
        return None


def write_exr_channels(path, channels: dict, header: dict | None = None,
                       dtype=None) -> None:
    """Write named channels (H, W) (or "RGB"/"RGBA" -> (H, W, 3|4), split into R, G, B, A)
    as a ZIP-compressed scanline OpenEXR file, atomically, with ``header``'s attributes
    (int, float, str). ``dtype``: numpy float32 (default) or float16."""
    import numpy as np

    OpenEXR = _openexr()
    dtype = np.float32 if dtype is None else dtype
    hdr = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    hdr.update(header or {})
    data = {name: np.ascontiguousarray(values, dtype=dtype) for name, values in channels.items()}
    with atomic_path(path) as tmp, OpenEXR.File(hdr, data) as f:
        f.write(tmp)


def read_exr_channels(path) -> tuple[dict, dict]:
    """Every channel of an EXR file as ``{name: (H, W) array}`` (OpenEXR's pixel types:
    float32, float16, uint32) and its header; FileAccessError / FileFormatError naming the
    file when it is missing or not an OpenEXR file."""
    OpenEXR = _openexr()
    path = Path(path)
    if not path.is_file():
        raise FileAccessError(f"{path}: no such file")
    try:
        with OpenEXR.File(str(path), separate_channels=True) as f:
            return ({name: ch.pixels for name, ch in f.channels().items()},
                    dict(f.header()))
    except Exception as e:  # OpenEXR raises RuntimeError/OSError on broken files
        raise FileFormatError(f"{path}: not a readable OpenEXR file ({first_line(e)})") from None


def read_channel_exr(path, name: str):
    """One channel of an EXR as (H, W) float32 and the header; FileFormatError when the file
    has no such channel."""
    import numpy as np

    channels, header = read_exr_channels(path)
    if name not in channels:
        raise FileFormatError(f"{path}: no {name} channel (has {', '.join(channels)})")
    return np.asarray(channels[name], dtype=np.float32), header


def _float32_tensor(tensor):
    import drjit as dr

    if dr.type_v(tensor) != dr.VarType.Float32:
        tensor = dr.float32_array_t(type(tensor))(tensor)
    return tensor


def _write_bitmap(path, tensor, header: dict | None, file_format: str) -> None:
    """Write an (H, W, 3) Dr.Jit tensor with Mitsuba's own image writer (``mi.Bitmap``);
    ``header`` becomes the bitmap's metadata, which the EXR writer stores as attributes."""
    import drjit as dr
    import mitsuba as mi

    bitmap = mi.Bitmap(tensor, mi.Bitmap.PixelFormat.RGB)
    if file_format == "PNG":
        bitmap.set_srgb_gamma(True)  # the codes are sRGB-encoded: an sRGB PNG
    metadata = bitmap.metadata()
    for key, value in (header or {}).items():
        metadata[key] = value
    threads = dr.thread_count()
    with atomic_path(path) as tmp:
        if threads < WRITER_THREADS:
            dr.set_thread_count(WRITER_THREADS)
        try:
            bitmap.write(tmp, getattr(mi.Bitmap.FileFormat, file_format))
        finally:
            if threads < WRITER_THREADS:
                dr.set_thread_count(threads)


def read_exr(path) -> tuple[np.ndarray, dict]:
    """Read an RGB(A) EXR (spectrace's, or Mitsuba's half-float one) as (H, W, 3) float32
    numpy array and its header; a one-channel ``Y`` file as grey."""

    channels, header = read_exr_channels(path)
    return _channels_rgb(path, channels), header


def _channels_rgb(path, channels: dict):
    """(H, W, 3) float32 of a file's R, G, B channels, or its Y as grey."""
    import numpy as np

    if all(c in channels for c in "RGB"):
        return np.stack([np.asarray(channels[c], np.float32) for c in "RGB"], axis=-1)
    if "Y" in channels:
        return np.repeat(np.asarray(channels["Y"], np.float32)[..., None], 3, axis=-1)
    raise FileFormatError(f"{path}: no R, G, B channels (has {', '.join(channels)})")


def read_linear_srgb(path):
    """Any EXR spectrace or Mitsuba writes as (H, W, 3) float32 linear sRGB: R, G, B
    channels (also a spectral EXR's preview), a one-channel ``Y`` as grey, or the spectra
    of a Fichet 2021 spectral EXR without preview (through
    :func:`spectrace.spectral.spectral_image_to_linear_srgb`)."""
    import numpy as np

    channels, _ = read_exr_channels(path)
    if all(c in channels for c in "RGB") or "Y" in channels:
        return _channels_rgb(path, channels)
    from spectrace.spectral.exr import read_spectral_exr
    from spectrace.spectral.image import spectral_image_to_linear_srgb

    image, wavelengths, header = read_spectral_exr(path, with_header=True)
    illuminant = "D65" if not any(k.startswith("S0.") for k in channels) else None
    return np.asarray(spectral_image_to_linear_srgb(image, wavelengths, illuminant),
                      np.float32)


def encode_srgb_8bit(rgb):
    """Linear sRGB -> 8-bit sRGB-encoded (IEC 61966-2-1), clipped to [0, 1], NaN -> 0; a
    one-channel (mono) image as grey. A numpy array gives numpy uint8, a Dr.Jit tensor a
    uint8 tensor (computed in float64 as numpy does)."""
    if is_tensor(rgb):
        return _encode_srgb_8bit_tensor(as_rgb(rgb))
    import numpy as np

    from spectrace.spectral.srgb import encode_srgb

    rgb = np.nan_to_num(as_rgb(rgb).astype(np.float64), nan=0.0, posinf=1.0)
    return np.round(encode_srgb(np.clip(rgb, 0.0, 1.0)) * 255.0).astype(np.uint8)


def _encode_srgb_8bit_tensor(rgb):
    """:func:`spectrace.spectral.srgb.encode_srgb` in Dr.Jit (the same constants), so that
    the render's PNG needs no numpy."""
    import drjit as dr

    from spectrace.spectral import srgb

    flat = type(rgb.array)
    L = dr.clip(dr.float64_array_t(flat)(rgb.array), 0.0, 1.0)  # +inf -> 1, -inf -> 0
    V = dr.select(L <= srgb.SRGB_LINEAR_MAX, srgb.SRGB_SLOPE * L,
                  srgb.SRGB_SCALE * dr.power(L, 1.0 / srgb.SRGB_GAMMA) - srgb.SRGB_OFFSET)
    V = dr.select(dr.isnan(V), 0.0, V)  # NaN -> 0, as numpy's nan_to_num
    codes = dr.uint8_array_t(flat)(dr.round(V * 255.0))
    return dr.uint8_array_t(type(rgb))(codes, rgb.shape)


def write_png(path, rgb) -> None:
    """Write linear sRGB as an 8-bit sRGB-encoded PNG."""
    if is_tensor(rgb):
        _write_bitmap(path, encode_srgb_8bit(rgb), None, "PNG")
        return
    write_png_codes(path, encode_srgb_8bit(rgb))


#: zlib level of :func:`write_png_codes`: level 1 with PNG's Sub filter is within a few
#: per cent of level 6's size on renders and several times faster.
PNG_ZLIB_LEVEL = 1


def write_png_codes(path, codes, cicp: bytes | None = None) -> None:
    """Write (H, W, 3) uint8 or uint16 display codes as an 8- or 16-bit RGB PNG (ISO/IEC
    15948, filter type 1 "Sub" on every line), atomically. ``cicp``: the 4 bytes of a cICP
    chunk (PNG 3rd edition: the colour primaries and transfer of the codes, ITU-T H.273);
    sRGB PNGs also get the sRGB chunk."""
    import struct
    import zlib

    import numpy as np

    codes = np.asarray(codes)
    if codes.ndim != 3 or codes.shape[-1] != 3 or codes.dtype not in (np.uint8, np.uint16):
        raise ParameterError(f"write_png_codes: codes must be (H, W, 3) uint8 or uint16 "
                             f"(got {codes.shape} {codes.dtype})")
    height, width = codes.shape[:2]
    bits = 8 * codes.dtype.itemsize
    rows = codes.astype(codes.dtype.newbyteorder(">"), copy=False).view(np.uint8)
    rows = rows.reshape(height, width * 3 * codes.dtype.itemsize)
    step = 3 * codes.dtype.itemsize  # bytes per pixel: Sub subtracts the pixel to the left
    filtered = np.empty((height, rows.shape[1] + 1), np.uint8)
    filtered[:, 0] = 1
    filtered[:, 1:step + 1] = rows[:, :step]
    np.subtract(rows[:, step:], rows[:, :-step], out=filtered[:, step + 1:])

    def chunk(kind: bytes, data: bytes) -> bytes:
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    parts = [b"\x89PNG\r\n\x1a\n",
             chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, bits, 2, 0, 0, 0))]
    if cicp is not None:
        parts.append(chunk(b"cICP", bytes(cicp)))
    if cicp is None or cicp[0] == 1:
        parts.append(chunk(b"sRGB", b"\x00"))  # rendering intent: perceptual
    parts += [chunk(b"IDAT", zlib.compress(filtered.tobytes(), PNG_ZLIB_LEVEL)),
              chunk(b"IEND", b"")]
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        f.write(b"".join(parts))


def read_image(path) -> np.ndarray:
    """Read an EXR (linear) or PNG/JPEG (sRGB-decoded) as (H, W, 3) linear sRGB float32."""
    import numpy as np

    path = Path(path)
    if not path.is_file():
        raise FileAccessError(f"{path}: no such file")
    if path.suffix.lower() == ".exr":
        return read_exr(path)[0]
    from PIL import Image, UnidentifiedImageError

    from spectrace.spectral.srgb import decode_srgb

    try:
        with Image.open(path) as im:
            data = np.asarray(im.convert("RGB"), dtype=np.float64) / 255.0
    except (OSError, UnidentifiedImageError) as e:
        raise FileFormatError(f"cannot read image {path}: {first_line(e)}") from None
    return decode_srgb(data).astype(np.float32)
