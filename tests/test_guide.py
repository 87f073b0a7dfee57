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
