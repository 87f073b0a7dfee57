"""Figures in the manner of the paper: learning curves (Fig. 4 and 5), goal histograms with the
region tree over time (Fig. 3; the boundary of the reachable disk in cyan; a 3-D goal space is
shown in its (x, y) and (x, z) projections) and the arm with the quantities of the competence
(Fig. 2; in 3-D for the spatial arm).
Matplotlib's object API only (no pyplot state), so figures can be made in worker processes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.figure import Figure
from matplotlib.patches import Arc, Patch, Rectangle
from matplotlib.ticker import FuncFormatter

from .. import _core
from ..config import Config
from ..files import write_file
from ..bodies.reachable import ReachableSet

PNG = b"\x89PNG\r\n\x1a\n"
#: Written into every figure's PNG metadata, so that saggriac recognises its own files.
MARK = "saggriac"


def _ours(path: Path) -> bool:
    """A PNG saggriac wrote: it carries the mark, or it sits in a study folder's figures/ (made
    before figures were marked)."""
    try:
        with open(path, "rb") as f:
            head = f.read(4096)
    except OSError:
        return False
    if not head.startswith(PNG):
        return False
    return MARK.encode() in head or (path.parent.name == "figures" and (path.parent.parent / "study.json").is_file())


def write_png(fig: Figure, path: str | Path, dpi: int, title: str = "") -> Path:
    """Save ``fig`` as a PNG at ``path`` atomically; an existing file is replaced only if it is a
    figure saggriac wrote."""
    meta = {"Software": f"{MARK} {_core.__version__}", **({"Title": title} if title else {})}
    return write_file(Path(path), lambda tmp: fig.savefig(tmp, dpi=dpi, format="png", metadata=meta), what="a figure", overwrite=True, ours=_ours)

LABELS = {
    "sagg_riac": "SAGG-RIAC",
    "sagg_random": "SAGG-Random",
    "actuator_random": "ACTUATOR-Random",
    "actuator_riac": "ACTUATOR-RIAC",
}
SD_BAND_LABEL = "shaded: mean \u00b1 1 sd over seeds"
METRIC_TITLES = {
    "reach_error": "reaching error (distance goal - end effector)",
    "pred_error": "prediction error (end-effector position)",
    "dx_error": "relative error of the learnt dx = J dtheta",
}
# What each metric is without learning: its value at step 0 (nothing stored: no motion, the
# origin predicted), except dx_error, whose no-motion prediction is 1 by definition.
NO_LEARNING_LABEL = "no learning"


def _no_learning(sel: pd.DataFrame, metric: str) -> float | None:
    if metric == "dx_error":
        return 1.0
    start = sel[sel["step"] == 0]["value"]
    return float(start.mean()) if len(start) else None


def curves_figure(frame: pd.DataFrame, title: str = "", step_unit: str = "micro-actions") -> Figure:
    """Mean +- one standard deviation over seeds of each metric against time steps, one line per
    condition; the legend says what the shaded band is."""
    metrics = [m for m in METRIC_TITLES if m in set(frame["metric"])] or ["reach_error", "pred_error"]
    fig = Figure(figsize=(5.5 * len(metrics), 4.2), layout="constrained")
    axes = fig.subplots(1, len(metrics), squeeze=False)[0]
    conditions = [c for c in LABELS if c in set(frame["condition"])] + sorted(set(frame["condition"]) - set(LABELS))
    for ax, metric in zip(axes, metrics):
        sel = frame[frame["metric"] == metric]
        reference = _no_learning(sel, metric)
        if reference is not None:
            ax.axhline(reference, color="0.35", linestyle="--", linewidth=1.0, label=NO_LEARNING_LABEL)
        for i, cond in enumerate(conditions):
            g = sel[sel["condition"] == cond].groupby("step")["value"]
            mean, std, n = g.mean(), g.std(ddof=1).fillna(0.0), g.count()
            steps = mean.index.to_numpy()
            (line,) = ax.plot(steps, mean.to_numpy(), label=f"{LABELS.get(cond, cond)} (n={int(n.max())})")
            # Shade +- std, as the paper's error bars.
            ax.fill_between(steps, (mean - std).to_numpy(), (mean + std).to_numpy(), color=line.get_color(), alpha=0.15, linewidth=0)
        ax.set_xlabel(f"time steps ({step_unit})")
        # 200000 and its neighbours overlap as plain numbers: 50k, 100k, ...
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v / 1000:g}k" if v else "0"))
        ax.set_ylabel(METRIC_TITLES[metric])
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
    handles, _ = axes[0].get_legend_handles_labels()
    band = Patch(facecolor="0.5", alpha=0.3, linewidth=0, label=SD_BAND_LABEL)
    axes[0].legend(handles=[*handles, band], fontsize=8)
    if title:
        fig.suptitle(title)
    return fig


def plot_curves(frame: pd.DataFrame, path: str | Path, title: str = "", step_unit: str = "micro-actions") -> Path:
    """Write :func:`curves_figure` to ``path`` (PNG; its title is also kept as the file's
    ``Title`` metadata)."""
    path = Path(path)
    write_png(curves_figure(frame, title, step_unit), path, dpi=120, title=title)
    return path


def _leaves_at(regions: pd.DataFrame, n_measurements: int) -> pd.DataFrame:
    """Leaves of the region tree when it held `n_measurements` measurements."""
    alive = regions[regions["created_at"] <= n_measurements]
    parents_split = set(alive["parent"][alive.index != 0].astype(int)) if len(alive) else set()
    ids = [i for i in alive.index if i not in parents_split]
    return regions.loc[ids]


def goal_histograms_figure(run_dir: str | Path, n_windows: int = 4, bins: int = 40) -> Figure:
    """Histograms of the self-generated goals over windows of goal indices, with the regions
    existing at the end of each window (white) and the boundary of the reachable disk (cyan),
    drawn to scale (equal aspect: the half-disk of exp1 looks like one). A 3-D goal space gets
    two rows of panels: its (x, y) and (x, z) projections; a 1-D one gets plain histograms with
    the region boundaries as vertical lines."""
    from ..runs.result import RunResult

    res = RunResult.load(run_dir)
    cfg = res.config
    goals, attempts, regions = res.goals, res.attempts, res.regions.reset_index(drop=True)
    if len(cfg.goal_low) == 1:
        return _goal_histograms_1d(res, n_windows, bins)
    # Planes shown, as pairs of coordinate names; a projection of the ball is its disk.
    planes = [("x", "y")] if len(cfg.goal_low) == 2 else [("x", "y"), ("x", "z")]
    axis_index = {"x": 0, "y": 1, "z": 2}
    cols = min(n_windows, 4)
    rows_per_plane = (n_windows + 3) // 4
    # Size each panel to the goal space's shape so that the equal-aspect panels fill it: a fixed
    # height, the width that keeps the scale (within limits that leave room for the titles).
    width_per_height = max((cfg.goal_high[axis_index[u]] - cfg.goal_low[axis_index[u]]) / (cfg.goal_high[axis_index[w]] - cfg.goal_low[axis_index[w]]) for u, w in planes)
    panel_h = 3.4
    panel_w = float(np.clip(panel_h * width_per_height, 2.0, 6.0))
    n_rows = rows_per_plane * len(planes)
    fig = Figure(figsize=(cols * (panel_w + 0.8), n_rows * (panel_h + (1.1 if len(planes) > 1 else 0.9)) + 0.4), layout="constrained")
    grid = np.atleast_2d(fig.subplots(n_rows, cols, squeeze=False))
    edges, windows = _window_bounds(len(goals), n_windows)
    reach = cfg.reach
    reachable = ReachableSet(cfg) if cfg.chain is not None else None
    for p, (u, w) in enumerate(planes):
        iu, iw = axis_index[u], axis_index[w]
        lo, hi = (cfg.goal_low[iu], cfg.goal_low[iw]), (cfg.goal_high[iu], cfg.goal_high[iw])
        axes = grid[p * rows_per_plane : (p + 1) * rows_per_plane].ravel()
        for k, ax in enumerate(axes):
            if k + 1 >= len(edges):
                ax.set_axis_off()
                continue
            start, end = windows[k]
            sel = goals[(goals["goal_index"] >= start) & (goals["goal_index"] < end)]
            h, _, _ = np.histogram2d(sel[f"goal_{u}"], sel[f"goal_{w}"], bins=bins, range=[[lo[0], hi[0]], [lo[1], hi[1]]])
            ax.imshow(h.T, origin="lower", extent=(lo[0], hi[0], lo[1], hi[1]), cmap="inferno", aspect="equal", interpolation="nearest")
            if len(regions) and "created_at" in regions:
                n_meas = int((attempts["goal_index"] < end).sum()) if len(attempts) else 0
                for _, r in _leaves_at(regions, n_meas).iterrows():
                    ax.add_patch(Rectangle((r[f"low_{u}"], r[f"low_{w}"]), r[f"high_{u}"] - r[f"low_{u}"], r[f"high_{w}"] - r[f"low_{w}"], fill=False, edgecolor="white", linewidth=0.6))
            if reachable is None:
                # The whole reachable circle; the axis limits clip it to the goal space.
                ax.add_patch(Arc((0, 0), 2 * reach, 2 * reach, theta1=0, theta2=360, edgecolor="cyan", linewidth=1.5))
            else:
                # A chain's reachable set, projected: the outline of its occupied cells.
                proj = reachable.projection((iu, iw)).astype(float)
                ax.contour(proj.T, levels=[0.5], colors="cyan", linewidths=1.5, extent=(lo[0], hi[0], lo[1], hi[1]), origin="lower")
            ax.set_xlim(lo[0], hi[0])
            ax.set_ylim(lo[1], hi[1])
            ax.set_aspect("equal")
            ax.set_xlabel(u)
            ax.set_ylabel(w)
            ax.set_title(_window_title(windows, k) + (f"\n({u}, {w}) projection" if len(planes) > 1 else ""), fontsize=10)
    fig.suptitle(f"{LABELS.get(cfg.condition, cfg.condition)}, seed {res.seed}: self-generated goals and regions")
    return fig


def plot_goal_histograms(run_dir: str | Path, path: str | Path, n_windows: int = 4, bins: int = 40) -> Path:
    """Write :func:`goal_histograms_figure` of the run in ``run_dir`` to ``path`` (PNG)."""
    path = Path(path)
    write_png(goal_histograms_figure(run_dir, n_windows, bins), path, dpi=110)
    return path


def _window_title(windows: list[tuple[int, int]], k: int) -> str:
    start, end = windows[k]
    # The last panel holds every goal (see _window_bounds).
    return f"all goals (0-{end})" if k == len(windows) - 1 and k > 0 else f"goals {start}-{end}"


def _window_bounds(n_goals: int, n_windows: int) -> tuple[np.ndarray, list[tuple[int, int]]]:
    edges = np.unique(np.linspace(0, n_goals, n_windows + 1).round().astype(int))
    # The last window shows all goals, as in the paper's last panel.
    return edges, [(0, edges[-1]) if k == len(edges) - 2 and k > 0 else (edges[k], edges[k + 1]) for k in range(len(edges) - 1)]


def _goal_histograms_1d(res, n_windows: int, bins: int) -> Figure:
    cfg, goals, attempts, regions = res.config, res.goals, res.attempts, res.regions.reset_index(drop=True)
    lo, hi = cfg.goal_low[0], cfg.goal_high[0]
    _, windows = _window_bounds(len(goals), n_windows)
    fig = Figure(figsize=(4.0 * max(len(windows), 1), 3.5), layout="constrained")
    for k, (start, end) in enumerate(windows):
        ax = fig.add_subplot(1, len(windows), k + 1)
        sel = goals[(goals["goal_index"] >= start) & (goals["goal_index"] < end)]
        ax.hist(sel["goal_x"], bins=bins, range=(lo, hi), color="0.3")
        if len(regions) and "created_at" in regions:
            n_meas = int((attempts["goal_index"] < end).sum()) if len(attempts) else 0
            for v in sorted(set(_leaves_at(regions, n_meas)["low_x"]) - {lo}):
                ax.axvline(v, color="tab:orange", linewidth=0.6)
        ax.set_xlim(lo, hi)
        ax.set_xlabel("x")
        ax.set_ylabel("goals")
        ax.set_title(_window_title(windows, k), fontsize=10)
    fig.suptitle(f"{LABELS.get(cfg.condition, cfg.condition)}, seed {res.seed}: self-generated goals and region boundaries")
    return fig


def arm_points(theta: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """Joint positions of the planar arm, base first (n + 1 points)."""
    phi = np.cumsum(theta)
    pts = np.cumsum(np.stack([lengths * np.cos(phi), lengths * np.sin(phi)], axis=1), axis=0)
    return np.vstack([[0.0, 0.0], pts])


def spatial_arm_points(theta: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """Joint positions of the spatial arm, base first (n + 1 points in 3-D)."""
    from ..bodies.environments import SpatialArm

    # Joint i sits at the tip of the arm made of the first i links.
    return np.vstack([np.zeros(3)] + [SpatialArm(link_lengths=lengths[:i]).forward(theta[:i]) for i in range(1, len(theta) + 1)])


def plot_arm(config: Config, path: str | Path) -> Path:
    """The arm at rest and in a bent pose, with x_start, a goal x_g and a final position x_f: the
    quantities of the competence C = -D(x_g, x_f) / D(x_start, x_g) (eq. 7)."""
    if config.chain is not None:
        return _plot_chain(config, path)
    lengths = np.asarray(config.link_lengths if config.link_lengths else [config.arm_length / config.n_joints] * config.n_joints, dtype=float)
    if config.body == "spatial_arm":
        return _plot_spatial_arm(lengths, path)
    n = len(lengths)
    fig = Figure(figsize=(6.5, 5.5), layout="constrained")
    ax = fig.subplots()
    rest = arm_points(np.zeros(n), lengths)
    bent = arm_points(np.full(n, 0.12), lengths)
    ax.plot(rest[:, 0], rest[:, 1], "-o", color="0.3", markersize=3, label="rest pose (theta_rest, x_rest)")
    ax.plot(bent[:, 0], bent[:, 1], "-o", color="tab:blue", markersize=3, label="a configuration after a reaching attempt")
    x_start, x_f = rest[-1], bent[-1]
    x_g = x_f + np.array([3.0, -4.0])
    ax.plot(*x_start, "ks")
    ax.annotate("x_start", x_start, textcoords="offset points", xytext=(5, 5))
    ax.plot(*x_g, "r*", markersize=12)
    ax.annotate("x_g", x_g, textcoords="offset points", xytext=(5, -12))
    ax.plot(*x_f, "bo")
    ax.annotate("x_f", x_f, textcoords="offset points", xytext=(-20, 6))
    ax.plot([x_start[0], x_g[0]], [x_start[1], x_g[1]], "k--", linewidth=0.8, label="D(x_start, x_g)")
    ax.plot([x_f[0], x_g[0]], [x_f[1], x_g[1]], "r--", linewidth=1.2, label="D(x_g, x_f)")
    ax.add_patch(Arc((0, 0), 2 * lengths.sum(), 2 * lengths.sum(), theta1=-90, theta2=90, edgecolor="0.6", linewidth=1))
    ax.set_aspect("equal")
    ax.set_xlim(-5, lengths.sum() + 5)
    ax.set_ylim(-lengths.sum() * 0.6, lengths.sum() + 5)
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(f"{n}-joint planar arm, total length {lengths.sum():g}")
    path = Path(path)
    write_png(fig, path, dpi=110)
    return path


def _plot_spatial_arm(lengths: np.ndarray, path: str | Path) -> Path:
    """The spatial arm at rest and in a bent pose (yaw joints at 0.15 rad curl it sideways, pitch
    joints at -0.12 rad upwards), with x_start, x_g, x_f as in the planar figure."""
    n = len(lengths)
    fig = Figure(figsize=(7.0, 6.0), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    rest = spatial_arm_points(np.zeros(n), lengths)
    bent = spatial_arm_points(np.where(np.arange(n) % 2 == 0, 0.15, -0.12), lengths)
    ax.plot(rest[:, 0], rest[:, 1], rest[:, 2], "-o", color="0.3", markersize=3, label="rest pose (theta_rest, x_rest)")
    ax.plot(bent[:, 0], bent[:, 1], bent[:, 2], "-o", color="tab:blue", markersize=3, label="a configuration after a reaching attempt")
    x_start, x_f = rest[-1], bent[-1]
    x_g = x_f + np.array([6.0, -8.0, -6.0])
    ax.scatter(*x_start, color="k", marker="s")
    ax.text(*x_start, "  x_start")
    ax.scatter(*x_g, color="r", marker="*", s=120)
    ax.text(*x_g, "  x_g")
    ax.scatter(*x_f, color="b")
    ax.text(*x_f, "  x_f")
    ax.plot(*zip(x_start, x_g), "k--", linewidth=0.8, label="D(x_start, x_g)")
    ax.plot(*zip(x_f, x_g), "r--", linewidth=1.2, label="D(x_g, x_f)")
    # The reachable sphere's equator and a meridian, for scale.
    t = np.linspace(0, 2 * np.pi, 200)
    r = lengths.sum()
    ax.plot(r * np.cos(t), r * np.sin(t), 0 * t, color="0.7", linewidth=0.8)
    ax.plot(r * np.cos(t), 0 * t, r * np.sin(t), color="0.7", linewidth=0.8)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.set_box_aspect((1, 1, 1))
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title(f"{n}-joint spatial arm (joints alternately yaw and pitch), total length {r:g}")
    path = Path(path)
    write_png(fig, path, dpi=110)
    return path


def _plot_chain(config: Config, path: str | Path) -> Path:
    """A chain body (a MuJoCo model's arm) at rest and in a bent pose, over a sample of the
    positions it reaches, inside the goal box."""
    chain = list(config.chain or ())
    n = config.joints
    fig = Figure(figsize=(7.0, 6.0), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    cloud = _core.chain_cloud(chain, float(config.joint_limit), 3000, 0)
    ax.scatter(cloud[:, 0], cloud[:, 1], cloud[:, 2], s=1, color="0.75", alpha=0.5, label="positions at random configurations")
    rest = _core.chain_points(chain, [0.0] * n)
    bent = _core.chain_points(chain, list(np.linspace(-0.4, 0.4, n) * config.joint_limit))
    ax.plot(rest[:, 0], rest[:, 1], rest[:, 2], "-o", color="0.2", markersize=3, label="rest pose (every joint mid-range)")
    ax.plot(bent[:, 0], bent[:, 1], bent[:, 2], "-o", color="tab:blue", markersize=3, label="another configuration")
    lo, hi = np.asarray(config.goal_low, float), np.asarray(config.goal_high, float)
    for a in range(3):
        for corner in range(4):
            b, c = [i for i in range(3) if i != a]
            p0, p1 = lo.copy(), lo.copy()
            p0[b] = p1[b] = hi[b] if corner & 1 else lo[b]
            p0[c] = p1[c] = hi[c] if corner & 2 else lo[c]
            p1[a] = hi[a]
            ax.plot(*zip(p0, p1), color="0.5", linewidth=0.6)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.set_box_aspect(tuple(hi - lo))
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title(f"{n}-joint chain (reach {config.reach:.3g}) in its goal box")
    path = Path(path)
    write_png(fig, path, dpi=110)
    return path
