"""Where a configuration's body reaches, to tell which goals and regions lie in reach.

The built-in arms reach the ball of radius ``Config.reach`` around their base (the origin). A
chain (``body="chain"``, such as the MuJoCo Pusher's arm) reaches an irregular set, offset from
the origin and carved by its joint ranges: it is estimated from a dense sample of the positions
of uniformly drawn configurations, as the cells of a grid over the goal box that a sample falls
in. Cells on the boundary of the set count as reachable whole, so shares are a little high
there, and a thin part of the set may be missed (0.05 % of the Pusher's reachable positions fall
in cells the sample left empty); the grid, a 48th of the box per axis, is fine enough for the
statistics it serves. Sets are cached per body and goal box within a process.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np

from .. import _core
from ..config import Config

#: Configurations sampled for a chain, and the grid's cells per axis.
CHAIN_SAMPLES = 1_000_000
CHAIN_GRID = 48


class ReachableSet:
    """``contains(points)``: which rows of ``points`` (k, d) the body of ``config`` reaches."""

    def __init__(self, config: Config, seed: int = 0) -> None:
        self.reach = config.reach
        self.low, self.high = np.asarray(config.goal_low, float), np.asarray(config.goal_high, float)
        self.occupied: np.ndarray | None = None
        if config.chain is not None:
            self.occupied = _occupied(config.chain, float(config.joint_limit), config.goal_low, config.goal_high, seed)

    def _cells(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return _cells(points, self.low, self.high)

    def contains(self, points: Any) -> np.ndarray:
        pts = np.atleast_2d(np.asarray(points, dtype=float))
        if self.occupied is None:
            return np.sum(pts**2, axis=1) <= self.reach**2
        cells, inside = self._cells(pts)
        return inside & self.occupied[tuple(cells.T)]

    def projection(self, axes: tuple[int, int]) -> np.ndarray | None:
        """A chain's occupied cells seen along the other axes (CHAIN_GRID x CHAIN_GRID over the
        goal box's extent on ``axes``); None for a ball."""
        if self.occupied is None:
            return None
        other = tuple(i for i in range(self.occupied.ndim) if i not in axes)
        proj = self.occupied.any(axis=other) if other else self.occupied
        return proj if axes[0] < axes[1] else proj.T


def _cells(points: np.ndarray, low: np.ndarray, high: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    rel = (points - low) / (high - low)
    inside = np.all((rel >= 0) & (rel <= 1), axis=1)
    return np.clip((rel * CHAIN_GRID).astype(int), 0, CHAIN_GRID - 1), inside


@functools.lru_cache(maxsize=8)
def _occupied(chain: tuple[float, ...], limit: float, low: tuple[float, ...], high: tuple[float, ...], seed: int) -> np.ndarray:
    lo, hi = np.asarray(low, float), np.asarray(high, float)
    cloud = _core.chain_cloud(list(chain), limit, CHAIN_SAMPLES, seed)[:, : len(lo)]
    cells, inside = _cells(cloud, lo, hi)
    occupied = np.zeros((CHAIN_GRID,) * len(lo), dtype=bool)
    occupied[tuple(cells[inside].T)] = True
    occupied.flags.writeable = False
    return occupied


__all__ = ["ReachableSet", "CHAIN_SAMPLES", "CHAIN_GRID"]
