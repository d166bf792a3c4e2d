"""Typed parameters of view synthesis (VSRS) and depth estimation (DERS).

One dataclass field per configuration key of the MPEG reference programs. Each
field's metadata holds the key as the reference programs spell it, its meaning,
the values it allows and whether it names a file to read or to write. Configuration
files (read by the io layer, which imports this module and not the reverse) and
command-line options are both derived from this one table through
:func:`param_specs`, so a program's options and its configuration keys are the same
parameters. The instances hold plain values: which file, line and key gave each one
is kept beside them by the io layer's loaded configuration (``LoadedConfig``).

The instances validate themselves on construction and raise :class:`ParamError`
(a ``ValueError``) naming the configuration key at fault.

A depth range whose two values are 0 is "not given" (the reference defaults); the
programs then take it from elsewhere or refuse to run.
"""

import dataclasses
import enum
import functools
import math
import numbers
import os
from dataclasses import dataclass
from typing import Any, ClassVar

from mvtools.depth.options import DEFAULT_METHOD, VIEW_COMBINATIONS
from mvtools.geometry.depth import check_depth_range, depth_sign


class Kind(enum.Enum):
    """What a parameter's value is: a plain value, a file to read or a file to write."""

    VALUE = "value"
    INPUT_FILE = "input"
    OUTPUT_FILE = "output"


@dataclass(frozen=True)
class ParamSpec:
    """Everything the configuration reader and the command line need about one parameter.

    Attributes
    ----------
    name : str
        Field name (snake_case), e.g. ``"left_nearest_depth_value"``.
    key : str
        Configuration key as the reference programs spell it, e.g. ``"LeftNearestDepthValue"``.
    type : type
        ``int``, ``float`` or ``str`` (file names are ``str``, see ``kind``).
    default
        Value when neither the configuration file nor the command line gives one.
    help : str
        Meaning of the parameter, one line.
    choices : tuple or None
        The allowed values, when they are a short list.
    minimum, maximum : int, float or None
        Inclusive bounds (``minimum`` is exclusive when ``min_open``).
    min_open : bool
        The value must be strictly greater than ``minimum``.
    kind : Kind
        Whether the value names an input file (searched for, see
        the io layer's ``resolve_input_path``) or an output file.
    """

    name: str
    key: str
    type: type
    default: Any
    help: str
    choices: tuple | None = None
    minimum: float | None = None
    maximum: float | None = None
    min_open: bool = False
    kind: Kind = Kind.VALUE


class ParamError(ValueError):
    """An invalid parameter value.

    ``keys`` are the configuration keys involved, the one at fault first; a
    consistency error between two keys names both, so that the configuration
    reader can point at whichever of them a file gave.
    """

    def __init__(self, keys: str | tuple[str, ...], message: str):
        self.keys = (keys,) if isinstance(keys, str) else tuple(keys)
        self.key = self.keys[0]
        self.message = message
        super().__init__(f"{self.key}: {message}")


_META = "mvtools"


def _param(
    key: str,
    default: Any,
    help: str,
    *,
    choices: tuple | None = None,
    minimum: float | None = None,
    maximum: float | None = None,
    min_open: bool = False,
    kind: Kind = Kind.VALUE,
) -> Any:
    """A dataclass field carrying its configuration key and constraints."""
    meta = {
        "key": key,
        "help": help,
        "choices": choices,
        "minimum": minimum,
        "maximum": maximum,
        "min_open": min_open,
        "kind": kind,
    }
    return dataclasses.field(default=default, metadata={_META: meta})


@functools.cache
def param_specs(cls: type) -> tuple[ParamSpec, ...]:
    """The parameters of a parameter class, in configuration-file order.

    Parameters
    ----------
    cls : type
        :class:`VsrsParams` or :class:`DersParams`.

    Returns
    -------
    tuple of ParamSpec
        One entry per configuration key; a command-line program derives one
        option from each (``--`` + name with dashes, type from ``type``,
        ``choices`` or the bounds, ``help``), with ``None`` as the option's default
        so that only the options actually given override the configuration file.
    """
    return tuple(
        ParamSpec(name=f.name, type=f.type, default=f.default, **f.metadata[_META])
        for f in dataclasses.fields(cls)
        if _META in f.metadata
    )


