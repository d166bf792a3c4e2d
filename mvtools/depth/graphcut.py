"""Graph-cut depth estimation as in MPEG's DERS: alpha-expansion (Boykov, Veksler & Zabih
2001) on a 4-connected grid with max-flow by PyMaxflow (Boykov-Kolmogorov), a truncated
linear (or Potts) smoothness on the label difference whose weight DERS calls
``SmoothingCoefficient``, lowered across colour edges by ``SmoothingCoefficient2``.

The smoothness weights are shared with :mod:`mvtools.depth.bp`, which minimises the same
energy by belief propagation."""

from __future__ import annotations

from collections.abc import Callable, Iterator

import maxflow
import numpy as np
from numba import njit, prange

__all__ = [
    "alpha_expansion",
    "graphcut_labels",
    "graphcut_levels",
    "graphcut_volume",
    "label_energy_levels",
    "smoothness_weights",
]

#: The ``graphcut`` method's tuning, shared by :func:`graphcut_volume` and
#: :func:`graphcut_labels` (see :func:`graphcut_volume`).
SMOOTHING = 16.0
SMOOTHING2 = 1.0
TRUNCATION = 4
COLOUR_SCALE = 10.0
CYCLES = 2


def smoothness_weights(
    cost: np.ndarray, guide: np.ndarray, *, smoothing: float, smoothing2: float, colour_scale: float
) -> tuple[np.ndarray, np.ndarray]:
    """Weights of the pairwise terms between 4-connected neighbours, DERS style.

    DERS charges ``SmoothingCoefficient`` grey levels of its 8-bit absolute-difference
    data cost per label of difference, times ``SmoothingCoefficient2`` across edges. Here
    one such grey level is 1/255 of the cost volume's range, whatever its units, and the
    edge factor goes smoothly from 1 between equal colours to ``smoothing2`` across
    strong edges: ``w = smoothing * range / 255 * (s2 + (1 - s2) exp(-|dI| / scale))``.

    Parameters
    ----------
    cost : ndarray, shape (H, W, D)
        Data costs; only their range is used.
    guide : ndarray, shape (H, W, 3)
        Colour image of the costs' view.
    smoothing : float
        DERS ``SmoothingCoefficient``, at least 0.
    smoothing2 : float
        DERS ``SmoothingCoefficient2``: the weight's factor across colour edges, at least 0.
    colour_scale : float
        Mean absolute channel difference (guide units) at which the edge factor is
        ``1/e`` of the way from 1 to ``smoothing2``; positive.

    Returns
    -------
    right : ndarray of float32, shape (H, W - 1)
        Weight between ``(y, x)`` and ``(y, x + 1)``.
    down : ndarray of float32, shape (H - 1, W)
        Weight between ``(y, x)`` and ``(y + 1, x)``.
    """
    if smoothing < 0 or smoothing2 < 0:
        raise ValueError(
            f"smoothing coefficients must be non-negative, got {smoothing} and {smoothing2}"
        )
    if colour_scale <= 0:
        raise ValueError(f"colour_scale must be positive, got {colour_scale}")
    guide = np.asarray(guide, np.float32)
    grey_level = float(np.max(cost) - np.min(cost)) / 255.0
    weights = []
    for step in (guide[:, 1:] - guide[:, :-1], guide[1:] - guide[:-1]):
        similarity = np.exp(-np.abs(step).mean(axis=2) / colour_scale)
        weights.append(
            (smoothing * grey_level * (smoothing2 + (1.0 - smoothing2) * similarity)).astype(
                np.float32
            )
        )
    return weights[0], weights[1]


# the two ends of the horizontal and of the vertical neighbour pairs
_LEFT, _RIGHT = (slice(None), slice(None, -1)), (slice(None), slice(1, None))
_TOP, _BOTTOM = (slice(None, -1), slice(None)), (slice(1, None), slice(None))


