"""Conformance checkers for components users plug into saggriac.

``check_environment(env)`` and ``check_goal_selector(selector)`` exercise an object the way the
run loop will, and raise :class:`saggriac.errors.ConformanceError` naming the first thing that is
wrong. Our own tests run them over every built-in component.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .errors import ConformanceError, ParameterError
from .seeding import FIXED


def _bounds(obj: Any, owner: str, attr_low: str, attr_high: str) -> tuple[np.ndarray, np.ndarray]:
    try:
        lo = np.asarray(getattr(obj, attr_low), dtype=np.float64)
        hi = np.asarray(getattr(obj, attr_high), dtype=np.float64)
    except AttributeError as e:
        raise ConformanceError(f"{owner} needs '{attr_low}' and '{attr_high}' arrays: {e}.") from None
    except (TypeError, ValueError):
        raise ConformanceError(f"{owner}.{attr_low} and {owner}.{attr_high} must be arrays of floats.") from None
    if lo.ndim != 1 or lo.shape != hi.shape or lo.size == 0:
        raise ConformanceError(f"{owner}.{attr_low} and {owner}.{attr_high} must be 1-D arrays of one non-zero length; got shapes {lo.shape} and {hi.shape}.")
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(lo < hi)):
        raise ConformanceError(f"{owner} bounds must be finite with {attr_low} < {attr_high}; got {lo.tolist()} and {hi.tolist()}.")
    return lo, hi


# The run loop's task spaces have 1 to MAX_TASK_DIM dimensions.
MAX_TASK_DIM = 3


def _pair(out: Any, n: int, m: int, call: str) -> tuple[np.ndarray, np.ndarray]:
    if not (isinstance(out, tuple) and len(out) == 2):
        raise ConformanceError(f"{call} must return a pair (theta, x); got {out!r}.")
    try:
        theta = np.asarray(out[0], dtype=np.float64)
        x = np.asarray(out[1], dtype=np.float64)
    except (TypeError, ValueError):
        raise ConformanceError(f"{call} must return arrays of floats; got {out!r}.") from None
    if theta.shape != (n,):
        raise ConformanceError(f"theta returned by {call} must have shape ({n},), one angle per joint; got {theta.shape}.")
    if x.shape != (m,):
        raise ConformanceError(f"x returned by {call} must have shape ({m},), one coordinate per task-space dimension; got {x.shape}.")
    if not (np.all(np.isfinite(theta)) and np.all(np.isfinite(x))):
        raise ConformanceError(f"{call} returned a non-finite value: theta={theta.tolist()}, x={x.tolist()}.")
    return theta, x


def joint_space_of(env: Any) -> tuple[np.ndarray, np.ndarray]:
    if not hasattr(env, "joint_space"):
        raise ConformanceError("environment needs a 'joint_space' attribute: a Box of the joint angles (saggriac.bodies.environments.Box or gymnasium.spaces.Box).")
    for method in ("reset", "step"):
        if not callable(getattr(env, method, None)):
            raise ConformanceError(f"environment needs a '{method}' method (see saggriac.bodies.environments).")
    lo, hi = _bounds(env.joint_space, "environment.joint_space", "low", "high")
    if not np.allclose(lo, -hi, rtol=0, atol=1e-12) or not np.allclose(hi, hi[0], rtol=0, atol=1e-12):
        raise ConformanceError(f"environment.joint_space must have the same symmetric limit on every joint, [-limit, limit]; got low={lo.tolist()}, high={hi.tolist()}.")
    return lo, hi


def _task_dim(env: Any) -> int | None:
    """The dimension of ``env.task_space``, if it has one."""
    if not hasattr(env, "task_space"):
        return None
    lo, _ = _bounds(env.task_space, "environment.task_space", "low", "high")
    if not 1 <= lo.size <= MAX_TASK_DIM:
        raise ConformanceError(f"environment.task_space must have 1 to {MAX_TASK_DIM} dimensions (the run loop's limit); got {lo.size}.")
    return int(lo.size)


def check_environment_interface(env: Any, config: Any) -> None:
    """The cheap checks ``saggriac.run`` makes before a run: the attributes exist and agree with
    the configuration (number of joints, joint limit, task-space dimension)."""
    lo, hi = joint_space_of(env)
    m = _task_dim(env)
    if m is not None and m != len(config.goal_low):
        raise ParameterError(f"The 'goal_low' parameter of Config must have one bound per dimension of the environment's task_space ({m}). Got {list(config.goal_low)} instead.", "goal_low", repr(config.goal_low))
    if config.link_lengths is not None and len(config.link_lengths) != len(hi):
        raise ParameterError(f"The 'link_lengths' parameter of Config must have one length per joint of the environment's joint_space ({len(hi)} joints). Got {len(config.link_lengths)} lengths instead.", "link_lengths", repr(config.link_lengths))
    if config.chain is not None and config.joints != len(hi):
        raise ParameterError(f"The 'chain' parameter of Config must have one joint per joint of the environment's joint_space ({len(hi)} joints). Got a chain of {config.joints} joints instead.", "chain", f"{config.joints} joints")
    if config.link_lengths is None and config.chain is None and len(hi) != config.n_joints:
        raise ParameterError(f"The 'n_joints' parameter of Config must match the environment's joint_space ({len(hi)} joints). Got {config.n_joints} instead.", "n_joints", repr(config.n_joints))
    if not math.isclose(float(hi[0]), config.joint_limit, rel_tol=1e-12):
        raise ParameterError(f"The 'joint_limit' parameter of Config must match the environment's joint_space (limit {float(hi[0])!r}). Got {config.joint_limit!r} instead.", "joint_limit", repr(config.joint_limit))
    placed = _check_placement(env, lo, hi)
    # An episodic run places the body and never steps it.
    if placed is not None and config.paradigm != "episodic":
        _check_moves(env, placed, lo, hi)


def _check_placement(env: Any, lo: np.ndarray, hi: np.ndarray) -> np.ndarray | None:
    """The evaluation places the body at test configurations with reset(options={"theta": t});
    a body that ignores it would be evaluated at the wrong configurations without a word. Two
    fixed configurations (the same for every run, so the check changes no result) must be taken
    as asked and give two different positions. Returns the configuration the body is left at,
    or None when its answers are malformed (the run names them)."""
    n = len(hi)
    rng = np.random.default_rng(FIXED["placement_check"])
    seen = []
    for _ in range(2):
        target = lo + (hi - lo) * rng.uniform(0.25, 0.75, n)
        out = env.reset(options={"theta": target})
        try:
            theta, x = np.asarray(out[0], dtype=np.float64), np.asarray(out[1], dtype=np.float64)
        except (TypeError, ValueError, IndexError, KeyError):
            return None  # a malformed answer: the run names it, with the call and the time step
        if theta.shape != target.shape or not np.all(np.isfinite(x)):
            return None
        if not np.allclose(theta, target, rtol=0, atol=1e-6 * max(1.0, float(np.max(hi - lo)))):
            raise ConformanceError(
                f"environment.reset(options={{'theta': t}}) must place the joints at t: saggriac places the body there to evaluate it. Asked {np.round(target, 6).tolist()}, got {np.round(theta, 6).tolist()}."
            )
        seen.append(x)
    if np.array_equal(seen[0], seen[1]):
        raise ConformanceError(f"environment.reset(options={{'theta': t}}) gave the same position {seen[0].tolist()} for two different t: the body seems to ignore the configuration it is given, and would be evaluated at the wrong place.")
    return theta


def _small_step(env: Any, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """A micro-action's size per joint: 1 % of the joint range, within the action space if the
    body declares one."""
    step = 0.01 * (hi - lo)
    if hasattr(env, "action_space"):
        alo, ahi = _bounds(env.action_space, "environment.action_space", "low", "high")
        step = np.minimum(step, np.minimum(-alo, ahi))
    return step


def _short(a: np.ndarray) -> str:
    return np.array2string(a, precision=4, threshold=6, edgeitems=2)


def _check_moves(env: Any, theta: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> None:
    """The run moves the body by step(dtheta) and learns from the change it reads back; a body
    that ignores step() would run to the end, learning nothing, without a word. From ``theta``
    (a placement at least a quarter of the range from either limit, so that no joint saturates)
    one small micro-action must change the joints."""
    dtheta = _small_step(env, lo, hi)
    if not np.any(dtheta > 0):
        return  # an action space with no room to move: nothing to ask of step()
    out = env.step(dtheta.copy())
    try:
        after = np.asarray(out[0], dtype=np.float64)
    except (TypeError, ValueError, IndexError, KeyError):
        return  # a malformed answer: the run names it, with the call and the time step
    if after.shape == theta.shape and np.array_equal(after, theta):
        raise ConformanceError(
            f"environment.step(dtheta) must move the joints: a run moves the body by micro-actions and learns from the change it reads back. Placed by reset(options={{'theta': t}}) at t = {_short(theta)}, away from the joint limits, and stepped by dtheta = {_short(dtheta)}, the joints stayed at t: the body seems to ignore step(), and a run would learn nothing from it."
        )


def check_goal_selector_interface(selector: Any, config: Any) -> None:
    """The cheap checks ``saggriac.run`` makes before a run: methods exist and the bounds are the
    configured goal space."""
    for method in ("sample", "update"):
        if not callable(getattr(selector, method, None)):
            raise ConformanceError(f"goal_selector needs a '{method}' method (sample() -> goal, update(goal, competence)).")
    from .teachers import TaskListSelector

    if isinstance(selector, TaskListSelector):
        # Its low/high are task indices; fitting the goal space to them would not help.
        raise ParameterError(
            f"The 'goal_selector' parameter of a run must be a teacher of goals in a box (a run's goals are points of the goal space). Got {type(selector).__name__}, a teacher of task indices (for Syllabus or a list of levels), instead.",
            "goal_selector",
            type(selector).__name__,
        )
    lo, hi = _bounds(selector, "goal_selector", "low", "high")
    if not (np.array_equal(lo, np.asarray(config.goal_low, dtype=float)) and np.array_equal(hi, np.asarray(config.goal_high, dtype=float))):
        raise ParameterError(
            f"The 'goal_low'/'goal_high' parameters of Config must be the goal_selector's bounds ({lo.tolist()}, {hi.tolist()}). Got {list(config.goal_low)}, {list(config.goal_high)} instead.",
            "goal_low",
            repr(config.goal_low),
        )


def check_environment(env: Any, n_steps: int = 50, seed: int = 0) -> None:
    """Check that ``env`` follows the environment protocol of ``saggriac.bodies.environments``.

    Resets with a seed (twice: the same pose), places the body at random configurations (twice
    each: the same position; the angles kept), checks what ``saggriac.run`` checks (placements
    taken, and a small micro-action from a placement away from the limits moves the joints),
    runs ``n_steps`` small micro-actions (finite values, angles within the joint space) and a
    zero micro-action (nothing moves)."""
    lo, hi = joint_space_of(env)
    n = len(hi)
    rng = np.random.default_rng(seed)
    first = env.reset(seed=seed)
    m = _task_dim(env)
    if m is None:
        # No task_space: the first position fixes the dimension (a malformed answer is named
        # by _pair below).
        try:
            m = int(np.asarray(first[1], dtype=np.float64).size)
        except (TypeError, ValueError, IndexError, KeyError):
            m = 2
        if not 1 <= m <= MAX_TASK_DIM:
            raise ConformanceError(f"x returned by environment.reset(seed=...) must have 1 to {MAX_TASK_DIM} coordinates (the run loop's limit); got {m}.")
    t0, x0 = _pair(first, n, m, "environment.reset(seed=...)")
    t1, x1 = _pair(env.reset(seed=seed), n, m, "environment.reset(seed=...)")
    if not (np.array_equal(t0, t1) and np.array_equal(x0, x1)):
        raise ConformanceError("environment.reset(seed=s) must give the same (theta, x) each time for the same s.")
    for _ in range(5):
        target = rng.uniform(lo, hi)
        ta, xa = _pair(env.reset(options={"theta": target}), n, m, "environment.reset(options={'theta': ...})")
        tb, xb = _pair(env.reset(options={"theta": target}), n, m, "environment.reset(options={'theta': ...})")
        if not np.allclose(ta, target, rtol=0, atol=1e-9):
            raise ConformanceError(f"environment.reset(options={{'theta': t}}) must place the joints at t (within the joint space); asked {target.tolist()}, got {ta.tolist()}.")
        if not np.array_equal(xa, xb):
            raise ConformanceError("environment.reset(options={'theta': t}) must give the same x each time for the same t.")
    placed = _check_placement(env, lo, hi)
    if placed is not None:
        _check_moves(env, placed, lo, hi)
    theta, _ = _pair(env.reset(), n, m, "environment.reset()")
    step = _small_step(env, lo, hi)
    for i in range(n_steps):
        theta, x = _pair(env.step(rng.uniform(-step, step)), n, m, f"environment.step() (call {i + 1})")
        if np.any(theta < lo - 1e-12) or np.any(theta > hi + 1e-12):
            raise ConformanceError(f"theta returned by environment.step() must stay within joint_space; got {theta.tolist()}.")
    t2, x2 = _pair(env.step(np.zeros(n)), n, m, "environment.step(zeros)")
    if not np.allclose(t2, theta, rtol=0, atol=1e-12):
        raise ConformanceError("environment.step(zeros) must leave the joints where they are.")


def check_goal_selector(selector: Any, n_goals: int = 200, seed: int = 0) -> None:
    """Check that ``selector`` follows the goal-selector protocol: ``low``/``high`` bounds,
    ``sample()`` returning finite goals inside them, ``update(goal, competence)`` accepting a
    competence in [-1, 0] for each (in its ``competence_range`` if it has one). A selector with a ``save`` method (saggriac's teachers) must
    also come back from pickle, and from ``save(path)`` and ``saggriac.load_selector``, asking
    exactly the goals it would have asked next."""
    for method in ("sample", "update"):
        if not callable(getattr(selector, method, None)):
            raise ConformanceError(f"goal_selector needs a '{method}' method (sample() -> goal, update(goal, competence)).")
    lo, hi = _bounds(selector, "goal_selector", "low", "high")
    rng = np.random.default_rng(seed)
    c_lo, c_hi = getattr(selector, "competence_range", (-1.0, 0.0))
    for i in range(n_goals):
        try:
            g = np.asarray(selector.sample(), dtype=np.float64)
        except (TypeError, ValueError):
            raise ConformanceError(f"goal_selector.sample() must return an array of {len(lo)} floats (call {i + 1}).") from None
        if g.shape != lo.shape:
            raise ConformanceError(f"goal_selector.sample() must return shape {lo.shape}; got {g.shape} (call {i + 1}).")
        if not np.all(np.isfinite(g)) or np.any(g < lo) or np.any(g > hi):
            raise ConformanceError(f"goal_selector.sample() must return a finite goal within [low, high]; got {g.tolist()} (call {i + 1}).")
        selector.update(g, float(rng.uniform(c_lo, c_hi)))
    if callable(getattr(selector, "save", None)):
        _check_restore(selector, n_goals, rng, (c_lo, c_hi))


def _check_restore(selector: Any, n_goals: int, rng: np.random.Generator, competences: tuple[float, float]) -> None:
    import os
    import pickle
    import tempfile

    from .teachers import load_selector

    try:
        copies = [("pickle", pickle.loads(pickle.dumps(selector)))]
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "teacher.bin")
            selector.save(path)
            copies.append(("save(path) and load_selector", load_selector(path)))
    except Exception as e:
        raise ConformanceError(f"goal_selector has a save method, so it must come back from pickle and from save(path) / saggriac.load_selector; that failed: {type(e).__name__}: {e}") from e
    for i in range(n_goals):
        g = np.asarray(selector.sample(), dtype=np.float64)
        for how, other in copies:
            h = np.asarray(other.sample(), dtype=np.float64)
            if not np.array_equal(g, h):
                raise ConformanceError(f"goal_selector restored by {how} must ask the same goals as the original; goal {i + 1} after the restore differs ({h.tolist()} against {g.tolist()}).")
        c = float(rng.uniform(*competences))
        for s in (selector, *(o for _, o in copies)):
            s.update(g, c)


def example_teacher(teacher: Any, seed: int = 0, dim: int = 2, n_tasks: int = 6, **params: Any) -> Any:
    """A teacher of the class ``teacher`` (or of that name in ``saggriac.teachers.available()``)
    over a small space of its kind (its ``spaces``): the box [0, 1]^dim, or ``n_tasks`` tasks.
    Tests, benchmarks and the bench build any registered teacher this way, without a list."""
    from .teachers import available

    cls = available()[teacher] if isinstance(teacher, str) else teacher
    if "tasks" in getattr(cls, "spaces", ("box",)):
        return cls(n_tasks, seed=seed, **params)
    return cls(np.zeros(dim), np.ones(dim), seed=seed, **params)
