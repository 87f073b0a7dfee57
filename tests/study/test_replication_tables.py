"""docs/reproduction.md's replication on the report seeds recomputes from the committed rows of
its runs (docs/figures/replication/EXP_runs_LABEL.csv, issue 48): every table row of the section
is a row that `benchmarks/replication.py --from-tables` prints, every CI the prose quotes is in
its tables, and the statistics, time budgets and claims it recomputes equal the committed files
``saggriac reproduce`` and the rule's script wrote from the run folders."""

import re
from pathlib import Path

import pytest

from tests import benchmark_scripts

ROOT = Path(__file__).resolve().parents[2]
TABLES = ROOT / "docs" / "figures" / "replication"
PAGE = ROOT / "docs" / "reproduction.md"
SECTION = ("## Replication on the report seeds 15-29", "## The episodic paradigm")
Q_TABLE = ("Rerun at q = 20 on the report seeds 15-29", "python benchmarks/reading_checks.py q20")


def replication():
    return benchmark_scripts.load("replication")


@pytest.fixture(scope="module")
def recomputed():
    r = replication()
    sets = r.from_tables(TABLES)
    text, claims, stats_of = r.report(sets, ROOT / "docs" / "figures" / "readings" / "runs.csv")
    return r, sets, text, claims, stats_of


def part(text, start, end):
    return text[text.index(start) : text.index(end, text.index(start))]


def test_the_committed_rows_are_every_run_of_both_experiments(recomputed):
    _, sets, *_ = recomputed
    assert "15-29" in sets
    for label, by_exp in sets.items():
        first = int(label.split("-")[0])
        for exp, n_steps in (("exp1", 50_000), ("exp2", 200_000)):
            runs = by_exp[exp]
            assert len(runs) == 60, (exp, label)
            assert sorted(runs.groupby("condition")["seed"].apply(lambda s: tuple(sorted(s))).unique()) == [tuple(range(first, first + 15))]
            assert (runs["n_steps"] == n_steps).all()
            assert (runs["reach_error"] == runs[f"reach_error@{n_steps}"]).all()


def test_every_table_row_of_the_section_is_recomputed(recomputed):
    _, _, text, *_ = recomputed
    section = part(PAGE.read_text(), *SECTION)
    rows = [line for line in section.splitlines() if line.startswith("| ")]
    assert len(rows) >= 50
    missing = [row for row in rows if row not in text.splitlines()]
    assert not missing, f"rows of the replication section that replication.py --from-tables does not give: {missing[:3]}"


def test_the_cis_the_prose_quotes_are_in_the_tables(recomputed):
    _, _, text, *_ = recomputed
    section = part(PAGE.read_text(), *SECTION)
    prose = " ".join(" ".join(line.split()) for line in section.splitlines() if not line.startswith("|"))
    quoted = re.findall(r"[+-]?\d+\.\d+ \[[+-]?\d+\.\d+, [+-]?\d+\.\d+\](?:, p = \d+(?:\.\d+)?(?:e-\d+)?)?", prose)
    assert len(quoted) >= 5
    absent = [q for q in quoted if q not in text]
    assert not absent, f"differences quoted in the section's prose that the recomputation does not give: {absent}"


def test_the_q100_side_of_figure_3s_q20_table_is_recomputed(recomputed):
    """The table beside Fig. 3 pairs the replication's exp2 runs (q = 100) with the q = 20 runs
    of docs/figures/readings/runs.csv; only its q = 20 shares by quarter are in no committed table."""
    _, _, text, *_ = recomputed
    rows = [line for line in part(PAGE.read_text(), *Q_TABLE).splitlines() if line.strip().startswith("| ") and "q = 100 |" not in line]
    assert len(rows) == 8
    lines = text.splitlines()
    for row in (r.strip() for r in rows):
        if "share by quarter" in row:
            assert any(row.startswith(line + " ") for line in lines if line.startswith("| SAGG-RIAC, share by quarter |")), row
        else:
            assert row in lines, row


def test_the_committed_statistics_time_budgets_and_claims_equal_the_recomputation(recomputed):
    r, sets, _, claims, stats_of = recomputed
    assert r.check(sets, claims, stats_of, TABLES) == []


def test_the_q100_rows_of_the_readings_table_are_the_replications_runs(recomputed):
    """docs/figures/readings/runs.csv carries the replication's SAGG runs of exp2 as its q = 100
    side: they are the committed rows' runs, to the bit."""
    r, sets, *_ = recomputed
    readings = r.read_csv(ROOT / "docs" / "figures" / "readings" / "runs.csv")
    readings = readings[readings["study"] == "replication exp2 (q = 100)"]
    for c in ("sagg_riac", "sagg_random"):
        mine = r.per_condition(sets["15-29"]["exp2"], c)
        theirs = readings[readings["condition"] == c].set_index("seed").sort_index()
        assert list(theirs.index) == list(range(15, 30))
        for k in ("reach_error", "pred_error", "goals", "share_2nd_half"):
            assert (theirs[k] == mine.loc[theirs.index, k]).all(), (c, k)
