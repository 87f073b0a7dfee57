"""What a teacher does, seen while it teaches (issue 46, item 4): TeacherCallback writes each
teacher's readings and the figure of its goals through SB3's own logger, read back from the
TensorBoard event files and the CSV. Skipped when SB3 or TensorBoard is not installed, unless
SAGGRIAC_REQUIRE_EXTRAS=1 (CI sets it)."""

import os

import numpy as np
import pytest

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("stable_baselines3", reason='the SB3 extra is not installed (pip install "saggriac[sb3]")')
    pytest.importorskip("tensorboard", reason='the SB3 extra is not installed (pip install "saggriac[sb3]")')

import gymnasium
import pandas as pd
from stable_baselines3 import PPO
from stable_baselines3.common.callbacks import CheckpointCallback
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.logger import configure
from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

import saggriac as sg
from saggriac.adapters.sb3 import TeacherCallback, teacher_path

ENV = "saggriac.adapters.gym:saggriac/PlanarArm-v0"
LOW, HIGH = [0.0, -50.0], [50.0, 50.0]


def _train(teacher, folder, steps=640, formats=("csv", "tensorboard"), model=None, **kw):
    venv = make_vec_env(lambda: gymnasium.make(ENV, max_episode_steps=20), n_envs=2, seed=0)
    if model is None:
        model = PPO("MultiInputPolicy", venv, n_steps=64, batch_size=64, n_epochs=1, seed=0, device="cpu")
    else:
        model.set_env(venv)
    model.set_logger(configure(str(folder), list(formats)))
    cb = TeacherCallback(teacher, competence="distance", **kw.pop("cb", {}))
    model.learn(total_timesteps=steps, callback=[*kw.pop("callbacks", []), cb], reset_num_timesteps=kw.pop("reset", True))
    model.logger.close()
    venv.close()
    return model, cb


def _events(folder):
    ea = EventAccumulator(str(folder), size_guidance={"scalars": 0, "images": 0, "histograms": 0})
    ea.Reload()
    return ea


def _last(ea, tag):
    return ea.Scalars(tag)[-1].value


@pytest.fixture(scope="module")
def adr_run(tmp_path_factory):
    """ADR behind PPO whose thresholds any distance passes, so its ranges grow; a figure every
    2 rollouts."""
    folder = tmp_path_factory.mktemp("adr")
    teacher = sg.AdrSelector(LOW, HIGH, seed=0, buffer_size=2, t_low=-2e6, t_high=-1e6)
    _train(teacher, folder, cb={"figure_every": 2})
    return teacher, folder


def test_adr_logs_its_ranges_per_dimension_and_no_uniform_share(adr_run):
    teacher, folder = adr_run
    ea = _events(folder)
    tags = set(ea.Tags()["scalars"])
    lo, hi = teacher.bounds
    for i in range(2):
        assert _last(ea, f"teacher/low_{i}") == pytest.approx(lo[i], abs=1e-4)
        assert _last(ea, f"teacher/high_{i}") == pytest.approx(hi[i], abs=1e-4)
    # The ranges grew from the centre (25, 0) while PPO trained: the log shows it happen.
    assert ea.Scalars("teacher/high_0")[0].value == pytest.approx(25.0) and _last(ea, "teacher/high_0") > 25.0
    # ecosystem-review-5 N5: ADR's draws inside its ranges are not uniform in the box.
    assert "teacher/uniform_share" not in tags and "teacher/regions" not in tags
    shares = [e.value for e in ea.Scalars("teacher/boundary_share")]
    assert all(0.0 <= s <= 1.0 for s in shares) and 0.2 < np.mean(shares) < 0.8  # boundary_prob 0.5
    width = (hi - lo) / (np.array(HIGH) - np.array(LOW))
    assert _last(ea, "teacher/range_share") == pytest.approx(width.mean(), abs=1e-4)
    log = pd.read_csv(folder / "progress.csv")
    assert log["teacher/told"].iloc[-1] == len(teacher.history()["told_goal"]) == 30
    assert log["teacher/low_0"].iloc[-1] == pytest.approx(lo[0])


def test_the_figure_of_the_goals_reaches_tensorboard_every_n_rollouts(adr_run):
    _, folder = adr_run
    ea = _events(folder)
    assert ea.Tags()["images"] == ["teacher/goals"]
    images = ea.Images("teacher/goals")
    # 640 steps of 2 environments x 64: 5 rollouts, a figure after the 2nd and the 4th.
    assert [im.step for im in images] == [256, 512]
    assert all(im.width > 300 and im.height > 200 and im.encoded_image_string.startswith(b"\x89PNG") for im in images)
    assert "teacher/goals" not in pd.read_csv(folder / "progress.csv").columns


