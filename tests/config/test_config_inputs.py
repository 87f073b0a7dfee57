"""No coercion, no silently dropped flag: the command line refuses conflicting and unbounded
inputs, a configuration file's size is bounded, a teacher in the configuration and a goal
selector conflict. From the third newcomer audit (issue 27)."""

from __future__ import annotations

import subprocess
import sys

import pytest

import saggriac
from saggriac import Config
from saggriac.errors import ParameterError


def _cli(args, cwd):
    r = subprocess.run([sys.executable, "-m", "saggriac.cli", *args], capture_output=True, text=True, cwd=cwd)
    return r.returncode, r.stderr


@pytest.mark.parametrize(
    "args, says",
    [
        (["run", "--set", "n_steps=500", "--steps", "300"], "--steps and --set n_steps"),
        (["run", "--set", "condition=sagg_riac", "--condition", "sagg_random"], "--condition and --set condition"),
        (["run", "--set", "zeta=10", "--set", "zeta=12"], "given twice"),
        (["run", "--out", ""], "--out"),
        (["reproduce", "exp1", "--out", ""], "--out"),
        (["reproduce", "exp1", "--seeds", "1000000000"], "seeds"),
        (["run", "--config", "/dev/zero"], "not a regular file"),
    ],
)
def test_cli_refuses_conflicts_and_unbounded_inputs(tmp_path, args, says):
    rc, err = _cli(args, tmp_path)
    assert rc != 0 and says in err, err
    assert "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_config_file_size_is_bounded(tmp_path):
    big = tmp_path / "big.toml"
    big.write_text("# " + "x" * 2_000_000 + "\nzeta = 20\n")
    with pytest.raises(ParameterError, match="larger than"):
        Config.from_toml(big)


def test_a_teacher_in_config_and_a_goal_selector_conflict():
    cfg = Config.from_preset("exp1", n_steps=200, n_evals=1, teacher="riac")
    sel = saggriac.RiacSelector(cfg.goal_low, cfg.goal_high)
    with pytest.raises(ParameterError, match="teacher='riac'"):
        saggriac.run(cfg, 0, goal_selector=sel)
