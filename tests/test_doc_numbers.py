"""benchmarks/doc_numbers.py: every number of the deep-RL pages recomputes from committed tables.
The whole check runs on the committed data; the cases below show it fails where a user would want
it to: a number no table holds, a number given to the wrong teacher, a wrong formula, a derived
table that its runs do not give."""

import shutil
from pathlib import Path

import pytest

from tests.benchmark_scripts import load

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def doc_numbers():
    pytest.importorskip("stable_baselines3", reason='the studies\' scripts need the SB3 extra (pip install "saggriac[sb3]")')
    return load("doc_numbers")


def test_every_number_of_the_deep_rl_pages_recomputes_from_the_committed_tables(doc_numbers, capsys):
    assert doc_numbers.main([]) == 0, capsys.readouterr().err
    out = capsys.readouterr().out
    assert "every table recomputes" in out and "docs/rl_curriculum.md" in out and "docs/choosing_a_teacher.md" in out


def page(tmp_path: Path, body: str) -> Path:
    p = tmp_path / "page.md"
    p.write_text("# A page\n\nThe tables: [results](figures/rl_curriculum/results.md).\n\n## Results\n\n" + body + "\n")
    return p


def problems(doc_numbers, path: Path) -> list[str]:
    return doc_numbers.check_page(path, doc_numbers.teacher_names())[0]


def test_a_number_in_the_cited_tables_is_found_and_one_in_none_is_named_with_its_line(doc_numbers, tmp_path):
    # SPDL's dense gain and CI as results.md gives them, and the oracle's final distance.
    good = page(tmp_path, "SPDL helps (+0.137 [+0.098, +0.176], d_z = 1.48); the oracle ends at 0.420.")
    assert problems(doc_numbers, good) == []
    bad = page(tmp_path, "SPDL helps (+0.137 [+0.098, +0.176]).\nIts gain was\n+0.9871 in truth.")
    found = problems(doc_numbers, bad)
    assert len(found) == 1 and "page.md:9: +0.9871" in found[0]


def test_a_number_is_found_only_in_a_record_of_the_teacher_its_sentence_names(doc_numbers, tmp_path):
    # +0.270 is ADR's sparse gain; no RIAC row holds it.
    assert problems(doc_numbers, page(tmp_path, "ADR helps by +0.270.")) == []
    found = problems(doc_numbers, page(tmp_path, "RIAC helps by +0.270."))
    assert len(found) == 1 and "+0.270" in found[0]


def test_a_table_the_section_does_not_cite_does_not_count(doc_numbers, tmp_path):
    p = tmp_path / "page.md"
    p.write_text("# A page\n\nSPDL helps (+0.137 [+0.098, +0.176]).\n")
    assert len(problems(doc_numbers, p)) == 3


def test_a_computed_number_carries_its_formula_and_a_wrong_one_fails(doc_numbers, tmp_path):
    right = page(tmp_path, "The oracle's distance is 29 %<!-- = 100 * (1 - 0.420 / 0.592) --> shorter than random's.")
    assert problems(doc_numbers, right) == []
    wrong = page(tmp_path, "The oracle's distance is 31 %<!-- = 100 * (1 - 0.420 / 0.592) --> shorter than random's.")
    assert len(problems(doc_numbers, wrong)) == 1
    # Its measured operands must be in the tables too.
    made_up = page(tmp_path, "The oracle's distance is 29 %<!-- = 100 * (1 - 0.4201 / 0.5921) --> shorter than random's.")
    assert len(problems(doc_numbers, made_up)) == 1


def test_protocol_paragraphs_and_names_are_not_claims_but_counted_apart(doc_numbers, tmp_path):
    p = page(tmp_path, "<!-- protocol -->\nThe budget is 123,457 steps.\n\nSeed 987 of issue 4242 ran.")
    found, count, fixed = doc_numbers.check_page(p, doc_numbers.teacher_names())
    assert found == [] and count == 0 and fixed == 1


def test_a_derived_table_its_runs_do_not_give_is_named(doc_numbers, tmp_path):
    figures = tmp_path / "committed"
    shutil.copytree(REPO / "docs" / "figures" / "rl_curriculum" / "pilot", figures / "rl_curriculum" / "pilot")
    d = doc_numbers.Derivation("rl_curriculum/pilot", ("curves.csv",), ("rl_curriculum.py", "--out", "{out}", "--analyse"), ("results.md",))
    assert doc_numbers.recompute(d, tmp_path / "a", figures) == []
    results = figures / "rl_curriculum" / "pilot" / "results.md"
    results.write_text(results.read_text().replace("0.0", "0.1", 1))
    found = doc_numbers.recompute(d, tmp_path / "b", figures)
    assert len(found) == 1 and "rl_curriculum/pilot/results.md is not what" in found[0]