def format_value(value: Any) -> str:
    """The configuration-file text of a value (floats exactly, as ``repr``)."""
    return repr(value) if isinstance(value, float) else str(value)


def _checked(spec: ParamSpec, value: Any) -> Any:
    """``value`` converted to ``spec.type`` and checked against the constraints."""
    if spec.type is str:
        if isinstance(value, os.PathLike):
            value = os.fspath(value)
        if not isinstance(value, str):
            raise ParamError(spec.key, f"{value!r} is not a string")
        if spec.choices is not None and value not in spec.choices:
            raise ParamError(spec.key, f"{value!r} is not one of {', '.join(spec.choices)}")
        return value
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParamError(spec.key, f"{value!r} is not a number")
    if spec.type is int:
        if not isinstance(value, numbers.Integral):
            raise ParamError(spec.key, f"{value!r} is not an integer")
        value = int(value)
    else:
        value = float(value)
        if not math.isfinite(value):
            raise ParamError(spec.key, f"{value!r} is not a finite number")
    if spec.choices is not None and value not in spec.choices:
        allowed = ", ".join(format_value(choice) for choice in spec.choices)
        raise ParamError(spec.key, f"{format_value(value)} is not one of {allowed}")
    low, high = spec.minimum, spec.maximum
    below = low is not None and (value <= low if spec.min_open else value < low)
    if below or (high is not None and value > high):
        text = format_value(value)
        if low is not None and high is not None:
            raise ParamError(spec.key, f"{text} is outside [{low}, {high}]")
        if below:
            raise ParamError(spec.key, f"{text} must be {'>' if spec.min_open else '>='} {low}")
        raise ParamError(spec.key, f"{text} must be <= {high}")
    return value


def _check_depth_range(
    near_key: str, near: float, far_key: str, far: float, depth_type: int
) -> None:
    """Check a (Znear, Zfar) pair of the depth mapping; both 0 = not given.

    The rule is :func:`mvtools.geometry.depth.check_depth_range`'s; this names the keys.
    """
    if near == 0 and far == 0:
        return
    keys = (near_key, far_key)
    if near == 0 or far == 0:
        missing = keys if near == 0 else keys[::-1]
        raise ParamError(
            missing, f"{near_key} and {far_key} must be given together (both 0 means not given)"
        )
    try:
        check_depth_range(near, far, depth_type=depth_type)
    except ValueError as error:
        raise ParamError(keys, f"{error} (with {far_key} {far:g})") from None


def _depth_range(near: float, far: float) -> tuple[float, float] | None:
    return None if near == 0 and far == 0 else (near, far)


@dataclass(frozen=True, kw_only=True)
class _ProgramParams:
    """Validation shared by the parameter classes."""

    program: ClassVar[str]

    # The keys both programs start with.
    depth_type: int = _param(
        "DepthType",
        0,
        "0: depth measured from the camera, 1: from the world origin",
        choices=(0, 1),
    )
    source_width: int = _param("SourceWidth", 1280, "frame width in pixels", minimum=1)
    source_height: int = _param("SourceHeight", 960, "frame height in pixels", minimum=1)
    start_frame: int = _param(
        "StartFrame",
        0,
        "first frame read from the inputs; the output starts at its frame 0",
        minimum=0,
    )
    total_number_of_frames: int = _param(
        "TotalNumberOfFrames", 300, "number of frames to process", minimum=1
    )

    def __post_init__(self):
        for spec in param_specs(type(self)):
            # Frozen: normalise in place (int -> float, Path -> str) before checking the whole.
            object.__setattr__(self, spec.name, _checked(spec, getattr(self, spec.name)))
        self._check_consistency()

    def _check_consistency(self) -> None:
        """Checks across parameters; raise :class:`ParamError`."""