def _pairwise(first: np.ndarray, second, truncation: int) -> np.ndarray:
    return np.minimum(np.abs(first - second), truncation)


def _edge_terms(labels, alpha, right, down, truncation):
    # Per neighbour pair (p, q), q right of or below p, the pairwise energies of the
    # move: E00 (both keep), E01 (q takes alpha), E10 (p takes alpha); E11 = 0.
    terms = []
    for weight, head, tail in ((right, _LEFT, _RIGHT), (down, _TOP, _BOTTOM)):
        lp, lq = labels[head], labels[tail]
        terms.append(
            (
                head,
                tail,
                weight * _pairwise(lp, lq, truncation),
                weight * _pairwise(lp, alpha, truncation),
                weight * _pairwise(alpha, lq, truncation),
            )
        )
    return terms


def _stays(keep, take, terms):
    # Persistency: a pixel whose data cost rises by more than taking alpha can save on
    # its pairs in any configuration of its neighbours keeps its label in every
    # optimal move, so it need not enter the graph.
    bound = take - keep
    for head, tail, e00, e01, e10 in terms:
        bound[head] += np.minimum(e10 - e00, -e01)
        bound[tail] += np.minimum(e01 - e00, -e10)
    return bound > 0


def _move_energies(keep, take, terms, active):
    # Unary costs of keeping (keep) or taking alpha (take) per pixel, and the
    # active-active pairs with their capacities, by the Kolmogorov-Zabih construction:
    # E(xp, xq) = E00 + (E10 - E00) xp + (E11 - E10) xq + (E01 + E10 - E00 - E11)(1 - xp) xq;
    # the last coefficient is >= 0 because the truncated linear term is a metric.
    keep = keep.copy()
    take = take.copy()
    edges = []
    for head, tail, e00, e01, e10 in terms:
        ap, aq = active[head], active[tail]
        both = ap & aq
        only_p, only_q = ap & ~aq, aq & ~ap
        # an inactive neighbour keeps its label: the term is unary on the active pixel
        keep[head] += np.where(only_p | both, e00, 0.0)
        take[head] += np.where(only_p | both, e10, 0.0)
        keep[tail] += np.where(only_q, e00, 0.0)
        take[tail] += np.where(only_q, e01, np.where(both, -e10, 0.0))
        edges.append((head, tail, both, (e01 + e10 - e00)[both]))
    return keep, take, edges


def _expansion_move(alpha_cost, labels, current, alpha, right, down, truncation):
    # One alpha-expansion move; updates labels and current (each pixel's data cost) in
    # place and returns the energy change; alpha_cost: the (H, W) costs of level alpha.
    keep = current.astype(np.float64)
    take = alpha_cost.astype(np.float64)
    terms = _edge_terms(labels, alpha, right, down, truncation)
    active = (labels != alpha) & ~_stays(keep, take, terms)
    count = int(active.sum())
    if count == 0:
        return 0.0
    keep, take, edges = _move_energies(keep, take, terms, active)
    index = np.full(labels.shape, -1, np.int64)
    index[active] = np.arange(count)
    graph = maxflow.GraphFloat(count, 2 * count)
    nodes = graph.add_nodes(count)
    for head, tail, both, capacity in edges:
        graph.add_edges(index[head][both], index[tail][both], capacity, np.zeros_like(capacity))
    keep_active, take_active = keep[active], take[active]
    lower = np.minimum(keep_active, take_active)
    # sink capacity is paid when the node stays on the source side (keeps its label)
    graph.add_grid_tedges(nodes, take_active - lower, keep_active - lower)
    graph.maxflow()
    expand = graph.get_grid_segments(nodes)
    change = float(np.sum(np.where(expand, take_active, keep_active)) - keep_active.sum())
    for head, tail, both, capacity in edges:
        # the (1 - xp) xq edge term, not part of the unaries
        xp = expand[index[head][both]]
        xq = expand[index[tail][both]]
        change += float(capacity[~xp & xq].sum())
    if change >= 0.0:
        return 0.0
    where = np.zeros(labels.shape, bool)
    where[active] = expand
    labels[where] = alpha
    current[where] = alpha_cost[where]
    return change


