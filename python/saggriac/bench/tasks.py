"""The bench's tasks: small learners a teacher chooses goals for, each with a score that is higher
when the learner is better, and a registry that adds a task with one line (``register(MyTask)``).

A task is built for one run, ``MyTask(seed)``, from the seed the runner derives for it. It offers
a space (a box ``low``/``high``, or a list of ``n_tasks`` tasks whose goals are indices), and
``attempt(goal)`` practises one goal and returns the competence reached, in [0, 1] (the runner
maps it into each teacher's ``competence_range``). ``score()`` is the learner's skill now;
``oracle()`` is the goal a perfect teacher (one that sees the learner's state) would ask next,
which the tests use as a known answer. A task whose learner runs a loop of its own (the arm)
overrides ``play`` instead. ``expert_knowledge()`` is what an expert could tell a teacher about
a box task (the easy start and the target; :mod:`saggriac.bench.expert`).
"""

from __future__ import annotations

from typing import Any, Callable, ClassVar

import numpy as np

from ..errors import ParameterError
from ..teachers.progress_niches import ProgressNiches
from .expert import Knowledge, Region

#: The tiers: seeds per task (0 .. N-1) and which budget each task takes. ``quick`` is every task
#: with few seeds; ``full`` has the sizes of the studies the toy tasks came from, and a task a
#: registered study ran takes that study's seeds (:func:`tier_seeds`).
TIERS = {"quick": 5, "standard": 10, "full": 20}

#: The registry, in the order tasks were registered: name -> class.
TASKS: dict[str, type["BenchTask"]] = {}


def register(cls: type["BenchTask"]) -> type["BenchTask"]:
    """Add a task to the bench (usable as a class decorator). Its name must be new."""
    name = getattr(cls, "name", "")
    if not isinstance(name, str) or not name or name in TASKS:
        raise ParameterError(f"The 'name' of a bench task must be a new, non-empty str. Got {name!r} instead (taken: {', '.join(TASKS)}).", "name", repr(name))
    budgets_ok = set(cls.budgets) == set(TIERS) and all(b is None or (isinstance(b, int) and b > 0) for b in cls.budgets.values()) and any(b is not None for b in cls.budgets.values())
    if cls.space not in ("box", "tasks") or not budgets_ok:
        raise ParameterError(f"The bench task {name!r} must have space 'box' or 'tasks' and, for each tier {tuple(TIERS)}, a budget (an int > 0, or None where the task is not in the tier; at least one int). Got space {cls.space!r}, budgets {cls.budgets!r}.", "budgets", repr(cls.budgets))
    TASKS[name] = cls
    return cls


def in_tier(name: str, tier: str) -> bool:
    """Whether the task ``name`` is run in ``tier`` (it has a budget there)."""
    return TASKS[name].budgets[tier] is not None


def tier_seeds(name: str, tier: str) -> list[int]:
    """The seeds ``tier`` runs the task ``name`` on: 0 .. N-1; a task a registered study ran
    takes the study's report seeds (``study_seeds``) instead: all of them in the full tier, the
    first N in the others. So the tiers stay nested (each tier's seeds begin the next one's), and
    where a tier's budget is the study's its runs are the study's runs."""
    cls = TASKS[name]
    if cls.study_seeds:
        return list(cls.study_seeds) if tier == "full" else list(cls.study_seeds[: TIERS[tier]])
    return list(range(TIERS[tier]))


def missing_extra(name: str) -> str | None:
    """What the task ``name`` needs that is not installed (its ``requires``), or None."""
    import importlib.util

    requires = TASKS[name].requires
    modules = (requires[0],) if requires and isinstance(requires[0], str) else requires[0] if requires else ()
    if any(importlib.util.find_spec(m) is None for m in modules):
        return requires[1]
    return None


