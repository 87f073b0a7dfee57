"""Configuration of one run: every parameter, its default, and the paper's two presets.

The rules are checked by the Rust core (``saggriac._core.validate_config``), so the command line,
TOML files and the Python API report the same message. Python checks only what the core never
sees (``n_evals``, turned into a schedule here) and the condition's name (to list the choices in
Config's terms). This module adds the file and key to messages about configuration files.
"""

from __future__ import annotations

import dataclasses
import math
import os
import stat
import sys
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any


from .. import _core
from .presets import PRESETS
from ..errors import ParameterError, StorageError
from ..teachers.params import TeacherParams
from ..teachers.params import teacher_params as _teacher_params
from ..values import plain as _plain

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib

CONDITIONS = ("sagg_riac", "sagg_random", "actuator_random", "actuator_riac")


_REMOVED_INDEXES = ("kdtree", "kdtree_crate")
# Keys added after runs were already being saved, with the value that reproduces what such a run
# did: a run.json without "test_configs" tested its forward model at uniform configurations, and
# one without "actuator_candidates" ran ACTUATOR-RIAC's free-proposal variant.
# A run.json without "interest_divisor" (saggriac <= 0.2) divided a young region's eq. 2 by its
# own window.
#: The length parameters that follow the body: left None, each is the reach divided by this (for
#: the paper's 50-unit arm, exactly the values the paper's runs were tuned with: 0.5, 0.1, 0.01).
#: The reach is the built-in arm's length, or a user's body's (saggriac.bodies.scale). A value given
#: is used as given.
LENGTH_DIVISORS = {"v": 100, "eps_max": 500, "eval_tolerance": 5000}
_LEGACY_VALUES = {"test_configs": "uniform", "actuator_candidates": 0, "interest_divisor": "window"}


#: Every parameter's default as the Rust core declares it (the one declaration; Config reads it).
_CORE: dict[str, Any] = _core.config_defaults()


