"""Published test material made ready for scoring: files read (mvtools.io) and the
scoring rules applied (mvtools.metrics). Used by ``mvtools evaluate``, the tests and
the benchmarks, so that every one of them scores a set the same way."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from mvtools.color.space import rgb_to_yuv
from mvtools.depth.refine import fill_from_background
from mvtools.errors import UsageError
from mvtools.geometry.camera import Camera
from mvtools.geometry.depth import z_to_depth
from mvtools.io.cameras import write_cameras
from mvtools.io.config import write_config
from mvtools.io.images import read_image
from mvtools.io.middlebury import (
    MIDDLEBURY_SETS,
    check_same_size,
    read_ground_truth,
    read_nonoccluded_mask,
)
from mvtools.io.yuv import YuvFormat, frame_from_luma, write_video
from mvtools.metrics.disparity import nonoccluded_from_other_view, score_disparity
from mvtools.params import VsrsParams

__all__ = [
    "ConesCase",
    "MiddleburyGroundTruth",
    "cones_multiview",
    "ders_case_disparity",
    "ders_search_level",
    "estimate_cones_disparities",
    "fill_from_farther_neighbour",
    "load_middlebury_ground_truth",
    "middlebury_pair",
    "nonoccluded_pixels",
    "opencv_sgbm_reference",
    "score_ders_case",
    "score_middlebury",
    "write_cones_case",
    "write_hall_ders_case",
    "write_middlebury_ders_case",
]

#: Focal length (pixels) and baseline of the parallel cameras a Middlebury pair is written
#: with as a DERS case: any pair gives the same disparities, d = f B / z.
DERS_CASE_FOCAL = 1000.0
DERS_CASE_BASELINE = 1.0

#: DERS searches at most this many labels (planes): the finest SearchLevel that keeps the
#: disparity search range within it is the case's.
DERS_LABELS = 256


@dataclass(frozen=True)
class MiddleburyGroundTruth:
    """Ground truth of a set's left view, ready for scoring.

    Attributes
    ----------
    disparity : ndarray of float32, shape (H, W)
        Disparity in pixels, 0 where unknown.
    known : ndarray of bool, shape (H, W)
    nonoccluded : ndarray of bool, shape (H, W), or None
        Non-occluded known pixels; None when the set defines none.
    """

    disparity: np.ndarray
    known: np.ndarray
    nonoccluded: np.ndarray | None


def nonoccluded_pixels(
    ground_truth: np.ndarray,
    known: np.ndarray,
    *,
    scale: float,
    mask_path: str | os.PathLike | None = None,
    other_view_path: str | os.PathLike | None = None,
) -> np.ndarray | None:
    """Non-occluded known pixels, from a mask file (2003 sets) or from the other view's
    ground truth (2005 rule); None when neither is given."""
    if mask_path is not None:
        mask = read_nonoccluded_mask(mask_path)
        check_same_size(mask, ground_truth, mask_path)
        return mask & known
    if other_view_path is not None:
        other, _ = read_ground_truth(other_view_path, scale=scale)
        check_same_size(other, ground_truth, other_view_path)
        return nonoccluded_from_other_view(ground_truth, other)
    return None


def load_middlebury_ground_truth(root: str | os.PathLike, name: str) -> MiddleburyGroundTruth:
    """Ground truth, known and non-occluded pixels of one set of :data:`MIDDLEBURY_SETS`.

    Parameters
    ----------
    root : path-like
        The ``middlebury`` data folder (holding ``2001/``, ``2003/``, ...).
    name : str
        Key of :data:`MIDDLEBURY_SETS`.
    """
    if name not in MIDDLEBURY_SETS:
        raise UsageError(
            f"unknown Middlebury set; known sets: {', '.join(MIDDLEBURY_SETS)}", key=name
        )
    entry = MIDDLEBURY_SETS[name]
    root = Path(root)
    disparity, known = read_ground_truth(root / entry.ground_truth, scale=entry.scale)
    nonoccluded = nonoccluded_pixels(
        disparity,
        known,
        scale=entry.scale,
        mask_path=root / entry.nonoccluded_mask if entry.nonoccluded_mask else None,
        other_view_path=root / entry.right_ground_truth if entry.right_ground_truth else None,
    )
    return MiddleburyGroundTruth(disparity, known, nonoccluded)


# --------------------------------------------------------------------------- Cones as MVD

#: Focal length (pixels) and camera centres (x) of the Cones multiview-plus-depth case.
CONES_FOCAL = 1000.0
CONES_CENTRES = {"im2": 0.0, "im4": 2.0, "im6": 4.0}
#: Ground-truth file value / scale = disparity in pixels between im2 and im6 (baseline 4).
CONES_GT_SCALE = 4
CONES_SIZE = (448, 368)
#: Disparities searched between im2 and im6 by the Middlebury protocol.
CONES_DISPARITIES = 64


@dataclass(frozen=True)
class ConesCase:
    """Middlebury Cones (2003) as multiview-plus-depth: im4 to synthesize from im2 and im6.

    Three parallel cameras share ``K`` (f = 1000 px, principal point at the picture
    centre), ``R = I`` and centres ``x = 0, 2, 4`` for im2, im4, im6, so the im2-im6
    disparity ``d`` (ground truth / 4) gives ``z = f * 4 / d = 4000 / d``.

    Attributes
    ----------
    cameras : dict of str to Camera
        ``"im2"``, ``"im4"``, ``"im6"`` (``size`` set).
    rgb : dict of str to ndarray of uint8, shape (H, W, 3)
        The cropped pictures, im4 included (the truth to score against).
    yuv : dict of str to tuple of ndarray
        The same as 8-bit BT.601 limited-range YUV 4:2:0 planes ``(Y, U, V)``.
    disparity : dict of str to ndarray of float64, shape (H, W)
        Ground-truth disparity (pixels) of im2 and im6, unknown pixels filled
        (:func:`fill_from_farther_neighbour`).
    z : dict of str to ndarray of float64, shape (H, W)
        Depth along the camera axis of im2 and im6, ``4000 / disparity``.
    depth_range : tuple of float
        ``(Znear, Zfar)`` for 8-bit depth maps, chosen so that depth value
        ``v`` is ground-truth value ``v + min`` over the disparities of both
        maps: every ground-truth step (1/4 px) is one depth-value step, so the
        8-bit depth maps hold the ground truth without loss.
    """

    cameras: dict[str, Camera]
    rgb: dict[str, np.ndarray]
    yuv: dict[str, tuple[np.ndarray, ...]]
    disparity: dict[str, np.ndarray]
    z: dict[str, np.ndarray]
    depth_range: tuple[float, float]

    @property
    def size(self) -> tuple[int, int]:
        """(width, height)."""
        height, width = self.rgb["im4"].shape[:2]
        return width, height


def fill_from_farther_neighbour(disparity: np.ndarray, known: np.ndarray) -> np.ndarray:
    """Fill unknown disparities from the farther of their row neighbours.

    Each unknown pixel takes the smaller disparity of the nearest known pixels to
    its left and to its right in its row (the background side of an occlusion),
    or the one that exists at a row end. A row without any known pixel takes the
    smallest known disparity of the map.

    Parameters
    ----------
    disparity : ndarray, shape (H, W)
    known : ndarray of bool, shape (H, W)

    Returns
    -------
    ndarray of float64, shape (H, W)
    """
    disparity = np.asarray(disparity, dtype=np.float64)
    if not known.any():
        raise ValueError("no known disparity to fill from")
    filled = fill_from_background(disparity, known).astype(np.float64)
    return np.where(known, disparity, np.where(np.isnan(filled), disparity[known].min(), filled))


def cones_multiview(
    middlebury_root: str | os.PathLike,
    *,
    size: tuple[int, int] = CONES_SIZE,
    disparities: dict[str, np.ndarray] | None = None,
) -> ConesCase:
    """The Cones multiview-plus-depth case of the synthesis benchmarks.

    Parameters
    ----------
    middlebury_root : path-like
        The ``middlebury`` data folder (holding ``2003/cones``).
    size : (width, height)
        Crop taken from the top-left corner; the benchmark's is 448x368
        (multiples of 8, so that the reference program runs on the same input).
    disparities : dict, optional
        ``{"im2": ..., "im6": ...}``: estimated im2-im6 disparities in pixels of the
        whole pictures, shape (375, 450), finite and positive, used instead of the
        ground truth (the end-to-end case of depth estimation).

    Raises
    ------
    UsageError
        Missing files, or a crop larger than the pictures.
    """
    folder = Path(middlebury_root) / "2003" / "cones"
    width, height = size
    rgb, disparity, z = {}, {}, {}
    for name in CONES_CENTRES:
        image = read_image(folder / f"{name}.png")
        if image.ndim != 3 or width > image.shape[1] or height > image.shape[0]:
            raise UsageError(
                f"expected an RGB picture of at least {width}x{height}", path=folder / f"{name}.png"
            )
        rgb[name] = np.ascontiguousarray(image[:height, :width])
    ground_truth = {}
    for name in ("im2", "im6"):
        if disparities is None:
            path = folder / f"disp{name[-1]}.png"
            values, known = read_ground_truth(path, scale=1)
            check_same_size(values, image[..., 0], path)
            ground_truth[name] = fill_from_farther_neighbour(
                values[:height, :width], known[:height, :width]
            )
        else:
            estimate = np.asarray(disparities[name], np.float64)
            check_same_size(estimate, image[..., 0], f"{name} disparity")
            if not (np.isfinite(estimate).all() and estimate.min() > 0):
                raise ValueError(f"the {name} disparities must be finite and positive")
            # in ground-truth units, so that the depth maps quantise them the same way
            ground_truth[name] = estimate[:height, :width] * CONES_GT_SCALE
    smallest = min(values.min() for values in ground_truth.values())
    focal_baseline = CONES_FOCAL * (CONES_CENTRES["im6"] - CONES_CENTRES["im2"])
    for name, values in ground_truth.items():
        disparity[name] = values / CONES_GT_SCALE
        z[name] = focal_baseline / disparity[name]
    # Depth value v <-> ground-truth value smallest + v, i.e. 1/z linear with a step
    # of one ground-truth unit (disparities up to 255 units above the smallest).
    zfar = focal_baseline * CONES_GT_SCALE / smallest
    znear = focal_baseline * CONES_GT_SCALE / (smallest + 255)
    K = [[CONES_FOCAL, 0.0, (width - 1) / 2], [0.0, CONES_FOCAL, (height - 1) / 2], [0.0, 0.0, 1.0]]
    cameras = {
        name: Camera(name, K, t=[x, 0.0, 0.0], size=(width, height))
        for name, x in CONES_CENTRES.items()
    }
    yuv = {name: rgb_to_yuv(image, chroma="420", bits=8) for name, image in rgb.items()}
    return ConesCase(cameras, rgb, yuv, disparity, z, (float(znear), float(zfar)))


def estimate_cones_disparities(
    middlebury_root: str | os.PathLike, estimate
) -> dict[str, np.ndarray]:
    """Disparities of Cones im2 and im6 estimated from that pair alone, ready for
    :func:`cones_multiview` (the end-to-end case of depth estimation).

    Parameters
    ----------
    middlebury_root : path-like
    estimate : callable
        ``estimate(left, right, disparities)`` -> left view's disparity map, NaN where
        unknown; the right view's map is the left one of the mirrored, swapped pair.

    Returns
    -------
    dict
        ``{"im2": ..., "im6": ...}`` of float64 (375, 450); unknown values take the
        smallest disparity searched that is positive (a quarter pixel), as far as the
        depth maps reach.
    """
    folder = Path(middlebury_root) / "2003" / "cones"
    im2, im6 = (read_image(folder / f"{name}.png") for name in ("im2", "im6"))
    disparities = {
        "im2": estimate(im2, im6, CONES_DISPARITIES),
        "im6": estimate(
            np.ascontiguousarray(im6[:, ::-1]),
            np.ascontiguousarray(im2[:, ::-1]),
            CONES_DISPARITIES,
        )[:, ::-1],
    }
    smallest = 1 / CONES_GT_SCALE
    return {
        name: np.clip(np.nan_to_num(np.asarray(values, np.float64), nan=smallest), smallest, None)
        for name, values in disparities.items()
    }


def write_cones_case(case: ConesCase, folder: str | os.PathLike, **settings) -> Path:
    """Write the case as the files of a VSRS run: im4 synthesized from im2 and im6.

    Files, in ``folder``: ``im{2,4,6}_WxH_yuv420p.yuv`` (textures; im4 is the truth),
    ``im{2,6}_depth_WxH_yuv420p.yuv`` (8-bit depth, chroma 128, quantised with
    :func:`mvtools.geometry.depth.z_to_depth` and each view's Znear/Zfar),
    ``cameras.txt`` and ``synthesize_im4.cfg``, whose output is
    ``synthesized_im4_WxH_yuv420p.yuv`` relative to the folder the program runs in.

    Parameters
    ----------
    case : ConesCase
    folder : path-like
        Existing folder.
    **settings
        :class:`mvtools.params.VsrsParams` fields overriding the defaults of the
        case (e.g. ``synthesis_mode=1``, ``precision=4``, or
        ``right_nearest_depth_value`` and ``right_farthest_depth_value`` to store the
        right depth map with another range).

    Returns
    -------
    Path
        The configuration file.
    """
    folder = Path(folder)
    width, height = case.size
    texture_format = YuvFormat(width, height)
    znear, zfar = case.depth_range
    suffix = f"{width}x{height}_yuv420p.yuv"
    params = VsrsParams(
        **{
            "source_width": width,
            "source_height": height,
            "total_number_of_frames": 1,
            "left_nearest_depth_value": znear,
            "left_farthest_depth_value": zfar,
            "right_nearest_depth_value": znear,
            "right_farthest_depth_value": zfar,
            "camera_parameter_file": "cameras.txt",
            "left_camera_name": "im2",
            "virtual_camera_name": "im4",
            "right_camera_name": "im6",
            "left_view_image_name": f"im2_{suffix}",
            "right_view_image_name": f"im6_{suffix}",
            "left_depth_map_name": f"im2_depth_{suffix}",
            "right_depth_map_name": f"im6_depth_{suffix}",
            "output_virtual_view_image_name": f"synthesized_im4_{suffix}",
            **settings,
        }
    )
    write_cameras(folder / "cameras.txt", case.cameras)
    for name, planes in case.yuv.items():
        write_video(folder / f"{name}_{suffix}", texture_format, [planes])
    for name, depth_range in (("im2", params.left_depth_range), ("im6", params.right_depth_range)):
        depth = z_to_depth(case.z[name], *depth_range)
        write_video(
            folder / f"{name}_depth_{suffix}",
            texture_format,
            [frame_from_luma(texture_format, depth)],
        )
    config = folder / "synthesize_im4.cfg"
    write_config(config, params)
    return config


def middlebury_pair(root: str | os.PathLike, name: str) -> tuple[np.ndarray, np.ndarray]:
    """The left and right views of a published set as ``(H, W, 3)`` uint8 RGB."""
    entry = MIDDLEBURY_SETS[name]
    return read_image(Path(root) / entry.left), read_image(Path(root) / entry.right)


#: Region each set is judged on by the issues' protocol: all known pixels for the 2001
#: sets, non-occluded ones for the others.
SCORED_REGION = {"tsukuba": "all", "venus": "all"}


def score_middlebury(
    disparity: np.ndarray, truth: MiddleburyGroundTruth, name: str, *, threshold: float = 1.0
) -> float:
    """Bad-``threshold`` percentage of a left-view disparity map over the set's scored
    region (:data:`SCORED_REGION`, non-occluded pixels by default)."""
    score = score_disparity(
        disparity,
        truth.disparity,
        known=truth.known,
        nonoccluded=truth.nonoccluded,
        thresholds=(threshold,),
    )
    region = SCORED_REGION.get(name, "nonocc")
    return (score.bad_all if region == "all" else score.bad_nonocc)[threshold]


def opencv_sgbm_reference(left: np.ndarray, right: np.ndarray, *, disparities: int) -> np.ndarray:
    """OpenCV StereoSGBM as the issues' baseline runs it: HH mode, block 5,
    P1 = 8*3*5^2, P2 = 32*3*5^2, minDisparity 0, other options at OpenCV's defaults,
    disparity = output / 16, invalid pixels filled from the background along their row.

    Parameters
    ----------
    left, right : ndarray, shape (H, W, 3) uint8 RGB
    disparities : int
        Number of disparities searched, rounded up to a multiple of 16 as OpenCV needs.

    Returns
    -------
    ndarray of float32, shape (H, W)
    """
    matcher = cv2.StereoSGBM_create(
        minDisparity=0,
        numDisparities=-(-disparities // 16) * 16,
        blockSize=5,
        P1=8 * 3 * 25,
        P2=32 * 3 * 25,
        mode=cv2.STEREO_SGBM_MODE_HH,
    )
    raw = matcher.compute(left[:, :, ::-1], right[:, :, ::-1])
    filled = fill_from_background(raw.astype(np.float32) / 16, raw >= 0)
    return np.nan_to_num(filled, nan=0.0)


def ders_search_level(disparities: int) -> float:
    """The finest SearchLevel (4, 2, 1) whose labels over ``0 .. disparities - 1`` fit in
    :data:`DERS_LABELS`."""
    for level in (4.0, 2.0, 1.0):
        if (disparities - 1) * level + 1 <= DERS_LABELS:
            return level
    raise ValueError(f"{disparities} disparities do not fit in {DERS_LABELS} DERS labels")


def write_middlebury_ders_case(
    root: str | os.PathLike,
    name: str,
    folder: str | os.PathLike,
    *,
    left_view: str | None = None,
    further_views: Sequence[tuple[str, float]] = (),
    **settings,
) -> Path:
    """Write a published pair as the files of a DERS run: the depth of its left picture.

    The center view is the set's left picture and its right neighbour the set's right
    picture (the right camera one baseline to the right), or with ``left_view`` also a
    left neighbour one baseline to the left (Tsukuba's ``2001/tsukuba/tsukuba2.png`` for
    view 3 between views 2 and 4). Cameras: parallel, focal length
    :data:`DERS_CASE_FOCAL`, principal point at the picture centre, baseline
    :data:`DERS_CASE_BASELINE`. The disparity search range is the set's (``0 ..
    disparities - 1``) at the finest SearchLevel with at most 256 labels
    (:func:`ders_search_level`), and the output disparity range the same, written as
    16-bit depth (``estimated_depth_WxH_gray16le.yuv``) so that its quantisation does
    not count; pictures as YUV 4:2:0 8-bit (BT.601 limited range), as DERS reads them.

    Parameters
    ----------
    root : path-like
        The ``middlebury`` data folder.
    name : str
        A key of :data:`mvtools.io.middlebury.MIDDLEBURY_SETS` with a stated number of
        disparities.
    folder : path-like
        Existing folder.
    left_view : str, optional
        Path (relative to ``root``) of a left neighbour's picture.
    further_views : sequence of (str, float)
        Pictures (relative to ``root``) of further cameras on the line and their
        places in baselines (Tsukuba's ``2001/tsukuba/tsukuba1.png`` at -2): each
        camera is named after its picture's stem, in the camera file, and its video is
        ``STEM_WxH_yuv420p.yuv``, for ``--view STEM VIDEO``.
    **settings
        :class:`mvtools.params.DersParams` fields overriding the case's (``method``,
        ``image_segmentation`` ...).

    Returns
    -------
    Path
        The configuration file, ``depth.cfg``.
    """
    from mvtools.params import DersParams

    entry = MIDDLEBURY_SETS[name]
    if entry.disparities is None:
        raise ValueError(f"{name}: the set states no number of disparities")
    folder = Path(folder)
    pictures = {"center": Path(root) / entry.left, "right": Path(root) / entry.right}
    if left_view is not None:
        pictures["left"] = Path(root) / left_view
    positions = {"left": -DERS_CASE_BASELINE, "center": 0.0, "right": DERS_CASE_BASELINE}
    for picture, place in further_views:
        pictures[Path(picture).stem] = Path(root) / picture
        positions[Path(picture).stem] = place * DERS_CASE_BASELINE
    images = {side: read_image(path) for side, path in pictures.items()}
    height, width = images["center"].shape[:2]
    K = [
        [DERS_CASE_FOCAL, 0.0, (width - 1) / 2],
        [0.0, DERS_CASE_FOCAL, (height - 1) / 2],
        [0, 0, 1],
    ]
    cameras = [
        Camera(side, K, t=[positions[side], 0.0, 0.0], size=(width, height)) for side in images
    ]
    write_cameras(folder / "cameras.txt", cameras)
    texture_format = YuvFormat(width, height)
    files = {}
    for side, image in images.items():
        files[side] = f"{side}_{width}x{height}_yuv420p.yuv"
        check_same_size(image[..., 0], images["center"][..., 0], pictures[side])
        write_video(folder / files[side], texture_format, [rgb_to_yuv(image, chroma="420", bits=8)])
    top = entry.disparities - 1
    params = DersParams(
        **{
            "source_width": width,
            "source_height": height,
            "total_number_of_frames": 1,
            "left_camera_name": "left" if left_view is not None else "",
            "center_camera_name": "center",
            "right_camera_name": "right",
            "file_left_view_image": files.get("left", ""),
            "file_center_view_image": files["center"],
            "file_right_view_image": files["right"],
            "file_output_depth_map_image": f"estimated_depth_{width}x{height}_gray16le.yuv",
            "file_camera_parameter": "cameras.txt",
            "minimum_value_of_disparity_search_range": 0,
            "maximum_value_of_disparity_search_range": top,
            "minimum_value_of_disparity_range": 0,
            "maximum_value_of_disparity_range": top,
            "search_level": ders_search_level(entry.disparities),
            "match_direction": 3 if left_view is not None else 2,
            **settings,
        }
    )
    config = folder / "depth.cfg"
    write_config(config, params)
    return config


def ders_case_disparity(depth_video: str | os.PathLike) -> tuple[np.ndarray, float]:
    """The center view's disparity (pixels, towards the right neighbour) from the depth
    video of a :func:`write_middlebury_ders_case` run: its first frame's values through
    the Znear/Zfar of its sidecar (``OUTPUT.json``) to ``z``, then ``d = f B / z``
    (0 at infinity); and the disparity of one step of the coding.

    The coding rounds a disparity by up to half a step (0.0006 px for 80 disparities at
    16 bits), so an error of exactly 1 px, the bad 1.0 threshold, would count or not by
    the coding's rounding: scores of a case take ``1 + step / 2`` as the threshold
    (:func:`score_ders_case`).
    """
    from mvtools.geometry.depth import DepthCoding
    from mvtools.io.depth_sidecar import depth_sidecar_path, read_depth_sidecar
    from mvtools.io.yuv import format_from_name, read_frame

    sidecar = read_depth_sidecar(depth_sidecar_path(depth_video))
    fmt = format_from_name(depth_video)
    values = read_frame(depth_video, fmt)[0]
    coding = DepthCoding(sidecar.depth_range, fmt.bits)
    focal_baseline = DERS_CASE_FOCAL * DERS_CASE_BASELINE
    with np.errstate(divide="ignore"):
        disparity = (focal_baseline / coding.z(values)).astype(np.float32)
        near, far = (focal_baseline / z for z in coding.z(np.array([(1 << fmt.bits) - 1, 0])))
    return disparity, float(near - far) / ((1 << fmt.bits) - 1)


def score_ders_case(depth_video: str | os.PathLike, root: str | os.PathLike, name: str) -> float:
    """Bad 1.0 (%) of a :func:`write_middlebury_ders_case` run of set ``name``: its
    disparity (:func:`ders_case_disparity`) against the published ground truth over the
    set's scored region, the threshold widened by half a step of the depth coding."""
    disparity, step = ders_case_disparity(depth_video)
    truth = load_middlebury_ground_truth(root, name)
    return score_middlebury(disparity, truth, name, threshold=1.0 + step / 2)