def alpha_expansion(
    cost: np.ndarray, right: np.ndarray, down: np.ndarray, *, truncation: int, cycles: int = 2
) -> np.ndarray:
    """Labels minimising ``sum_p C(p, f_p) + sum_pq w_pq min(|f_p - f_q|, truncation)``
    by alpha-expansion from the winner-takes-all labels.

    Parameters
    ----------
    cost : ndarray, shape (H, W, D)
        Data costs.
    right, down : ndarray, shapes (H, W - 1) and (H - 1, W)
        Non-negative weights of the horizontal and vertical neighbour pairs.
    truncation : int
        Largest charged label difference; 1 gives the Potts model.
    cycles : int
        Sweeps over all labels (DERS makes 2); stops early after a sweep that changed
        nothing.

    Returns
    -------
    ndarray of int64, shape (H, W)
    """
    cost = np.asarray(cost, np.float32)
    rows, cols, levels = cost.shape
    if right.shape != (rows, cols - 1) or down.shape != (rows - 1, cols):
        raise ValueError(
            f"weights of shapes {right.shape} and {down.shape} do not fit a {rows}x{cols} grid"
        )
    if truncation < 1 or cycles < 1:
        raise ValueError(f"truncation and cycles must be at least 1, got {truncation} and {cycles}")
    labels = np.argmin(cost, axis=2)
    current = np.min(cost, axis=2)
    # each level gathered from the (H, W, D) volume: a transposed copy would be a
    # second volume
    return _expand(
        lambda alpha: np.ascontiguousarray(cost[:, :, alpha]),
        levels,
        labels,
        current,
        right,
        down,
        truncation,
        cycles,
    )


def _expand(level_cost, levels, labels, current, right, down, truncation, cycles):
    right = right.astype(np.float64)
    down = down.astype(np.float64)
    for _ in range(cycles):
        improved = False
        for alpha in range(levels):
            change = _expansion_move(
                level_cost(alpha), labels, current, alpha, right, down, truncation
            )
            improved = improved or change < 0.0
        if not improved:
            break
    return labels


