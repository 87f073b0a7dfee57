"""PLR with its paper's scores as a bench teacher: ``saggriac.bench.value_loss:PlrValueLoss``.

Prioritized Level Replay (Jiang, Grefenstette & Rocktäschel, ICML 2021) ranks levels by the
learner's positive value loss, which only the task's learner has (PPO's generalised advantage
estimates), not by a competence. This class is PlrSelector with ``score="told"`` and a ``told``
attribute that asks the bench's guard for that score: a task that can tell it (its ``tells``
lists "positive_value_loss", as rl-minigrid's does) reads the guard's ``told`` and tells each
episode's mean positive GAE through :class:`saggriac.adapters.sb3.TeacherCallback`; on any
other task the guard refuses the teacher before the run starts.
"""

from __future__ import annotations

from ..teachers.plr import PlrSelector


class PlrValueLoss(PlrSelector):
    """PlrSelector(n_tasks, score="told") told each level's positive value loss (see the module)."""

    told = "positive_value_loss"

    def __init__(self, n_tasks: int, seed: int = 0, **params: object) -> None:
        super().__init__(n_tasks, seed, score="told", **params)  # type: ignore[arg-type]
