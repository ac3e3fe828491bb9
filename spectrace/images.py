"""Image files: float32 linear-sRGB EXR, 8-bit sRGB PNG, atomic writes, reading back.

Every writer goes through :func:`atomic_path`: the file is written under a temporary name
in the destination folder and renamed over the target, so a reader never sees a
half-written file and a failed write leaves nothing behind.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

import numpy as np

from spectrace.errors import UserError


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
        raise UserError(f"output {path} is a directory")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path.parent, prefix=f".{path.stem}.probe"):
            pass
    except OSError as e:
        raise UserError(f"cannot write output {path}: {e.strerror or e}") from None
    return path


def as_rgb(image: np.ndarray) -> np.ndarray:
    """The (H, W, 3) colour of a film's image: its first three channels, or, for the
    one-channel film of a mono variant (luminance, possibly with alpha: C = 1 or 2), that
    channel as grey (R = G = B = Y)."""
    image = np.asarray(image)
    if image.ndim == 2:
        image = image[..., None]
    if image.shape[-1] in (1, 2):
        return np.repeat(image[..., :1], 3, axis=-1)
    return image[..., :3]


def write_exr(path, rgb: np.ndarray, header: dict | None = None) -> None:
    """Write (H, W, 3) linear sRGB as float32 channels R, G, B with extra header attributes
    (a one-channel mono image as grey, see :func:`as_rgb`).

    Header values may be int, float or str (stored as EXR int, float and string attributes).
    """
    import OpenEXR

    rgb = np.ascontiguousarray(as_rgb(rgb), dtype=np.float32)
    hdr = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    hdr.update(header or {})
    with atomic_path(path) as tmp:
        OpenEXR.File(hdr, {"RGB": rgb}).write(tmp)


def read_exr(path) -> tuple[np.ndarray, dict]:
    """Read an RGB(A) EXR as (H, W, 3) float32 and its header."""
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
                raise UserError(f"{path}: no R, G, B channels (has {names})")
    except (OSError, RuntimeError) as e:
        raise UserError(f"cannot read EXR {path}: {e}") from None
    return np.asarray(rgb, dtype=np.float32), header


def encode_srgb_8bit(rgb: np.ndarray) -> np.ndarray:
    """Linear sRGB -> 8-bit sRGB-encoded (IEC 61966-2-1), clipped to [0, 1], NaN -> 0; a
    one-channel (mono) image as grey."""
    from spectrace.spectral.srgb import encode_srgb

    rgb = np.nan_to_num(as_rgb(rgb).astype(np.float64), nan=0.0, posinf=1.0)
    return np.round(encode_srgb(np.clip(rgb, 0.0, 1.0)) * 255.0).astype(np.uint8)


def write_png(path, rgb: np.ndarray) -> None:
    """Write linear sRGB as an 8-bit sRGB-encoded PNG."""
    from PIL import Image

    with atomic_path(path) as tmp:
        Image.fromarray(encode_srgb_8bit(rgb), "RGB").save(tmp, format="PNG")


def read_image(path) -> np.ndarray:
    """Read an EXR (linear) or PNG/JPEG (sRGB-decoded) as (H, W, 3) linear sRGB float32."""
    path = Path(path)
    if not path.is_file():
        raise UserError(f"{path}: no such file")
    if path.suffix.lower() == ".exr":
        return read_exr(path)[0]
    from PIL import Image, UnidentifiedImageError

    from spectrace.spectral.srgb import decode_srgb

    try:
        with Image.open(path) as im:
            data = np.asarray(im.convert("RGB"), dtype=np.float64) / 255.0
    except (OSError, UnidentifiedImageError) as e:
        raise UserError(f"cannot read image {path}: {e}") from None
    return decode_srgb(data).astype(np.float32)
