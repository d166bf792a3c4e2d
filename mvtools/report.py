"""A self-contained HTML page of a pipeline's results: sections of pictures, tables and
plots (inline SVG), no file names or I/O here (``mvtools report`` gathers the content).

The page counts its pictures once they have loaded and puts the count in its title
(``... : N of N pictures``), so that a headless browser can tell that all are shown.
"""

from __future__ import annotations

import base64
import html
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

__all__ = ["Picture", "Plot", "Section", "Table", "bar_plot", "html_page", "line_plot"]

_COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b")
_WIDTH, _HEIGHT, _MARGIN = 560, 300, 48


@dataclass(frozen=True)
class Picture:
    """A PNG shown with a caption."""

    caption: str
    png: bytes


@dataclass(frozen=True)
class Table:
    caption: str
    header: Sequence[str]
    rows: Sequence[Sequence[object]]


@dataclass(frozen=True)
class Plot:
    """An SVG drawing (from :func:`line_plot` or :func:`bar_plot`) with a caption."""

    caption: str
    svg: str


@dataclass
class Section:
    title: str
    items: list = field(default_factory=list)


def _format(value) -> str:
    if isinstance(value, float):
        return f"{value:.4g}" if abs(value) < 1e4 else f"{value:.0f}"
    return str(value)


def _ticks(low: float, high: float, count: int = 5) -> list[float]:
    if high <= low:
        return [low]
    step = 10 ** math.floor(math.log10((high - low) / count))
    for factor in (1, 2, 5, 10):
        if (high - low) / (step * factor) <= count:
            step *= factor
            break
    first = math.ceil(low / step) * step
    return [first + index * step for index in range(int((high - first) / step) + 1)]


def _frame(x_label: str, y_label: str, x_ticks, y_ticks, to_x, to_y, x_text=_format) -> list[str]:
    parts = [
        f'<rect x="{_MARGIN}" y="10" width="{_WIDTH - _MARGIN - 10}" '
        f'height="{_HEIGHT - _MARGIN - 10}" fill="none" stroke="#888"/>'
    ]
    for tick in x_ticks:
        parts.append(
            f'<text x="{to_x(tick):.1f}" y="{_HEIGHT - _MARGIN + 16}" font-size="11" '
            f'text-anchor="middle">{html.escape(x_text(tick))}</text>'
        )
    for tick in y_ticks:
        parts.append(
            f'<text x="{_MARGIN - 6}" y="{to_y(tick) + 4:.1f}" font-size="11" '
            f'text-anchor="end">{html.escape(_format(tick))}</text>'
        )
        parts.append(
            f'<line x1="{_MARGIN}" x2="{_WIDTH - 10}" y1="{to_y(tick):.1f}" '
            f'y2="{to_y(tick):.1f}" stroke="#eee"/>'
        )
    parts.append(
        f'<text x="{(_WIDTH + _MARGIN) / 2}" y="{_HEIGHT - 8}" font-size="12" '
        f'text-anchor="middle">{html.escape(x_label)}</text>'
    )
    parts.append(
        f'<text x="12" y="{_HEIGHT / 2}" font-size="12" text-anchor="middle" '
        f'transform="rotate(-90 12 {_HEIGHT / 2})">{html.escape(y_label)}</text>'
    )
    return parts


def _scale(low, high, start, stop):
    span = high - low or 1.0
    return lambda value: start + (value - low) / span * (stop - start)


