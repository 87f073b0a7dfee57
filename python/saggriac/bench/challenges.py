"""One cheap task for each challenge TeachMyAgent's paper (Romac et al., ICML 2021) names that the
toy tasks do not cover: a mostly trivial space, a student that forgets what it does not
practise, students of different ability on one space, and a rugged difficulty landscape."""

from __future__ import annotations

from typing import Any

import numpy as np

from .tasks import BUDGETS_10K, Hypercube, Niches, register

#: The learnable strip of ``trivial-90``: goals with a first coordinate below it are trivial.
STRIP = 0.9


@register
class MostlyTrivial(Hypercube):
    """The 2d hypercube squeezed into the strip x >= 0.9 of the box; the other 90 % is trivial:
    the competence is 1 there at every try, and nothing is learnt."""

    name, budgets = "trivial-90", BUDGETS_10K
    learner = "hypercube in a strip, the rest trivial"
    measures = "finding the 10 % of the space where there is something to learn, when 90 % already answers with full competence"

    def cell(self, goal: Any) -> int:
        g = np.asarray(goal, float)
        return super().cell([(g[0] - STRIP) / (1 - STRIP), g[1]])

    def attempt(self, goal: Any) -> float:
        return 1.0 if float(np.asarray(goal, float)[0]) < STRIP else self.attempt_cell(self.cell(goal))

    def oracle(self) -> Any:
        x, y = self.centre(self.oracle_cell())
        return np.array([STRIP + (1 - STRIP) * x, y])

    def cell_box(self, cell: int) -> tuple[np.ndarray, np.ndarray]:
        """The cell's box in the strip. The expert's start is the strip's first cell, the
        easiest goal with something to learn (the trivial part is mastered from the start)."""
        lo, hi = super().cell_box(cell)
        return np.array([STRIP + (1 - STRIP) * lo[0], lo[1]]), np.array([STRIP + (1 - STRIP) * hi[0], hi[1]])


@register
class Forgetting(Hypercube):
    """The 2d hypercube where a mastered cell not tried for ``forget_after`` goals is forgotten
    down to half its practice (its neighbours stay unlocked). The score is the share of the cells
    mastered now."""

    name, budgets = "forgetting", BUDGETS_10K
    learner = "hypercube that forgets"
    measures = "coming back to what was learnt before it is forgotten, while still pushing the frontier"
    forget_after = 500

    def __init__(self, seed: int) -> None:
        super().__init__(seed)
        self.t = 0
        self.last = np.zeros(self.n_cells, np.int64)

    def attempt_cell(self, c: int) -> float:
        self.t += 1
        stale = self.mastered() & (self.t - self.last > self.forget_after)
        self.practice[stale] = self.need // 2
        self.last[c] = self.t
        return super().attempt_cell(c)

    def oracle_cell(self) -> int:
        """The mastered cell about to be forgotten, else the frontier, else the stalest."""
        held = np.flatnonzero(self.mastered())
        if len(held):
            oldest = int(held[np.argmin(self.last[held])])
            if self.t + 1 - self.last[oldest] > self.forget_after - 1:
                return oldest
        frontier = np.flatnonzero(self.unlocked & ~self.mastered())
        if len(frontier):
            return int(frontier[0])
        return oldest


@register
class Abilities(Niches):
    """The progress niches with a student drawn per seed: its learning rate is 0.02 x 4^u, u
    uniform in [-1, 1] (from 0.005 to 0.08), so that one seed's student is 16 times as quick as
    another's."""

    name = "abilities"
    learner = "progress niches, students of different speed"
    measures = "one teacher for students of different ability: the same curriculum paced for slow and quick learners"

    def __init__(self, seed: int) -> None:
        rng = np.random.default_rng(np.random.SeedSequence(seed).spawn(2)[1])
        self.learning_rate = 0.02 * 4.0 ** rng.uniform(-1.0, 1.0)
        super().__init__(seed)


@register
class Rugged(Hypercube):
    """A 10 x 10 grid of cells, all open from the start, whose difficulties (tries to master: 5,
    10, 20, 40 or 80) are drawn independently per cell: neighbouring cells share nothing. The
    competence is a cell's progress; the score the share of cells mastered."""

    name = "rugged"
    budgets = {"quick": 3_000, "standard": 3_000, "full": 3_000}
    learner = "grid of cells of random difficulty"
    measures = "a difficulty landscape without smoothness: what is easy is scattered, so a teacher cannot spread progress to a neighbourhood"

    def __init__(self, seed: int) -> None:
        super().__init__(seed)
        rng = np.random.default_rng(np.random.SeedSequence(seed))
        self.needs = 5 * 2 ** rng.integers(0, 5, self.n_cells)
        self.unlocked[:] = True

    def attempt_cell(self, c: int) -> float:
        if self.practice[c] < self.needs[c]:
            self.practice[c] += 1
        return float(self.practice[c] / self.needs[c])

    def mastered(self) -> np.ndarray:
        return self.practice >= self.needs

    def easy_cells(self) -> list[int]:
        """Every cell is open from the start; an expert knows the easiest (TeachMyAgent's
        rugged test maps its easy tasks into the shuffled space): the first of fewest tries."""
        return [int(np.argmin(self.needs))]

    def oracle_cell(self) -> int:
        """The unmastered cell with the fewest tries left."""
        left = np.where(self.mastered(), np.iinfo(np.int64).max, self.needs - self.practice)
        return int(np.argmin(left))
