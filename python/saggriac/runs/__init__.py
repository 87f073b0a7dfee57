"""One run: ``run(config, seed)`` and ``resume(out_dir)`` (runner), the learner they drive in the
open (learner), its result (result), and what surrounds it: the memory and threads it may take
(resources), where its time went (time_budget) and its folder on disk, written so that nothing
is lost (storage)."""

from .learner import Learner
from .result import RunResult
from .runner import CheckpointWarning, checkpoint_dir, resume, run
from .storage import RunExistsError

__all__ = ["run", "resume", "Learner", "RunResult", "CheckpointWarning", "RunExistsError", "checkpoint_dir"]