def test_adr_that_never_moves_logs_one_point_not_a_uniform_share(tmp_path):
    """The review's case: mean competences between t_low and t_high, so every goal is the centre."""
    teacher = sg.AdrSelector(LOW, HIGH, seed=0, boundary_prob=0.0, t_low=-2e6, t_high=-1e6)
    _train(teacher, tmp_path, steps=256, formats=("csv",))
    assert len(np.unique(teacher.history()["asked_goal"], axis=0)) == 1
    log = pd.read_csv(tmp_path / "progress.csv").iloc[-1]
    assert (log["teacher/low_0"], log["teacher/high_0"], log["teacher/low_1"], log["teacher/high_1"]) == (25.0, 25.0, 0.0, 0.0)
    assert log["teacher/range_share"] == 0.0 and log["teacher/boundary_share"] == 0.0
    assert "teacher/uniform_share" not in log.index


def test_spdl_logs_its_mean_spread_kl_and_expected_competence(tmp_path):
    teacher = sg.SpdlSelector(LOW, HIGH, seed=0, update_every=8, warmup=8, delta=0.0)
    # Competences in [0, 1]: a goal near the centre of the box succeeds more.
    cb = {"competence": lambda info: float(np.exp(-info["distance"] / 20.0))}
    venv = make_vec_env(lambda: gymnasium.make(ENV, max_episode_steps=20), n_envs=2, seed=0)
    model = PPO("MultiInputPolicy", venv, n_steps=64, batch_size=64, n_epochs=1, seed=0, device="cpu")
    model.set_logger(configure(str(tmp_path), ["tensorboard"]))
    model.learn(total_timesteps=640, callback=TeacherCallback(teacher, **cb))
    model.logger.close()
    ea = _events(tmp_path)
    r = teacher.regions()
    mean, std = (r["low"][0] + r["high"][0]) / 2, (r["high"][0] - r["low"][0]) / 2
    for i in range(2):
        assert _last(ea, f"teacher/mean_{i}") == pytest.approx(mean[i], rel=1e-5)
        assert _last(ea, f"teacher/std_{i}") == pytest.approx(std[i], rel=1e-5)
    kl = [e.value for e in ea.Scalars("teacher/kl_to_target")]
    assert _last(ea, "teacher/kl_to_target") == pytest.approx(r["interest"][0], rel=1e-5)
    assert kl[-1] < kl[0]  # it moved toward the target, and the log shows it
    assert all(0.0 <= e.value <= 1.0 for e in ea.Scalars("teacher/expected_competence"))
    assert "teacher/regions" not in ea.Tags()["scalars"]


def test_a_region_teacher_logs_its_regions_and_their_interests_as_a_histogram(tmp_path):
    teacher = sg.SaggRiacSelector(LOW, HIGH, seed=0, g_max=10)
    _train(teacher, tmp_path, formats=("csv", "tensorboard"))
    ea = _events(tmp_path)
    leaves = teacher.leaves()
    assert _last(ea, "teacher/regions") == len(leaves["interest"]) > 1
    assert _last(ea, "teacher/interest_max") == pytest.approx(leaves["interest"].max(), rel=1e-5)
    hist = ea.Histograms("teacher/interest")[-1].histogram_value
    assert hist.num == len(leaves["interest"]) and hist.max == pytest.approx(leaves["interest"].max(), rel=1e-5)
    assert "teacher/interest" not in pd.read_csv(tmp_path / "progress.csv").columns  # a list: TensorBoard only
    shares = pd.read_csv(tmp_path / "progress.csv")[["teacher/uniform_share", "teacher/interest_share", "teacher/lowest_share"]]
    assert np.allclose(shares.sum(axis=1), 1.0)


def test_the_counters_go_on_after_a_resume(tmp_path):
    """ecosystem-review-5 N6: the counts restarted at 0 after a resume, and the TensorBoard
    curve dropped there."""
    teacher = sg.SaggRiacSelector(LOW, HIGH, seed=0, g_max=10)
    ckpt = CheckpointCallback(save_freq=160, save_path=str(tmp_path / "ckpt"), name_prefix="rl_model")
    _train(teacher, tmp_path / "first", formats=("csv",), callbacks=[ckpt], cb={"save_with": ckpt})
    mid = sg.load_selector(teacher_path(tmp_path / "ckpt" / "rl_model_320_steps.zip"))
    told, asked = len(mid.history()["told_goal"]), len(mid.history()["asked_goal"])
    model = PPO.load(tmp_path / "ckpt" / "rl_model_320_steps.zip", device="cpu")
    _train(mid, tmp_path / "resumed", steps=320, formats=("csv",), model=model, reset=False)
    log = pd.read_csv(tmp_path / "resumed" / "progress.csv")
    assert log["teacher/told"].iloc[0] > told and log["teacher/asked"].iloc[0] > asked
    assert log["teacher/told"].is_monotonic_increasing
    assert log["teacher/told"].iloc[-1] == len(mid.history()["told_goal"])
    first = pd.read_csv(tmp_path / "first" / "progress.csv")
    assert log["teacher/told"].iloc[0] > first["teacher/told"].iloc[1]  # row 1: step 256 < 320


