"""MiniGrid's observation of the agent's view, computed from arrays for levels no action changes.

MiniGrid builds every observation from Python objects: it copies the 7 x 7 window of the grid
cell by cell, rotates the copy once to four times, walks it for what the agent can see, then
encodes it (``MiniGridEnv.gen_obs``). That is about two thirds of an environment step, and the
rl-minigrid task takes some 250,000 steps a run. Its levels (empty rooms and SimpleCrossing mazes
of walls) never change within an episode: no action opens, moves or picks up anything in them. So
the grid is encoded once per level, and each observation is a slice of that array, turned by
numpy, with MiniGrid's own visibility walk run on the 49 cells (and remembered by the pattern of
walls in view, which repeats), or every cell seen where the level sees through walls (the empty
rooms). The observation is MiniGrid's to the element
(tests/bench/test_minigrid_view.py compares them at every step of random walks on every grade).
A level with anything an action can change, a carried object, or an environment that steps or
observes otherwise than MiniGrid's base class falls back to MiniGrid's own ``gen_obs``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: Objects no action of MiniGrid's changes in place (they cannot be picked up, opened or moved).
STATIC = frozenset({"wall", "floor", "goal", "lava"})


def _rotate_left(a: np.ndarray) -> np.ndarray:
    """``Grid.rotate_left`` on an array indexed [x, y]: the cell (i, j) goes to (j, width-1-i)."""
    return a[::-1].swapaxes(0, 1)


def _visible(opaque: np.ndarray, agent: tuple[int, int]) -> np.ndarray:
    """``Grid.process_vis``: the cells seen from ``agent`` on a view whose ``opaque`` cells
    (walls, closed doors) hide what is behind them; the same walk, row by row from the agent's."""
    width, height = opaque.shape
    mask = np.zeros((width, height), dtype=bool)
    mask[agent] = True
    for j in reversed(range(height)):
        for i in range(width - 1):
            if not mask[i, j] or opaque[i, j]:
                continue
            mask[i + 1, j] = True
            if j > 0:
                mask[i + 1, j - 1] = True
                mask[i, j - 1] = True
        for i in reversed(range(1, width)):
            if not mask[i, j] or opaque[i, j]:
                continue
            mask[i - 1, j] = True
            if j > 0:
                mask[i - 1, j - 1] = True
                mask[i, j - 1] = True
    return mask


class ArrayView:
    """A drop-in ``gen_obs`` for one MiniGrid environment (``env.gen_obs = ArrayView(env)``)."""

    def __init__(self, env: Any) -> None:
        from minigrid.core.constants import OBJECT_TO_IDX
        from minigrid.core.world_object import Wall
        from minigrid.minigrid_env import MiniGridEnv

        self.env = env
        self.own = MiniGridEnv.gen_obs.__get__(env)
        # Subclasses that step or observe otherwise than MiniGrid's base class keep their own way.
        self.usable = type(env).step is MiniGridEnv.step and type(env).gen_obs is MiniGridEnv.gen_obs
        self.wall = np.array(Wall().encode(), dtype=np.uint8)
        self.nothing = np.array((OBJECT_TO_IDX["empty"], 0, 0), dtype=np.uint8)
        self.grid: Any = None
        self.static = False
        self.masks: dict[bytes, np.ndarray] = {}
        self.pad = 0

    def _encode(self, grid: Any, pad: int) -> None:
        """The level's encoding and its opaque cells, padded by ``pad`` cells of wall on every side
        (MiniGrid's slice sees walls beyond the grid)."""
        self.grid, self.pad = grid, pad
        cells = [[grid.get(i, j) for j in range(grid.height)] for i in range(grid.width)]
        self.static = all(c is None or c.type in STATIC for column in cells for c in column)
        if not self.static:
            return
        code = np.empty((grid.width + 2 * pad, grid.height + 2 * pad, 3), dtype=np.uint8)
        code[...] = self.wall
        code[pad:-pad, pad:-pad] = grid.encode()
        opaque = np.ones(code.shape[:2], dtype=bool)
        opaque[pad:-pad, pad:-pad] = [[c is not None and not c.see_behind() for c in column] for column in cells]
        self.code, self.opaque = code, opaque
        self.everything = np.ones((pad, pad), dtype=bool)

    def __call__(self) -> dict[str, Any]:
        env = self.env
        size = env.agent_view_size
        # A reset (step_count 0) may have drawn a new level, even into the same Grid object.
        if env.grid is not self.grid or env.step_count == 0:
            self._encode(env.grid, size)
        if not (self.usable and self.static and env.carrying is None and size == self.pad):
            return self.own()
        top_x, top_y, _, _ = env.get_view_exts()
        x, y = top_x + size, top_y + size
        view, opaque = self.code[x : x + size, y : y + size], self.opaque[x : x + size, y : y + size]
        for _ in range(env.agent_dir + 1):
            view, opaque = _rotate_left(view), _rotate_left(opaque)
        if env.see_through_walls:
            mask = self.everything
        else:
            key = np.packbits(opaque).tobytes()
            mask = self.masks.get(key)
            if mask is None:
                mask = self.masks[key] = _visible(opaque, (size // 2, size - 1))
        image = np.where(mask[..., None], view, np.uint8(0))
        # The agent's own cell shows what it carries: nothing, which MiniGrid encodes as empty.
        image[size // 2, size - 1] = self.nothing
        return {"image": image, "direction": env.agent_dir, "mission": env.mission}
