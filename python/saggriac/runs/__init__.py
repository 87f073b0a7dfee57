"""One run: the learner (learner), which ``run(config, seed)`` and ``resume(out_dir)`` (runner)
build and drive, its result (result), and what surrounds it: the memory and threads it may take
(resources), where its time went (time_budget), its checkpoints (checkpoint) and its folder on
disk, written so that nothing is lost (storage)."""

from .learner import Learner
from .result import RunResult
from .checkpoint import CheckpointWarning, checkpoint_dir
from .runner import resume, run
from .storage import RunExistsError

__all__ = ["run", "resume", "Learner", "RunResult", "CheckpointWarning", "RunExistsError", "checkpoint_dir"]