def graphcut_labels(
    level_cost: Callable[[int], np.ndarray],
    levels: int,
    guide: np.ndarray,
    *,
    smoothing: float = SMOOTHING,
    smoothing2: float = SMOOTHING2,
    truncation: int = TRUNCATION,
    colour_scale: float = COLOUR_SCALE,
    cycles: int = CYCLES,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The expansion of :func:`graphcut_volume` from the costs of one level at a time.

    The same labels as ``graphcut_volume`` on the volume whose level ``k`` is
    ``level_cost(k)``, without holding that volume: the weights' cost range and the
    winner-takes-all start are gathered level by level, each move asks for its level.

    Parameters
    ----------
    level_cost : callable
        ``level_cost(k)`` gives the (H, W) float32 costs of level ``k``, the same at
        every call (e.g. :func:`mvtools.depth.cost.ad_census_levels`).
    levels : int
        Number of levels D.
    guide, smoothing, smoothing2, truncation, colour_scale, cycles
        As for :func:`graphcut_volume`.

    Returns
    -------
    labels : ndarray of int64, shape (H, W)
    right, down : ndarray of float32, shapes (H, W - 1) and (H - 1, W)
        The smoothness weights (:func:`smoothness_weights`), for :func:`label_energies`.
    """
    if levels < 1 or truncation < 1 or cycles < 1:
        raise ValueError(
            f"levels, truncation and cycles must be at least 1, got "
            f"{levels}, {truncation} and {cycles}"
        )
    current = np.array(level_cost(0), np.float32)
    labels = np.zeros(current.shape, np.int64)
    lowest, highest = current.min(), current.max()
    for k in range(1, levels):
        costs = np.asarray(level_cost(k), np.float32)
        lowest, highest = min(lowest, costs.min()), max(highest, costs.max())
        # strictly lower: the first level of least cost, as argmin takes it
        lower = costs < current
        labels[lower] = k
        current[lower] = costs[lower]
    right, down = smoothness_weights(
        np.array([lowest, highest], np.float32),
        guide,
        smoothing=smoothing,
        smoothing2=smoothing2,
        colour_scale=colour_scale,
    )
    labels = _expand(level_cost, levels, labels, current, right, down, truncation, cycles)
    return labels, right, down


@njit(cache=True, nogil=True, parallel=True)
def _label_energies(cost, first, labels, right, down, truncation, volume):
    # cost holds levels first, first + 1, ...; each element is read before it is
    # written, so volume may be cost itself
    rows, cols, levels = cost.shape
    for y in prange(rows):
        for x in range(cols):
            for i in range(levels):
                d = first + i
                total = cost[y, x, i]
                if x > 0:
                    total += right[y, x - 1] * min(abs(d - labels[y, x - 1]), truncation)
                if x < cols - 1:
                    total += right[y, x] * min(abs(d - labels[y, x + 1]), truncation)
                if y > 0:
                    total += down[y - 1, x] * min(abs(d - labels[y - 1, x]), truncation)
                if y < rows - 1:
                    total += down[y, x] * min(abs(d - labels[y + 1, x]), truncation)
                volume[y, x, i] = total
    return volume


def label_energies(
    cost: np.ndarray,
    labels: np.ndarray,
    right: np.ndarray,
    down: np.ndarray,
    truncation: int,
    *,
    out: np.ndarray | None = None,
) -> np.ndarray:
    """Each level's energy at each pixel given its neighbours' labels.

    ``volume[y, x, d] = cost[y, x, d] + sum_q w_pq min(|d - f_q|, truncation)`` over the
    4 neighbours ``q``.

    Parameters
    ----------
    cost : ndarray of float32, shape (H, W, D)
    labels : ndarray of int64, shape (H, W)
    right, down : ndarray of float32, shapes (H, W - 1) and (H - 1, W)
    truncation : int
    out : ndarray of float32, shape (H, W, D), optional
        Where to write the energies; it may be ``cost`` itself (in place).

    Returns
    -------
    ndarray of float32, shape (H, W, D)
        ``out`` if given.
    """
    volume = np.empty_like(cost) if out is None else out
    return _label_energies(cost, 0, labels, right, down, truncation, volume)


#: Bytes of one level chunk of :func:`label_energy_levels` (a few levels of a large frame).
_CHUNK_BYTES = 1 << 24


def label_energy_levels(
    levels: Callable[[int, int], np.ndarray],
    count: int,
    labels: np.ndarray,
    right: np.ndarray,
    down: np.ndarray,
    truncation: int,
) -> Iterator[tuple[int, np.ndarray]]:
    """:func:`label_energies` a few levels at a time, from costs given a few levels at a
    time, so that neither volume is held whole.

    Parameters
    ----------
    levels : callable
        ``levels(start, stop)`` gives the (H, W, stop - start) float32 costs of levels
        ``start`` to ``stop`` (:data:`mvtools.depth.local.LevelSlices`).
    count : int
        Number of levels D.
    labels, right, down, truncation
        As for :func:`label_energies`.

    Returns
    -------
    iterator of (int, ndarray of float32, shape (H, W, n))
        The first level of each chunk and its energies, in order of level.
    """
    chunk = max(1, _CHUNK_BYTES // max(1, labels.size * 4))

    def chunks():
        for start in range(0, count, chunk):
            costs = np.ascontiguousarray(levels(start, min(start + chunk, count)), np.float32)
            # not in place: the chunk may be a view of the caller's costs
            energies = np.empty_like(costs)
            yield start, _label_energies(costs, start, labels, right, down, truncation, energies)

    return chunks()


def graphcut_levels(
    levels: Callable[[int, int], np.ndarray],
    count: int,
    guide: np.ndarray,
    *,
    smoothing: float = SMOOTHING,
    smoothing2: float = SMOOTHING2,
    truncation: int = TRUNCATION,
    colour_scale: float = COLOUR_SCALE,
    cycles: int = CYCLES,
) -> Iterator[tuple[int, np.ndarray]]:
    """The ``graphcut`` method's volume a few levels at a time, from costs given a few
    levels at a time, so that neither is held whole: the expansion asks for one level
    at a time (:func:`graphcut_labels`), then the label energies come in chunks
    (:func:`label_energy_levels`), those of :func:`graphcut_volume` bit for bit.

    Parameters
    ----------
    levels : callable
        ``levels(start, stop)`` gives the (H, W, stop - start) float32 costs of levels
        ``start`` to ``stop``, the same at every call
        (:data:`mvtools.depth.local.LevelSlices`).
    count : int
        Number of levels D.
    guide, smoothing, smoothing2, truncation, colour_scale, cycles
        As for :func:`graphcut_volume`.

    Returns
    -------
    iterator of (int, ndarray of float32, shape (H, W, n))
        The first level of each chunk and its label energies, in order of level; the
        expansion runs before the first chunk.
    """
    labels, right, down = graphcut_labels(
        lambda k: levels(k, k + 1)[:, :, 0],
        count,
        guide,
        smoothing=smoothing,
        smoothing2=smoothing2,
        truncation=truncation,
        colour_scale=colour_scale,
        cycles=cycles,
    )
    return label_energy_levels(levels, count, labels, right, down, int(truncation))


def graphcut_volume(
    cost: np.ndarray,
    guide: np.ndarray,
    *,
    smoothing: float = SMOOTHING,
    smoothing2: float = SMOOTHING2,
    truncation: int = TRUNCATION,
    colour_scale: float = COLOUR_SCALE,
    cycles: int = CYCLES,
    overwrite: bool = False,
) -> np.ndarray:
    """The ``graphcut`` method: DERS's alpha-expansion, returned as label energies.

    Every move's graph is built with whole-array operations; pixels that keep their
    label in every optimal move (a persistency bound on their data cost gap) stay out
    of it: smaller graphs, the same optimal move.

    Parameters
    ----------
    cost : ndarray of float32, shape (H, W, D)
        Matching costs, e.g. AD-census in [0, 2].
    guide : ndarray, shape (H, W, 3)
        The view the costs belong to.
    smoothing, smoothing2 : float
        DERS ``SmoothingCoefficient`` and ``SmoothingCoefficient2``
        (:func:`smoothness_weights`).
    truncation : int
        Largest charged label difference; 1 is the Potts model.
    colour_scale : float
        Colour difference scale of the edge factor.
    cycles : int
        See :func:`alpha_expansion`.
    overwrite : bool
        Write the result into ``cost`` (a contiguous float32 volume), which is then lost:
        one volume in memory instead of two.

    Returns
    -------
    ndarray of float32, shape (H, W, D)
        :func:`label_energies` of the expansion's labels: its per-pixel minimum is the
        graph-cut label (alpha-expansion ends where no single pixel can lower the
        energy, up to ties), and along the diagonals it scores the right view.
    """
    cost = np.ascontiguousarray(cost, dtype=np.float32)
    right, down = smoothness_weights(
        cost, guide, smoothing=smoothing, smoothing2=smoothing2, colour_scale=colour_scale
    )
    labels = alpha_expansion(cost, right, down, truncation=truncation, cycles=cycles)
    return label_energies(
        cost, labels, right, down, int(truncation), out=cost if overwrite else None
    )
