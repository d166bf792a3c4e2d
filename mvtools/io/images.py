"""Still images: PNG (8 and 16 bit), PGM/PPM, JPEG, BMP, TIFF through OpenCV, and PFM.

Arrays are ``(H, W)`` grey or ``(H, W, 3)`` in RGB order (OpenCV's BGR is
converted here, at the file edge), ``uint8`` or ``uint16``; PFM gives ``float32``.
PFM (Portable Float Map, as Middlebury stores disparities) is read and written
here: a ``PF`` (colour) or ``Pf`` (grey) line, ``width height``, then a scale whose
sign gives the byte order (negative = little-endian), then rows bottom to top.
Every output goes through :func:`mvtools.io.atomic.atomic_output`.
"""

from __future__ import annotations

import functools
import logging
import os
import re
from pathlib import Path

import numpy as np

from mvtools.errors import DataError, UsageError
from mvtools.io.atomic import atomic_output
from mvtools.io.files import read_bytes

__all__ = ["IMAGE_EXTENSIONS", "encode_image", "read_image", "read_pfm", "write_image", "write_pfm"]

logger = logging.getLogger(__name__)


@functools.cache
def _opencv():
    """OpenCV, imported when an image is first read or written (0.1 s a process that
    writes none does not pay)."""
    import cv2

    # OpenCV's decoders report damage on stderr from C++ ("[ERROR:0@0.057] ... IHDR chunk
    # shall be first"), before and beside read_image's one line naming the file: silenced.
    cv2.utils.logging.setLogLevel(cv2.utils.logging.LOG_LEVEL_SILENT)
    return cv2


# Extensions written through OpenCV, and whether they hold 16-bit samples.
_CV2_EXTENSIONS = {
    ".png": True,
    ".pgm": True,
    ".ppm": True,
    ".pnm": True,
    ".tif": True,
    ".tiff": True,
    ".jpg": False,
    ".jpeg": False,
    ".bmp": False,
}
IMAGE_EXTENSIONS = (*_CV2_EXTENSIONS, ".pfm")

_PFM_HEADER = re.compile(rb"^(P[Ff])\s+(\d+)\s+(\d+)\s+([-+]?[0-9.]+(?:[eE][-+]?\d+)?)\s")


def read_image(path: str | os.PathLike, *, grayscale: bool = False) -> np.ndarray:
    """Read an image file.

    Parameters
    ----------
    path : path-like
        PNG, PGM/PPM, JPEG, BMP, TIFF (decoded by OpenCV, unchanged bit depth) or PFM.
    grayscale : bool
        Convert colour to grey (OpenCV's BT.601 luma weights).

    Returns
    -------
    ndarray
        ``(H, W)`` or ``(H, W, 3)`` RGB; ``uint8``/``uint16``, ``float32`` for PFM.
        An alpha channel is dropped.

    Raises
    ------
    UsageError
        Missing or unreadable file.
    DataError
        A file that does not decode as an image.
    """
    path = Path(path)
    if path.suffix.lower() == ".pfm":
        image = read_pfm(path)
    else:
        data = read_bytes(path, "image")
        cv2 = _opencv()
        image = cv2.imdecode(np.frombuffer(data, dtype=np.uint8), cv2.IMREAD_UNCHANGED)
        if image is None:
            raise DataError(
                f"cannot decode the image ({len(data)} bytes; not a PNG, PGM, "
                f"JPEG, BMP or TIFF file, or damaged)",
                path=path,
            )
        image = _from_opencv(image, path)
    if grayscale and image.ndim == 3:
        cv2 = _opencv()
        image = cv2.cvtColor(image, cv2.COLOR_RGB2GRAY)
    return image


def _from_opencv(image: np.ndarray, path: Path) -> np.ndarray:
    """OpenCV's BGR(A) / grey(+alpha) to grey or RGB."""
    if image.ndim == 2:
        return image
    channels = image.shape[2]
    if channels in (2, 4):
        alpha = image[..., -1]
        opaque = image.dtype.kind == "u" and alpha.min() == np.iinfo(image.dtype).max
        if not opaque:
            logger.warning("%s: the alpha channel (transparency) is ignored", path)
        image = image[..., :-1]
    if image.shape[2] == 1:
        return image[..., 0]
    return np.ascontiguousarray(image[..., ::-1])


def write_image(path: str | os.PathLike, array: np.ndarray, *, jpeg_quality: int = 95) -> None:
    """Write an image; the format follows the extension.

    Parameters
    ----------
    path : path-like
        ``.png``, ``.pgm``, ``.ppm``, ``.pnm``, ``.tif(f)`` (8 or 16 bit), ``.jpg``,
        ``.jpeg``, ``.bmp`` (8 bit) or ``.pfm`` (float32).
    array : ndarray
        ``(H, W)`` or ``(H, W, 3)`` RGB; ``uint8`` or ``uint16`` (any real dtype for PFM).
    jpeg_quality : int
        JPEG quality 0..100.

    Raises
    ------
    UsageError
        Unsupported extension.
    ValueError
        Shape or dtype the format cannot hold.
    """
    path = Path(path)
    ext = path.suffix.lower()
    if ext == ".pfm":
        write_pfm(path, array)
        return
    if ext not in _CV2_EXTENSIONS:
        raise UsageError(
            f"cannot write images of type {ext or '(no extension)'!r}; "
            f"use one of {', '.join(IMAGE_EXTENSIONS)}",
            path=path,
        )
    encoded = encode_image(array, ext, jpeg_quality=jpeg_quality)
    with atomic_output(path, "wb") as handle:
        handle.write(encoded)


