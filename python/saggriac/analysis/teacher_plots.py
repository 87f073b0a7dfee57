"""The picture of what a teacher chose over time: its goals in windows of its history, with what
shapes them drawn over them (the region tree and its interests, ADR's box, SPDL's Gaussian and a
mixture's components as ellipses, Goal GAN's goals of intermediate difficulty), or, for a task
list, each task's share of the draws over time. Matplotlib's object API only, as plots.py."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Mapping

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Ellipse, Rectangle

from ..errors import ParameterError
from ..teachers import MODES, load_selector
from .plots import write_png
from .readings import GOID_R_MAX, GOID_R_MIN, SHARES, attempts_per_goal, goal_rates, kind_of

#: The columns of a saved history (``teacher.history()``) plot_teacher reads.
HISTORY_KEYS = ("asked_goal",)
_TREES = ("sagg_riac", "riac")
_MIXTURES = ("alp_gmm", "covar_gmm")


def _source(source: Any) -> tuple[Any, dict[str, np.ndarray], np.ndarray, np.ndarray, str]:
    """(teacher or None, history, low, high, name) of a teacher, a saved teacher's file or a
    saved history (a mapping with ``asked_goal``, and ``low``/``high`` if the box is wanted)."""
    if isinstance(source, (str, os.PathLike)):
        source = load_selector(source)
    if kind_of(source) is not None:
        h = source.history()
        return source, h, np.asarray(source.low, dtype=float), np.asarray(source.high, dtype=float), type(source).__name__
    if isinstance(source, Mapping) and all(k in source for k in HISTORY_KEYS):
        h = {k: np.asarray(v) for k, v in source.items()}
        goals = np.asarray(h["asked_goal"], dtype=float)
        if goals.ndim != 2:
            raise ParameterError(f"The 'source' parameter of plot_teacher must be a history whose 'asked_goal' has shape (n, dim). Got shape {goals.shape} instead.", "source", f"asked_goal of shape {goals.shape}")
        low = np.asarray(h.get("low", goals.min(axis=0) if len(goals) else np.zeros(goals.shape[1])), dtype=float)
        high = np.asarray(h.get("high", goals.max(axis=0) if len(goals) else np.ones(goals.shape[1])), dtype=float)
        return None, h, low, high, "a saved history"
    raise ParameterError(f"The 'source' parameter of plot_teacher must be one of saggriac's teachers, the path of a saved teacher or a saved history (a mapping with {', '.join(map(repr, HISTORY_KEYS))}). Got {source!r} instead.", "source", repr(source))


def _windows(n: int, windows: int) -> list[tuple[int, int]]:
    edges = np.unique(np.linspace(0, n, windows + 1).round().astype(int))
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:])] or [(0, 0)]


def teacher_figure(source: Any, windows: int = 4, dims: tuple[int, int] = (0, 1)) -> Figure:
    """The figure of :func:`plot_teacher` (not written)."""
    if isinstance(windows, bool) or not isinstance(windows, (int, np.integer)) or not 1 <= windows <= 100:
        raise ParameterError(f"The 'windows' parameter of plot_teacher must be an int in [1, 100]. Got {windows!r} instead.", "windows", repr(windows))
    teacher, h, low, high, name = _source(source)
    kind = kind_of(teacher) if teacher is not None else None
    if teacher is not None and "tasks" in type(teacher).spaces:
        return _tasks_figure(teacher, h, name, windows)
    d = len(low)
    if not (isinstance(dims, (tuple, list)) and len(dims) == 2 and all(isinstance(i, (int, np.integer)) and not isinstance(i, bool) and 0 <= i < d for i in dims) and dims[0] != dims[1]) and d >= 2:
        raise ParameterError(f"The 'dims' parameter of plot_teacher must be two distinct dimensions of the goal space, ints in [0, {d}). Got {dims!r} instead.", "dims", repr(dims))
    goals = np.asarray(h["asked_goal"], dtype=float)
    spans = _windows(len(goals), windows)
    fig = Figure(figsize=(3.6 * len(spans), 3.9), layout="constrained")
    axes = fig.subplots(1, len(spans), squeeze=False)[0]
    labels = _labels(kind, h)
    # One colour per label in every panel.
    colour = {label: f"C{i}" for i, label in enumerate(dict.fromkeys(labels))}
    for k, (start, end) in enumerate(spans):
        ax = axes[k]
        chosen = goals[start:end]
        last = k == len(spans) - 1
        if d == 1:
            ax.hist(chosen[:, 0], bins=40, range=(low[0], high[0]), color="0.35")
            ax.set_xlim(low[0], high[0])
            ax.set_xlabel("goal")
        else:
            i, j = dims
            for label in dict.fromkeys(labels[start:end]):
                sel = labels[start:end] == label
                ax.scatter(chosen[sel, i], chosen[sel, j], s=4, alpha=0.5, color=colour[label], label=label.replace("_share", ""), rasterized=True)
            _overlay(ax, teacher, kind, h, chosen, (start, end), (i, j), last)
            ax.set_xlim(low[i], high[i])
            ax.set_ylim(low[j], high[j])
            ax.set_xlabel(f"goal[{i}]")
            ax.set_ylabel(f"goal[{j}]")
            handles = [Line2D([], [], linestyle="", marker="o", color=c, label=label.replace("_share", "")) for label, c in colour.items()]
            if kind == "goal_gan":
                handles.append(Line2D([], [], linestyle="", marker="o", markerfacecolor="none", color="k", label="intermediate difficulty"))
            if k == len(spans) - 1 and len(handles) > 1:
                ax.legend(handles=handles, fontsize=7, loc="upper right")
        ax.set_title(f"goals {start}-{end}", fontsize=10)
    fig.suptitle(f"{name}: the goals it chose over time", fontsize=11)
    return fig


def _labels(kind: str | None, h: Mapping[str, np.ndarray]) -> np.ndarray:
    """Each asked goal's label: what drew it, in the names of its teacher's shares."""
    n = len(h["asked_goal"])
    if kind is None or "asked_mode" not in h:
        return np.full(n, "goals", dtype=object)
    names = SHARES.get(kind, {})
    return np.array([names.get(MODES[int(m)], MODES[int(m)]) for m in h["asked_mode"]], dtype=object)


def _box(ax: Any, lo: np.ndarray, hi: np.ndarray, dims: tuple[int, int], **kw: Any) -> None:
    i, j = dims
    ax.add_patch(Rectangle((lo[i], lo[j]), hi[i] - lo[i], hi[j] - lo[j], fill=False, **kw))


def _ellipse(ax: Any, points: np.ndarray, dims: tuple[int, int], **kw: Any) -> None:
    """Two standard deviations of ``points`` in the plane ``dims``, along their principal axes."""
    p = points[:, list(dims)]
    cov = np.cov(p, rowvar=False) if len(p) > 1 else np.zeros((2, 2))
    vals, vecs = np.linalg.eigh(cov)
    angle = float(np.degrees(np.arctan2(vecs[1, 1], vecs[0, 1])))
    w, hgt = 4 * np.sqrt(np.maximum(vals[::-1], 0))
    ax.add_patch(Ellipse(tuple(p.mean(axis=0)), w, hgt, angle=angle, fill=False, **kw))


def _overlay(ax: Any, teacher: Any, kind: str | None, h: Mapping[str, np.ndarray], chosen: np.ndarray, span: tuple[int, int], dims: tuple[int, int], last: bool) -> None:
    start, end = span
    if len(chosen) == 0:
        return
    if kind in _TREES:
        r = teacher.regions()
        if "created_at" in r:  # the tree as it was after as many tells as goals asked by the window's end
            at = min(end, len(h["told_goal"]))
            alive = np.asarray(r["created_at"]) <= at
            split = set(np.asarray(r["parent"])[alive & (np.asarray(r["parent"]) >= 0)].tolist())
            leaf = alive & ~np.isin(np.arange(len(alive)), list(split))
        elif last:
            leaf = np.asarray(r["is_leaf"], dtype=bool)
        else:
            return
        interest = np.asarray(r["interest"], dtype=float)
        top = max(float(interest[leaf].max()), 1e-12) if leaf.any() else 1.0
        for q in np.flatnonzero(leaf):
            _box(ax, r["low"][q], r["high"][q], dims, edgecolor="k", linewidth=0.4 + 2.0 * max(interest[q], 0.0) / top)
    elif kind == "spdl":
        _ellipse(ax, chosen, dims, edgecolor="k", linewidth=1.2)
        if last:
            r = teacher.regions()
            mean, std = (r["low"][0] + r["high"][0]) / 2, (r["high"][0] - r["low"][0]) / 2
            i, j = dims
            ax.add_patch(Ellipse((mean[i], mean[j]), 4 * std[i], 4 * std[j], fill=False, edgecolor="tab:red", linestyle="--", linewidth=1.2))
    elif kind in _MIXTURES:
        region = np.asarray(h["asked_region"])[start:end]
        for c in np.unique(region[region >= 0]):
            if (region == c).sum() >= 3:
                _ellipse(ax, chosen[region == c], dims, edgecolor="k", linewidth=1.0)
    elif kind == "goal_gan":
        comp = np.asarray(h["told_competence"], dtype=float)
        if len(comp) and comp.min() >= 0.0 and comp.max() <= 1.0:
            goals, counts, rates, _ = goal_rates(h["told_goal"], comp)
            good = (counts >= attempts_per_goal(h["asked_goal"])) & (rates >= GOID_R_MIN) & (rates <= GOID_R_MAX)
            mine = np.isin(goals.view([("", goals.dtype)] * goals.shape[1]).ravel(), chosen.astype(np.float32).view([("", np.float32)] * chosen.shape[1]).ravel())
            sel = goals[good & mine]
            ax.scatter(sel[:, dims[0]], sel[:, dims[1]], s=14, facecolors="none", edgecolors="k", linewidths=0.6, label="intermediate difficulty")
    else:
        # ADR and any other: the box over the goals it chose (ADR's ranges then).
        _box(ax, chosen.min(axis=0), chosen.max(axis=0), dims, edgecolor="k", linewidth=1.2)
        if kind == "adr" and last:
            r = teacher.regions()
            _box(ax, r["low"][0], r["high"][0], dims, edgecolor="tab:red", linestyle="--", linewidth=1.2)


def _tasks_figure(teacher: Any, h: Mapping[str, np.ndarray], name: str, windows: int) -> Figure:
    """A task list: each task's share of the draws in each window (a heat map), and the last
    value told for each task."""
    n = int(teacher.n_tasks)
    tasks = np.asarray(h["asked_goal"], dtype=float).ravel().round().astype(int)
    spans = _windows(len(tasks), max(windows, 10))
    share = np.array([np.bincount(tasks[a:b], minlength=n)[:n] / max(b - a, 1) for a, b in spans]).T
    fig = Figure(figsize=(9.0, 0.3 * n + 2.4), layout="constrained")
    ax, bar = fig.subplots(1, 2, width_ratios=[3, 1])
    im = ax.imshow(share, aspect="auto", origin="lower", cmap="viridis", vmin=0, extent=(0, max(len(tasks), 1), -0.5, n - 0.5), interpolation="nearest")
    fig.colorbar(im, ax=ax, label="share of the draws")
    ax.set_xlabel("goals asked")
    ax.set_ylabel("task")
    told = np.asarray(h["told_goal"], dtype=float).ravel().round().astype(int)
    last = np.full(n, np.nan)
    if len(told):
        seen, first = np.unique(told[::-1], return_index=True)
        last[seen] = np.asarray(h["told_competence"], dtype=float)[len(told) - 1 - first]
    bar.barh(np.arange(n), np.nan_to_num(last), color="0.4")
    bar.set_ylim(-0.5, n - 0.5)
    bar.set_xlabel("last value told")
    fig.suptitle(f"{name}: each task's share of the draws over time", fontsize=11)
    return fig


def plot_teacher(source: Any, path: str | os.PathLike[str] | None = None, *, windows: int = 4, dims: tuple[int, int] = (0, 1)) -> Figure:
    """Draw what a teacher chose over time, from the teacher itself, the path of a teacher it
    saved (``save``, or ``TeacherCallback(save_with=...)``) or a saved history (the mapping of
    ``teacher.history()``, with ``low`` and ``high`` if known).

    A box teacher gets one panel per window of its asked goals (``windows`` of them), the goals
    in the plane ``dims`` coloured by what drew them, and over them: the regions of SAGG-RIAC's
    tree as it then was (RIAC's current ones on the last panel), line width growing with
    interest; ADR's box over the goals it chose (its ranges; the current ones dashed on the last
    panel); SPDL's Gaussian as the 2-sd ellipse of the goals it chose (the current one dashed);
    each mixture component's goals as a 2-sd ellipse; Goal GAN's goals of intermediate
    difficulty circled. A task list gets each task's share of the draws over time. Returns the
    figure; with ``path``, writes it there as a PNG too (replacing only a figure saggriac wrote)."""
    fig = teacher_figure(source, windows, dims)
    if path is not None:
        write_png(fig, Path(os.fspath(path)), dpi=110)
    return fig