class BenchTask:
    """A task of the bench. Subclasses set the class attributes and implement the methods."""

    name: ClassVar[str] = ""
    space: ClassVar[str] = "box"
    #: The learner, in a few words (``saggriac bench --list``).
    learner: ClassVar[str] = ""
    #: What a teacher must do well to score high here (docs/bench.md).
    measures: ClassVar[str] = ""
    #: Goals per run, by tier; None where the task is not in the tier.
    budgets: ClassVar[dict[str, int | None]] = {}
    #: (module or tuple of modules, what to install) where the task needs an optional extra;
    #: the bench leaves the task out, and says so, when a module is missing.
    requires: ClassVar[tuple[str | tuple[str, ...], str] | tuple[()]] = ()
    #: Points on the score curve (the score after every budget // points goals).
    points: ClassVar[int] = 20
    #: What the curve's x axis counts.
    unit: ClassVar[str] = "goals"
    #: The report seeds of the registered study that ran this task at its full-tier budget (the
    #: study's protocol gives them): the full tier runs these instead of 0 .. N-1 and a smaller
    #: tier their first N (:func:`tier_seeds`), so a full bench reruns the study, and the study's
    #: committed runs ship as the built-in rows of each tier whose budget is the study's
    #: (benchmarks/ship_studies.py). Empty: no study.
    study_seeds: ClassVar[tuple[int, ...]] = ()
    #: CPU seconds per unit of budget, for the listing's estimate of a tier that no shipped run
    #: measures (deep RL, not in the quick tier): its study's pilot's measure; None if none.
    cpu_per_unit: ClassVar[float | None] = None
    #: What the task can tell a teacher (a teacher's ``told`` must be one; saggriac.bench.teachers).
    tells: ClassVar[tuple[str, ...]] = ("competence",)
    low: np.ndarray
    high: np.ndarray
    n_tasks: int

    def __init__(self, seed: int) -> None:
        self.seed = seed

    def attempt(self, goal: Any) -> float:
        raise NotImplementedError

    def score(self) -> float:
        raise NotImplementedError

    def oracle(self) -> Any:
        raise NotImplementedError

    def oracle_teacher(self, seed: int) -> Any:
        """The oracle as a teacher of this run (``sample()`` and ``update(goal, competence)``),
        for the evidence runner's teacher "oracle"; ``seed`` is the run's teacher seed, for an
        oracle that draws at random. By default it asks :meth:`oracle` and ignores what it is told."""
        return _AskOracle(self)

    @classmethod
    def has_oracle(cls) -> bool:
        """Whether the task's class gives an oracle (overrides oracle or oracle_teacher)."""
        return cls.oracle is not BenchTask.oracle or cls.oracle_teacher is not BenchTask.oracle_teacher

    def own_measures(self) -> list[dict[str, float]]:
        """The task's own measures at each point of the score curve of the run just played (one
        dict per point, the same keys at every point), beside the score: for the evidence runner's
        tables. None by default (an empty list)."""
        return []

    @classmethod
    def notes(cls, runs: Any) -> list[str]:
        """Lines the evidence runner's results add for this task, from its runs (a DataFrame of
        runs.csv's rows of the task: teacher, seed, final, area, the own measures at the end)."""
        return []

    def expert_knowledge(self) -> Knowledge | None:
        """What an expert could tell a teacher about this box task, for the bench's expert
        levels (``TEACHER@high``): ``self.knowledge(easy, target)``, with ``easy`` the box where
        the learner can make progress from the start (TeachMyAgent's initial distribution of
        easy tasks) and ``target`` the box that holds the goals the score is measured on (its
        target distribution), each ``(low, high)`` in the task's own coordinates. Called on the
        task as built for a run, before its first goal. None (this default): the task declares
        nothing, and the bench runs no teacher with expert knowledge on it."""
        return None

    def knowledge(self, easy: tuple[Any, Any], target: tuple[Any, Any]) -> Knowledge:
        """The Knowledge of this task's box with the regions ``easy`` and ``target``."""
        return Knowledge(np.asarray(self.low, float).copy(), np.asarray(self.high, float).copy(), Region.of(*easy), Region.of(*target))

    @classmethod
    def declares_knowledge(cls) -> bool:
        """Whether the task's class declares expert knowledge (overrides expert_knowledge)."""
        return cls.expert_knowledge is not BenchTask.expert_knowledge

    def play(self, ask: Callable[[], Any], tell: Callable[[Any, float], None], budget: int) -> list[tuple[int, float]]:
        """Run ``budget`` goals: ``ask()`` a goal, attempt it, ``tell(goal, competence)``. The
        score curve: (goals so far, score) at every budget // points goals."""
        every = max(1, budget // self.points)
        curve = []
        for t in range(1, budget + 1):
            goal = ask()
            tell(goal, self.attempt(goal))
            if t % every == 0 or t == budget:
                if not curve or curve[-1][0] != t:
                    curve.append((t, self.score()))
        return curve


class _AskOracle:
    """A task's oracle() as a teacher: it is told competences and ignores them."""

    def __init__(self, task: BenchTask) -> None:
        self.task = task

    def sample(self) -> Any:
        return self.task.oracle()

    def update(self, goal: Any, competence: float) -> None:
        return None


class Hypercube(BenchTask):
    """Hypercube unlocking (after the toy space of Portelas et al., ALP-GMM, CoRL 2019): the
    first ``relevant`` dimensions of [0, 1]^d are cut into ``bins`` cells each, the others change
    nothing. The cell at the origin is unlocked; a cell is unlocked when a neighbour (one bin
    away on one relevant dimension) is mastered, and mastered after ``need`` tries. The
    competence is a cell's progress (tries / need), 0 in a locked cell; the score is the share of
    the cells that can be mastered that are. With ``reach``, only cells whose bin indices sum to
    at most ``reach`` can ever be unlocked (the rest is impossible, like goals out of an arm's
    reach)."""

    space = "box"
    learner = "hypercube unlocking"
    points = 20
    relevant, bins, irrelevant, need, reach = 2, 10, 0, 20, None

    def __init__(self, seed: int) -> None:
        super().__init__(seed)
        self.dim = self.relevant + self.irrelevant
        self.low, self.high = np.zeros(self.dim), np.ones(self.dim)
        self.n_cells = self.n_tasks = self.bins**self.relevant
        self.strides = self.bins ** np.arange(self.relevant)
        self.index = (np.arange(self.n_cells)[:, None] // self.strides) % self.bins
        self.possible = np.ones(self.n_cells, bool) if self.reach is None else self.index.sum(axis=1) <= self.reach
        self.practice = np.zeros(self.n_cells, np.int64)
        self.unlocked = np.zeros(self.n_cells, bool)
        self.unlocked[0] = True

    def cell(self, goal: Any) -> int:
        g = np.asarray(goal, float)[: self.relevant]
        return int(np.minimum((g * self.bins).astype(np.int64), self.bins - 1) @ self.strides)

    def centre(self, cell: int) -> np.ndarray:
        return np.concatenate([(self.index[cell] + 0.5) / self.bins, np.full(self.irrelevant, 0.5)])

    def attempt_cell(self, c: int) -> float:
        if not self.unlocked[c]:
            return 0.0
        if self.practice[c] < self.need:
            self.practice[c] += 1
            if self.practice[c] == self.need:
                for j in range(self.relevant):
                    for step in (-1, 1):
                        if 0 <= self.index[c, j] + step < self.bins:
                            n = c + step * int(self.strides[j])
                            self.unlocked[n] = self.possible[n]
        return float(self.practice[c] / self.need)

    def attempt(self, goal: Any) -> float:
        return self.attempt_cell(self.cell(goal))

    def mastered(self) -> np.ndarray:
        return self.practice >= self.need

    def score(self) -> float:
        return float(np.mean(self.mastered()[self.possible]))

    def oracle_cell(self) -> int:
        """An unlocked cell not yet mastered (the first by index); any cell once all are mastered."""
        frontier = np.flatnonzero(self.unlocked & ~self.mastered())
        return int(frontier[0]) if len(frontier) else 0

    def oracle(self) -> Any:
        return self.centre(self.oracle_cell())

    def cell_box(self, cell: int) -> tuple[np.ndarray, np.ndarray]:
        """The box of the goals in ``cell`` (the irrelevant dimensions whole)."""
        lo = np.concatenate([self.index[cell] / self.bins, np.zeros(self.irrelevant)])
        return lo, np.concatenate([(self.index[cell] + 1) / self.bins, np.ones(self.irrelevant)])

    def cells_box(self, cells: Any) -> tuple[np.ndarray, np.ndarray]:
        """The smallest box that holds every cell of ``cells``."""
        boxes = [self.cell_box(int(c)) for c in cells]
        return np.min([b[0] for b in boxes], axis=0), np.max([b[1] for b in boxes], axis=0)

    def easy_cells(self) -> list[int]:
        """The cells an expert starts from: the one at the origin, open from the start."""
        return [0]

    def expert_knowledge(self) -> Knowledge:
        """easy: :meth:`easy_cells`; target: the cells the score counts (those that can be
        mastered), as the box that holds them."""
        return self.knowledge(self.cells_box(self.easy_cells()), self.cells_box(np.flatnonzero(self.possible)))


class HypercubeCells(Hypercube):
    """The hypercube given as a list of its cells (goals are cell indices): for task-list teachers."""

    space = "tasks"

    def attempt(self, goal: Any) -> float:
        return self.attempt_cell(int(goal))

    def oracle(self) -> Any:
        return self.oracle_cell()


BUDGETS_10K = {"quick": 10_000, "standard": 10_000, "full": 10_000}


@register
class Cube2d(Hypercube):
    name, budgets = "2d", BUDGETS_10K
    measures = "finding the frontier of what can be learnt now and following it (100 cells, a chain from the origin)"


@register
class Cube5d(Hypercube):
    name, relevant, bins = "5d", 5, 3
    budgets = {"quick": 15_000, "standard": 15_000, "full": 15_000}
    measures = "the same in 5 dimensions (243 cells): a frontier a teacher cannot see by drawing uniformly"


@register
class Cube2dPlus3(Hypercube):
    name, irrelevant, budgets = "2d+3", 3, BUDGETS_10K
    measures = "ignoring 3 dimensions that change nothing (the 2d task in a 5-D box)"


@register
class Cube2dReach(Hypercube):
    name, reach, budgets = "2d-reach", 5, BUDGETS_10K
    measures = "leaving an impossible region alone: 79 % of the box can never be learnt (21 cells can)"


@register
class Cube2dCells(HypercubeCells):
    name, budgets = "2d-cells", BUDGETS_10K
    measures = "the 2d task given as its 100 cells, for task-list teachers"


class Niches(BenchTask):
    """Progress niches (saggriac.teachers.progress_niches): a chain of niches where skill grows
    with practice once unlocked, noisy cells that teach nothing but answer at random, impossible
    cells that always answer 0, and distractor dimensions. The score is the mean skill over the
    niches."""

    space = "box"
    learner = "progress niches"
    budgets = {"quick": 8_000, "standard": 8_000, "full": 8_000}
    points = 32
    distractors = 0
    learning_rate = 0.02

    def __init__(self, seed: int) -> None:
        super().__init__(seed)
        self.env = ProgressNiches(seed, distractors=self.distractors, learning_rate=self.learning_rate)
        self.low, self.high = self.env.low, self.env.high
        self.n_tasks = self.env.n_cells

    def attempt(self, goal: Any) -> float:
        return self.env.attempt(goal)

    def score(self) -> float:
        return self.env.mastery()

    def oracle_niche(self) -> int:
        """The last unlocked niche while the chain is not all open; then the least skilled."""
        if self.env.unlocked < len(self.env.skill):
            return self.env.unlocked - 1
        return int(np.argmin(self.env.skill))

    def oracle(self) -> Any:
        j, i = self.env.niche_cells[self.oracle_niche()]
        return self.env.centre(j * self.env.nx + i)

    def niche_box(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        """The box of niche ``k``'s cell (the distractor dimensions whole)."""
        j, i = self.env.niche_cells[k]
        lo, hi = np.zeros(self.env.dim), np.ones(self.env.dim)
        lo[:2], hi[:2] = (i / self.env.nx, j / self.env.ny), ((i + 1) / self.env.nx, (j + 1) / self.env.ny)
        return lo, hi

    def expert_knowledge(self) -> Knowledge:
        """easy: the first niche, open from the start; target: the niches (the score is their
        mean skill), as the box that holds them."""
        boxes = [self.niche_box(k) for k in range(len(self.env.niche_cells))]
        return self.knowledge(boxes[0], (np.min([b[0] for b in boxes], axis=0), np.max([b[1] for b in boxes], axis=0)))


@register
class Niches0(Niches):
    name = "niches-0"
    measures = "moving along a chain of niches as each opens, and spending little on noisy cells (whose competence moves without progress) and impossible ones"


@register
class Niches4(Niches):
    name, distractors = "niches-4", 4
    measures = "the same with 4 distractor dimensions (a 6-D box)"


@register
class Niches8(Niches):
    name, distractors = "niches-8", 8
    measures = "the same with 8 distractor dimensions (a 10-D box)"


@register
class NichesCells(Niches):
    name, space = "niches-cells", "tasks"
    measures = "the niches given as their 16 cells, for task-list teachers"

    def attempt(self, goal: Any) -> float:
        return self.env.attempt(self.env.centre(int(goal)))

    def oracle(self) -> Any:
        j, i = self.env.niche_cells[self.oracle_niche()]
        return j * self.env.nx + i