def test_a_teacher_that_is_not_saggriacs_gets_the_callbacks_counts(tmp_path):
    class Centre:
        low, high = np.array(LOW), np.array(HIGH)

        def sample(self):
            return np.array([25.0, 0.0])

        def update(self, goal, competence):
            pass

    _, cb = _train(Centre(), tmp_path, steps=256, formats=("csv",))
    log = pd.read_csv(tmp_path / "progress.csv")
    assert [c for c in log.columns if c.startswith("teacher/")] == sorted(["teacher/asked", "teacher/told", "teacher/competence"], key=list(log.columns).index)
    assert log["teacher/told"].iloc[-1] == len(cb.history) and log["teacher/asked"].iloc[-1] == cb.asked


def test_figure_every_is_refused_for_a_teacher_it_cannot_draw():
    class Mine:
        def sample(self):
            return np.zeros(2)

        def update(self, goal, competence):
            pass

    with pytest.raises(sg.errors.ParameterError, match=r"The 'figure_every' parameter of TeacherCallback draws one of saggriac's teachers .* Got figure_every=2 instead"):
        TeacherCallback(Mine(), figure_every=2)


@pytest.mark.parametrize("bad", [0, -1, 2.0, True, "2"])
def test_figure_every_must_be_a_positive_int(bad):
    with pytest.raises(sg.errors.ParameterError, match=r"The 'figure_every' parameter of TeacherCallback must be an int >= 1 .* Got " + repr(bad).replace(".", r"\.") + " instead"):
        TeacherCallback(sg.RandomSelector(LOW, HIGH), figure_every=bad)


@pytest.mark.parametrize("algo", ["ppo", "sac"])
def test_each_row_of_the_log_covers_the_goals_asked_since_the_row_before(tmp_path, algo):
    """On-policy (a log per rollout) and off-policy (a log every few episodes, rollouts of one
    step): each row's shares are those of the goals asked between its count and the previous
    row's, so no goal is counted twice or lost."""
    from stable_baselines3 import SAC

    from saggriac.teachers import MODES

    teacher = sg.SaggRiacSelector(LOW, HIGH, seed=0, g_max=10)
    venv = make_vec_env(lambda: gymnasium.make(ENV, max_episode_steps=10), n_envs=1, seed=0)
    if algo == "ppo":
        model = PPO("MultiInputPolicy", venv, n_steps=32, batch_size=32, n_epochs=1, seed=0, device="cpu")
    else:
        # No gradient step (learning_starts past the end): the rollouts and logs are what is tested.
        model = SAC("MultiInputPolicy", venv, buffer_size=500, learning_starts=10_000, seed=0, device="cpu")
    model.set_logger(configure(str(tmp_path), ["csv"]))
    model.learn(total_timesteps=320, callback=TeacherCallback(teacher, competence="distance"), log_interval=2)
    model.logger.close()
    log = pd.read_csv(tmp_path / "progress.csv")
    modes = np.array([MODES[int(m)] for m in teacher.history()["asked_mode"]])
    asked = log["teacher/asked"].astype(int).tolist()
    assert len(asked) >= 5 and asked == sorted(asked) and asked[-1] <= len(modes)
    for a, b, share in zip([0, *asked], asked, log["teacher/uniform_share"]):
        assert share == pytest.approx(np.isin(modes[a:b], ["initial", "global"]).mean()), (a, b)


def test_many_per_dimension_readings_stay_off_stdout_but_reach_the_csv(tmp_path, capsys, monkeypatch):
    import saggriac.adapters.sb3 as sb3

    teacher = sg.AdrSelector(LOW, HIGH, seed=0, t_low=-2e6, t_high=-1e6)
    monkeypatch.setattr(sb3, "STDOUT_ITEMS", 3)  # ADR's 4 bounds in 2-D are then too many
    _train(teacher, tmp_path / "few", steps=128, formats=("stdout", "csv"))
    out = capsys.readouterr().out
    assert "boundary_share" in out and "low_0" not in out and "high_1" not in out
    assert {"teacher/low_0", "teacher/high_1"} <= set(pd.read_csv(tmp_path / "few" / "progress.csv").columns)
    monkeypatch.setattr(sb3, "STDOUT_ITEMS", 4)
    _train(sg.AdrSelector(LOW, HIGH, seed=0, t_low=-2e6, t_high=-1e6), tmp_path / "all", steps=128, formats=("stdout",))
    out = capsys.readouterr().out
    assert "low_0" in out and "high_1" in out
