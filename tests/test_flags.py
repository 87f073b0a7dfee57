"""Every yes/no flag of every public entry point takes only True or False (numpy's included):
``overwrite="no"`` is truthy and ``progress=0`` falsy, so reading them by their truth would
replace a run the user asked to keep, or hide a bar they asked for (issue 33, item 1).

The flags are found by walking the package, so a new flag fails this test until it is listed
here with a way to call it."""

import importlib
import inspect
import os
import pkgutil
from pathlib import Path

import numpy as np
import pytest

import saggriac as sg
from saggriac.errors import ParameterError

BAD = ["no", "False", 0, 1, None, 1.0, np.int64(0), [True]]


def _public_flags() -> set[str]:
    """``module.qualname.param`` of every parameter whose default is a bool, over the public
    functions and methods of every saggriac module."""
    found = set()
    seen = set()

    def look(fn, where):
        fn = inspect.unwrap(fn)
        if not callable(fn) or id(fn) in seen or not getattr(fn, "__module__", "").startswith("saggriac"):
            return
        seen.add(id(fn))
        try:
            sig = inspect.signature(fn)
        except (TypeError, ValueError):
            return
        for p in sig.parameters.values():
            if isinstance(p.default, bool):
                found.add(f"{where}.{p.name}")

    for info in pkgutil.walk_packages(sg.__path__, "saggriac."):
        mod = importlib.import_module(info.name)
        for name, obj in vars(mod).items():
            if name.startswith("_") or getattr(obj, "__module__", None) != mod.__name__:
                continue
            if inspect.isfunction(obj):
                look(obj, f"{obj.__module__}.{obj.__qualname__}")
            elif inspect.isclass(obj):
                for cls in obj.__mro__:
                    if not cls.__module__.startswith("saggriac"):
                        continue
                    for mname, member in vars(cls).items():
                        if mname.startswith("_") and mname != "__init__":
                            continue
                        member = getattr(member, "__func__", member)
                        if inspect.isfunction(member):
                            look(member, f"{member.__module__}.{member.__qualname__}")
    return found


def _cfg():
    return sg.Config.from_preset("exp1", n_steps=300, n_evals=2, n_test_goals=5, n_test_configs=5)


def _gym():
    pytest.importorskip("gymnasium")
    import saggriac.adapters.gym

    return saggriac.adapters.gym


def _teacher():
    return sg.RandomSelector([0.0, -50.0], [50.0, 50.0])


def _mujoco_arm():
    pytest.importorskip("mujoco")
    from saggriac.bodies.mujoco_arm import pusher_arm

    return pusher_arm()


#: How to call each flag with the value ``v``, everything else valid, in ``tmp_path``.
CALLS = {
    "saggriac.runs.runner.run.progress": lambda v, t: sg.run(_cfg(), 1, out_dir=t / "r", progress=v),
    "saggriac.runs.runner.run.overwrite": lambda v, t: sg.run(_cfg(), 1, out_dir=t / "r", overwrite=v),
    "saggriac.runs.runner.resume.progress": lambda v, t: sg.resume(t / "r", progress=v),
    "saggriac.runs.learner.Learner.run.progress": lambda v, t: sg.Learner(_cfg(), 0).run(until=0, progress=v),
    "saggriac.runs.learner.Learner.save_checkpoint.overwrite": lambda v, t: sg.Learner(_cfg(), 0).save_checkpoint(t / "r", 100, overwrite=v),
    "saggriac.runs.result.RunResult.save.overwrite": lambda v, t: sg.RunResult.load(t / "r").save(t / "r", overwrite=v),
    "saggriac.teachers.ask_tell.AskTellSelector.save.overwrite": lambda v, t: sg.RandomSelector([0.0], [1.0]).save(t / "teacher", overwrite=v),
    "saggriac.study.run_study.progress": lambda v, t: sg.run_study(sg.Study(base=_cfg(), conditions=("sagg_random",), seeds=(0,)), t / "st", progress=v),
    "saggriac.study.reproduce.reproduce.progress": lambda v, t: __import__("saggriac.study.reproduce", fromlist=["x"]).reproduce("exp1", t / "st", seeds=1, steps=300, progress=v),
    "saggriac.config.Config.__init__.episodic_refine": lambda v, t: sg.Config(episodic_refine=v),
    "saggriac.config.Config.__init__.timeout_in_exploration": lambda v, t: sg.Config.from_preset("exp1", timeout_in_exploration=v),
    "saggriac.teachers.covar_gmm.CovarGmmSelector.__init__.absolute_lp": lambda v, t: sg.CovarGmmSelector([0.0], [1.0], absolute_lp=v),
    "saggriac.teachers.tscl.TsclSelector.__init__.absolute": lambda v, t: sg.TsclSelector(3, absolute=v),
    "saggriac.bench.suite.run_bench.rerun": lambda v, t: __import__("saggriac.bench.suite", fromlist=["x"]).run_bench(["random"], t / "b", tasks=["2d"], seeds=1, workers=1, rerun=v),
    "saggriac.bench.suite.run_bench.progress": lambda v, t: __import__("saggriac.bench.suite", fromlist=["x"]).run_bench(["random"], t / "b", tasks=["2d"], seeds=1, workers=1, progress=v),
    "saggriac.bench.suite.run_bench.expert": lambda v, t: __import__("saggriac.bench.suite", fromlist=["x"]).run_bench(["random"], t / "b", tasks=["2d"], seeds=1, workers=1, expert=v),
    "saggriac.bench.runner.execute.progress": lambda v, t: __import__("saggriac.bench.runner", fromlist=["x"]).execute([], t / "b", 1, progress=v),
    "saggriac.bodies.mujoco_arm.MujocoArm.chain.at_origin": lambda v, t: _mujoco_arm().chain(at_origin=v),
    "saggriac.adapters.gym.goals.SelectorGoals.__init__.allow_copy": lambda v, t: _gym().SelectorGoals(_gym().GoalArmEnv(), _teacher(), allow_copy=v),
    "saggriac.adapters.gym.goals.VectorSelectorGoals.__init__.allow_copy": lambda v, t: _gym().VectorSelectorGoals(__import__("gymnasium").vector.SyncVectorEnv([_gym().GoalArmEnv]), _teacher(), allow_copy=v),
    "saggriac.adapters.sb3.TeacherCallback.__init__.allow_copy": lambda v, t: __import__("saggriac.adapters.sb3", fromlist=["x"]).TeacherCallback(_teacher(), allow_copy=v),
    "saggriac.bench.minigrid.evaluate.greedy": lambda v, t: __import__("saggriac.bench.minigrid", fromlist=["x"]).evaluate(None, [], greedy=v),
}


