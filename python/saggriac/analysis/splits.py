"""The null model of Fig. 3's "regions split in the reachable area first" (docs/reproduction.md, "Fig. 3: where
SAGG-RIAC's goals and splits go"): where SAGG-RIAC's tree splits, against where the same tree splits when it is
fed the measurements of SAGG-Random, which chose its goals without looking at the tree.

Big regions nearly always meet the reachable area, so a share of splits "in" it means little
alone; the replayed SAGG-Random tree gives the share chance would give.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd

from ..config import Config
from ..teachers import SaggRiacSelector
from ..bodies.reachable import ReachableSet


def _dims(regions: pd.DataFrame) -> list[str]:
    return [c[len("low_") :] for c in regions.columns if c.startswith("low_")]


def replay_regions(attempts: pd.DataFrame, config: Config) -> pd.DataFrame:
    """The region tree that a SAGG-RIAC selector with ``config``'s tree parameters builds from
    the measurements of ``attempts`` (targets and competences, in order)."""
    dims = [c[len("target_") :] for c in attempts.columns if c.startswith("target_")]
    sel = SaggRiacSelector(config.goal_low, config.goal_high, g_max=config.g_max, zeta=config.zeta, min_child=config.min_child, interest_divisor=config.interest_divisor)
    told = attempts[np.isfinite(attempts["competence"].to_numpy(float))]
    if len(told):
        sel.update_batch(told[[f"target_{d}" for d in dims]].to_numpy(float), told["competence"].to_numpy(float))
    r = sel.regions()
    out: dict[str, Any] = {}
    for k, v in r.items():
        v = np.asarray(v)
        if v.ndim == 2:
            for j, d in enumerate(dims):
                out[f"{k}_{d}"] = v[:, j]
        else:
            out[k] = v
    return pd.DataFrame(out)


def reachable_share(low: np.ndarray, high: np.ndarray, reach: float | ReachableSet, grid: int = 40) -> float:
    """Share of the box [low, high] inside the ball of radius ``reach`` around the origin, or
    inside a :class:`~saggriac.bodies.reachable.ReachableSet` (midpoints of a grid of ``grid`` cells
    per side)."""
    return float(reachable_shares(np.asarray(low, float)[None, :], np.asarray(high, float)[None, :], reach, grid)[0])


def reachable_shares(lows: np.ndarray, highs: np.ndarray, reach: float | ReachableSet, grid: int = 40) -> np.ndarray:
    """:func:`reachable_share` of many boxes at once (one per row), in chunks that keep the
    grids to a few million points."""
    lows, highs = np.asarray(lows, float), np.asarray(highs, float)
    m, d = lows.shape
    out = np.empty(m)
    cells = np.arange(grid) + 0.5
    chunk = max(1, 4_000_000 // grid**d)
    if isinstance(reach, ReachableSet):
        mesh = np.stack(np.meshgrid(*([cells] * d), indexing="ij"), axis=-1).reshape(-1, d) / grid
        for i in range(m):
            out[i] = reach.contains(lows[i] + mesh * (highs[i] - lows[i])).mean()
        return out
    for start in range(0, m, chunk):
        lo, hi = lows[start : start + chunk], highs[start : start + chunk]
        # Per box and axis, the squared grid coordinates; summed over axes by broadcasting.
        sq = (lo[:, :, None] + cells[None, None, :] * (hi - lo)[:, :, None] / grid) ** 2
        r2 = np.zeros((len(lo),) + (grid,) * d)
        for j in range(d):
            shape = [len(lo)] + [1] * d
            shape[1 + j] = grid
            r2 = r2 + sq[:, j, :].reshape(shape)
        out[start : start + chunk] = (r2 <= reach * reach).reshape(len(lo), -1).mean(axis=1)
    return out


def split_shares(regions: pd.DataFrame, reach: float | ReachableSet, n_parts: int = 4) -> list[float]:
    """The splits of a tree in the order they happened, cut into ``n_parts`` equal parts; for
    each part, the mean share of the split regions' area inside the reachable ball (NaN for a
    part without splits)."""
    dims = _dims(regions)
    children = regions[regions["parent"] >= 0]
    if children.empty:
        return [float("nan")] * n_parts
    # A region was split when its children were created.
    when = children.groupby("parent")["created_at"].min().sort_values(kind="stable")
    shares = reachable_shares(regions.loc[when.index, [f"low_{d}" for d in dims]].to_numpy(float), regions.loc[when.index, [f"high_{d}" for d in dims]].to_numpy(float), reach)
    parts = np.array_split(shares, n_parts)
    return [float(p.mean()) if len(p) else float("nan") for p in parts]
