"""saggriac.analysis.plot_teacher: a teacher's goals over time, from the teacher, from the file it
was saved to or from its saved history (issue 46, item 4)."""

import numpy as np
import pytest
from matplotlib.patches import Ellipse, Rectangle

import saggriac as sg
from saggriac.analysis import plot_teacher
from saggriac.errors import ParameterError, StorageError
from saggriac.teachers import available
from saggriac.testing import example_teacher


def _taught(kind, n=400, seed=0):
    t = example_teacher(kind, seed=seed)
    rng = np.random.default_rng(seed)
    for _ in range(n):
        g = t.sample()
        t.update(g, float(rng.random() < (0.8 if g[0] < 0.5 else 0.2)))
    return t


@pytest.mark.parametrize("kind", list(available()))
def test_every_teacher_is_drawn_from_itself_and_from_its_saved_file(kind, tmp_path):
    t = _taught(kind)
    fig = plot_teacher(t, tmp_path / "a.png", windows=3)
    assert (tmp_path / "a.png").read_bytes().startswith(b"\x89PNG")
    saved = t.save(tmp_path / "t.saggriac")
    again = plot_teacher(saved, windows=3)
    panels = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    assert len(panels) == len([ax for ax in again.axes if ax.get_label() != "<colorbar>"])
    assert len(panels) == (2 if "tasks" in type(t).spaces else 3)
    assert [ax.get_title() for ax in panels] == [ax.get_title() for ax in again.axes if ax.get_label() != "<colorbar>"]


def test_adrs_panels_draw_the_box_over_the_goals_it_chose_and_its_current_ranges():
    t = sg.AdrSelector([0.0, 0.0], [10.0, 10.0], seed=0, buffer_size=2, step=0.1)
    for _ in range(400):
        t.update(t.sample(), 1.0)
    goals = t.history()["asked_goal"]
    fig = plot_teacher(t, windows=2)
    for ax, (a, b) in zip(fig.axes, [(0, 200), (200, 400)]):
        box = [p for p in ax.patches if isinstance(p, Rectangle)][0]
        assert np.allclose(box.get_xy(), goals[a:b].min(axis=0)) and np.allclose([box.get_width(), box.get_height()], np.ptp(goals[a:b], axis=0))
    lo, hi = t.bounds
    current = [p for p in fig.axes[-1].patches if isinstance(p, Rectangle)][-1]
    assert np.allclose(current.get_xy(), lo) and np.allclose([current.get_width(), current.get_height()], hi - lo)
    assert fig.axes[0].get_title() == "goals 0-200"


def test_spdl_draws_its_gaussian_and_a_mixture_its_components_as_ellipses():
    spdl = _taught("spdl")
    ellipses = [p for p in plot_teacher(spdl, windows=2).axes[-1].patches if isinstance(p, Ellipse)]
    reg = spdl.regions()
    mean, std = (reg["low"][0] + reg["high"][0]) / 2, (reg["high"][0] - reg["low"][0]) / 2
    assert len(ellipses) == 2 and np.allclose(ellipses[-1].center, mean[:2]) and np.allclose([ellipses[-1].width, ellipses[-1].height], 4 * std[:2])
    gmm = _taught("alp_gmm", n=600)
    assert any(isinstance(p, Ellipse) for p in plot_teacher(gmm, windows=2).axes[-1].patches)


def test_the_region_tree_is_drawn_as_it_was_in_each_window():
    t = _taught("sagg_riac", n=600)
    fig = plot_teacher(t, windows=3)
    boxes = [len([p for p in ax.patches if isinstance(p, Rectangle)]) for ax in fig.axes]
    assert boxes[0] <= boxes[1] <= boxes[2] == len(t.leaves()["interest"])


def test_a_task_lists_heat_map_is_each_tasks_share_of_the_draws():
    t = _taught("plr", n=300)
    fig = plot_teacher(t, windows=10)
    share = fig.axes[0].images[0].get_array()
    tasks = t.history()["asked_goal"][:, 0].astype(int)
    assert share.shape == (t.n_tasks, 10)
    assert np.allclose(share[:, 0], np.bincount(tasks[:30], minlength=t.n_tasks) / 30)
    assert np.allclose(share.sum(axis=0), 1.0)


def test_a_saved_history_is_drawn_without_its_teacher(tmp_path):
    t = _taught("riac")
    np.savez(tmp_path / "h.npz", low=t.low, high=t.high, **t.history())
    fig = plot_teacher(dict(np.load(tmp_path / "h.npz")), windows=4)
    assert len(fig.axes) == 4 and fig.axes[0].get_xlim() == (0.0, 1.0)
    assert "a saved history" in fig._suptitle.get_text()


def test_a_figure_replaces_only_a_figure_saggriac_wrote(tmp_path):
    mine = tmp_path / "photo.png"
    mine.write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 64)
    t = _taught("random", n=50)
    with pytest.raises(StorageError, match="not a figure saggriac wrote"):
        plot_teacher(t, mine)
    plot_teacher(t, tmp_path / "ok.png")
    plot_teacher(t, tmp_path / "ok.png")  # its own figure is replaced


@pytest.mark.parametrize(
    "kw, param",
    [({"source": 42}, "source"), ({"source": {"asked_goal": np.zeros(3)}}, "source"), ({"windows": 0}, "windows"), ({"windows": 2.0}, "windows"), ({"dims": (0, 0)}, "dims"), ({"dims": (0, 2)}, "dims")],
)
def test_bad_input_names_the_parameter(kw, param):
    kw = dict(kw)
    source = kw.pop("source", None)
    if source is None:
        source = _taught("random", n=20)
    with pytest.raises(ParameterError, match=rf"The '{param}' parameter of plot_teacher must be") as e:
        plot_teacher(source, **kw)
    assert e.value.param == param


def test_each_kind_of_draw_has_one_colour_in_every_panel():
    t = _taught("goal_gan", n=600)
    fig = plot_teacher(t, windows=3)
    colours: dict[str, set] = {}
    for ax in fig.axes:
        for c in ax.collections:
            if c.get_label() != "intermediate difficulty":
                colours.setdefault(c.get_label(), set()).add(tuple(np.round(c.get_facecolor()[0][:3], 3)))
    assert len(colours) >= 2 and all(len(v) == 1 for v in colours.values()), colours
    assert len({next(iter(v)) for v in colours.values()}) == len(colours)
    assert "intermediate difficulty" in [t.get_text() for t in fig.axes[-1].get_legend().get_texts()]


@pytest.mark.parametrize("kind", ["sagg_riac", "adr", "spdl", "goal_gan"])
def test_a_1d_teacher_gets_histograms_and_a_3d_one_the_plane_asked_for(kind):
    one = example_teacher(kind, seed=0, dim=1)
    for _ in range(200):
        one.update(one.sample(), 1.0)
    fig = plot_teacher(one, windows=2)
    assert all(ax.get_xlabel() == "goal" and len(ax.patches) == 40 for ax in fig.axes)
    three = example_teacher(kind, seed=0, dim=3)
    for _ in range(200):
        three.update(three.sample(), 1.0)
    fig = plot_teacher(three, windows=2, dims=(2, 0))
    goals = three.history()["asked_goal"]
    assert fig.axes[0].get_xlabel() == "goal[2]" and fig.axes[0].get_ylabel() == "goal[0]"
    shown = np.vstack([c.get_offsets() for c in fig.axes[0].collections if c.get_label() != "intermediate difficulty"])
    assert np.allclose(np.sort(shown[:, 0]), np.sort(goals[:100, 2]))