def encode_image(array: np.ndarray, ext: str = ".png", *, jpeg_quality: int = 95) -> bytes:
    """The bytes of an image file of type ``ext`` (``.png``, ``.jpg``, ...; not PFM),
    e.g. for a page that embeds its pictures. Shapes and dtypes as :func:`write_image`."""
    if ext not in _CV2_EXTENSIONS:
        raise ValueError(f"cannot encode images of type {ext!r}")
    array = np.asarray(array)
    if array.ndim == 3 and array.shape[2] == 1:
        array = array[..., 0]
    if array.ndim not in (2, 3) or (array.ndim == 3 and array.shape[2] != 3):
        raise ValueError(f"an image must have shape (H, W) or (H, W, 3), got {array.shape}")
    allowed = (np.uint8, np.uint16) if _CV2_EXTENSIONS[ext] else (np.uint8,)
    if array.dtype not in [np.dtype(t) for t in allowed]:
        raise ValueError(
            f"{ext} images take {' or '.join(np.dtype(t).name for t in allowed)} "
            f"samples, got {array.dtype}"
        )
    if ext == ".pgm" and array.ndim == 3:
        raise ValueError(f".pgm holds grey images, got shape {array.shape}; use .ppm or .png")
    if array.ndim == 3:
        array = array[..., ::-1]
    cv2 = _opencv()
    params = [cv2.IMWRITE_JPEG_QUALITY, int(jpeg_quality)] if ext in (".jpg", ".jpeg") else []
    ok, encoded = cv2.imencode(ext, np.ascontiguousarray(array), params)
    if not ok:
        raise ValueError(f"OpenCV could not encode a {array.dtype} {array.shape} image as {ext}")
    return encoded.tobytes()


def read_pfm(path: str | os.PathLike) -> np.ndarray:
    """Read a PFM file, rows top to bottom.

    Returns
    -------
    ndarray
        ``float32``, ``(H, W)`` for ``Pf``, ``(H, W, 3)`` for ``PF``. Infinities
        (Middlebury's unknown disparities) are kept; the magnitude of the scale is
        ignored, as Middlebury's readers do.

    Raises
    ------
    UsageError
        Missing file.
    DataError
        Bad header or too few bytes.
    """
    path = Path(path)
    data = read_bytes(path, "image")
    match = _PFM_HEADER.match(data[:256])
    if match is None:
        raise DataError("not a PFM file (header 'PF|Pf width height scale' expected)", path=path)
    kind, width, height, scale = (
        match.group(1),
        int(match.group(2)),
        int(match.group(3)),
        float(match.group(4)),
    )
    if scale == 0 or width == 0 or height == 0:
        raise DataError(f"bad PFM header: size {width}x{height}, scale {scale}", path=path)
    channels = 3 if kind == b"PF" else 1
    expected = width * height * channels * 4
    payload = len(data) - match.end()
    if payload < expected:
        raise DataError(
            f"PFM {width}x{height}x{channels} needs {expected} bytes of samples, "
            f"the file has {payload}",
            path=path,
        )
    if payload > expected:
        logger.warning("%s: %d bytes after the PFM samples ignored", path, payload - expected)
    dtype = np.dtype("<f4" if scale < 0 else ">f4")
    samples = np.frombuffer(data, dtype=dtype, count=width * height * channels, offset=match.end())
    shape = (height, width, channels) if channels == 3 else (height, width)
    return np.ascontiguousarray(samples.reshape(shape)[::-1], dtype=np.float32)


def write_pfm(path: str | os.PathLike, array: np.ndarray) -> None:
    """Write ``(H, W)`` or ``(H, W, 3)`` values as little-endian float32 PFM (scale -1)."""
    array = np.asarray(array)
    if array.ndim == 3 and array.shape[2] == 1:
        array = array[..., 0]
    if array.ndim not in (2, 3) or (array.ndim == 3 and array.shape[2] != 3):
        raise ValueError(f"a PFM image must have shape (H, W) or (H, W, 3), got {array.shape}")
    if array.dtype.kind not in "biuf":
        raise ValueError(f"PFM holds real numbers, got dtype {array.dtype}")
    kind = "PF" if array.ndim == 3 else "Pf"
    header = f"{kind}\n{array.shape[1]} {array.shape[0]}\n-1\n".encode("ascii")
    with atomic_output(path, "wb") as handle:
        handle.write(header)
        handle.write(np.ascontiguousarray(array[::-1], dtype="<f4").tobytes())
