"""``mvtools estimate-depth``: disparity maps from a rectified stereo pair.

Stereo-pair mode: the left view's disparity is written as PFM (float, ``inf`` where
no disparity was found, as Middlebury stores unknown values) and, on request, as a
16-bit PNG holding ``round(disparity * scale)`` with 0 for unknown, the convention
of Middlebury's ground-truth files, so that ``mvtools evaluate --disparity`` scores
either file. The DERS configuration mode of issue #4 is not implemented yet.
"""

from __future__ import annotations

import logging
import time
from pathlib import Path

import click
import numpy as np

from mvtools.cli.options import overrides_argument, program
from mvtools.depth import METHODS, estimate_disparity
from mvtools.errors import DataError, UsageError
from mvtools.io.images import read_image, write_image

LOG = logging.getLogger(__name__)

#: Disparity-map PNG value / scale = disparity in pixels: quarter pixels, as the
#: Middlebury 2003 ground truth (Teddy, Cones) stores them.
DEFAULT_PNG_SCALE = 4.0
_PNG_MAX = np.iinfo(np.uint16).max


@click.command(name="estimate-depth")
@click.argument("config", required=False, type=click.Path(dir_okay=False))
@overrides_argument
@click.option("--left", type=click.Path(dir_okay=False), default=None,
              help="Left picture of a rectified pair (PNG, PPM, JPEG...): the view whose "
                   "disparity is estimated.")
@click.option("--right", type=click.Path(dir_okay=False), default=None,
              help="Right picture of the pair, same size as --left.")
@click.option("--disparities", "max_disparity", type=int, default=None, metavar="N",
              help="Largest disparity searched, in pixels (left x - right x; inclusive).")
@click.option("--min-disparity", type=int, default=0, show_default=True,
              help="Smallest disparity searched, in pixels (inclusive).")
@click.option("--method", default="sgm", show_default=True,
              help=f"Matching method: {', '.join(METHODS)}.")
@click.option("-o", "--output", type=click.Path(dir_okay=False), default=None,
              help="Disparity map of the left view, PFM (float pixels, inf = unknown).")
@click.option("--png", type=click.Path(dir_okay=False), default=None,
              help="Also write the disparity map as a 16-bit PNG holding disparity * "
                   "--png-scale, rounded, 0 = unknown.")
@click.option("--png-scale", type=float, default=DEFAULT_PNG_SCALE, show_default=True,
              help="PNG value / scale = disparity in pixels (give the same number to "
                   "evaluate --disparity-scale).")
@program
def command(config, overrides, left, right, max_disparity, min_disparity, method, output,
            png, png_scale):
    """Estimate the disparity map of the left view of a rectified stereo pair.

    \b
    mvtools estimate-depth --left im2.png --right im6.png --disparities 64 \\
        -o disparity.pfm --png disparity.png --png-scale 4

    The pictures are rectified (corresponding points on the same row, the right
    view's point to the left: disparity = left x - right x >= 0 for the usual
    --min-disparity 0). The PFM keeps the float disparities with inf where the
    method found none (occlusions, failed consistency checks); the PNG, for
    Middlebury-style evaluation, holds disparity * --png-scale with 0 for those
    (a true disparity that rounds to 0 is then read as unknown too).

    CONFIG (a DERS configuration file, with Key=Value overrides) is the other mode
    of issue #4 and is not implemented yet.

    Exits with 2 for a bad option or missing file, 1 for inconsistent pictures
    (different sizes), leaving no output file.
    """
    if config is not None:
        raise UsageError("DERS configuration mode is not implemented yet (issue #4)", path=config)
    for name, value in (("--left", left), ("--right", right), ("--disparities", max_disparity),
                        ("-o/--output", output)):
        if value is None:
            raise UsageError(f"{name} is required (stereo-pair mode: --left L --right R "
                             "--disparities N -o OUT.pfm)")
    # Checked here rather than by click.Choice, whose message spans several lines.
    if method not in METHODS:
        raise UsageError(f"unknown method {method!r}; known methods: {', '.join(METHODS)}",
                         key="--method")
    if min_disparity >= max_disparity:
        raise UsageError(f"empty disparity range: --min-disparity {min_disparity} must be "
                         f"smaller than --disparities {max_disparity}")
    outputs = _check_outputs(Path(output), None if png is None else Path(png), png_scale,
                             min_disparity, max_disparity, inputs=(Path(left), Path(right)))
    left_rgb, right_rgb = _read_view(Path(left)), _read_view(Path(right))
    if left_rgb.shape != right_rgb.shape:
        raise DataError(f"the right picture is {right_rgb.shape[1]}x{right_rgb.shape[0]}, the "
                        f"left one {left_rgb.shape[1]}x{left_rgb.shape[0]}", path=right)
    height, width = left_rgb.shape[:2]
    LOG.info("%s: %dx%d, disparities %d..%d, method %s", left, width, height, min_disparity,
             max_disparity, method)
    start = time.perf_counter()
    try:
        disparity = estimate_disparity(left_rgb, right_rgb, max_disparity=max_disparity,
                                       min_disparity=min_disparity, method=method)
    except ValueError as error:
        # The method's own limits on the range or picture size, which options can break.
        raise UsageError(str(error)) from None
    known = np.isfinite(disparity)
    LOG.info("disparity estimated in %.2f s, %.1f %% of the pixels unknown",
             time.perf_counter() - start, 100.0 * (1.0 - known.mean()))
    write_image(outputs[0], np.where(known, disparity, np.inf).astype(np.float32))
    LOG.info("wrote %s", outputs[0])
    if len(outputs) > 1:
        write_image(outputs[1], disparity_png_values(disparity, scale=png_scale))
        LOG.info("wrote %s (disparity * %g)", outputs[1], png_scale)


