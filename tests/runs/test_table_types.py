"""Counters in the run tables are signed (issue 25): differences of steps do not wrap around in
pandas, pyarrow or polars."""

import os

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest

import saggriac as sg
from saggriac.runs.storage import signed_integers

TABLES = ("metrics", "goals", "attempts", "regions")


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    out = tmp_path_factory.mktemp("types") / "run"
    sg.run(sg.Config(n_steps=800, n_evals=2, n_test_goals=10, n_test_configs=10), seed=1, out_dir=out)
    return out


def test_no_table_holds_an_unsigned_column(saved):
    r = sg.RunResult.load(saved)
    for name in TABLES:
        frame = getattr(r, name)
        assert not [c for c in frame.columns if frame[c].dtype.kind == "u"], name
        schema = pq.read_schema(saved / f"{name}.parquet")
        assert not [f.name for f in schema if str(f.type).startswith("uint")], name


def test_a_step_difference_is_negative_when_it_should_be(saved):
    goals = sg.RunResult.load(saved).goals
    back = goals["step_start"] - goals["step_end"]
    assert (back <= 0).all() and (back < 0).any()


def test_polars_reads_differences_without_wrapping(saved):
    if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") == "1":
        import polars as pl
    else:
        pl = pytest.importorskip("polars", reason='polars is not installed (pip install ".[test]")')
    g = pl.read_parquet(saved / "goals.parquet")
    assert (g["step_start"] - g["step_end"]).max() <= 0


def test_old_unsigned_tables_read_back_signed():
    old = pd.DataFrame({"step": np.array([5, 7], dtype=np.uint64), "mode": np.array([1, 2], dtype=np.uint8), "x": [0.5, 1.5]})
    new = signed_integers(old.copy())
    assert new["step"].dtype == np.int64 and new["mode"].dtype == np.int64 and new["x"].dtype == np.float64
    assert (new["step"] - 10).tolist() == [-5, -3]


def test_the_core_hands_out_signed_counts():
    from saggriac import _core
    from saggriac.seeding import derive_seeds

    cfg = sg.Config(n_steps=600, n_evals=2, n_test_goals=5, n_test_configs=5)
    learner = _core.Learner(cfg.core_dict(), *derive_seeds(0))
    learner.run()
    tables = [learner.metrics(), learner.goals(), learner.attempts(), learner.regions(), sg.SaggRiacSelector([0, 0], [1, 1]).regions()]
    unsigned = [k for t in tables for k, v in t.items() if np.asarray(v).dtype.kind == "u"]
    assert unsigned == []
