"""docs/choosing_a_teacher.md's table of verdicts is what the committed tables give (recomputed by
benchmarks/guide.py), and the generator's rule reads a gain as a user would."""

import math

import pytest

from . import benchmark_scripts


@pytest.fixture(scope="module")
def guide():
    return benchmark_scripts.load("guide")


def test_the_guides_table_of_verdicts_recomputes_from_the_committed_tables(guide, capsys):
    assert guide.main(["--check"]) == 0, capsys.readouterr().err


def test_the_verdict_rule_and_a_drifted_guide_is_caught(guide, tmp_path, monkeypatch, capsys):
    assert guide.verdict(0.1, 0.01) == "helps" and guide.verdict(-0.1, 0.01) == "hurts"
    assert guide.verdict(0.5, 0.05) == "no difference shown" and guide.verdict(0.5, math.nan) == "no difference shown"
    # A hand edit of one number in the generated block makes --check fail and names the fix.
    text = guide.GUIDE.read_text()
    cols, table = guide.gather()
    row = table[(table.teacher == "spdl") & table.key.str.endswith("dense")].iloc[0]
    shown = f"{row.gain:+.3f}"
    assert shown in text
    edited = tmp_path / "guide.md"
    at = text.index(shown, text.index(guide.START))  # the number in the generated block
    edited.write_text(text[:at] + f"{row.gain + 0.1:+.3f}" + text[at + len(shown):])
    monkeypatch.setattr(guide, "GUIDE", edited)
    assert guide.main(["--check"]) == 1
    assert "differs from the committed tables; run python benchmarks/guide.py" in capsys.readouterr().err
    # Rewriting it puts the number back, and the rest of the page is left as it was.
    assert guide.main([]) == 0 and edited.read_text() == text


def test_an_evidence_study_joins_the_table_once_its_report_is_complete(guide, tmp_path):
    import json

    import pandas as pd

    study = tmp_path / "mystudy"
    study.mkdir()
    (study / "protocol.json").write_text(json.dumps({"study": "mystudy", "tasks": ["rl-arm-dense"], "report": {"rl-arm-dense": "900-902,910"}, "rule": {"primary": "final"}}))
    rows = [dict(family="against the baseline", a="spdl", b="random", gain=0.2, ci_low=0.1, ci_high=0.3, p_holm=0.01, verdict="helps", task="rl-arm-dense", seeds=4),
            dict(family="against the oracle", a="spdl", b="oracle", gain=-0.1, ci_low=-0.2, ci_high=0.0, p_holm=0.2, verdict="no difference shown", task="rl-arm-dense", seeds=4)]
    pd.DataFrame(rows).to_csv(study / "comparisons.csv", index=False)
    cols, table = guide.evidence_rows(tmp_path)
    assert [c.key for c in cols] == ["mystudy:rl-arm-dense"] and cols[0].learner.startswith("PPO")
    assert table.to_dict("records") == [dict(key="mystudy:rl-arm-dense", teacher="spdl", n=4, gain=0.2, ci_low=0.1, ci_high=0.3, p_holm=0.01, verdict="helps")]
    # Three of the four report seeds done: interim, no column.
    pd.DataFrame([{**r, "seeds": 3} for r in rows]).to_csv(study / "comparisons.csv", index=False)
    assert guide.evidence_rows(tmp_path)[0] == []