@dataclass(frozen=True)
class Config:
    """All parameters of a run. Defaults are the core's (the ``exp1`` preset); see
    docs/parameters.md."""

    condition: str = _CORE["condition"]
    n_steps: int = _CORE["n_steps"]
    # Arm (paper Fig. 2): n joints, equal links summing to arm_length, rest pose straight.
    # body="spatial_arm" moves it in 3-D (joints alternately yaw and pitch; 3-D goal space).
    body: str = _CORE["body"]
    n_joints: int = _CORE["n_joints"]
    arm_length: float = _CORE["arm_length"]
    link_lengths: tuple[float, ...] | None = _CORE["link_lengths"]
    joint_limit: float = _CORE["joint_limit"]
    max_joint_step: float = _CORE["max_joint_step"]
    # Body variants (beyond the paper): noise, and one link changing length at a given step.
    motor_noise: float = _CORE["motor_noise"]
    sensor_noise: float = _CORE["sensor_noise"]
    body_change_step: int | None = _CORE["body_change_step"]
    body_change_link: int | None = _CORE["body_change_link"]
    body_change_length: float | None = _CORE["body_change_length"]
    # body="chain": a serial arm of hinges as fixed transforms, read out of a MuJoCo model by
    # saggriac.bodies.mujoco_arm.MujocoArm.chain() (15 numbers per joint, then the tip; see
    # docs/mujoco.md). Its joints are in [-1, 1] (each one's range), so joint_limit <= 1.
    chain: tuple[float, ...] | None = _CORE["chain"]
    # Goal space S' (one bound per task-space dimension: 2 for the planar arm, 3 in space).
    goal_low: tuple[float, ...] = tuple(_CORE["goal_low"])
    goal_high: tuple[float, ...] = tuple(_CORE["goal_high"])
    # Low level (paper III.D). Lengths left None follow the body's reach (LENGTH_DIVISORS):
    # v = reach / 100, 0.5 for the paper's 50-unit arm.
    v: float | None = None
    n_subgoals: int = _CORE["n_subgoals"]
    # reach / 500, 0.1 for the paper's arm: chosen by the sensitivity study's rerun with eq. 2
    # as printed (docs/sensitivity.md).
    eps_max: float | None = None
    timeout_factor: float = _CORE["timeout_factor"]
    timeout_min: int = _CORE["timeout_min"]
    # Also end an exploration phase at the timeout (Algorithm 1 checks it between phases only).
    timeout_in_exploration: bool = _CORE["timeout_in_exploration"]
    # What the exploration trigger compares the realised displacement with: "executed" (J dtheta
    # of the command executed, the default) or "desired" (the desired step, the paper's epsilon).
    # See docs/parameters.md.
    exploration_trigger: str = _CORE["exploration_trigger"]
    q: int = _CORE["q"]
    explore_step: float = _CORE["explore_step"]
    # Local models (paper III.B).
    k_neighbours: int = _CORE["k_neighbours"]
    ridge: float = _CORE["ridge"]
    pinv_rcond: float = _CORE["pinv_rcond"]
    bandwidth: float = _CORE["bandwidth"]
    # Competence (eq. 7).
    min_c: float = _CORE["min_c"]
    eps_c: float = _CORE["eps_c"]
    # "relative": eq. 7; "absolute": -D(x_g, x_f) / arm length (for the episodic paradigm).
    competence: str = _CORE["competence"]
    # High level (paper II.D).
    g_max: int = _CORE["g_max"]
    zeta: int = _CORE["zeta"]
    min_child: int = _CORE["min_child"]
    # Eq. 2's reading: "zeta" (the default: divided by zeta, the last zeta values), "window"
    # (a young region divided by its own count, saggriac <= 0.2) or "printed" (the printed index
    # ranges: a full region compares the last zeta + 1 values, the middle one cancelling).
    # See docs/parameters.md.
    interest_divisor: str = _CORE["interest_divisor"]
    p_interest: float = _CORE["p_interest"]
    p_global: float = _CORE["p_global"]
    p_lowest: float = _CORE["p_lowest"]
    # Mode 3's reading: "lowest_competence" (the paper's: uniform in the region of lowest mean
    # competence) or "interest_worst" (a region by interest, a Gaussian of sd mode3_sigma times
    # the box's width about its worst goal). See docs/parameters.md, "Mode 3".
    mode3: str = _CORE["mode3"]
    mode3_sigma: float = _CORE["mode3_sigma"]
    reset_every: int = _CORE["reset_every"]
    # Beyond the paper: the teacher choosing sagg_riac's goals. "own" is SAGG-RIAC's high level;
    # any registered teacher of goals in a box (saggriac.teachers.available(), spaces "box")
    # replaces it, with its paper's defaults (docs/teachers.md) except those teacher_params sets:
    # a dict of the parameters of that teacher's class (kept as a read-only TeacherParams mapping,
    # so that a Config stays hashable).
    teacher: str = _CORE["teacher"]
    teacher_params: Mapping[str, Any] = dataclasses.field(default_factory=lambda: TeacherParams({}))
    # Evaluation (docs/reproduction.md, "What is measured").
    n_test_goals: int = _CORE["n_test_goals"]
    n_test_configs: int = _CORE["n_test_configs"]
    # "ik_min_norm": each test goal's least-norm configuration; "uniform": uniform in the limits.
    test_configs: str = _CORE["test_configs"]
    n_evals: int = 20
    eval_schedule: tuple[int, ...] | None = None
    # reach / 5000: 0.01 for the paper's arm.
    eval_tolerance: float | None = None
    eval_patience: int = _CORE["eval_patience"]
    eval_timeout_factor: float = _CORE["eval_timeout_factor"]
    eval_timeout_min: int = _CORE["eval_timeout_min"]
    # ACTUATOR conditions (motor babbling). 0.02 by the sensitivity study (docs/sensitivity.md:
    # 27-34 % lower final reaching error than 0.01 in both experiments, tuning seeds).
    babble_step: float = _CORE["babble_step"]
    # ACTUATOR-RIAC: candidate commands per step chosen among in the current context (0: the
    # earlier variant, commands proposed anywhere in the (theta, dtheta) space).
    actuator_candidates: int = _CORE["actuator_candidates"]
    actuator_reset_every: int = _CORE["actuator_reset_every"]
    # Episodic paradigm (one whole configuration per goal; see docs/episodic.md).
    paradigm: str = _CORE["paradigm"]
    episodic_noise: float = _CORE["episodic_noise"]
    episodic_refine: bool = _CORE["episodic_refine"]
    episodic_k: int = _CORE["episodic_k"]
    # Implementation.
    knn_index: str = _CORE["knn_index"]
    warm_start_recent: int = _CORE["warm_start_recent"]

    def __post_init__(self) -> None:
        # None would silently mean "the core's default" there: only optional fields take it.
        for f in dataclasses.fields(self):
            if getattr(self, f.name) is None and f.default is not None:
                raise ParameterError(f"The '{f.name}' parameter of Config must be given a value (default {f.default!r}). Got None instead.", f.name, "None")
            # numpy scalars become the Python values they stand for (JSON, TOML and the core take those).
            object.__setattr__(self, f.name, _plain(getattr(self, f.name)))
        # The k-d trees of saggriac 0.1 were removed: every index returns the same neighbours, so
        # a run recorded with one is the run the block index gives, bit for bit.
        if self.knn_index in _REMOVED_INDEXES:
            warnings.warn(f"knn_index={self.knn_index!r} was removed in saggriac 0.2; 'blocks' returns the same neighbours and is used instead.", DeprecationWarning, stacklevel=3)
            object.__setattr__(self, "knn_index", "blocks")
        # Lists from TOML or JSON become tuples so configs stay hashable and comparable.
        for name in ("link_lengths", "goal_low", "goal_high", "eval_schedule", "chain"):
            val = getattr(self, name)
            if isinstance(val, list):
                object.__setattr__(self, name, tuple(val))
            elif not (isinstance(val, tuple) or (val is None and name in ("link_lengths", "eval_schedule", "chain"))):
                raise ParameterError(f"The '{name}' parameter of Config must be a list of numbers. Got {val!r} instead.", name, repr(val))
        object.__setattr__(self, "teacher_params", _teacher_params(self.teacher_params))
        if self.eval_schedule is not None and len(self.eval_schedule) == 0:
            raise ParameterError("The 'eval_schedule' parameter of Config must be a non-empty list of steps (or None for n_evals). Got () instead.", "eval_schedule", "()")
        _check_types(self)
        _check_goal_space(self)
        _check_magnitudes(self)
        _check_body_change(self)
        n_steps = self.n_steps if isinstance(self.n_steps, int) and not isinstance(self.n_steps, bool) and self.n_steps > 0 else 0
        most = max(n_steps, MIN_EVALS_BOUND)
        if not isinstance(self.n_evals, int) or isinstance(self.n_evals, bool) or not 1 <= self.n_evals <= most:
            raise ParameterError(
                f"The 'n_evals' parameter of Config must be an int in [1, max(n_steps, {MIN_EVALS_BOUND})] "
                f"(a run evaluates at most once per time step; n_steps = {self.n_steps!r}). Got {self.n_evals!r} instead.",
                "n_evals",
                repr(self.n_evals),
            )
        if self.condition not in CONDITIONS:
            raise ParameterError(
                f"The 'condition' parameter of Config must be one of {', '.join(map(repr, CONDITIONS))}. "
                f"Got {self.condition!r} instead.",
                "condition",
                repr(self.condition),
            )
        _core.validate_config(self.core_dict())

    @property
    def reach(self) -> float:
        """Length of the built-in arm: the radius of its reachable ball (for a chain, the summed
        distances between its joints and to the end effector, which bound its reach)."""
        if self.chain is not None:
            return float(sum(_core.chain_link_lengths(list(self.chain))))
        return float(sum(self.link_lengths)) if self.link_lengths is not None else float(self.arm_length)

    @property
    def joints(self) -> int:
        """Number of joints of the built-in arm (``link_lengths`` replaces ``n_joints`` when
        given; a chain has its own)."""
        if self.chain is not None:
            return max(0, (len(self.chain) - 3) // 15)
        return len(self.link_lengths) if self.link_lengths is not None else self.n_joints

    def schedule(self) -> list[int]:
        """Time steps at which the run is evaluated (0 and the last step included)."""
        if self.eval_schedule is not None:
            return [int(s) for s in self.eval_schedule]
        n = self.n_steps
        if n >= 2**53:
            # Beyond 2**53 the float quotient is inexact (the last step came out above n_steps).
            return sorted({round(Fraction(i * n, self.n_evals)) for i in range(self.n_evals + 1)})
        return sorted({round(i * n / self.n_evals) for i in range(self.n_evals + 1)})

    def lengths(self, reach: float | None = None) -> dict[str, float]:
        """``v``, ``eps_max`` and ``eval_tolerance`` as a run uses them: each value given as
        is, else ``reach`` (default: the built-in arm's, :attr:`reach`) divided by its
        :data:`LENGTH_DIVISORS` entry."""
        r = self.reach if reach is None else float(reach)
        # A value of another type goes to the core as given, which names it with its rule.
        given = {k: getattr(self, k) for k in LENGTH_DIVISORS}
        return {k: r / d if v is None else float(v) if _number(v, float) else v for (k, v), d in zip(given.items(), LENGTH_DIVISORS.values())}

    def core_dict(self, reach: float | None = None) -> dict[str, Any]:
        """The flat dict the Rust core takes. ``reach``: a user's body's reach, which replaces
        the built-in arm's length (the length parameters follow it, see :meth:`lengths`)."""
        d = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        d.pop("n_evals")
        d.update(self.lengths(reach))
        if reach is not None:
            d.update(arm_length=float(reach), n_joints=self.joints, link_lengths=None)
        for name in ("link_lengths", "goal_low", "goal_high", "chain"):
            if d[name] is not None:
                d[name] = list(d[name])
        d["eval_schedule"] = self.schedule() if isinstance(self.n_steps, int) and self.n_steps > 0 else []
        d["teacher_params"] = dict(self.teacher_params)
        return d

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict of every field (tuples as lists)."""
        d = dataclasses.asdict(self)
        d = {k: list(v) if isinstance(v, tuple) else v for k, v in d.items()}
        d["teacher_params"] = dict(self.teacher_params)
        return d

    @classmethod
    def from_saved(cls, d: Mapping[str, Any], written_by: Any = None) -> Config:
        """The configuration a run.json or study.json recorded. Keys it predates take the values
        that reproduce what it ran, not today's defaults. Keys this version does not know (a
        record of a newer saggriac) are refused with a message saying so, and naming the version
        that wrote the record (``written_by``, the record's "version") where it is known."""
        if not isinstance(d, Mapping):
            raise StorageError(f"The saved configuration is not a JSON object (got {type(d).__name__}); the file is damaged.")
        known = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(str(k) for k in d if k not in known)
        if unknown:
            raise StorageError(
                f"The saved configuration has parameters this saggriac ({_core.__version__}) does not know: {', '.join(unknown)}. "
                + (f"It was written by saggriac {written_by}; read it with that version." if isinstance(written_by, str) else "It was written by another version of saggriac; read it with that version.")
            )
        return cls(**{**{k: v for k, v in _LEGACY_VALUES.items() if k not in d}, **d})

    def replace(self, **changes: Any) -> Config:
        check_keys(changes, source=None)
        return dataclasses.replace(self, **changes)

    @classmethod
    def from_preset(cls, name: str, **overrides: Any) -> Config:
        if name not in PRESETS:
            raise ParameterError(
                f"The 'preset' parameter must be one of {', '.join(map(repr, PRESETS))}. Got {name!r} instead.",
                "preset",
                repr(name),
            )
        check_keys(overrides, source=None)
        return cls(**{**PRESETS[name], **overrides})

    @classmethod
    def from_toml(cls, path: str | Path, preset: str | None = None, **overrides: Any) -> Config:
        """Read a TOML file: an optional ``preset = "exp2"`` plus any parameters, flat.

        ``preset`` (the command line's ``--preset``) applies when the file names none; if both
        name a preset they must agree."""
        path = Path(path)
        preset, data = read_toml(path, preset)
        try:
            return cls.from_preset(preset, **{**data, **overrides})
        except ParameterError as e:
            keys = (e.param or "").split("/")
            if any(k in data for k in keys) or e.param == "preset":
                raise ParameterError(f"{path}: key '{next((k for k in keys if k in data), e.param)}': {e}", e.param, e.value) from None
            raise


#: The largest configuration file read (a TOML of every parameter is about 2 kB).
MAX_CONFIG_BYTES = 1_000_000


def read_toml(path: Path, preset: str | None = None) -> tuple[str, dict[str, Any]]:
    """The preset (the file's, else ``preset``, else exp1) and the other keys of a TOML file."""
    try:
        # Looked at before opening: opening a FIFO would wait for a writer, a device never ends.
        if not stat.S_ISREG(os.stat(path).st_mode) and not stat.S_ISDIR(os.stat(path).st_mode):
            raise ParameterError(f"Configuration file {path} is not a regular file (a device, FIFO or socket cannot be a TOML file).", "config", str(path))
        with open(path, "rb") as f:
            raw = f.read(MAX_CONFIG_BYTES + 1)
        if len(raw) > MAX_CONFIG_BYTES:
            raise ParameterError(f"Configuration file {path} is larger than {MAX_CONFIG_BYTES // 1000} kB; a saggriac configuration is a few lines.", "config", str(path))
        # Editors on Windows may start UTF-8 files with a byte-order mark, which tomllib refuses.
        text = raw.decode("utf-8").removeprefix("\ufeff")
    except FileNotFoundError:
        raise ParameterError(f"Configuration file {path} does not exist.", "config", str(path)) from None
    except IsADirectoryError:
        raise ParameterError(f"Configuration file {path} is a folder, not a TOML file.", "config", str(path)) from None
    except UnicodeDecodeError as e:
        raise ParameterError(f"Configuration file {path} is not UTF-8 text (byte {e.start} is {e.object[e.start]:#04x}); TOML files are UTF-8.", "config", str(path)) from None
    except OSError as e:
        raise ParameterError(f"Configuration file {path} cannot be read: {e.strerror}.", "config", str(path)) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ParameterError(f"Configuration file {path} is not valid TOML: {e}", "config", str(path)) from None
    named = data.pop("preset", None)
    if named is not None and preset is not None and named != preset:
        raise ParameterError(f"{path} names preset {named!r} but --preset (preset=) says {preset!r}; give one of them, or the same in both.", "preset", repr(preset))
    check_keys(data, source=path)
    return (named if named is not None else preset if preset is not None else "exp1"), data


#: Parameters whose default is None, with the type of their values.
_OPTIONAL_KINDS = {"link_lengths": "floats", "chain": "floats", "eval_schedule": "ints", "body_change_step": int, "body_change_link": int, "body_change_length": float, "v": float, "eps_max": float, "eval_tolerance": float}
#: Lengths and goal bounds beyond this overflow nothing yet, but squared distances and the step
#: counts derived from them would lose their meaning long before float overflow; refuse them.
MAX_MAGNITUDE = 1e12
#: ... and a body's length below this: its squared distances would underflow toward 0 (a reach
#: of 1e-300 gave v = 1e-302 and no test goal reached).
MIN_LENGTH = 1e-12
#: n_evals up to this is taken whatever n_steps is (short runs keep the default 20).
MIN_EVALS_BOUND = 100


#: The rule of a body's length (``arm_length``, a body's reach), the same in every message.
REACH_RULE = f"a float in [{MIN_LENGTH:g}, {MAX_MAGNITUDE:g}] (lengths in the units of the task space; beyond, squared distances and step counts lose their meaning)"


def reach_ok(reach: float) -> bool:
    return MIN_LENGTH <= reach <= MAX_MAGNITUDE


def _number(v: Any, kind: Any) -> bool:
    if isinstance(v, bool):
        return False
    return isinstance(v, int) if kind is int else isinstance(v, (int, float))


def _check_types(cfg: Config) -> None:
    """Refuse values the core would coerce silently: booleans for numbers, floats for ints."""
    for f in dataclasses.fields(cfg):
        v = getattr(cfg, f.name)
        kind = _OPTIONAL_KINDS.get(f.name, type(f.default))
        if v is None or kind is str or f.name == "teacher_params":
            continue
        if kind is bool:
            ok, rule = isinstance(v, bool), "a bool (true or false)"
        elif kind in (int, float):
            # Other types are named by the core's conversion, with the parameter's rule.
            ok, rule = not isinstance(v, bool) and not (kind is int and isinstance(v, float)), "an int" if kind is int else "a float"
        else:  # a list
            item = int if kind == "ints" else float
            ok = isinstance(v, tuple) and all(_number(x, item) for x in v)
            rule = "a list of ints (time steps)" if kind == "ints" else "a list of floats"
        if not ok:
            raise ParameterError(f"The '{f.name}' parameter of Config must be {rule}. Got {v!r} instead.", f.name, repr(v))


def _check_goal_space(cfg: Config) -> None:
    low, high = cfg.goal_low, cfg.goal_high
    if not all(_number(v, float) for v in (*low, *high)):
        return  # the core names the wrong element type
    if len(low) != len(high) or not low:
        raise ParameterError(f"The 'goal_low' and 'goal_high' parameters of Config must be lists of the same non-zero length. Got goal_low = {list(low)} and goal_high = {list(high)} instead.", "goal_low/goal_high", repr((low, high)))
    for i, (lo, hi) in enumerate(zip(low, high)):
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ParameterError(
                f"The 'goal_low' and 'goal_high' parameters of Config must be finite with goal_low < goal_high in every dimension. "
                f"Got goal_low = {list(low)} and goal_high = {list(high)} instead (dimension {i}: {lo} and {hi}).",
                "goal_low/goal_high",
                repr((low, high)),
            )


def _check_body_change(cfg: Config) -> None:
    """A body change needs its step, link and length: one left None would reach the core as a
    placeholder (link 2**64-1) and be named in place of the one missing."""
    names = ("body_change_step", "body_change_link", "body_change_length")
    given = [n for n in names if getattr(cfg, n) is not None]
    if given and len(given) < 3:
        missing = next(n for n in names if getattr(cfg, n) is None)
        raise ParameterError(
            f"The '{missing}' parameter of Config must be given with {', '.join(given)} (a body change needs its step, link and length). Got None instead.",
            missing,
            "None",
        )


def _check_magnitudes(cfg: Config) -> None:
    # arm_length makes the links: name it, not the link_lengths derived from it.
    a = cfg.arm_length
    if not _number(a, float) or (cfg.link_lengths is None and cfg.chain is None and not reach_ok(a)):
        shown = f"{a:g}" if _number(a, float) else repr(a)
        raise ParameterError(f"The 'arm_length' parameter of Config must be {REACH_RULE}. Got {shown} instead.", "arm_length", shown)
    values = {"arm_length": [cfg.arm_length], "link_lengths": list(cfg.link_lengths or ()), "chain": list(cfg.chain or ()), "goal_low": list(cfg.goal_low), "goal_high": list(cfg.goal_high)}
    for name, vals in values.items():
        for v in vals:
            if _number(v, float) and math.isfinite(v) and abs(v) > MAX_MAGNITUDE:
                raise ParameterError(f"The '{name}' parameter of Config must be at most {MAX_MAGNITUDE:g} in absolute value (lengths in the units of the task space). Got {v!r} instead.", name, repr(v))


def check_keys(d: dict[str, Any], source: Path | None) -> None:
    known = {f.name for f in dataclasses.fields(Config)}
    for k in d:
        if k not in known:
            where = f"{source}: " if source else ""
            raise ParameterError(
                f"{where}The '{k}' parameter is not a parameter of Config. Known parameters: {', '.join(sorted(known))}.",
                k,
                repr(d[k]),
            )
