"""What a run records of itself beside its configuration (:class:`RunInfo`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass
class RunInfo:
    """A run's seeds, whether it may replace a finished run at its target, and the steps where it
    was resumed and last checkpointed. run.json and checkpoint.json record it."""

    seed: int
    learner_seed: int
    eval_seed: int
    overwrite: bool = False
    resumed_at: int | None = None
    last_checkpoint: int | None = None
    checkpoint_every: int | None = None

    def for_checkpoint(self) -> dict[str, Any]:
        """The keys checkpoint.json holds (``checkpoint_every`` is written by itself)."""
        out: dict[str, Any] = {"seed": self.seed, "learner_seed": self.learner_seed, "eval_seed": self.eval_seed, "overwrite": self.overwrite}
        if self.resumed_at is not None:
            out["resumed_at"] = self.resumed_at
        if self.last_checkpoint is not None:
            out["last_checkpoint"] = self.last_checkpoint
        return out
