"""Image files: float32 linear-sRGB EXR, 8-bit sRGB PNG, atomic writes, reading back.

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

from spectrace.errors import FileAccessError, FileFormatError

if TYPE_CHECKING:
    import numpy as np

# IEC 61966-2-1, as spectrace.spectral.srgb.encode_srgb
_SRGB_LINEAR_MAX = 0.0031308
_SRGB_SLOPE = 12.92
_SRGB_GAMMA = 2.4


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
    import OpenEXR

    rgb = np.ascontiguousarray(as_rgb(rgb), dtype=np.float32)
    hdr = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    hdr.update(header or {})
    with atomic_path(path) as tmp:
        OpenEXR.File(hdr, {"RGB": rgb}).write(tmp)


def _float32_tensor(tensor):
    import drjit as dr

    if dr.type_v(tensor) != dr.VarType.Float32:
        tensor = dr.float32_array_t(type(tensor))(tensor)
    return tensor


def _write_bitmap(path, tensor, header: dict | None, file_format: str) -> None:
    """Write an (H, W, 3) Dr.Jit tensor with Mitsuba's own image writer (``mi.Bitmap``);
    ``header`` becomes the bitmap's metadata, which the EXR writer stores as attributes."""
    import mitsuba as mi

    bitmap = mi.Bitmap(tensor, mi.Bitmap.PixelFormat.RGB)
    if file_format == "PNG":
        bitmap.set_srgb_gamma(True)  # the codes are sRGB-encoded: an sRGB PNG
    metadata = bitmap.metadata()
    for key, value in (header or {}).items():
        metadata[key] = value
    with atomic_path(path) as tmp:
        bitmap.write(tmp, getattr(mi.Bitmap.FileFormat, file_format))


def read_exr(path) -> tuple[np.ndarray, dict]:
    """Read an RGB(A) EXR as (H, W, 3) float32 numpy array and its header."""
    import numpy as np
    import OpenEXR

    try:
        with OpenEXR.File(str(path)) as f:
            channels = f.channels()
            header = dict(f.header())
            if "RGB" in channels:
                rgb = channels["RGB"].pixels
            elif "RGBA" in channels:
                rgb = channels["RGBA"].pixels[..., :3]
            else:
                names = ", ".join(channels)
                raise FileFormatError(f"{path}: no R, G, B channels (has {names})")
    except (OSError, RuntimeError) as e:
        raise FileFormatError(f"cannot read EXR {path}: {e}") from None
    return np.asarray(rgb, dtype=np.float32), header


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
    import drjit as dr

    flat = type(rgb.array)
    L = dr.clip(dr.float64_array_t(flat)(rgb.array), 0.0, 1.0)  # +inf -> 1, -inf -> 0
    V = dr.select(L <= _SRGB_LINEAR_MAX, _SRGB_SLOPE * L,
                  1.055 * dr.power(L, 1.0 / _SRGB_GAMMA) - 0.055)
    V = dr.select(dr.isnan(V), 0.0, V)  # NaN -> 0, as numpy's nan_to_num
    codes = dr.uint8_array_t(flat)(dr.round(V * 255.0))
    return dr.uint8_array_t(type(rgb))(codes, rgb.shape)


def write_png(path, rgb) -> None:
    """Write linear sRGB as an 8-bit sRGB-encoded PNG."""
    if is_tensor(rgb):
        _write_bitmap(path, encode_srgb_8bit(rgb), None, "PNG")
        return
    from PIL import Image

    with atomic_path(path) as tmp:
        Image.fromarray(encode_srgb_8bit(rgb), "RGB").save(tmp, format="PNG")


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
        raise FileFormatError(f"cannot read image {path}: {e}") from None
    return decode_srgb(data).astype(np.float32)