@dataclass(frozen=True, kw_only=True)
class VsrsParams(_ProgramParams):
    """Parameters of view synthesis from two reference views, as VSRS 4.2 reads them."""

    program: ClassVar[str] = "VSRS"
    camera_file_field: ClassVar[str] = "camera_parameter_file"

    left_nearest_depth_value: float = _param(
        "LeftNearestDepthValue", 0.0, "Znear of the left depth map (depth value 255)"
    )
    left_farthest_depth_value: float = _param(
        "LeftFarthestDepthValue", 0.0, "Zfar of the left depth map (depth value 0)"
    )
    right_nearest_depth_value: float = _param(
        "RightNearestDepthValue", 0.0, "Znear of the right depth map (depth value 255)"
    )
    right_farthest_depth_value: float = _param(
        "RightFarthestDepthValue", 0.0, "Zfar of the right depth map (depth value 0)"
    )
    camera_parameter_file: str = _param(
        "CameraParameterFile",
        "cam_param.txt",
        "camera parameter file holding the real and virtual cameras",
        kind=Kind.INPUT_FILE,
    )
    left_camera_name: str = _param("LeftCameraName", "", "left camera's name in that file")
    virtual_camera_name: str = _param("VirtualCameraName", "", "virtual camera's name in that file")
    right_camera_name: str = _param("RightCameraName", "", "right camera's name in that file")
    left_view_image_name: str = _param(
        "LeftViewImageName", "", "left texture video, YUV 4:2:0 8-bit", kind=Kind.INPUT_FILE
    )
    right_view_image_name: str = _param(
        "RightViewImageName", "", "right texture video, YUV 4:2:0 8-bit", kind=Kind.INPUT_FILE
    )
    left_depth_map_name: str = _param(
        "LeftDepthMapName", "", "left depth map video", kind=Kind.INPUT_FILE
    )
    right_depth_map_name: str = _param(
        "RightDepthMapName", "", "right depth map video", kind=Kind.INPUT_FILE
    )
    output_virtual_view_image_name: str = _param(
        "OutputVirtualViewImageName", "", "synthesized view, YUV 4:2:0 8-bit", kind=Kind.OUTPUT_FILE
    )
    color_space: int = _param(
        "ColorSpace", 0, "internal colour space, 0: YUV, 1: RGB", choices=(0, 1)
    )
    precision: int = _param(
        "Precision",
        2,
        "horizontal upsampling of the references, 1: integer, 2: half, 4: quarter pixel; "
        "8, 16: eighth, sixteenth pixel (mvtools extensions)",
        choices=(1, 2, 4, 8, 16),
    )
    filter: int = _param(
        "Filter", 1, "upsampling filter, 0: bilinear, 1: bicubic, 2: AVC 6-tap", choices=(0, 1, 2)
    )
    synthesis_mode: int = _param(
        "SynthesisMode",
        0,
        "0: general (full 3D warping), 1: 1D parallel (linear rectified cameras)",
        choices=(0, 1),
    )
    boundary_noise_removal: int = _param(
        "BoundaryNoiseRemoval",
        0,
        "1: remove foreground-colour noise along disoccluded object boundaries",
        choices=(0, 1),
    )
    view_blending: int = _param(
        "ViewBlending",
        0,
        "0: blend both views, 1: take the nearer camera, the other fills its holes",
        choices=(0, 1),
    )
    depth_blend_difference: int = _param(
        "DepthBlendDifference",
        5,
        "blend only where the two warped depths differ by less than this, "
        "else take the nearer surface",
        minimum=0,
    )
    ivsrs_inpaint: int = _param(
        "IvsrsInpaint",
        1,
        "1: depth-aware (background-side) hole filling, 0: plain image inpainting",
        choices=(0, 1),
    )
    splatting_option: int = _param(
        "SplattingOption",
        2,
        "1D: splatting 0 off, 1 all pixels, 2 boundary pixels only",
        choices=(0, 1, 2),
    )
    boundary_growth: int = _param(
        "BoundaryGrowth", 40, "1D: width of the boundary band for SplattingOption 2", minimum=0
    )
    merging_option: int = _param(
        "MergingOption",
        2,
        "1D: 0 z-buffer, 1 averaging, 2 adaptive (z-buffer and averaging)",
        choices=(0, 1, 2),
    )
    depth_threshold: int = _param(
        "DepthThreshold",
        75,
        "1D: depth difference under which MergingOption 2 averages",
        minimum=0,
        maximum=255,
    )
    hole_count_threshold: int = _param(
        "HoleCountThreshold",
        30,
        "1D: hole-count difference that makes MergingOption 2 pick one view",
        minimum=0,
        maximum=49,
    )
    temporal_improvement_option: int = _param(
        "TemporalImprovementOption",
        1,
        "1D: 1 smooths the depth of static blocks over time",
        choices=(0, 1),
    )
    warp_enhancement_option: int = _param(
        "WarpEnhancementOption", 1, "1D: 1 fills one-pixel cracks after warping", choices=(0, 1)
    )
    clean_noise_option: int = _param(
        "CleanNoiseOption",
        1,
        "1D: 1 skips unreliable background-side pixels at depth edges",
        choices=(0, 1),
    )

    def _check_consistency(self) -> None:
        for side in ("Left", "Right"):
            lower = side.lower()
            _check_depth_range(
                f"{side}NearestDepthValue",
                getattr(self, f"{lower}_nearest_depth_value"),
                f"{side}FarthestDepthValue",
                getattr(self, f"{lower}_farthest_depth_value"),
                self.depth_type,
            )
        ranges = [self.left_depth_range, self.right_depth_range]
        if (
            self.depth_type == 0
            and None not in ranges
            and (len({depth_sign(*depth_range) for depth_range in ranges}) > 1)
        ):
            raise ParamError(
                ("LeftNearestDepthValue", "RightNearestDepthValue"),
                f"{ranges[0][0]:g} and {ranges[1][0]:g} "
                "have opposite signs: the two views would put the scene on "
                "opposite sides of their cameras",
            )
        if self.synthesis_mode == 1 and self.color_space != 0:
            raise ParamError(
                ("ColorSpace", "SynthesisMode"),
                "the 1D mode (SynthesisMode 1) works in YUV, ColorSpace must be 0",
            )

    @property
    def left_depth_range(self) -> tuple[float, float] | None:
        """(Znear, Zfar) of the left depth map, or None when not given."""
        return _depth_range(self.left_nearest_depth_value, self.left_farthest_depth_value)

    @property
    def right_depth_range(self) -> tuple[float, float] | None:
        """(Znear, Zfar) of the right depth map, or None when not given."""
        return _depth_range(self.right_nearest_depth_value, self.right_farthest_depth_value)