def line_plot(
    series: dict[str, Sequence[tuple[float, float]]],
    *,
    x_label: str,
    y_label: str,
    log_x: bool = False,
) -> str:
    """An SVG plot of named point series, markers joined by lines (e.g. rate-distortion
    curves, ``log_x`` for the rate)."""
    points = [point for values in series.values() for point in values]
    if not points:
        raise ValueError("nothing to plot")
    transform = (math.log10) if log_x else (lambda x: x)
    xs = [transform(x) for x, _ in points]
    ys = [y for _, y in points]
    pad = 0.05 * ((max(ys) - min(ys)) or 1.0)
    to_x = _scale(min(xs), max(xs), _MARGIN + 10, _WIDTH - 20)
    to_y = _scale(min(ys) - pad, max(ys) + pad, _HEIGHT - _MARGIN, 20)
    x_ticks = _ticks(min(xs), max(xs))
    parts = _frame(
        x_label,
        y_label,
        x_ticks,
        _ticks(min(ys) - pad, max(ys) + pad),
        to_x,
        to_y,
        x_text=(lambda t: _format(10**t)) if log_x else _format,
    )
    for index, (name, values) in enumerate(series.items()):
        colour = _COLOURS[index % len(_COLOURS)]
        coordinates = [(to_x(transform(x)), to_y(y)) for x, y in sorted(values)]
        path = " ".join(f"{x:.1f},{y:.1f}" for x, y in coordinates)
        parts.append(f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="2"/>')
        parts += [
            f'<circle cx="{x:.1f}" cy="{y:.1f}" r="3.5" fill="{colour}"/>' for x, y in coordinates
        ]
        parts.append(
            f'<text x="{_MARGIN + 10}" y="{26 + 14 * index}" font-size="12" '
            f'fill="{colour}">{html.escape(name)}</text>'
        )
    return _svg(parts)


def bar_plot(
    groups: dict[str, Sequence[float]], *, y_label: str, series: Sequence[str] | None = None
) -> str:
    """An SVG bar chart: one group of bars per name (e.g. the reprojection error of
    each capture, per camera). Bars take the colour of their group, or with ``series``
    (names of the bars' positions in every group, e.g. one per camera in each bin of a
    histogram) the colour of their position, named in a legend."""
    values = [value for bars in groups.values() for value in bars]
    if not values:
        raise ValueError("nothing to plot")
    if series is not None and any(len(bars) > len(series) for bars in groups.values()):
        raise ValueError(f"a group has more bars than the {len(series)} series named")
    top = max(values) * 1.1 or 1.0
    count = sum(len(bars) for bars in groups.values()) + len(groups)
    width = (_WIDTH - _MARGIN - 30) / max(count, 1)
    to_y = _scale(0.0, top, _HEIGHT - _MARGIN, 20)
    parts = _frame("", y_label, [], _ticks(0.0, top), None, to_y)
    slot = 0
    for index, (name, bars) in enumerate(groups.items()):
        start = slot
        for position, value in enumerate(bars):
            colour = _COLOURS[(index if series is None else position) % len(_COLOURS)]
            x = _MARGIN + 10 + slot * width
            parts.append(
                f'<rect x="{x:.1f}" y="{to_y(value):.1f}" width="{width * 0.8:.1f}" '
                f'height="{to_y(0) - to_y(value):.1f}" fill="{colour}"/>'
            )
            slot += 1
        centre = _MARGIN + 10 + (start + slot) / 2 * width
        parts.append(
            f'<text x="{centre:.1f}" y="{_HEIGHT - _MARGIN + 16}" font-size="11" '
            f'text-anchor="middle">{html.escape(name)}</text>'
        )
        slot += 1
    for position, name in enumerate(series or ()):
        parts.append(
            f'<text x="{_WIDTH - 20}" y="{26 + 14 * position}" font-size="12" '
            f'text-anchor="end" fill="{_COLOURS[position % len(_COLOURS)]}">'
            f"{html.escape(name)}</text>"
        )
    return _svg(parts)


def _svg(parts: list[str]) -> str:
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{_WIDTH}" height="{_HEIGHT}" '
        f'viewBox="0 0 {_WIDTH} {_HEIGHT}">' + "".join(parts) + "</svg>"
    )


def _item(item) -> str:
    if isinstance(item, Picture):
        data = base64.b64encode(item.png).decode("ascii")
        return (
            f'<figure><img src="data:image/png;base64,{data}" alt="{html.escape(item.caption)}">'
            f"<figcaption>{html.escape(item.caption)}</figcaption></figure>"
        )
    if isinstance(item, Plot):
        return f"<figure>{item.svg}<figcaption>{html.escape(item.caption)}</figcaption></figure>"
    if isinstance(item, Table):
        header = "".join(f"<th>{html.escape(str(cell))}</th>" for cell in item.header)
        rows = "".join(
            "<tr>" + "".join(f"<td>{html.escape(_format(cell))}</td>" for cell in row) + "</tr>"
            for row in item.rows
        )
        return (
            f"<table><caption>{html.escape(item.caption)}</caption><tr>{header}</tr>{rows}</table>"
        )
    raise TypeError(f"cannot show a {type(item).__name__}")


_STYLE = """body{font-family:sans-serif;margin:24px;color:#222}
figure{display:inline-block;margin:8px;vertical-align:top}
figure img{max-width:480px;border:1px solid #ccc}figcaption{font-size:12px;max-width:480px}
table{border-collapse:collapse;margin:12px 0;font-size:13px}
td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}caption{font-weight:bold}"""

# Counts the pictures that have loaded and are not empty, and says so in the title.
_SCRIPT = """window.addEventListener('load', function () {
  var images = Array.prototype.slice.call(document.images);
  var shown = images.filter(function (i) { return i.complete && i.naturalWidth > 0; });
  document.title += ': ' + shown.length + ' of ' + images.length + ' pictures';
});"""


def html_page(title: str, sections: Sequence[Section]) -> str:
    """The whole page."""
    body = "".join(
        f"<h2>{html.escape(section.title)}</h2>" + "".join(map(_item, section.items))
        for section in sections
        if section.items
    )
    return (
        f'<!DOCTYPE html><html><head><meta charset="utf-8"><title>{html.escape(title)}'
        f"</title><style>{_STYLE}</style><script>{_SCRIPT}</script></head><body>"
        f"<h1>{html.escape(title)}</h1>{body}</body></html>\n"
    )
