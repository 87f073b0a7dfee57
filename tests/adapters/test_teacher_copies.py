"""A teacher split across processes is refused under every start method, and a teacher that lives
in one process only is not (saggriac.teachers.ownership). Each case runs as a user runs it: a
script file in a fresh interpreter, with the framework's own worker processes."""

import json
import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

ENV = "saggriac.adapters.gym:saggriac/PlanarArm-v0"  # the module prefix registers the ids in spawned workers too
METHODS = ["default", "fork", "forkserver", "spawn"]

PRELUDE = f"""
import json, multiprocessing as mp, os, sys
import numpy as np, gymnasium, saggriac as sg, saggriac.adapters.gym as sgym
ENV = {ENV!r}
method = None if sys.argv[1] == "default" else sys.argv[1]
def report(**kw):
    print("RESULT " + json.dumps(kw), flush=True)
"""


def _run(tmp_path, body: str, method: str, timeout: float = 300, until: str | None = None, args: list[str] = ()) -> tuple[dict, str]:
    """Run ``body`` as a script; return its RESULT line and its stderr. With ``until``, stop once
    stderr shows it: under fork, SB3's SubprocVecEnv waits forever on a worker that failed while
    building its environment (its siblings hold the failed worker's pipe), whatever the failure."""
    script = tmp_path / f"case_{method}.py"
    script.write_text(PRELUDE + textwrap.dedent(body))
    out_f, err_f = tmp_path / f"out_{method}.txt", tmp_path / f"err_{method}.txt"
    with open(out_f, "w") as out, open(err_f, "w") as err:
        p = subprocess.Popen([sys.executable, str(script), method, *args], stdout=out, stderr=err, cwd=tmp_path, start_new_session=True)
        deadline = time.monotonic() + timeout
        try:
            while p.poll() is None and time.monotonic() < deadline:
                if until is not None and until in err_f.read_text():
                    time.sleep(1.0)  # let the rest of the traceback reach the file
                    break
                time.sleep(0.2)
        finally:
            # The script's worker processes too: a forked worker whose parent ended at os._exit
            # waits on its pipe for ever.
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait()
    stdout, stderr = out_f.read_text(), err_f.read_text()
    lines = [l for l in stdout.splitlines() if l.startswith("RESULT ")]
    if not lines and until is not None and until in stderr:
        return {"refused": True, "error": "a worker's " + until}, stderr
    # The timeout is a guard against a hang, not a speed test: a machine loaded by other jobs may
    # take minutes to import torch and SB3 in every process.
    assert lines, f"rc {p.returncode} (-9: killed at the {timeout} s guard)\nstdout {stdout[-2000:]}\nstderr {stderr[-3000:]}"
    return json.loads(lines[-1][len("RESULT ") :]), stderr


SB3_SPLIT = """
from stable_baselines3.common.vec_env import SubprocVecEnv
teacher = sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=0)
N, ALLOW = int(sys.argv[2]), sys.argv[3] == "allow"
def make():
    return sgym.SelectorGoals(gymnasium.make(ENV, max_episode_steps=5), teacher, allow_copy=ALLOW)
if __name__ == "__main__":
    try:
        v = SubprocVecEnv([make] * N, start_method=method)
        o = v.reset()
        for _ in range(12):
            v.step(np.stack([v.action_space.sample()] * N))
        report(refused=False, goals=o["desired_goal"].tolist(), told=len(teacher.history()["told_goal"]))
    except Exception as e:
        report(refused=True, error=type(e).__name__, message=str(e))
    os._exit(0)  # the surviving worker may still wait on its pipe
"""


@pytest.mark.parametrize("n_workers", [1, 2])
@pytest.mark.parametrize("method", METHODS)
def test_sb3_subproc_workers_given_a_copy_of_one_teacher_are_refused_in_the_main_process(tmp_path, method, n_workers):
    # before: ConnectionResetError in the main process (a hang under fork) with two workers, and a
    # silent copy with one (the main process's teacher told 0)
    out, _ = _run(tmp_path, SB3_SPLIT, method, args=[str(n_workers), "no"])
    assert out["refused"] and out["error"] == "WorkerRefusalError", out
    assert "A worker process refused its teacher" in out["message"] and "handed to this worker when it started" in out["message"], out
    assert "saggriac.adapters.sb3.TeacherCallback" in out["message"] and "allow_copy=True" in out["message"], out


@pytest.mark.parametrize("method", ["default", "fork"])
def test_sb3_subproc_workers_with_allowed_copies_run(tmp_path, method):
    out, _ = _run(tmp_path, SB3_SPLIT, method, args=["2", "allow"])
    assert not out["refused"], out
    assert out["told"] == 0  # each worker's copy learns alone, as allow_copy says


