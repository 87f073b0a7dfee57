"""Every number of the deep-RL pages recomputes from committed tables, by one command.

    python benchmarks/doc_numbers.py                          # docs/rl_curriculum.md and docs/choosing_a_teacher.md
    python benchmarks/doc_numbers.py docs/rl_curriculum.md    # one page
    python benchmarks/doc_numbers.py --list                   # also print where each number was found

Two steps, and the command fails (exit 1, naming the file, line and number) if either does:

1. **Recompute.** Each study's derived tables are rebuilt by its own script from its committed
   runs alone (``runs.csv`` or ``curves.csv``, and ``protocol.json``), copied to a scratch folder,
   and must equal the committed ones. Then ``benchmarks/guide.py --check`` rebuilds the guide's
   table of verdicts from the tables so checked.
2. **Locate.** Every number in a page's prose and tables (not in code, links, dates or the guide's
   generated block, which step 1 checks whole) is looked for in the tables its section cites
   (a path under ``figures/``, a study's ``--out`` or ``--study``; a section also reads what its
   parents cite). It counts as found when a record (a CSV row, a line of Markdown, a whole JSON
   file) holds the number at the precision printed (``29 %`` may be 0.29 or 29; the sign may be
   dropped) and, if the page's line names teachers, the record names one of them too. A number
   computed from others carries its formula in a comment after it, ``29 %<!-- = 1 - 0.420 / 0.592 -->``;
   the formula's numbers are located like any other and its value must round to the printed one.

Numbers that are the protocol's own (seeds, budgets, thresholds) are found in its protocol, in
the commands the section prints, or stand in a paragraph marked ``<!-- protocol -->`` (a section
whose first line is the marker is a protocol whole, its tables still checked): rules and settings
fixed before the runs, choices rather than results, counted apart. Numbers that name things
(seed 500, issue 46, rule 2) are not claims.
"""

from __future__ import annotations

import argparse
import atexit
import json
import math
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

REPO = Path(__file__).resolve().parents[1]
PAGES = ("docs/rl_curriculum.md", "docs/choosing_a_teacher.md")
FIGURES = "docs/figures"


@dataclass(frozen=True)
class Derivation:
    """A folder of committed tables and how its derived ones are rebuilt from its inputs."""

    folder: str  # under docs/figures
    inputs: tuple[str, ...]  # copied to the scratch folder; a missing one is skipped
    args: tuple[str, ...]  # the script and its arguments; {out} and {root} are the scratch copies
    outputs: tuple[str, ...]  # compared with the committed ones
    stdout: str = ""  # a file the command's printout is kept in (compared like an output)


def _study(folder: str, pilot: bool = False) -> Derivation:
    name = folder.split("/")[1]
    sub = "pilot/" if pilot else ""
    return Derivation(folder, ("protocol.json", f"{sub}runs.csv", f"{sub}curves.csv"), ("evidence.py", "--root", "{root}", "--study", name, *(("--pilot",) if pilot else ()), "--analyse"),
                      (f"{sub}comparisons.csv", f"{sub}results.md"))


def _rl(folder: str) -> Derivation:
    return Derivation(folder, ("curves.csv", "protocol.json"), ("rl_curriculum.py", "--out", "{out}", "--analyse"), ("runs.csv", "comparisons.csv", "results.md"))


