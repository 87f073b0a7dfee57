"""The ``saggriac`` command."""

from __future__ import annotations

import argparse
import hashlib
import re
import sys
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

from . import _core
from .config import CONDITIONS, PRESETS, Config, read_toml
from .errors import ParameterError, SaggriacError, StorageError
from .runs.storage import RunExistsError, as_path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def _parse_value(text: str) -> Any:
    """A value as TOML reads it (numbers, booleans, lists, quoted strings); bare words stay strings."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def parse_overrides(pairs: list[str]) -> dict[str, Any]:
    """``--set`` arguments (``["g_max=40", "condition=sagg_random"]``) as Config keyword
    arguments, each value read as TOML reads it (bare words stay strings); ``teacher_params.NAME``
    keys gather into the ``teacher_params`` dict."""
    out: dict[str, Any] = {}
    for p in pairs:
        if "=" not in p:
            raise SaggriacError(f"--set takes KEY=VALUE, got {p!r}.")
        k, v = p.split("=", 1)
        k = k.strip()
        head, dot, sub = k.partition(".")
        if dot and head == "teacher_params":
            # One teacher parameter at a time, as run folders name them: teacher_params.fit_rate=100.
            params = out.setdefault("teacher_params", {})
            if not isinstance(params, dict) or sub in params:
                raise SaggriacError(f"--set {k}=... is given twice (or beside --set teacher_params=...); give it once.")
            params[sub] = _parse_value(v.strip())
            continue
        if k in out:
            raise SaggriacError(f"--set {k}=... is given twice; give it once.")
        out[k] = _parse_value(v.strip())
    return out


_overrides = parse_overrides  # its former, private name


def _cmd_run(args: argparse.Namespace) -> int:
    from .runs.runner import resume, run

    if args.resume is not None:
        flags = (("--config", args.config), ("--preset", args.preset), ("--seed", args.seed), ("--steps", args.steps), ("--condition", args.condition), ("--set", args.set), ("--out", args.out), ("--checkpoint-every", args.checkpoint_every), ("--overwrite", args.overwrite))
        given = [flag for flag, v in flags if v is not None and v is not False and v != []]
        if given:
            raise SaggriacError(f"--resume continues a run with the configuration, seed and target it was started with; drop {', '.join(given)}.")
        res = _saved_or_recovered(lambda: resume(args.resume, progress=not args.no_progress, threads=args.threads), Path(args.resume))
        print(f"resumed at step {res.manifest['resumed_at_step']}")
        _print_run(res, res.config, res.seed, res.path)
        return 0
    overrides = parse_overrides(args.set)
    for flag, key, value in (("--steps", "n_steps", args.steps), ("--condition", "condition", args.condition)):
        if value is None:
            continue
        if key in overrides:
            raise SaggriacError(f"{flag} and --set {key}=... both set {key}; give one of them.")
        overrides[key] = value
    if args.config:
        preset, _ = read_toml(Path(args.config), args.preset)
        cfg = Config.from_toml(args.config, preset=preset, **overrides)
    else:
        preset = args.preset or "exp1"
        cfg = Config.from_preset(preset, **overrides)
    seed = 0 if args.seed is None else args.seed
    out = Path(args.out) if args.out is not None else default_run_dir(preset, cfg, seed)
    if args.out is not None:
        as_path(args.out, "--out", "saggriac run")
    try:
        res = _saved_or_recovered(lambda: run(cfg, seed=seed, out_dir=out, progress=not args.no_progress, overwrite=args.overwrite, checkpoint_every=args.checkpoint_every, threads=args.threads), out)
    except RunExistsError:
        if args.out is not None:
            raise SaggriacError(f"{out} already holds a finished run; pass --overwrite to replace it, or choose another --out.") from None
        raise SaggriacError(f"{out} already holds a finished run of this configuration and seed; pass --overwrite to replace it, or --out DIR to write elsewhere.") from None
    _print_run(res, cfg, seed, out)
    return 0


def default_run_dir(preset: str, cfg: Config, seed: int) -> Path:
    """runs/PRESET-CONDITION-seedSEED, plus every parameter that differs from the preset, so
    that runs of other --steps or --set land in folders of their own and say what they are."""
    base = Config.from_preset(preset, condition=cfg.condition).to_dict()
    mine = cfg.to_dict()
    # A dict (teacher_params) is spelled one key at a time: teacher_params.fit_rate=100.
    mine.update({f"teacher_params.{k}": v for k, v in mine.pop("teacher_params").items()})
    base.pop("teacher_params")
    diffs = [f"{k}={_name_value(mine[k])}" for k in sorted(mine) if mine[k] != base.get(k)]
    head = f"{preset}-{cfg.condition}-seed{seed}"
    name = "-".join([head, *diffs])
    if len(name) > 120 or not re.fullmatch(r"[A-Za-z0-9_.,=+-]+", name):
        # Too long or not a plain name: the digest of every difference, after as many of the
        # plain ones as fit (the teacher first), so that the folder still says what it holds.
        digest = hashlib.sha256(repr(sorted(diffs)).encode()).hexdigest()[:10]
        plain = [d for d in sorted(diffs, key=lambda d: not d.startswith("teacher")) if re.fullmatch(r"[A-Za-z0-9_.,=+-]+", d)]
        shown: list[str] = []
        for d in plain:
            if len("-".join([head, *shown, d, "custom", digest])) <= 120:
                shown.append(d)
        name = "-".join([head, *shown, "custom", digest])
    return Path("runs") / name


def _name_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, list):
        return ",".join(_name_value(x) for x in v)
    if isinstance(v, float) and v.is_integer() and abs(v) < 1e15:
        return str(int(v))
    return str(v)


def _saved_or_recovered(work: Callable[[], Any], out: Path) -> Any:
    """Run ``work``; if it finished but its result could not be written to ``out``, write it to a
    recovery folder beside ``out`` (or in the current folder, or the temporary folder) and say
    where, so that nothing computed is lost."""
    try:
        return work()
    except StorageError as e:
        result = getattr(e, "result", None)
        if result is None:
            raise
        from .runs.runner import recover

        raise SaggriacError(recover(result, out, str(e))) from None


def _print_run(res: Any, cfg: Config, seed: int, out: Path) -> None:
    m = res.metrics
    print(f"condition {cfg.condition}, seed {seed}, {int(m['step'].iloc[-1])} {'movements' if cfg.paradigm == 'episodic' else 'micro-actions'} in {res.manifest['wall_seconds']:.1f} s")
    print(f"reaching error: start {m['reach_error'].iloc[0]:.3f}, middle {m['reach_error'].iloc[len(m) // 2]:.3f}, end {m['reach_error'].iloc[-1]:.3f}")
    print(f"prediction error: start {m['pred_error'].iloc[0]:.3f}, end {m['pred_error'].iloc[-1]:.3f}")
    print(f"results written to {out}")


def _cmd_reproduce(args: argparse.Namespace) -> int:
    from .study.reproduce import final_summary, reproduce, time_budget_summary

    if args.conditions is None:
        conditions = CONDITIONS
    else:
        conditions = tuple(c.strip() for c in args.conditions.split(","))
        if not all(conditions):
            raise SaggriacError(f"--conditions takes a comma-separated list of conditions ({', '.join(CONDITIONS)}). Got {args.conditions!r}.")
    if args.out is not None:
        as_path(args.out, "--out", "saggriac reproduce")
    # A study of one condition or one seed has no statistics: said, and not an error here.
    written, _ = _incomplete(lambda: _in_flags(lambda: reproduce(
        args.experiment,
        out_dir=args.out,
        seeds=args.seeds,
        first_seed=args.first_seed,
        conditions=conditions,
        steps=args.steps,
        backend=args.backend,
        n_workers=args.workers,
        scheduler=args.scheduler,
        progress=not args.no_progress,
        **({} if args.worker_timeout is None else {"worker_timeout": args.worker_timeout}),
    )))
    out = Path(args.out) if args.out else Path(f"reproduce-{args.experiment}")
    print(final_summary(out).to_string(index=False))
    budget = time_budget_summary(out)
    if not budget.empty:
        print("\ntime budget (means over runs; shares of all micro-actions):")
        print(budget.to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    for name, path in written.items():
        print(f"{name}: {path}")
    return 0


def _in_flags(work: Callable[[], Any]) -> Any:
    """``work()``, its advice to give the workers more time in this command's words."""
    try:
        return work()
    except ParameterError as e:
        if "worker_timeout= " not in str(e):
            raise
        raise ParameterError(str(e).replace("worker_timeout= ", "--worker-timeout "), e.param, e.value) from None