#: Poznan Hall 2's depth range as its VSRS configurations give it (negative: the scene
#: lies at negative z of its cameras, which VSRS and DERS accept).
HALL_DEPTH_RANGE = (-23.394160, -172.531931)


def write_hall_ders_case(
    hall: str | os.PathLike, folder: str | os.PathLike, *, planes: int = 128, **settings
) -> Path:
    """Write a DERS run for the depth of Poznan Hall 2's camera 5 from camera 7 (the two
    cameras the published frame has): the sequence's camera file and depth range, the
    range searched in ``planes`` steps, the output coded with that range (8-bit, as the
    shipped depth maps), ``estimated_D_cam05_1920x1088_yuv420p.yuv`` in ``folder``.

    Parameters
    ----------
    hall : path-like
        The ``mpeg/poznan_hall2`` data folder.
    folder : path-like
        Existing folder.
    planes : int
        NumberOfDepthSteps.
    **settings
        :class:`mvtools.params.DersParams` fields overriding the case's.

    Returns
    -------
    Path
        The configuration file, ``depth_cam5.cfg``.
    """
    from mvtools.params import DersParams

    hall = Path(hall).resolve()
    nearest, farthest = HALL_DEPTH_RANGE
    params = DersParams(
        **{
            "source_width": 1920,
            "source_height": 1088,
            "total_number_of_frames": 1,
            "left_camera_name": "",
            "center_camera_name": "param_cam5",
            "right_camera_name": "param_cam7",
            "file_left_view_image": "",
            "file_center_view_image": str(hall / "hall_I_cam05.yuv"),
            "file_right_view_image": str(hall / "hall_I_cam07.yuv"),
            "file_output_depth_map_image": "estimated_D_cam05_1920x1088_yuv420p.yuv",
            "file_camera_parameter": str(hall / "config" / "VSRS" / "cam_param_poznanhall2.cfg"),
            "nearest_depth_value": nearest,
            "farthest_depth_value": farthest,
            "nearest_search_depth_value": nearest,
            "farthest_search_depth_value": farthest,
            "number_of_depth_steps": planes,
            "match_direction": 2,
            **settings,
        }
    )
    config = Path(folder) / "depth_cam5.cfg"
    write_config(config, params)
    return config