def derivations() -> list[Derivation]:
    """The studies the pages rest on; an evidence study counts once it has report runs."""
    found = [
        _rl("rl_curriculum"), _rl("rl_curriculum/replication"), _rl("rl_curriculum/free_joints"), _rl("rl_curriculum/pilot"),
        Derivation("rl_curriculum/pilot", ("curves.csv",), ("rl_curriculum.py", "--out", "{out}", "--pilot"), ("decision.md",), stdout="decision.md"),
        Derivation("rl_curriculum", (), ("rl_curriculum.py", "--power"), ("power.md",), stdout="power.md"),
        Derivation("teachers", ("toy_tasks_runs.csv", "toy_tasks_curves.csv"), ("toy_tasks.py", "--out", "{out}", "--report-only"), ("toy_tasks_results.csv", "toy_tasks_results.md")),
        Derivation("teachers/spdl_after46", ("toy_tasks_runs.csv", "toy_tasks_curves.csv"), ("toy_tasks.py", "--out", "{out}", "--report-only"), ("toy_tasks_results.csv", "toy_tasks_results.md")),
        *(Derivation(f"teachers/{name}", ("runs.csv", "curves.csv"), ("teacher_niches.py", "--out", "{out}", "--report-only"), ("comparisons.csv", "results.md"))
          for name in ("niches", "niches_plr", "niches_adr_spdl_goal_gan")),
        # The bench's quick leaderboard, from the results shipped with the package (nothing run).
        Derivation("bench/quick", (), ("saggriac", "bench", "--tier", "quick", "--out", "{out}", "--workers", "1", "--no-progress"), ("leaderboard.csv", "leaderboard.md")),
    ]
    for study in sorted((REPO / FIGURES / "evidence").glob("*/protocol.json")):
        folder = study.parent.relative_to(REPO / FIGURES).as_posix()
        if (study.parent / "runs.csv").exists():
            found.append(_study(folder))
        # A pilot analysed by evidence.py (the SAC study's); the others' pilots have scripts of their own.
        if (study.parent / "pilot" / "results.md").exists():
            found.append(_study(folder, pilot=True))
    return found


