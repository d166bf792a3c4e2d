"""Colour correction fitted to a chart: a per-channel tone curve to linear RGB plus a
colour-correction matrix, as OpenCV's ``ccm`` module models it.

The matrix acts on row vectors, ``corrected = linear @ matrix`` (as OpenCV's ``ccm``);
colours are arrays of shape ``(..., 3)``, display RGB in [0, 1] and linear RGB linear
sRGB (D65) as in :mod:`mvtools.color.colorimetry`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.optimize

from mvtools.color.chart import GREY_PATCHES
from mvtools.color.colorimetry import (
    WHITE_D50,
    _colours,
    _white,
    delta_e_2000,
    gamma_to_linear,
    lab_to_linear_rgb,
    linear_rgb_to_lab,
    linear_to_srgb,
    srgb_to_linear,
    xyz_to_lab,
)
from mvtools.errors import DataError

__all__ = ["ChartCorrection", "fit_chart_correction"]

_CURVE_CODES = np.linspace(0.0, 1.0, 256)
_LINEARIZATIONS = ("gamma", "srgb", "grey-curve")
_MODELS = {"3x3": 3, "4x3": 4}


@dataclass(frozen=True)
class ChartCorrection:
    """A colour correction fitted to a chart: per-channel tone curves to linear RGB,
    a colour-correction matrix, and sRGB encoding.

    The matrix acts on row vectors, as OpenCV's ``ccm``:
    ``corrected_linear = linear @ matrix`` (3x3), or ``[linear, 1] @ matrix`` (4x3,
    affine); the result is linear sRGB (D65).

    Attributes
    ----------
    curve : ndarray, shape (3, 256)
        The linear value of each channel at display values ``0, 1/255, ..., 1``;
        linear in between.
    matrix : ndarray, shape (3, 3) or (4, 3)
    delta_e : ndarray, shape (N,)
        CIEDE2000 of each chart patch after correction.
    used : ndarray of bool, shape (N,)
        The patches the fit used: those not saturated.
    """

    curve: np.ndarray
    matrix: np.ndarray
    delta_e: np.ndarray
    used: np.ndarray

    def apply_linear(self, rgb) -> np.ndarray:
        """Corrected linear sRGB, not clipped, shape (..., 3), of display RGB (..., 3)
        in [0, 1] (values outside take the curve's end values)."""
        return _apply_matrix(_apply_curve(self.curve, _colours(rgb, "rgb")), self.matrix)

    def apply(self, rgb) -> np.ndarray:
        """Corrected display RGB: :meth:`apply_linear` clipped to [0, 1], sRGB-encoded.

        Parameters
        ----------
        rgb : array_like, shape (..., 3)
            Display RGB in [0, 1].

        Returns
        -------
        ndarray, shape (..., 3)
            float64 in [0, 1].
        """
        return linear_to_srgb(np.clip(self.apply_linear(rgb), 0.0, 1.0))


def _apply_curve(curve: np.ndarray, rgb: np.ndarray) -> np.ndarray:
    return np.stack([np.interp(rgb[..., c], _CURVE_CODES, curve[c]) for c in range(3)], axis=-1)


def _apply_matrix(linear: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    if len(matrix) == 4:
        return linear @ matrix[:3] + matrix[3]
    return linear @ matrix


def _grey_response(parameters, codes: np.ndarray) -> np.ndarray:
    gain, offset, gamma = parameters
    return srgb_to_linear(gain * np.maximum(codes - offset, 0.0) ** gamma)


def _grey_lightness_error(parameters, codes: np.ndarray, lightness: np.ndarray) -> np.ndarray:
    grey = _grey_response(parameters, codes)
    return xyz_to_lab(grey[:, None] * WHITE_D50, white=WHITE_D50)[:, 0] - lightness


def _grey_curve(
    measured: np.ndarray, reference_lab: np.ndarray, used: np.ndarray, grey_patches: Sequence[int]
) -> np.ndarray:
    """Per channel, the curve ``srgb_to_linear(a * max(v - b, 0) ** g)`` that best gives
    the unsaturated grey patches, in L*, the reference lightness as a neutral grey.

    That is the sRGB decoding after a per-channel gain, offset and gamma on display
    values: a camera whose encoding departs from sRGB by those. Three parameters, with
    ``a, g > 0``, keep the curve increasing where six points could not pin a free one.
    """
    greys = [g for g in grey_patches if used[g]]
    if len(greys) < 3:
        raise DataError(
            f"the grey-curve needs at least 3 unsaturated grey patches, got "
            f"{len(greys)} of {len(grey_patches)}"
        )
    target = reference_lab[greys, 0]
    curve = np.empty((3, _CURVE_CODES.size))
    for channel in range(3):
        values = measured[greys, channel]
        if np.ptp(values) <= 0:
            raise DataError(
                f"the grey patches all measure {values[0]:.4g} in channel "
                f"{channel}; no tone curve can be fitted"
            )
        # From the plain sRGB decoding; the offset stays below the darkest grey.
        fit = scipy.optimize.least_squares(
            _grey_lightness_error,
            x0=[1.0, min(0.0, values.min() - 1e-3), 1.0],
            args=(values, target),
            bounds=([1e-3, -1.0, 0.1], [1e3, values.min() - 1e-6, 10.0]),
        )
        curve[channel] = _grey_response(fit.x, _CURVE_CODES)
    return curve


def _mean_delta_e(parameters, linear, reference_lab, white, shape) -> float:
    corrected = _apply_matrix(linear, parameters.reshape(shape))
    return float(delta_e_2000(linear_rgb_to_lab(corrected, white=white), reference_lab).mean())


def fit_chart_correction(
    measured,
    reference_lab,
    *,
    linearization: str = "gamma",
    gamma: float = 2.2,
    model: str = "3x3",
    white=WHITE_D50,
    saturation: float = 0.98,
    grey_patches: Sequence[int] = GREY_PATCHES,
) -> ChartCorrection:
    """Fit tone curves and a colour-correction matrix that take a chart's measured
    patches to its reference colours.

    The matrix starts from the linear least-squares fit in linear RGB and is refined
    (BFGS) to minimise the mean CIEDE2000 over the patches; OpenCV's
    ``ColorCorrectionModel`` minimises their root mean square instead.

    Parameters
    ----------
    measured : array_like, shape (N, 3)
        Display RGB of the patches in [0, 1] (e.g. :func:`sample_patches` / 255).
    reference_lab : array_like, shape (N, 3)
        The patches' CIELAB relative to ``white``.
    linearization : {"gamma", "srgb", "grey-curve"}
        The per-channel tone curve to linear RGB: ``v ** gamma``
        (:func:`gamma_to_linear`), the sRGB decoding (:func:`srgb_to_linear`), or an
        increasing curve per channel fitted to the grey patches so that they come out
        neutral with the reference lightness.
    gamma : float
        The exponent of "gamma".
    model : {"3x3", "4x3"}
        A linear matrix, or an affine one (a fourth row of offsets).
    white : array_like, shape (3,)
        The white ``reference_lab`` is relative to; D50 for the published ColorChecker.
    saturation : float
        Patches with a measured channel above it are clipped: they are left out of the
        fit (OpenCV's default threshold, 0.98).
    grey_patches : sequence of int
        Indices of the grey scale for "grey-curve"; 18..23 on the ColorChecker 24.

    Returns
    -------
    ChartCorrection

    Raises
    ------
    ValueError
        Bad shapes or options, or measured values outside [0, 1].
    DataError
        Fewer unsaturated patches than the matrix has rows, or, for "grey-curve",
        fewer than 3 unsaturated greys or greys that do not vary in a channel.
    """
    measured = _colours(measured, "measured")
    reference_lab = _colours(reference_lab, "reference_lab")
    if measured.ndim != 2 or measured.shape != reference_lab.shape:
        raise ValueError(
            f"measured and reference_lab must both have shape (N, 3), got "
            f"{measured.shape} and {reference_lab.shape}"
        )
    if not np.all(np.isfinite(measured)) or measured.min() < 0 or measured.max() > 1:
        raise ValueError("measured must be display RGB in [0, 1] (8-bit codes divided by 255)")
    if not np.all(np.isfinite(reference_lab)):
        raise ValueError("reference_lab must be finite")
    if linearization not in _LINEARIZATIONS:
        raise ValueError(
            f"linearization must be one of {', '.join(_LINEARIZATIONS)}, got {linearization!r}"
        )
    if model not in _MODELS:
        raise ValueError(f"model must be one of {', '.join(_MODELS)}, got {model!r}")
    if linearization == "grey-curve" and any(not 0 <= g < len(measured) for g in grey_patches):
        raise ValueError(
            f"grey_patches must index the {len(measured)} patches, got {tuple(grey_patches)}"
        )
    white = _white(white)
    used = np.all(measured <= saturation, axis=1)
    rows = _MODELS[model]
    if used.sum() < rows:
        raise DataError(
            f"only {used.sum()} of {len(measured)} patches are at most the "
            f"saturation {saturation}; a {model} matrix needs {rows}"
        )
    if linearization == "gamma":
        curve = np.tile(gamma_to_linear(_CURVE_CODES, gamma=gamma), (3, 1))
    elif linearization == "srgb":
        curve = np.tile(srgb_to_linear(_CURVE_CODES), (3, 1))
    else:
        curve = _grey_curve(measured, reference_lab, used, grey_patches)
    linear = _apply_curve(curve, measured)
    design = linear if rows == 3 else np.column_stack([linear, np.ones(len(linear))])
    target = lab_to_linear_rgb(reference_lab, white=white)
    start, *_ = np.linalg.lstsq(design[used], target[used], rcond=None)
    fit = scipy.optimize.minimize(
        _mean_delta_e,
        start.ravel(),
        method="BFGS",
        args=(linear[used], reference_lab[used], white, start.shape),
    )
    matrix = fit.x.reshape(start.shape)
    delta_e = delta_e_2000(
        linear_rgb_to_lab(_apply_matrix(linear, matrix), white=white), reference_lab
    )
    return ChartCorrection(curve=curve, matrix=matrix, delta_e=delta_e, used=used)