ASYNC_SPLIT = """
teacher = sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=0)
def make():
    return sgym.SelectorGoals(gymnasium.make(ENV, max_episode_steps=5), teacher)
if __name__ == "__main__":
    try:
        v = gymnasium.vector.AsyncVectorEnv([make, make], context=method)
        o, _ = v.reset(seed=0)
        report(refused=False, goals=o["desired_goal"].tolist())
    except Exception as e:
        report(refused=True, error=type(e).__name__, message=str(e))
    os._exit(0)
"""


@pytest.mark.parametrize("method", METHODS)
def test_gymnasium_async_workers_sharing_one_teacher_are_refused(tmp_path, method):
    out, _ = _run(tmp_path, ASYNC_SPLIT, method)
    assert out["refused"] and out["error"] == "WorkerRefusalError", out  # before: ConnectionResetError
    assert "A worker process refused its teacher" in out["message"] and "VectorSelectorGoals" in out["message"], out


POOL = """
def train(teacher):
    env = sgym.SelectorGoals(gymnasium.make(ENV, max_episode_steps=5), teacher, allow_copy=ALLOW)
    env.reset(seed=0)
    for _ in range(20):
        _, _, term, trunc, _ = env.step(env.action_space.sample())
        if term or trunc:
            env.reset()
    return os.getpid(), teacher.history()["told_goal"].tolist()

if __name__ == "__main__":
    shared = sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=0)
    teachers = [shared, shared] if SHARED else [sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=s) for s in (1, 2)]
    ctx = mp.get_context(method)
    try:
        # One task per worker, both running at once (a barrier would do; two slow tasks suffice).
        with ctx.Pool(2, maxtasksperchild=1) as pool:
            out = pool.map(train, teachers, chunksize=1)
        report(refused=False, pids=[p for p, _ in out], told=[len(t) for _, t in out])
    except Exception as e:
        report(refused=True, error=type(e).__name__, message=str(e))
"""


@pytest.mark.parametrize("method", METHODS)
def test_a_pool_of_independent_trainings_each_with_its_own_teacher_is_allowed(tmp_path, method):
    out, _ = _run(tmp_path, "SHARED, ALLOW = False, False\n" + POOL, method)
    assert not out["refused"], out  # before: refused under spawn ("a copy of a teacher made when it was sent to a worker")
    assert out["told"] == [4, 4]  # 20 steps of 5-step episodes, each told in its own worker


@pytest.mark.parametrize("method", ["fork", "forkserver", "spawn"])
def test_one_teacher_given_to_two_pool_workers_is_refused_unless_allowed(tmp_path, method):
    body = POOL.replace("def train(teacher):", "import time\ndef train(teacher):\n    time.sleep(0.0)")
    # The two tasks must overlap for two processes to hold the teacher at once: each keeps it
    # while it trains, and the pool starts both workers together.
    body = body.replace("    return os.getpid()", "    time.sleep(3)\n    return os.getpid()")
    out, _ = _run(tmp_path, "SHARED, ALLOW = True, False\n" + body, method)
    # the pool hands the worker's ConformanceError back; under fork the signal may come first
    assert out["refused"] and out["error"] in ("ConformanceError", "WorkerRefusalError") and "allow_copy=True" in out["message"], out
    out, _ = _run(tmp_path, "SHARED, ALLOW = True, True\n" + body, method)
    assert not out["refused"] and out["told"] == [4, 4], out


SEQUENTIAL = """
def train(teacher):
    env = sgym.SelectorGoals(gymnasium.make(ENV, max_episode_steps=5), teacher)
    env.reset(seed=0)
    return os.getpid()

if __name__ == "__main__":
    teacher = sg.SaggRiacSelector([0.0, -50.0], [50.0, 50.0], seed=0)
    workers = int(sys.argv[2])
    try:
        with mp.get_context(method).Pool(workers) as pool:
            pids = pool.map(train, [teacher, teacher], chunksize=1)
        report(refused=False, pids=pids)
    except Exception as e:
        report(refused=True, error=type(e).__name__, message=str(e))
"""


@pytest.mark.parametrize("workers", [1, 2])
@pytest.mark.parametrize("method", ["fork", "spawn"])
def test_one_teacher_given_twice_to_a_pool_is_refused_even_when_the_tasks_do_not_overlap(tmp_path, method, workers):
    # before: Pool(1) trained two copies one after the other, and Pool(2) with short tasks was
    # refused or not from run to run; the second copy sent is now refused whatever the timing
    for _ in range(2):
        out, _ = _run(tmp_path, SEQUENTIAL, method, args=[str(workers)])
        # the pool hands the worker's ConformanceError back; under fork the signal may come first
        assert out["refused"] and out["error"] in ("ConformanceError", "WorkerRefusalError"), out
        assert "copy number 2 of a teacher" in out["message"] and "allow_copy=True" in out["message"], out
