"""The null model of Fig. 3's "regions split in the reachable area first" (SPEC "What every run
and study reports"): where SAGG-RIAC's tree splits, against where the same tree splits when it is
fed the measurements of SAGG-Random, which chose its goals without looking at the tree.

Big regions nearly always meet the reachable area, so a share of splits "in" it means little
alone; the replayed SAGG-Random tree gives the share chance would give.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd

from .config import Config
from .goal_selection import SaggRiacSelector


def _dims(regions: pd.DataFrame) -> list[str]:
    return [c[len("low_") :] for c in regions.columns if c.startswith("low_")]


def replay_regions(attempts: pd.DataFrame, config: Config) -> pd.DataFrame:
    """The region tree that a SAGG-RIAC selector with ``config``'s tree parameters builds from
    the measurements of ``attempts`` (targets and competences, in order)."""
    dims = [c[len("target_") :] for c in attempts.columns if c.startswith("target_")]
    sel = SaggRiacSelector(config.goal_low, config.goal_high, g_max=config.g_max, zeta=config.zeta, min_child=config.min_child)
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


def reachable_share(low: np.ndarray, high: np.ndarray, reach: float, grid: int = 40) -> float:
    """Share of the box [low, high] inside the ball of radius ``reach`` around the origin
    (midpoints of a grid of ``grid`` cells per side)."""
    axes = [lo + (np.arange(grid) + 0.5) * (hi - lo) / grid for lo, hi in zip(low, high)]
    mesh = np.meshgrid(*axes, indexing="ij")
    r2 = sum(m**2 for m in mesh)
    return float((r2 <= reach * reach).mean())


def split_shares(regions: pd.DataFrame, reach: float, n_parts: int = 4) -> list[float]:
    """The splits of a tree in the order they happened, cut into ``n_parts`` equal parts; for
    each part, the mean share of the split regions' area inside the reachable ball (NaN for a
    part without splits)."""
    dims = _dims(regions)
    children = regions[regions["parent"] >= 0]
    if children.empty:
        return [float("nan")] * n_parts
    # A region was split when its children were created.
    when = children.groupby("parent")["created_at"].min().sort_values(kind="stable")
    shares = [reachable_share(regions.loc[p, [f"low_{d}" for d in dims]].to_numpy(float), regions.loc[p, [f"high_{d}" for d in dims]].to_numpy(float), reach) for p in when.index]
    parts = np.array_split(np.asarray(shares), n_parts)
    return [float(p.mean()) if len(p) else float("nan") for p in parts]
