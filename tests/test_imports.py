"""The package's import weight and its names (issues 26 and 34): a teacher costs numpy and the
core, not pandas; a former module path (``saggriac.goal_selection``, ``saggriac.gym``...) warns
and gives the module now at its new path, for imports and for old pickles; run, results and
studies load on first use."""

import pickle
import subprocess
import sys

import saggriac

HEAVY = ("pandas", "pyarrow", "matplotlib", "scipy", "tqdm")


def _loaded_after(code: str) -> list[str]:
    probe = f"import sys\n{code}\nprint(','.join(m for m in {HEAVY!r} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    return [m for m in out.stdout.strip().split(",") if m]


def test_a_teacher_loads_no_dataframe_library():
    assert _loaded_after("import saggriac.teachers as t\nt.SaggRiacSelector([0, 0], [1, 1]).sample()") == []
    assert _loaded_after("import saggriac\nsaggriac.Config.from_preset('exp2')") == []


def test_run_and_studies_load_on_first_use():
    assert "pandas" in _loaded_after("import saggriac\nsaggriac.run")
    assert {"run", "resume", "RunResult", "Study", "run_study", "load_study"} <= set(dir(saggriac))
    from saggriac import load_study, run

    assert callable(run) and callable(load_study)


def test_the_former_module_name_is_the_same_module():
    import pytest

    sys.modules.pop("saggriac.goal_selection", None)
    with pytest.warns(DeprecationWarning, match="saggriac.goal_selection is now saggriac.teachers"):
        import saggriac.goal_selection as old
    import saggriac.teachers as new

    assert old is new and old.MODES[1] == "interest"
    # A teacher pickled when the classes lived in saggriac.goal_selection still loads.
    t = saggriac.SaggRiacSelector([0, 0], [1, 1], seed=3)
    t.update(t.sample(), -0.5)
    new_pickle = pickle.dumps(t, protocol=0)
    assert b"saggriac.teachers.sagg_riac\n" in new_pickle
    want = pickle.loads(new_pickle).sample().tolist()
    # As pickled when the classes lived in saggriac.goal_selection, and in saggriac.teachers itself (0.5).
    for old_module in (b"saggriac.goal_selection", b"saggriac.teachers"):
        back = pickle.loads(new_pickle.replace(b"saggriac.teachers.sagg_riac", old_module))
        assert type(back) is saggriac.SaggRiacSelector and back.sample().tolist() == want


def test_moved_modules_keep_their_former_names_with_a_warning():
    code = """
import warnings
warnings.simplefilter("error", DeprecationWarning)
import saggriac, saggriac.analysis.statistics
try:
    import saggriac.statistics
except DeprecationWarning as e:
    print(e)
warnings.simplefilter("ignore", DeprecationWarning)
from saggriac import plots, reproduce, runner, storage
import saggriac.statistics
assert saggriac.statistics.paired is saggriac.analysis.statistics.paired
assert runner.run is saggriac.run and storage.write_run is saggriac.runs.storage.write_run
assert plots.plot_curves is saggriac.analysis.plots.plot_curves and reproduce.reproduce is saggriac.study.reproduce.reproduce
assert saggriac.result is saggriac.runs.result and saggriac.runner is saggriac.runs.runner
# A Gymnasium entry point written against the former path still resolves.
import gymnasium
env = gymnasium.make("saggriac.gym:saggriac/PlanarArm-v0")
print(type(env.unwrapped).__module__)
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines() == ["saggriac.statistics is now saggriac.analysis.statistics: import it from there (the former path will be removed in 0.7.0).", "saggriac.adapters.gym.arm_env"]


def test_a_result_pickled_under_the_former_module_name_still_loads(small_config):
    res = saggriac.run(small_config.replace(n_steps=500, n_evals=2), seed=1)
    old_pickle = pickle.dumps(res, protocol=0).replace(b"saggriac.runs.result", b"saggriac.result")
    assert b"saggriac.result\n" in old_pickle
    import pytest

    sys.modules.pop("saggriac.result", None)  # as in a new process: the first import of the former path
    with pytest.warns(DeprecationWarning, match="saggriac.result is now saggriac.runs.result"):
        back = pickle.loads(old_pickle)
    assert type(back) is saggriac.RunResult and back.reach_error.tolist() == res.reach_error.tolist()


def test_a_missing_module_under_a_former_path_is_named_as_typed():
    """import saggriac.gym.nothere named saggriac.adapters.gym.nothere, a path never typed
    (issue 44, item 10)."""
    code = """
import warnings
warnings.simplefilter("ignore", DeprecationWarning)
for name in ("saggriac.gym.nothere", "saggriac.storage.nothere"):
    try:
        __import__(name)
    except ModuleNotFoundError as e:
        print(e.name, "|", e)
import saggriac.gym.goals
print(saggriac.gym.goals.__name__)
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines() == [
        "saggriac.gym.nothere | No module named 'saggriac.gym.nothere'",
        "saggriac.storage.nothere | No module named 'saggriac.storage.nothere'; 'saggriac.storage' is not a package",
        "saggriac.adapters.gym.goals",
    ]