def _incomplete(work: Callable[[], Any]) -> tuple[Any, int]:
    """Run ``work``, printing each IncompleteStudyWarning it gives as a warning of the command;
    the exit status is 1 when some were given (what was written leaves runs out), else 0."""
    from .study import IncompleteStudyWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", IncompleteStudyWarning)
        value = work()
    rc = 0
    for w in caught:
        if issubclass(w.category, IncompleteStudyWarning):
            print(f"saggriac: warning: {w.message}", file=sys.stderr)
            rc = 1
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return value, rc


def _cmd_plot(args: argparse.Namespace) -> int:
    from .study.reproduce import make_report

    written, rc = _incomplete(lambda: make_report(args.study))
    for name, path in written.items():
        print(f"{name}: {path}")
    return rc


def _cmd_stats(args: argparse.Namespace) -> int:
    from .study.reproduce import write_stats

    written, rc = _incomplete(lambda: write_stats(args.study))
    print(written["stats_md"].read_text(), end="")
    return rc


def _cmd_bench(args: argparse.Namespace) -> int:
    from .bench.command import run_command

    return run_command(args, _parse_value)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="saggriac", description="SAGG-RIAC goal exploration (Baranes & Oudeyer, IROS 2010).")
    p.add_argument("--version", action="version", version=f"saggriac {_core.__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run one learner and save its results")
    r.add_argument("--preset", choices=sorted(PRESETS), help="the paper's experiments exp1 and exp2, explauto's episodic task, arm3d: exp1 with an arm in space, or pusher: the 7-joint arm of Gymnasium's MuJoCo Pusher (default: the --config file's preset, else exp1; if both name one, they must agree)")
    r.add_argument("--config", help="TOML file with parameters (and optionally preset = ...)")
    r.add_argument("--seed", type=int, help="root seed of the run (default 0)")
    r.add_argument("--condition", help="sagg_riac (default), sagg_random, actuator_random or actuator_riac")
    r.add_argument("--steps", type=int, help="number of time steps: micro-actions, or movements in the episodic paradigm (overrides the preset)")
    r.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="override any parameter, e.g. --set g_max=40")
    r.add_argument("--out", help="run directory, new or empty (default runs/PRESET-CONDITION-seedSEED, plus each parameter that differs from the preset)")
    r.add_argument("--overwrite", action="store_true", help="replace a finished saggriac run in the target (never any other file or folder)")
    r.add_argument("--no-progress", action="store_true", help="no progress bar")
    r.add_argument("--checkpoint-every", type=int, metavar="N", help="save the whole run state at the first evaluation after every N steps, next to the run directory")
    r.add_argument("--resume", metavar="DIR", help="continue the interrupted run that was to be written to DIR, from its checkpoint")
    r.add_argument("--threads", type=int, metavar="N", help="threads for the evaluations, which run while learning goes on (default: all cores; results do not depend on it)")
    r.set_defaults(func=_cmd_run)

    rp = sub.add_parser("reproduce", help="run one of the paper's experiments (4 conditions x seeds) with figures and statistics")
    rp.add_argument("experiment", choices=sorted(PRESETS), help="the preset to study: exp1 or exp2 (the paper's), explauto, arm3d or pusher")
    rp.add_argument("--seeds", type=int, default=15, help="how many seeds (default 15, as the paper)")
    rp.add_argument("--first-seed", type=int, default=0, help="the first seed: seeds FIRST..FIRST+N-1 (default 0; e.g. 15 for a second, independent set)")
    rp.add_argument("--conditions", help="comma-separated subset of the conditions (default: all four)")
    rp.add_argument("--steps", type=int, help="time steps per run (default: the paper's)")
    rp.add_argument("--out", help="study folder (default reproduce-EXPERIMENT); rerunning resumes it")
    rp.add_argument("--backend", default="local", choices=["local", "dask"], help="process pool on this machine (default) or Dask")
    rp.add_argument("--workers", type=int, help="worker processes (default: all cores)")
    rp.add_argument("--scheduler", help="address of a running Dask scheduler (with --backend dask)")
    rp.add_argument("--worker-timeout", type=float, help="seconds to wait for the first worker of --scheduler to join (default 120)")
    rp.add_argument("--no-progress", action="store_true", help="no progress bar")
    rp.set_defaults(func=_cmd_reproduce)

    pl = sub.add_parser("plot", help="rebuild the figures and statistics of a study folder from its saved results")
    pl.add_argument("study", help="study folder written by saggriac reproduce or saggriac.run_study")
    pl.set_defaults(func=_cmd_plot)

    st = sub.add_parser("stats", help="rebuild the statistics table of a study folder and print it")
    st.add_argument("study", help="study folder written by saggriac reproduce or saggriac.run_study")
    st.set_defaults(func=_cmd_stats)

    from .bench.command import add_arguments

    b = sub.add_parser("bench", help="place a teacher (built-in, or yours by import path) on the bench's leaderboard among the built-in teachers (docs/bench.md)")
    add_arguments(b)
    b.set_defaults(func=_cmd_bench)
    return p


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except SaggriacError as e:
        print(f"saggriac: error: {e}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # Output piped into a command that stopped reading (e.g. `| head`): not an error.
        sys.stderr.close()
        return 0
    except KeyboardInterrupt:
        # A study keeps its finished runs; only the runs under way are lost.
        lost = "runs; the finished ones are kept, and the same command resumes the study" if args.func is _cmd_reproduce else "run"
        print(f"saggriac: interrupted; nothing was written for the unfinished {lost}.", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
