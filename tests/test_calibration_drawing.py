"""The report picture of a calibration: circles at the detected corners, magnified error lines."""

from __future__ import annotations

import numpy as np
import pytest

from mvtools.calibration.drawing import draw_corners


def test_corner_circle_and_magnified_error_line():
    image = np.full((40, 60), 200, np.uint8)
    found = np.array([[20.0, 20.0]])
    # 0.5 px to the right, drawn 20 times as long: a red line from x 20 to x 30
    picture = draw_corners(image, [found], [found + [0.5, 0.0]], error_scale=20.0)
    assert picture.shape == (40, 60, 3)
    assert tuple(picture[5, 5]) == (100, 100, 100)  # background at half brightness
    red = picture[20, 22:29]
    assert np.all(red[:, 0] > 200) and np.all(red[:, 1] < 120)  # the error line
    green = picture[17, 20]  # the circle, radius 3 px
    assert green[1] > 150 and green[0] < green[1]
    assert np.all(picture[20, 33:] == 100)  # nothing beyond the line's end


def test_mismatched_corner_sets_are_refused():
    with pytest.raises(ValueError, match="2 detected"):
        draw_corners(np.zeros((4, 4), np.uint8), [np.zeros((1, 2))] * 2, [np.zeros((1, 2))])
