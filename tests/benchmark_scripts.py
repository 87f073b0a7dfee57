"""What the tests of the benchmark scripts share: loading one of benchmarks/*.py as a module."""

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"


def load(name: str) -> ModuleType:
    """benchmarks/<name>.py (``name`` may hold a subfolder) as a fresh module, registered under
    ``<its file name>_under_test`` (dataclasses and pickle look a module up by name)."""
    spec = importlib.util.spec_from_file_location(f"{Path(name).name}_under_test", BENCHMARKS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module
