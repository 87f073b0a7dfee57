"""A task space with progress niches, to compare curriculum teachers (docs/teachers.md).

The tasks are points of the unit box. Its first two dimensions are cut into a grid of cells
(4 x 4 by default); the other dimensions, if any, are distractors that change nothing. Each
cell is one of three kinds:

* a **niche** of a chain (labels ``1``-``9``): the learner's skill in it starts at 0 and grows
  with each practice, ``s <- s + learning_rate (1 - s)``, but only once it is unlocked; niche 1
  is unlocked at the start, and niche k+1 when the skill in niche k reaches ``unlock_at``;
* **noisy** (``N``): the competence is uniform in [0, 1] at every try, and nothing is learnt;
* **impossible** (``X``): the competence stays at 0, and nothing is learnt.

A try at a goal returns the competence there: the cell's skill plus Gaussian noise of sd
``noise_sd``, clipped to [0, 1] (a locked niche behaves as an impossible cell). What a teacher
should do: find the unlocked niche, practise it until the next one opens, move on, and spend
little on the noisy and impossible cells. The score is the mean skill over the niches.

The layout is a list of rows, the first row at the bottom (low second coordinate), the first
column at the left (low first coordinate). Each niche of the chain must touch the previous one
by a side, so progress spreads from niche to niche.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from ..errors import ParameterError

#: Eight niches in a snake from the bottom left, four noisy cells and four impossible ones.
LAYOUT = (
    "123X",
    "654N",
    "78XN",
    "NNXX",
)

KINDS = ("niche", "noisy", "impossible")


def _check_layout(layout: Sequence[str]) -> tuple[int, int, np.ndarray, list[tuple[int, int]]]:
    rows = list(layout)
    if not rows or any(not isinstance(r, str) for r in rows) or len({len(r) for r in rows}) != 1 or not rows[0]:
        raise ParameterError(f"The 'layout' parameter of ProgressNiches must be equal-length rows of cell labels. Got {layout!r} instead.", "layout", repr(layout))
    ny, nx = len(rows), len(rows[0])
    labels = np.array([list(r) for r in rows])  # labels[j, i]: row j (second coordinate), column i
    bad = sorted(set(labels.ravel()) - set("123456789NX"))
    if bad:
        raise ParameterError(f"The 'layout' parameter of ProgressNiches holds only 1-9 (niches), N (noisy) and X (impossible). Got {bad[0]!r}.", "layout", repr(layout))
    niches = sorted((int(c), j, i) for j, r in enumerate(rows) for i, c in enumerate(r) if c.isdigit())
    order = [n for n, _, _ in niches]
    if order != list(range(1, len(order) + 1)):
        raise ParameterError(f"The niches of the 'layout' parameter of ProgressNiches must be numbered 1, 2, ... once each. Got {order}.", "layout", repr(layout))
    cells = [(j, i) for _, j, i in niches]
    for k in range(1, len(cells)):
        (j0, i0), (j1, i1) = cells[k - 1], cells[k]
        if abs(j0 - j1) + abs(i0 - i1) != 1:
            raise ParameterError(f"Niche {k + 1} of the 'layout' parameter of ProgressNiches must touch niche {k} by a side.", "layout", repr(layout))
    return nx, ny, labels, cells


def _unit(name: str, value: Any, open_low: bool) -> float:
    v = float(value)
    ok = (0.0 < v if open_low else 0.0 <= v) and v <= 1.0
    if not (ok and np.isfinite(v)):
        rule = "in (0, 1]" if open_low else "in [0, 1]"
        raise ParameterError(f"The '{name}' parameter of ProgressNiches must be {rule}. Got {value!r} instead.", name, repr(value))
    return v


class ProgressNiches:
    """The learner of the niche benchmark: ``attempt(goal)`` practises and returns the competence."""

    def __init__(self, seed: int = 0, *, distractors: int = 0, layout: Sequence[str] = LAYOUT, learning_rate: float = 0.02, unlock_at: float = 0.6, noise_sd: float = 0.05) -> None:
        if isinstance(distractors, bool) or not isinstance(distractors, (int, np.integer)) or not 0 <= distractors <= 1000:
            raise ParameterError(f"The 'distractors' parameter of ProgressNiches must be an int in [0, 1000]. Got {distractors!r} instead.", "distractors", repr(distractors))
        self.nx, self.ny, self.labels, self.niche_cells = _check_layout(layout)
        self.learning_rate = _unit("learning_rate", learning_rate, open_low=True)
        self.unlock_at = _unit("unlock_at", unlock_at, open_low=True)
        self.noise_sd = _unit("noise_sd", noise_sd, open_low=False)
        self.dim = 2 + int(distractors)
        self.low, self.high = np.zeros(self.dim), np.ones(self.dim)
        self._rng = np.random.default_rng(np.random.SeedSequence(int(seed)))
        self._niche_of = {cell: k for k, cell in enumerate(self.niche_cells)}
        self.skill = np.zeros(len(self.niche_cells))
        self.unlocked = 1

    @property
    def n_cells(self) -> int:
        return self.nx * self.ny

    def cell(self, goal: Any) -> int:
        """The cell holding ``goal``: ``j * nx + i`` for column i and row j."""
        g = np.asarray(goal, dtype=np.float64)
        if g.shape != (self.dim,) or not np.all(np.isfinite(g)):
            raise ParameterError(f"A goal of ProgressNiches must be {self.dim} finite floats. Got {goal!r} instead.", "goal", repr(goal))
        i = min(max(int(g[0] * self.nx), 0), self.nx - 1)
        j = min(max(int(g[1] * self.ny), 0), self.ny - 1)
        return j * self.nx + i

    def kind(self, cell: int) -> str:
        c = self.labels[cell // self.nx, cell % self.nx]
        return "niche" if c.isdigit() else ("noisy" if c == "N" else "impossible")

    def centre(self, cell: int) -> np.ndarray:
        """A goal at the centre of ``cell`` (distractors at 0.5)."""
        g = np.full(self.dim, 0.5)
        g[0] = (cell % self.nx + 0.5) / self.nx
        g[1] = (cell // self.nx + 0.5) / self.ny
        return g

    def attempt(self, goal: Any) -> float:
        """Practise ``goal``; the competence reached, in [0, 1]."""
        cell = self.cell(goal)
        where = (cell // self.nx, cell % self.nx)
        label = self.labels[where]
        if label == "N":
            return float(self._rng.random())
        k = self._niche_of.get(where)
        level = 0.0
        if k is not None and k < self.unlocked:
            self.skill[k] += self.learning_rate * (1.0 - self.skill[k])
            level = self.skill[k]
            if k == self.unlocked - 1 and level >= self.unlock_at and self.unlocked < len(self.skill):
                self.unlocked += 1
        return float(min(1.0, max(0.0, level + self.noise_sd * self._rng.standard_normal())))

    def mastery(self) -> float:
        """Mean skill over the niches: the score."""
        return float(self.skill.mean())