#: Methods of depth estimation, :data:`mvtools.depth.PAIR_METHODS` (named here so that
#: reading a configuration does not load the numba kernels); all but ``patchmatch``
#: also run in DERS mode.
DEPTH_METHODS = ("sgm", "bp", "graphcut", "local", "patchmatch")

#: Depth labels of an 8-bit depth map.
_MAX_DEPTH_LABELS = 256

#: DepthEstimationMode values that DERS has and mvtools does not, for the message.
_UNSUPPORTED_DEPTH_MODES = {
    1: "semi-automatic, with manual input",
    2: "semi-automatic, with manual input",
    3: "from a reference depth",
}


@dataclass(frozen=True, kw_only=True)
class DersParams(_ProgramParams):
    """Parameters of depth estimation for a center view, as DERS 6.1 reads them.

    The z search range (``NearestDepthValue`` ...) defaults to 0 = not given, the
    disparity range is used then; DERS's own defaults for it (-1, -10) are
    placeholders no run can use.
    """

    program: ClassVar[str] = "DERS"
    camera_file_field: ClassVar[str] = "file_camera_parameter"

    left_camera_name: str = _param(
        "LeftCameraName", "", "left neighbour's camera name (may be empty)"
    )
    center_camera_name: str = _param("CenterCameraName", "", "camera whose depth is estimated")
    right_camera_name: str = _param(
        "RightCameraName", "", "right neighbour's camera name (may be empty)"
    )
    file_left_view_image: str = _param(
        "FileLeftViewImage", "", "left view video, YUV 4:2:0", kind=Kind.INPUT_FILE
    )
    file_center_view_image: str = _param(
        "FileCenterViewImage", "", "center view video, YUV 4:2:0", kind=Kind.INPUT_FILE
    )
    file_right_view_image: str = _param(
        "FileRightViewImage", "", "right view video, YUV 4:2:0", kind=Kind.INPUT_FILE
    )
    file_output_depth_map_image: str = _param(
        "FileOutputDepthMapImage", "", "estimated depth video, 8-bit YUV", kind=Kind.OUTPUT_FILE
    )
    file_camera_parameter: str = _param(
        "FileCameraParameter", "", "camera parameter file", kind=Kind.INPUT_FILE
    )
    minimum_value_of_disparity_search_range: int = _param(
        "MinimumValueOfDisparitySearchRange",
        0,
        "smallest disparity searched (pixels, between the center and the BaselineBasis view)",
    )
    maximum_value_of_disparity_search_range: int = _param(
        "MaximumValueOfDisparitySearchRange", 20, "largest disparity searched (pixels)"
    )
    minimum_value_of_disparity_range: int = _param(
        "MinimumValueOfDisparityRange", 0, "disparity mapped to depth value 0 (pixels)"
    )
    maximum_value_of_disparity_range: int = _param(
        "MaximumValueOfDisparityRange", 20, "disparity mapped to depth value 255 (pixels)"
    )
    nearest_depth_value: float = _param(
        "NearestDepthValue",
        0.0,
        "Znear mapped to depth value 255, instead of the disparity range (0: not given)",
    )
    farthest_depth_value: float = _param(
        "FarthestDepthValue",
        0.0,
        "Zfar mapped to depth value 0, instead of the disparity range (0: not given)",
    )
    nearest_search_depth_value: float = _param(
        "NearestSearchDepthValue", 0.0, "nearest z searched (0: not given)"
    )
    farthest_search_depth_value: float = _param(
        "FarthestSearchDepthValue", 0.0, "farthest z searched (0: not given)"
    )
    number_of_depth_steps: int = _param(
        "NumberOfDepthSteps",
        10,
        "number of depth candidates searched in the z range",
        minimum=2,
        maximum=_MAX_DEPTH_LABELS,
    )
    smoothing_coefficient: float = _param(
        "SmoothingCoefficient", 4.0, "weight of the smoothness term", minimum=0
    )
    smoothing_coefficient2: float = _param(
        "SmoothingCoefficient2", 1.0, "smoothness weight factor across image edges", minimum=0
    )
    baseline_basis: int = _param(
        "BaselineBasis",
        1,
        "baseline the disparity range refers to: 0 shorter, 1 longer, 2 left, 3 right",
        choices=(0, 1, 2, 3),
    )
    precision: int = _param(
        "Precision",
        4,
        "horizontal upsampling of the references, 1: integer, 2: half, 4: quarter pixel",
        choices=(1, 2, 4),
    )
    search_level: float = _param(
        "SearchLevel",
        2.0,
        "disparity step = 1 / SearchLevel pixel",
        choices=(0.25, 0.5, 1.0, 2.0, 4.0),
    )
    filter: int = _param(
        "Filter", 1, "upsampling filter, 0: bilinear, 1: bicubic, 2: AVC 6-tap", choices=(0, 1, 2)
    )
    vertical_precision: int = _param(
        "VerticalPrecision",
        1,
        "vertical upsampling for the sub-pixel search, 1, 2 or 4",
        choices=(1, 2, 4),
    )
    vertical_filter: int = _param(
        "VerticalFilter",
        1,
        "vertical upsampling filter, 0: bilinear, 1: bicubic, 2: AVC 6-tap",
        choices=(0, 1, 2),
    )
    matching_method: int = _param(
        "MatchingMethod",
        2,
        "0/1 disparity shift, 2 homography (general camera geometry), 3 soft-segment, 4 epipolar",
        choices=(0, 1, 2, 3, 4),
    )
    matching_block: int = _param(
        "MatchingBlock", 1, "matching cost 1: per pixel, 3: over a 3x3 block", choices=(1, 3)
    )
    image_segmentation: int = _param(
        "ImageSegmentation", 0, "1: segment-based plane fitting of the result", choices=(0, 1)
    )
    segmentation_method: int = _param(
        "SegmentationMethod", 3, "segmentation algorithm for ImageSegmentation", minimum=0
    )
    max_cluster: int = _param("MaxCluster", 32, "largest number of segments", minimum=1)
    temporal_enhancement: int = _param(
        "TemporalEnhancement", 0, "1: temporal consistency for static regions", choices=(0, 1)
    )
    threshold: float = _param(
        "Threshold",
        0.0,
        "TemporalEnhancement: luma change under which a block counts as static",
        minimum=0,
    )
    temporal_refresh_period: int = _param(
        "TemporalRefreshPeriod",
        0,
        "TemporalEnhancement: frames that are multiples of it are estimated afresh "
        "(0: only frame 0); chunks of a run that start there need no earlier frames",
        minimum=0,
    )
    depth_estimation_mode: int = _param(
        "DepthEstimationMode",
        0,
        "0 automatic; 1, 2 semi-automatic with manual input; 3 from a reference depth",
        choices=(0, 1, 2, 3),
    )
    file_center_manual: str = _param(
        "FileCenterManual", "", "manual input of modes 1 and 2", kind=Kind.INPUT_FILE
    )
    temporal_weight: float = _param(
        "TemporalWeight",
        0.8,
        "weight of the previous frame's depth in modes 1 and 2",
        minimum=0,
        maximum=1,
    )
    ref_depth_camera_name: str = _param(
        "RefDepthCameraName", "", "camera of the reference depth of mode 3"
    )
    ref_depth_file: str = _param(
        "RefDepthFile", "", "reference depth video of mode 3", kind=Kind.INPUT_FILE
    )
    soft_distance_coeff: float = _param(
        "SoftDistanceCoeff",
        20.0,
        "soft-segment matching: spatial distance scale",
        minimum=0,
        min_open=True,
    )
    soft_color_coeff: float = _param(
        "SoftColorCoeff",
        20.0,
        "soft-segment matching: colour difference scale",
        minimum=0,
        min_open=True,
    )
    soft_block_width: int = _param(
        "SoftBlockWidth", 3, "soft-segment matching: block width", minimum=1
    )
    soft_block_height: int = _param(
        "SoftBlockHeight", 3, "soft-segment matching: block height", minimum=1
    )
    match_direction: int = _param(
        "MatchDirection",
        3,
        "neighbours matched, 1: left only, 2: right only, 3: both",
        choices=(1, 2, 3),
    )
    method: str = _param(
        "Method",
        DEFAULT_METHOD,
        "depth optimisation (mvtools extension): sgm semi-global, bp belief propagation, "
        "graphcut alpha-expansion, local guided-filter aggregation, patchmatch slanted "
        "planes (stereo pairs only)",
        choices=DEPTH_METHODS,
    )
    view_combination: str = _param(
        "ViewCombination",
        "least-cost",
        "how the neighbours combine (mvtools extension): least-cost: per depth the least "
        "cost of the views that see the point, one sweep (DERS); vote: each neighbour's "
        "own depth with its left-right check, each pixel the depth most neighbours agree "
        "on (for dense camera lines)",
        choices=VIEW_COMBINATIONS,
    )

    def _check_consistency(self) -> None:
        search = (
            self.minimum_value_of_disparity_search_range,
            self.maximum_value_of_disparity_search_range,
        )
        mapped = (self.minimum_value_of_disparity_range, self.maximum_value_of_disparity_range)
        if search[0] > search[1]:
            raise ParamError(
                ("MinimumValueOfDisparitySearchRange", "MaximumValueOfDisparitySearchRange"),
                f"disparity search range [{search[0]}, {search[1]}] is empty",
            )
        if mapped[0] >= mapped[1]:
            raise ParamError(
                ("MinimumValueOfDisparityRange", "MaximumValueOfDisparityRange"),
                f"disparity range [{mapped[0]}, {mapped[1]}] must have minimum < maximum",
            )
        if search[0] < mapped[0]:
            raise ParamError(
                ("MinimumValueOfDisparitySearchRange", "MinimumValueOfDisparityRange"),
                f"{search[0]} is below MinimumValueOfDisparityRange {mapped[0]}: "
                "the search range must lie inside the disparity range",
            )
        if search[1] > mapped[1]:
            raise ParamError(
                ("MaximumValueOfDisparitySearchRange", "MaximumValueOfDisparityRange"),
                f"{search[1]} is above MaximumValueOfDisparityRange {mapped[1]}: "
                "the search range must lie inside the disparity range",
            )
        labels = (mapped[1] - mapped[0]) * self.search_level + 1
        if labels > _MAX_DEPTH_LABELS:
            raise ParamError(
                ("MaximumValueOfDisparityRange", "SearchLevel"),
                f"disparity range [{mapped[0]}, {mapped[1]}] at SearchLevel "
                f"{format_value(self.search_level)} gives {labels:g} depth "
                f"values, an 8-bit depth map holds {_MAX_DEPTH_LABELS}",
            )
        _check_depth_range(
            "NearestDepthValue",
            self.nearest_depth_value,
            "FarthestDepthValue",
            self.farthest_depth_value,
            self.depth_type,
        )
        _check_depth_range(
            "NearestSearchDepthValue",
            self.nearest_search_depth_value,
            "FarthestSearchDepthValue",
            self.farthest_search_depth_value,
            self.depth_type,
        )
        if self.search_depth_range is not None and self.depth_range is None:
            raise ParamError(
                ("NearestSearchDepthValue", "NearestDepthValue"),
                "a z search range needs NearestDepthValue and FarthestDepthValue",
            )
        if (
            self.depth_type == 0
            and self.search_depth_range is not None
            and depth_sign(*self.search_depth_range) != depth_sign(*self.depth_range)
        ):
            raise ParamError(
                ("NearestSearchDepthValue", "NearestDepthValue"),
                f"{self.search_depth_range[0]:g} and {self.depth_range[0]:g} have "
                "opposite signs: the search would put the scene on the other "
                "side of the cameras",
            )
        mode = self.depth_estimation_mode
        if mode != 0:
            # The keys of modes 1 to 3 are read, so that DERS's files load unmodified,
            # but nothing here uses them: asking for their files would mislead.
            raise ParamError(
                "DepthEstimationMode",
                f"mode {mode} ({_UNSUPPORTED_DEPTH_MODES[mode]}) is not "
                "supported; mvtools estimates depth with mode 0 (automatic)",
            )

    @property
    def depth_range(self) -> tuple[float, float] | None:
        """(Znear, Zfar) mapped to depth values 255 and 0, or None (disparity range used)."""
        return _depth_range(self.nearest_depth_value, self.farthest_depth_value)

    @property
    def search_depth_range(self) -> tuple[float, float] | None:
        """(nearest, farthest) z searched, or None when not given."""
        return _depth_range(self.nearest_search_depth_value, self.farthest_search_depth_value)
