"""Memory a run will take, estimated before it starts, against what the machine has.

Without this a run of 10^8 joints is accepted and dies on an allocation failure (an abort, not an
error) after a minute of work. The estimate is an upper bound calibrated on the measured memory
(docs/performance.md: 350 bytes per sample at n = 15 joints, block index and its float32 screen
included; the estimate allows 426).
"""

from __future__ import annotations

import os
import platform
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ParameterError

if TYPE_CHECKING:
    from ..config import Config

#: Interpreter, numpy, pandas and the compiled core, before any sample.
BASE_BYTES = 200_000_000


def machine_memory() -> tuple[int | None, int | None]:
    """(total, available) bytes of memory of this machine, None where the system does not say."""
    total = available = None
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                key, _, rest = line.partition(":")
                if key in ("MemTotal", "MemAvailable"):
                    value = int(rest.split()[0]) * 1024
                    if key == "MemTotal":
                        total = value
                    else:
                        available = value
    except (OSError, ValueError, IndexError):
        pass
    if total is None and hasattr(os, "sysconf"):
        try:
            total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
        except (ValueError, OSError):
            total = None
    return total, available


def bytes_per_sample(cfg: Config) -> int:
    """One stored micro-action: theta (kept in the block index), dtheta (n each), the task-space
    change and position (m each), the index's boxes (2n bytes is above their share of 8n/7), its
    float32 copy of theta for the screen (4n), slack, and ACTUATOR-RIAC's second index over
    (theta, dtheta) with its own copy."""
    n, m = cfg.joints, len(cfg.goal_low)
    per = 8 * (2 * n + 2 * m) + 2 * n + 4 * n + 64
    if cfg.condition == "actuator_riac":
        per += 16 * n + 8 * n + 64
    return per


def estimate_run_bytes(cfg: Config) -> int:
    """Upper estimate of the memory a run of ``cfg`` takes at its end."""
    n = cfg.joints
    fixed = 8 * n * (4 * cfg.n_test_configs + 2 * cfg.n_test_goals + 8 * cfg.k_neighbours + 64)
    return BASE_BYTES + fixed + cfg.n_steps * bytes_per_sample(cfg)


def checkpoint_bytes(cfg: Config) -> int:
    """Upper estimate of a checkpoint of ``cfg``'s run near its end: state.bin holds every stored
    sample (theta, dtheta, the position and its change, a few counters) and the goal history."""
    n, m = cfg.joints, len(cfg.goal_low)
    return 1_000_000 + cfg.n_steps * 8 * (2 * n + 2 * m + 4)


def _gb(b: float) -> str:
    return f"{b / 1e9:.3g} GB"


def check_run_fits(cfg: Config) -> int:
    """Refuse, before any work, a run whose estimated memory exceeds what this machine has
    available; return the estimate."""
    need = estimate_run_bytes(cfg)
    total, available = machine_memory()
    limit = available if available is not None else total
    if limit is not None and need > limit:
        have = f"{_gb(available)} available of {_gb(total)}" if available is not None and total is not None else _gb(limit)
        raise ParameterError(
            f"This run would need about {_gb(need)} of memory ({cfg.n_steps} time steps x {bytes_per_sample(cfg)} bytes per sample for {cfg.joints} joints), "
            f"more than this machine has ({have}). Reduce 'n_steps' or 'n_joints', or run it on a larger machine.",
            "n_steps",
            repr(cfg.n_steps),
        )
    return need


def usable_cores() -> int:
    """Cores this process may run on (its CPU affinity where the system tells it)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


#: The vector extensions the math libraries under a deep-RL learner (MKL, oneDNN) choose their
#: kernels by, narrowest first: runs of the same seed agree to the bit only between machines that
#: have the same of these (docs/bench.md, "Reproducing the shipped rows").
VECTOR_FLAGS = ("avx", "avx2", "fma", "avx512f", "avx512_vnni", "avx512_bf16", "avx512_fp16", "amx_tile", "amx_bf16", "amx_int8", "asimd", "sve", "sve2")


def cpu_kind(cpuinfo: str | None = None) -> str:
    """The kind of CPU a run is made on, as far as its floating-point results can tell: the
    architecture and the vector extensions of :data:`VECTOR_FLAGS` it has, such as
    ``"x86_64 avx avx2 fma avx512f avx512_vnni"``. ``cpuinfo`` is the text of /proc/cpuinfo (read
    when None; where the system has none, the architecture alone)."""
    arch = platform.machine() or "unknown"
    if cpuinfo is None:
        try:
            with open("/proc/cpuinfo") as f:
                cpuinfo = f.read()
        except OSError:
            return arch
    for line in cpuinfo.splitlines():
        key, _, rest = line.partition(":")
        # x86 says "flags", ARM says "Features"; the first processor stands for all of them.
        if key.strip() in ("flags", "Features"):
            have = set(rest.split())
            return " ".join([arch, *(f for f in VECTOR_FLAGS if f in have)])
    return arch


#: The variable capping a mixture refit's threads (read by the Rust core when a teacher is built).
FIT_THREADS_VAR = "SAGGRIAC_FIT_THREADS"


def share_cores(n_workers: int) -> None:
    """Pool worker initializer: with ``n_workers`` processes side by side, a mixture teacher's
    refit takes this worker's share of the cores, not all of them (threads beyond the free cores
    only wait: docs/performance.md, issue 49 item 4). A cap the user set is kept."""
    if FIT_THREADS_VAR not in os.environ:
        os.environ[FIT_THREADS_VAR] = str(max(1, usable_cores() // max(1, n_workers)))


def check_threads(threads: object, owner: str) -> int:
    """The number of threads a run's evaluations may use: None means every usable core."""
    if threads is None:
        return usable_cores()
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or not 1 <= int(threads) <= 1024:
        raise ParameterError(f"The 'threads' parameter of {owner} must be an int in [1, 1024] or None (every core). Got {threads!r} instead.", "threads", repr(threads))
    return int(threads)
