"""Every public constructor and method of the teachers and the Python bodies, driven with
extreme, non-finite, wrong-type and wrong-shape values (issue 27, item 2). Each call must give a
correct answer or a saggriac error: never a Rust panic, an abort, a hang or another exception.
The calls run in a child process, so that an abort (a failed allocation kills the interpreter)
fails this test instead of the test run, and the child names the call it was making."""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import textwrap

CHILD = textwrap.dedent(
    r'''
    import itertools, json, math, sys
    import numpy as np
    import saggriac
    from saggriac.errors import SaggriacError
    from saggriac.bodies.environments import PlanarArm, SpatialArm

    INTS = [0, 1, -1, 2**31, 2**40, 2**62, 2**64, 10**30, 2.5, True, "3", None, float("nan")]
    FLOATS = [0.0, -0.0, 1e-320, 1e300, -1e300, float("inf"), float("nan"), True, "0.5", None, [0.5]]
    VECTORS = [[], [0.5], [0.5, 0.5, 0.5], [float("nan"), 0.5], [float("inf"), 0.5], [1e300, -1e300], ["a", "b"], [True, False], "ab", None, [[0.5, 0.5]], np.zeros((2, 2))]
    BOX = ([0.0, 0.0], [1.0, 1.0])

    def teachers():
        yield "SaggRiacSelector", lambda **kw: saggriac.SaggRiacSelector(*BOX, **kw), {"g_max": INTS, "zeta": INTS, "min_child": INTS, "p_interest": FLOATS, "seed": INTS, "interest_divisor": ["zeta", "w", 3, None]}
        yield "RiacSelector", lambda **kw: saggriac.RiacSelector(*BOX, **kw), {"max_region_size": INTS, "split_attempts": INTS, "min_child_share": FLOATS, "min_dims_range_ratio": FLOATS, "p_alp": FLOATS, "seed": INTS}
        yield "AlpGmmSelector", lambda **kw: saggriac.AlpGmmSelector(*BOX, **kw), {"fit_rate": INTS, "max_components": INTS, "random_task_ratio": FLOATS, "bootstrap": INTS, "seed": INTS}
        yield "CovarGmmSelector", lambda **kw: saggriac.CovarGmmSelector(*BOX, **kw), {"fit_rate": INTS, "max_components": INTS, "random_task_ratio": FLOATS, "bootstrap": INTS, "seed": INTS}
        yield "DiscreteLpSelector", lambda **kw: saggriac.DiscreteLpSelector(kw.pop("n_tasks", 4), **kw), {"n_tasks": INTS, "alpha": FLOATS, "theta": FLOATS, "seed": INTS}

    def attempt(name, call):
        print(name, flush=True)  # the last line printed names the call that killed the process
        try:
            out = call()
        except SaggriacError:
            return "error"
        except BaseException as e:
            print(json.dumps({"bad": name, "type": type(e).__name__, "msg": str(e)[:300]}), flush=True)
            return "bad"
        return out

    for cls, make, params in teachers():
        for key, values in params.items():
            for v in values:
                attempt(f"{cls}({key}={v!r})", lambda: make(**{key: v}))
        for low, high in itertools.product(VECTORS[:8], VECTORS[:8]):
            if cls != "DiscreteLpSelector":
                attempt(f"{cls} bounds {low!r} {high!r}", lambda: type(make())(low, high))
        t = make(seed=1)
        c_lo, c_hi = t.competence_range
        for i in range(30):
            g = t.sample()
            t.update(g, c_lo + (c_hi - c_lo) * (i % 7) / 7)
        for n in INTS:
            attempt(f"{cls}.sample_batch({n!r})", lambda: t.sample_batch(n))
        for g in VECTORS + [np.array([0.5, 0.5])]:
            for c in FLOATS + [np.float32(-0.5), np.array(-0.5), np.array([-0.5])]:
                attempt(f"{cls}.update({g!r}, {c!r})", lambda: t.update(g, c))
        for goals, comps in [(np.zeros((3, 2)), np.zeros(2)), (np.zeros((3, 3)), np.zeros(3)), (np.full((2, 2), np.nan), np.zeros(2)), ([["a", "b"]], [0.0]), (np.zeros((2, 2)), [1e300, 0.0]), (np.zeros((0, 2)), np.zeros(0))]:
            attempt(f"{cls}.update_batch({np.asarray(goals).shape}, {comps!r})", lambda: t.update_batch(goals, comps))
        for scale in (1e150, 1e99, -1e99):
            for i in range(300):
                g = t.sample()
                attempt(f"{cls}.update(g, {scale} * u)", lambda: t.update(g, scale * ((i * 0.618) % 1.0 - 0.5)))
            g = attempt(f"{cls}.sample() after extreme competences", lambda: t.sample_batch(20))
            if not isinstance(g, str) and not np.all(np.isfinite(g)):
                print(json.dumps({"bad": f"{cls}: non-finite goals after competences of scale {scale}"}), flush=True)
        for path in ["", None, 3, "/dev/null", "/proc/self/status"]:
            attempt(f"{cls}.save({path!r}, overwrite=True)", lambda: t.save(path, overwrite=True))

    for arm_cls in (PlanarArm, SpatialArm):
        for key, values in {"n_joints": INTS, "arm_length": FLOATS, "joint_limit": FLOATS, "max_joint_step": FLOATS, "link_lengths": VECTORS}.items():
            for v in values:
                attempt(f"{arm_cls.__name__}({key}={v!r})", lambda: arm_cls(**{key: v}))
        arm = arm_cls(n_joints=4)
        for v in VECTORS + [np.zeros(4), np.full(4, np.nan), np.full(4, 1e300)]:
            attempt(f"{arm_cls.__name__}.step({v!r})", lambda: arm.step(v))
            attempt(f"{arm_cls.__name__}.reset(theta={v!r})", lambda: arm.reset(options={"theta": v}))
            theta = arm.theta
            if theta.shape != (4,) or not np.all(np.isfinite(theta)):
                print(json.dumps({"bad": f"{arm_cls.__name__} state corrupted by {v!r}: theta {theta.tolist()}"}), flush=True)
    print("DONE", flush=True)
    '''
)


def _limit_memory() -> None:
    # 4 GB of address space: a huge allocation fails (and aborts) instead of swapping the machine.
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))


def test_every_public_call_gives_an_answer_or_a_saggriac_error():
    r = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, timeout=600, preexec_fn=_limit_memory)
    lines = r.stdout.splitlines()
    bad = [json.loads(line) for line in lines if line.startswith("{")]
    assert r.returncode == 0 and lines and lines[-1] == "DONE", f"the child died (rc {r.returncode}) during: {lines[-1] if lines else '?'}\n{r.stderr[-2000:]}"
    assert not bad, "\n".join(map(str, bad))
    assert len(lines) > 1000  # the calls were made
