"""Pictures of a GoalArmEnv (its render modes): the arm, its reach, the goal and the distance at
which it counts as reached. matplotlib draws them off screen ("rgb_array") or in a window
("human")."""

from __future__ import annotations

import copy
from typing import Any

import numpy as np


def joint_points(arm: Any, theta: np.ndarray) -> np.ndarray:
    """Positions of the base, every joint and the tip: the tip of the arm cut after k links."""
    cut = copy.copy(arm)
    points = [np.zeros(arm.task_dim)]
    for k in range(1, len(arm.lengths) + 1):
        cut.lengths = list(arm.lengths[:k]) + [0.0] * (len(arm.lengths) - k)
        points.append(cut.forward(theta))
    return np.array(points)


class ArmView:
    """One figure per environment, redrawn in place."""

    SIZE = (4.8, 4.8)

    def __init__(self, env: Any, interactive: bool) -> None:
        import matplotlib

        self.env = env
        self.interactive = interactive
        if interactive:
            import matplotlib.pyplot as plt

            self.plt = plt
            self.fig = plt.figure(figsize=self.SIZE)
        else:
            from matplotlib.backends.backend_agg import FigureCanvasAgg
            from matplotlib.figure import Figure

            self.fig = Figure(figsize=self.SIZE, dpi=100)
            FigureCanvasAgg(self.fig)
        three_d = env.arm.task_dim == 3
        # A 3-D arm: seen from above (x, y) and from the side (x, z).
        self.views = [(0, 1), (0, 2)] if three_d else [(0, 1)]
        if three_d:
            self.fig.set_size_inches(self.SIZE[0] * 2, self.SIZE[1])
        self.axes = self.fig.subplots(1, len(self.views), squeeze=False)[0]
        del matplotlib

    def draw(self, theta: np.ndarray, goal: np.ndarray) -> np.ndarray | None:
        from matplotlib.patches import Circle, Rectangle

        env = self.env
        pts = joint_points(env.arm, theta)
        lo, hi = env.goal_space.low, env.goal_space.high
        for ax, (i, j) in zip(self.axes, self.views):
            ax.clear()
            ax.add_patch(Circle((0, 0), env.reach, fill=False, linestyle=":", color="0.6", label="reach"))
            ax.add_patch(Rectangle((lo[i], lo[j]), hi[i] - lo[i], hi[j] - lo[j], fill=False, color="0.8", label="goal box"))
            ax.plot(pts[:, i], pts[:, j], "-o", color="tab:blue", markersize=2.5, linewidth=1.5, label="arm")
            ax.add_patch(Circle((goal[i], goal[j]), max(env.distance_threshold, 0.01 * env.reach), color="tab:red", alpha=0.5))
            ax.plot([goal[i]], [goal[j]], "x", color="tab:red", label="goal")
            for k, set_lim in ((i, ax.set_xlim), (j, ax.set_ylim)):
                a, b = min(-env.reach, lo[k]), max(env.reach, hi[k])
                pad = 0.05 * (b - a)
                set_lim(a - pad, b + pad)
            ax.set_aspect("equal")
            ax.set_xlabel("xyz"[i])
            ax.set_ylabel("xyz"[j])
        self.axes[0].legend(loc="upper left", fontsize=7)
        d = float(np.linalg.norm(pts[-1] - goal))
        self.fig.suptitle(f"distance to goal {d:.3g}", fontsize=9)
        if self.interactive:
            self.fig.canvas.draw_idle()
            self.plt.pause(1.0 / self.env.metadata["render_fps"])
            return None
        self.fig.canvas.draw()
        return np.asarray(self.fig.canvas.buffer_rgba())[..., :3].copy()

    def close(self) -> None:
        if self.interactive:
            self.plt.close(self.fig)