#: Helpers of the package's own modules, called only with a flag their public caller checked.
INTERNAL = {
    "saggriac.files.lock.remove",
    "saggriac.files.write_file.overwrite",
    "saggriac.runs.storage.check_output_dir.overwrite",
    "saggriac.runs.storage.write_run.overwrite",
    "saggriac.teachers.ownership.claim.allow_copy",
    "saggriac.teachers.private_folder.open_claims_dir.make",
    "saggriac.teachers.private_folder.folder.make",
    # A record the runner fills from run()'s checked overwrite, or a checkpoint's checked one.
    "saggriac.runs.run_info.RunInfo.__init__.overwrite",
}


def test_every_flag_is_listed():
    assert _public_flags() - INTERNAL == set(CALLS)


def _tree(root: Path) -> dict[str, bytes | None]:
    out = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for name in dirnames + filenames:
            p = Path(dirpath) / name
            out[str(p.relative_to(root))] = p.read_bytes() if p.is_file() and not p.is_symlink() else None
    return out


@pytest.mark.parametrize("flag", sorted(CALLS))
def test_a_flag_takes_only_true_or_false(flag, tmp_path):
    """Refused with the parameter, the value and the rule, and nothing written or changed: the
    overwrite flags meet a finished run they must keep."""
    call, param = CALLS[flag], flag.rsplit(".", 1)[1]
    if param == "overwrite" or "resume" in flag:
        sg.run(_cfg(), 0, out_dir=tmp_path / "r")
    before = _tree(tmp_path)
    for bad in BAD:
        with pytest.raises(ParameterError) as e:
            call(bad, tmp_path)
        assert _tree(tmp_path) == before, (flag, bad)
        assert e.value.param == param, (flag, bad, str(e.value))
        rule = "must be given a value" if bad is None and "Config" in flag else "must be a bool"
        assert f"'{param}' parameter" in str(e.value) and rule in str(e.value) and any(repr(b) in str(e.value) for b in (bad, getattr(bad, "item", lambda: bad)())), str(e.value)


def test_overwrite_no_keeps_the_finished_run(tmp_path):
    """The audit's data loss: run(..., overwrite="no") replaced the finished seed-0 run."""
    first = sg.run(_cfg(), 0, out_dir=tmp_path / "r")
    kept = _tree(first.path)
    for bad in ("no", 1, "False"):
        with pytest.raises(ParameterError, match="'overwrite' parameter of run"):
            sg.run(_cfg(), 1, out_dir=tmp_path / "r", overwrite=bad)
    assert _tree(first.path) == kept
    assert sg.RunResult.load(first.path).seed == 0
    for bad in ("no", 1):
        with pytest.raises(ParameterError, match="'overwrite' parameter of RunResult.save"):
            sg.run(_cfg(), 1).save(tmp_path / "r", overwrite=bad)
    assert _tree(first.path) == kept


def test_numpy_bools_are_the_bools_they_stand_for(tmp_path):
    first = sg.run(_cfg(), 0, out_dir=tmp_path / "r", progress=np.False_)
    second = sg.run(_cfg(), 1, out_dir=tmp_path / "r", overwrite=np.True_, progress=np.False_)
    assert sg.RunResult.load(second.path).seed == 1 and first.path == second.path
    learner = sg.Learner(_cfg(), 0)
    ck = learner.save_checkpoint(tmp_path / "c", 100, overwrite=np.False_)
    assert ck.is_dir()
    assert sg.resume(tmp_path / "c", progress=np.False_).seed == 0