def recompute(d: Derivation, scratch: Path, figures: Path = REPO / FIGURES) -> list[str]:
    """Rebuild one derivation in ``scratch`` from the inputs under ``figures``; where it differs
    from the tables committed there."""
    root = scratch / "figures"
    out = root / d.folder
    committed = figures / d.folder
    out.mkdir(parents=True, exist_ok=True)
    for name in d.inputs:
        if (committed / name).exists():
            (out / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(committed / name, out / name)
    evidence_root = root / "evidence"
    args = [a.replace("{out}", str(out)).replace("{root}", str(evidence_root)) for a in d.args]
    # "saggriac ..." is the package's command line; anything else a script of benchmarks/.
    program = [sys.executable, "-c", "import sys; from saggriac.cli import main; sys.exit(main(sys.argv[1:]))"] if args[0] == "saggriac" else [sys.executable, str(REPO / "benchmarks" / args[0])]
    done = subprocess.run([*program, *args[1:]], capture_output=True, text=True, cwd=REPO)
    if done.returncode:
        return [f"{FIGURES}/{d.folder}: `{' '.join(d.args)}` failed: {done.stderr.strip()[-400:]}"]
    if d.stdout:
        (out / d.stdout).write_text(done.stdout)
    problems = []
    for name in d.outputs:
        mine, theirs = out / name, committed / name
        if not mine.exists():
            problems.append(f"{FIGURES}/{d.folder}/{name}: `{' '.join(d.args)}` did not write it")
            continue
        # A report names the folder it was made in: the scratch copy stands for the committed one.
        text = mine.read_text().replace(str(out), f"{FIGURES}/{d.folder}")
        if not theirs.exists() or text != theirs.read_text():
            problems.append(f"{FIGURES}/{d.folder}/{name} is not what `benchmarks/{' '.join(d.args)}` recomputes from its runs")
    return problems


# -- locating the numbers ------------------------------------------------------------------------------

# A number standing alone (11/12 is two; figures/1500 and v1.2 are none).
NUMBER = re.compile(r"(?<![\w.,\-+−])(?<![A-Za-z_]/)[-+−]?(?:\d{1,3}(?:,\d{3})+|\d+)(?:\.\d+)?(?!\w|,\d|/[A-Za-z_])(?:\s?%)?")
CITE = re.compile(r"\b[0-9a-f]{7,40}:(?:docs/)?figures/[\w/.+-]+|(?:docs/)?figures/[\w/.+-]+|(?<=--out )[\w/.+-]+|(?<=--study )[\w+-]+|python/saggriac/bench/results[\w/.-]*")
LOOSE = re.compile(r"[-+]?(?:\d{1,3}(?:,\d{3})+|\d+)(?:\.\d+)?(?:[eE][-+]?\d+)?")
# Numbers that name things rather than measure them: issues, rules, items, stops, years of papers.
NAMING = re.compile(r"(?:#|\b(?:[Ii]ssues?|[Rr]ules?|[Ii]tems?|[Ss]tops?|[Ss]tudy|[Ss]eeds?|al\.,?|[Ss]ection)\s)$")
FORMULA = re.compile(r"<!--\s*=\s*(.*?)-->")
SKIP = (re.compile(r"`[^`]*`"), re.compile(r"\]\([^)]*\)"), re.compile(r"<!--.*?-->"), re.compile(r"\b\d{4}-\d{2}-\d{2}\b"), re.compile(r"https?://\S+"))
GENERATED = ("<!-- verdicts -->", "<!-- /verdicts -->")  # guide.py --check rebuilds this block whole


def teacher_names() -> dict[str, str]:
    """Every spelling of a teacher's name a page or a table uses, to its normal form."""
    from saggriac.bench.suite import builtin_specs

    spell: dict[str, str] = {}
    words = {s.label.split("@")[0] for s in builtin_specs(False)} | {"oracle", "random", "goal_gan", "GoalGAN", "Goal GAN", "discrete LP", "PLR", "TSCL", "SPDL", "ADR", "RIAC", "SAGG-RIAC",
                                     "ALP-GMM", "Covar-GMM"}
    for w in words:
        norm = re.sub(r"[^a-z0-9]", "", w.lower())
        if len(norm) >= 3:
            spell[norm] = norm
    spell["plrvalueloss"] = "plr"  # saggriac.bench.value_loss:PlrValueLoss, PLR with its paper's score
    return spell


def names_in(text: str, spell: dict[str, str]) -> set[str]:
    # Two-word names (Goal GAN, discrete LP) are joined before the words are read.
    words = re.findall(r"[A-Za-z][A-Za-z0-9_-]*(?:\s(?:GAN|LP|GMM))?", text)
    found = set()
    for w in words:
        norm = re.sub(r"[^a-z0-9]", "", w.lower()).removesuffix("selector")  # GoalGanSelector is Goal GAN
        if norm in spell:
            found.add(spell[norm])
    return found


@dataclass
class Record:
    """A row of a table, a line of a report, or a whole small file: its numbers and teachers."""

    where: str
    values: list[float]
    names: set[str]


def parse_number(token: str) -> tuple[float, int, bool]:
    """A printed number: its value, its decimals and whether it was a percentage."""
    percent = token.rstrip().endswith("%")
    t = token.rstrip("% ").replace(",", "").replace("−", "-").lstrip("+")
    decimals = len(t.split(".")[1]) if "." in t else 0
    return float(t), decimals, percent


def records_of(path: Path, spell: dict[str, str]) -> list[Record]:
    rel = path.relative_to(REPO).as_posix() if path.is_relative_to(REPO) else str(path)
    if path.suffix == ".csv":
        try:
            table = pd.read_csv(path, dtype=str)
        except pd.errors.EmptyDataError:
            return []
        out = []
        for i, row in enumerate(table.itertuples(index=False), 2):
            values, names = [], set()
            for cell in row:
                if isinstance(cell, str):
                    try:
                        values.append(float(cell))
                    except ValueError:
                        values += _numbers(cell)
                        names |= names_in(cell.replace("_", " "), spell) | ({re.sub(r"[^a-z0-9]", "", cell.lower())} & set(spell))
            out.append(Record(f"{rel}:{i}", values, names))
        return out
    text = path.read_text()
    if path.suffix == ".json":
        return [Record(rel, _numbers(json.dumps(json.loads(text))), set())]
    return [Record(f"{rel}:{i}", _numbers(line), names_in(line, spell)) for i, line in enumerate(text.splitlines(), 1)]


def _numbers(text: str) -> list[float]:
    """Every number a table holds, read generously (11/12, 1.2e-06, 120,000)."""
    return [float(m.replace(",", "")) for m in LOOSE.findall(text.replace("−", "-"))]


def matches(value: float, decimals: int, percent: bool, candidate: float) -> bool:
    half = 0.5 * 10.0 ** -decimals + 1e-9
    targets = [value / 100.0, value] if percent else [value]
    for t in targets:
        scale = half / 100.0 if (percent and t is targets[0]) else half
        if abs(abs(candidate) - abs(t)) <= scale:
            return True
    return False


@dataclass
class Section:
    title: str
    level: int
    start: int
    lines: list[tuple[int, str]] = field(default_factory=list)
    cites: set[Path] = field(default_factory=set)
    parents: list["Section"] = field(default_factory=list)


def sections(page: Path) -> list[Section]:
    out: list[Section] = []
    stack: list[Section] = []
    current = Section("(top)", 0, 1)
    out.append(current)
    for i, line in enumerate(page.read_text().splitlines(), 1):
        m = re.match(r"(#+) ", line)
        if m:
            level = len(m.group(1))
            stack = [s for s in stack if s.level < level]
            current = Section(line.strip(), level, i, parents=list(stack))
            stack.append(current)
            out.append(current)
        for c in CITE.findall(line):
            path = resolve(c)
            if path is not None:
                current.cites.add(path)
        current.lines.append((i, line))
    return out


_HISTORY: list[Path] = []


def history() -> Path:
    """A scratch folder for tables read from earlier commits, made on first use (not at import,
    so a test importing this module leaves nothing behind) and removed at exit."""
    if not _HISTORY:
        _HISTORY.append(Path(tempfile.mkdtemp(prefix="doc_numbers_history_")))
        atexit.register(shutil.rmtree, _HISTORY[0], True)
    return _HISTORY[0]


def resolve(cited: str) -> Path | None:
    """A cited table: a path of the checkout, or ``<commit>:<path>``, a table as an earlier
    commit held it (read with git, for numbers a page quotes from before a rerun)."""
    cited = cited.rstrip(".,):")
    commit, colon, rest = cited.partition(":")
    if colon:
        rest = rest if rest.startswith("docs/") else f"docs/{rest}"
        shown = subprocess.run(["git", "-C", str(REPO), "show", f"{commit}:{rest}"], capture_output=True)
        if shown.returncode:
            return None
        path = history() / commit / rest
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(shown.stdout)
        return path
    for base in (REPO, REPO / "docs", REPO / FIGURES / "evidence"):
        path = base / cited
        if path.exists() and path.is_relative_to(REPO):
            return path
    return None


RAW = re.compile(r"(^|_)(runs|curves|modes)\.csv$")


def files_of(path: Path) -> list[Path]:
    """A cited file, or a cited folder's summaries (its own, not its subfolders'): a folder's raw
    tables of runs and curves hold so many numbers that any would match, so a page quoting one
    cites it by name."""
    if path.is_file():
        return [path] if path.suffix in (".csv", ".md", ".json") else []
    return sorted(p for p in path.iterdir() if p.is_file() and p.suffix in (".csv", ".md", ".json") and not RAW.search(p.name))


# A paragraph holding it (or a section whose first line it is) states rules and settings fixed
# before the runs: its numbers are choices, not results, and are counted apart.
PROTOCOL = "<!-- protocol -->"
SENTENCE = re.compile(r"[.;](?=\s+[A-Z*(])")


def paragraphs(lines: list[tuple[int, str]]):
    """The page's paragraphs whose numbers are claims, each as [(line number, text)]: not code,
    headings or the generated block; a table row or a list item starts a paragraph of its own."""
    fence = generated = code_block = False
    previous_blank = True
    current: list[tuple[int, str]] = []
    for i, line in lines:
        stripped = line.strip()
        if line.startswith("```"):
            fence = not fence
        if stripped == GENERATED[0]:
            generated = True
        if stripped == GENERATED[1]:
            generated = False
            previous_blank = False
            continue
        if line.startswith("    ") and (previous_blank or code_block) and not line.lstrip().startswith(("-", "|", "*")):
            code_block = True
        elif stripped:
            code_block = False
        previous_blank = not stripped
        skip = fence or generated or code_block or line.startswith("```") or re.match(r"#+ ", line)
        starts = not stripped or skip or stripped.startswith(("|", "- ", "* ")) or re.match(r"\d+\. ", stripped)
        if starts and current:
            yield current
            current = []
        if not skip and stripped:
            current.append((i, line))
        if stripped.startswith("|") and current:
            yield current
            current = []
    if current:
        yield current


def check_page(page: Path, spell: dict[str, str], listing: bool = False) -> tuple[list[str], int, int]:
    """Every number of ``page`` located: (problems, numbers found, numbers in protocol paragraphs)."""
    rel = page.relative_to(REPO).as_posix() if page.is_relative_to(REPO) else str(page)
    problems: list[str] = []
    count = fixed = 0
    cache: dict[str, list[Record]] = {}
    for sec in sections(page):
        cited = set(sec.cites).union(*(p.cites for p in sec.parents)) if sec.parents else set(sec.cites)
        records = []
        for c in sorted(cited):
            if c not in cache:
                cache[c] = [r for f in files_of(c) for r in records_of(f, spell)]
            records += cache[c]
        # The numbers of the commands and code a section prints (seeds, budgets, defaults) are the
        # protocol's own: indented code and what stands between backticks, not the prose around it.
        code = [line for _, line in sec.lines if line.startswith("    ") and not line.lstrip().startswith(("-", "|", "*"))]
        code += [m for _, line in sec.lines for m in re.findall(r"`([^`]*)`", line)]
        given = Record(f"{rel}: the section's commands", _numbers("\n".join(code)), set())
        records.append(given)
        # A section whose first line under its heading is the marker is a protocol: its prose is
        # rules and settings; its tables (a power table) are still located.
        whole = next((line.strip() for _, line in sec.lines[1:] if line.strip()), "") == PROTOCOL
        for para in paragraphs(sec.lines):
            raw = " ".join(line for _, line in para)
            numbers = claims(para)
            if PROTOCOL in raw or (whole and not raw.lstrip().startswith("|")):
                fixed += len(numbers)
                continue
            text = "".join(t for _, t, _ in _joined(para))
            for line_no, token, pos, formula in numbers:
                count += 1
                value, decimals, percent = parse_number(token)
                names = names_in(sentence(text, pos), spell)
                where = evaluate(formula, records, names, value, decimals, percent) if formula else locate(value, decimals, percent, records, names)
                if where is None:
                    problems.append(f"{rel}:{line_no}: {token.strip()} is in none of the tables its section cites ({sec.title})")
                elif listing:
                    print(f"{rel}:{line_no}: {token.strip()} <- {where}")
    return problems, count, fixed


def _joined(para: list[tuple[int, str]]):
    """The paragraph's lines as (line number, text without code, links or dates, formulas)."""
    for i, line in para:
        formulas = [(m.start(), m.group(1)) for m in FORMULA.finditer(line)]
        text = line
        for pattern in SKIP:
            text = pattern.sub(lambda m: " " * len(m.group()), text)
        yield i, text + " ", formulas


def claims(para: list[tuple[int, str]]) -> list[tuple[int, str, int, str | None]]:
    """(line number, token, offset in the joined paragraph, formula or None) of every number."""
    out = []
    offset = 0
    for i, text, formulas in _joined(para):
        for m in NUMBER.finditer(text):
            if NAMING.search(text[: m.start()]):
                continue
            formula = next((f for pos, f in formulas if 0 <= pos - m.end() <= 3), None)
            out.append((i, m.group(), offset + m.start(), formula))
        offset += len(text)
    return out


def sentence(text: str, pos: int) -> str:
    """The sentence of ``text`` around ``pos``: the teachers it names are the number's."""
    starts = [m.end() for m in SENTENCE.finditer(text, 0, pos)]
    end = SENTENCE.search(text, pos)
    return text[starts[-1] if starts else 0: end.start() if end else len(text)]


def locate(value: float, decimals: int, percent: bool, records: list[Record], names: set[str]) -> str | None:
    for r in records:
        # A record naming no teacher (a setting, a cost, a power table) attributes to none.
        if any(matches(value, decimals, percent, v) for v in r.values) and (not names or not r.names or names & r.names):
            return r.where
    return None


def power(n: int, d: float, alpha: float) -> float:
    """The power of a paired t-test, as the studies size themselves (rl_curriculum.py's)."""
    sys.path.insert(0, str(REPO / "benchmarks"))
    try:
        import rl_curriculum
    finally:
        sys.path.pop(0)
    return rl_curriculum.power(int(n), float(d), float(alpha))


FUNCTIONS = {"power": power}


def evaluate(formula: str, records: list[Record], names: set[str], value: float, decimals: int, percent: bool) -> str | None:
    """A computed number: each operand located, the result rounding to the printed value."""
    for m in NUMBER.finditer(formula):
        v, d, p = parse_number(m.group())
        # Whole numbers in a formula are arithmetic (a count, a scale); measured ones are located.
        if (d or p) and locate(v, d, p, records, names) is None:
            return None
    if not re.fullmatch(r"(?:[\d\s.,+\-*/()]|power)+", formula.replace("−", "-")):
        return None
    result = eval(formula.replace("−", "-"), {"__builtins__": {}}, dict(FUNCTIONS))  # numbers, + - * / ( ) and FUNCTIONS only
    shown = result * 100 if percent and abs(value) > 1.5 * abs(result) else result
    return f"= {formula.strip()}" if math.isclose(round(abs(shown), decimals), abs(value), abs_tol=1.01 * 10.0 ** -decimals) else None


EMBEDDED = re.compile(r"```python\n(.*?)```", re.S)


def embedded(figures: Path = REPO / FIGURES) -> list[str]:
    """A summary table made by the Python it shows (a ```python block in a Markdown file under
    docs/figures): the block is run from the repository's root and every line it prints must be
    in the file."""
    problems = []
    for md in sorted(figures.rglob("*.md")):
        for block in EMBEDDED.findall(md.read_text()):
            done = subprocess.run([sys.executable, "-c", block], capture_output=True, text=True, cwd=REPO)
            text = md.read_text()
            missing = [line for line in done.stdout.splitlines() if line.strip() and line not in text]
            if done.returncode or missing:
                problems.append(f"{md.relative_to(REPO)}: its Python block " + (f"failed: {done.stderr.strip()[-300:]}" if done.returncode else f"prints {len(missing)} line(s) the file does not hold, e.g. {missing[0][:120]}"))
    return problems


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("pages", nargs="*", default=list(PAGES), help=f"pages to check (default: {' '.join(PAGES)})")
    ap.add_argument("--list", action="store_true", help="print where each number was found")
    ap.add_argument("--no-recompute", action="store_true", help="skip step 1 (locate the numbers in the committed tables only)")
    args = ap.parse_args(argv)
    problems: list[str] = []
    if not args.no_recompute:
        with tempfile.TemporaryDirectory(prefix="doc_numbers_") as tmp:
            for d in derivations():
                problems += recompute(d, Path(tmp))
        problems += embedded()
        guide = subprocess.run([sys.executable, str(REPO / "benchmarks" / "guide.py"), "--check"], capture_output=True, text=True, cwd=REPO)
        if guide.returncode:
            problems.append(guide.stderr.strip())
    spell = teacher_names()
    total = protocol = 0
    for page in args.pages:
        path = (Path.cwd() / page).resolve()
        if not path.is_file():
            ap.error(f"pages: {page} is not a file")
        found, count, fixed = check_page(path, spell, args.list)
        problems += found
        total += count
        protocol += fixed
    for p in problems:
        print(p, file=sys.stderr)
    if problems:
        print(f"{len(problems)} problem(s)", file=sys.stderr)
        return 1
    checked = "the committed tables (not recomputed: --no-recompute)" if args.no_recompute else "every table recomputes, and"
    print(f"{checked} all {total} numbers of {', '.join(args.pages)} are in them ({protocol} more are rules fixed before the runs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
