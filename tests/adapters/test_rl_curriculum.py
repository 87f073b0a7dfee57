"""The RL curriculum study's one command (docs/rl_curriculum.md) runs end to end on a tiny
budget: every teacher, two seeds, the tables, the statistics and the figure. Skipped without
the SB3 extra, unless SAGGRIAC_REQUIRE_EXTRAS=1 (CI sets it)."""

import os
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("stable_baselines3", reason='the SB3 extra is not installed (pip install "saggriac[sb3]")')

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "rl_curriculum.py"


def test_the_study_runs_and_reports(tmp_path):
    out = tmp_path / "rl"
    cmd = [sys.executable, str(SCRIPT), "--out", str(out), "--seeds", "0,1", "--steps", "4096", "--every", "4096", "--workers", "2"]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=900, env={**os.environ, "TQDM_DISABLE": "1"})
    assert done.returncode == 0, done.stderr[-2000:]
    runs = pd.read_csv(out / "runs.csv")
    assert sorted(runs["teacher"].unique()) == ["alp_gmm", "covar_gmm", "random", "riac", "sagg_riac"] and len(runs) == 10
    assert runs["final"].between(0, 1).all()
    comparisons = pd.read_csv(out / "comparisons.csv")
    assert set(comparisons["family"]) == {"primary", "secondary"} and (comparisons["family"] == "primary").sum() == 4
    assert (out / "rl_curriculum.png").stat().st_size > 10_000 and "Holm" in (out / "results.md").read_text()
    # Finished runs are kept and not run again.
    again = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env={**os.environ, "TQDM_DISABLE": "1"})
    assert again.returncode == 0 and pd.read_csv(out / "runs.csv").equals(runs)
