"""What is made of finished runs and studies: the statistics table (statistics), the figures
(plots) and the null model of where the region tree splits (splits); and what a teacher does
while it teaches: its readings (readings, numpy only) and the picture of its goals over
time (teacher_plots).

Import the module you need (``from saggriac.analysis import statistics``): they bring scipy and
matplotlib, which a run does not need. ``saggriac.analysis.plot_teacher`` and
``saggriac.analysis.teacher_readings`` load their module on first use."""

from importlib import import_module
from typing import Any

_LAZY = {"plot_teacher": "teacher_plots", "teacher_figure": "teacher_plots", "teacher_readings": "readings"}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = list(_LAZY)