def disparity_png_values(disparity: np.ndarray, *, scale: float) -> np.ndarray:
    """16-bit PNG samples of a disparity map: ``round(disparity * scale)``, 0 where unknown.

    Parameters
    ----------
    disparity : ndarray of float, shape (H, W)
        Disparities in pixels, NaN or infinite where unknown, within
        ``[0, 65535 / scale]``.
    scale : float
        File value / scale = disparity in pixels.

    Returns
    -------
    ndarray of uint16, shape (H, W)
    """
    known = np.isfinite(disparity)
    values = np.round(np.where(known, disparity, 0.0) * scale)
    return np.clip(values, 0, _PNG_MAX).astype(np.uint16)


def _check_outputs(output: Path, png: Path | None, png_scale: float, min_disparity: int,
                   max_disparity: int, *, inputs: tuple[Path, Path]) -> list[Path]:
    """The output paths, checked before any work so that a bad one leaves nothing behind."""
    if output.suffix.lower() != ".pfm":
        raise UsageError("the disparity map is written as PFM: give a name ending in .pfm",
                         path=output, key="-o")
    outputs = [output]
    if png is not None:
        if png.suffix.lower() != ".png":
            raise UsageError("--png needs a name ending in .png", path=png, key="--png")
        if not png_scale > 0:
            raise UsageError(f"--png-scale must be positive, got {png_scale:g}")
        if min_disparity < 0:
            raise UsageError(f"a PNG disparity map cannot hold negative disparities "
                             f"(--min-disparity {min_disparity}); use the PFM output alone")
        if max_disparity * png_scale > _PNG_MAX:
            raise UsageError(f"--disparities {max_disparity} * --png-scale {png_scale:g} exceeds "
                             f"{_PNG_MAX}, the largest 16-bit value; lower --png-scale")
        outputs.append(png)
    resolved = [path.resolve() for path in (*inputs, *outputs)]
    if len(set(resolved)) != len(resolved):
        raise UsageError("the inputs and outputs must be different files")
    for path in outputs:
        if not path.resolve().parent.is_dir():
            raise UsageError("the output folder does not exist", path=path)
    return outputs


def _read_view(path: Path) -> np.ndarray:
    """A picture as ``(H, W, 3)`` uint8 RGB; grey is repeated, 16-bit samples reduced."""
    image = read_image(path)
    if image.dtype.kind == "f":
        raise DataError("a picture is expected, this is a float (PFM) map", path=path)
    if image.dtype == np.uint16:
        image = (image // 257).astype(np.uint8)
    if image.ndim == 2:
        image = np.repeat(image[..., None], 3, axis=2)
    return image
