"""The figures of a study as a user gets them: `saggriac plot` redraws exactly what `reproduce`
wrote, goal panels are drawn to scale with readable titles, the +-1 sd band is explained, and
a folder that cannot be written gives a saggriac error and leaves nothing behind."""

import contextlib
import errno
import itertools
import os
import shutil
import subprocess

import pandas as pd
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from PIL import Image

import saggriac
from saggriac.analysis import plots
from saggriac.cli import main
from saggriac.study import reproduce as rep
from saggriac.errors import StorageError

STEPS = 400


@pytest.fixture(scope="module")
def study_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "exp1"
    rep.reproduce("exp1", out_dir=out, seeds=2, steps=STEPS, conditions=("sagg_riac", "sagg_random"), n_workers=1, progress=False)
    return out


def small(preset, **kw):
    return saggriac.Config.from_preset(preset, **{"n_evals": 2, "n_test_goals": 10, "n_test_configs": 10, **kw})


@pytest.fixture(scope="module")
def goal_runs(study_dir, tmp_path_factory):
    """Run folders of an exp1 (2-D half-disk), an explauto (2-D square) and an arm3d (3-D) run."""
    root = tmp_path_factory.mktemp("goal_runs")
    saggriac.run(small("explauto", n_steps=150), seed=0, out_dir=root / "explauto")
    saggriac.run(small("arm3d", n_steps=1500), seed=0, out_dir=root / "arm3d")
    return {"exp1": study_dir / "runs" / "sagg_riac" / "seed0", "explauto": root / "explauto", "arm3d": root / "arm3d"}


def figures(study_dir):
    return {p.name: p.read_bytes() for p in sorted((study_dir / "figures").iterdir())}


def test_plot_redraws_the_figures_reproduce_wrote(study_dir):
    written = figures(study_dir)
    assert Image.open(study_dir / "figures" / "curves.png").text["Title"] == f"exp1: 2 seed(s), {STEPS} time steps"
    for p in (study_dir / "figures").iterdir():
        p.unlink()
    assert main(["plot", str(study_dir)]) == 0
    # The same files, byte for byte: the title keeps the experiment's name.
    assert figures(study_dir) == written


def test_the_title_names_a_preset_only_when_the_study_is_one():
    def title(base):
        return rep.study_title(saggriac.Study(base=base, conditions=("sagg_riac",), seeds=(0, 1, 2)))

    assert title(saggriac.Config.from_preset("arm3d", n_steps=700)) == "arm3d: 3 seed(s), 700 time steps"
    assert title(saggriac.Config.from_preset("exp2", condition="sagg_random")) == "exp2: 3 seed(s), 200000 time steps"
    # One parameter away from every preset: no name is claimed.
    assert title(saggriac.Config.from_preset("exp1", q=21)) == "3 seed(s), 50000 time steps"


@pytest.mark.parametrize("name", ["exp1", "explauto", "arm3d"])
def test_goal_panels_are_to_scale_and_their_titles_do_not_overlap(goal_runs, name):
    fig = plots.goal_histograms_figure(goal_runs[name])
    panels = [ax for ax in fig.axes if ax.axison]
    # One panel per window of goals (short runs have fewer windows than the default 4), two
    # projections for the 3-D goal space.
    assert len(panels) >= (4 if name == "arm3d" else 2)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    for ax in panels:
        # Equal aspect: one unit of x is as long on screen as one unit of y (or z), as drawn.
        assert ax.get_aspect() == 1.0
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        box = ax.get_position()
        w, h = box.width * fig.get_figwidth(), box.height * fig.get_figheight()
        assert (w / (x1 - x0)) == pytest.approx(h / (y1 - y0), rel=0.02)
    renderer = canvas.get_renderer()
    boxes = [ax.title.get_window_extent(renderer) for ax in panels] + [fig._suptitle.get_window_extent(renderer)]
    for a, b in itertools.combinations(boxes, 2):
        assert not a.overlaps(b), (name, a, b)
    assert all(ax.get_title() for ax in panels)


def test_the_sd_band_is_labelled(study_dir):
    frame = saggriac.load_study(study_dir)
    fig = plots.curves_figure(frame, "t")
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any("1 sd over seeds" in label for label in labels), labels


@contextlib.contextmanager
def read_only(folder):
    """Make ``folder`` refuse new files, also for root (for whom permission bits do not count)."""
    if os.geteuid() != 0:
        folder.chmod(0o555)
        try:
            yield
        finally:
            folder.chmod(0o755)
        return
    if shutil.which("chattr") is None:
        pytest.skip("running as root without chattr: cannot make a folder read-only for root")
    done = subprocess.run(["chattr", "+i", str(folder)], capture_output=True, text=True)
    if done.returncode:
        pytest.skip(f"running as root and chattr +i failed ({done.stderr.strip()}): cannot make a folder read-only for root")
    try:
        yield
    finally:
        subprocess.run(["chattr", "-i", str(folder)], check=True)


def test_plot_into_a_read_only_figures_folder_is_a_storage_error(study_dir, capsys):
    figs = study_dir / "figures"
    before = figures(study_dir)
    with read_only(figs):
        with pytest.raises(StorageError, match=f"to {figs}/curves.png: (Permission denied|Operation not permitted)"):
            rep.make_report(study_dir)
        capsys.readouterr()
        assert main(["plot", str(study_dir)]) != 0
        err = capsys.readouterr().err
        assert str(figs) in err and "Traceback" not in err
    assert figures(study_dir) == before


def test_a_failed_rename_leaves_no_temporary_file(study_dir, monkeypatch):
    figs = study_dir / "figures"
    before = figures(study_dir)

    def refuse(src, dst):
        raise PermissionError(errno.EACCES, "Permission denied", str(dst))

    monkeypatch.setattr(saggriac.files.os, "replace", refuse)
    with pytest.raises(StorageError, match=f"Cannot write a figure to {figs}/curves.png: Permission denied"):
        rep.make_report(study_dir)
    monkeypatch.undo()
    assert figures(study_dir) == before  # nothing new, nothing half-written


def test_an_error_while_writing_removes_the_temporary_file(tmp_path):
    def half_then_fail(p):
        p.write_text("half")
        raise TypeError("not JSON serializable")

    with pytest.raises(TypeError, match="not JSON serializable"):
        rep._atomic(tmp_path / "stats.csv", half_then_fail)
    assert list(tmp_path.iterdir()) == []
    frame = pd.DataFrame({"a": [1]})
    assert rep._atomic(tmp_path / "t.csv", lambda p: frame.to_csv(p, index=False)).read_text() == "a\n1\n"
    assert [p.name for p in tmp_path.iterdir()] == ["t.csv"]
