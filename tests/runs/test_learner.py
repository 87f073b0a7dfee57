"""saggriac.Learner, the public learner that run() wraps (issue 26): the same bits as run(),
stopping at evaluations and going on, its test sets, its result."""

import numpy as np
import pandas as pd
import pytest

import saggriac as sg
from saggriac import _core
from saggriac.errors import ParameterError
from saggriac.seeding import derive_seeds


def small(**kw):
    return sg.Config.from_preset("exp1", **{"n_steps": 3000, "n_evals": 6, "n_test_goals": 10, "n_test_configs": 10, **kw})


@pytest.mark.parametrize("condition", ["sagg_riac", "actuator_riac"])
def test_a_learner_run_in_pieces_gives_the_run(condition, tmp_path):
    cfg = small(condition=condition)
    ref = sg.run(cfg, seed=5)
    learner = sg.Learner(cfg, seed=5, threads=1)
    assert not learner.run(until=1200)
    # In one thread it stops after the evaluation at step 1500, at the end of that goal attempt.
    assert 1500 <= learner.steps < 2000
    assert learner.result().metrics["step"].tolist() == [0, 500, 1000, 1500]
    assert learner.run() and learner.done
    got = learner.result()
    for name in ("metrics", "goals", "attempts", "regions"):
        pd.testing.assert_frame_equal(getattr(got, name), getattr(ref, name), check_exact=True)
    saved = got.save(tmp_path / "r")
    assert sg.RunResult.load(saved).final_reach_error == ref.final_reach_error
    # With evaluations beside learning (two threads) it stops a little later, with the same bits.
    learner = sg.Learner(cfg, seed=5, threads=2)
    learner.run(until=1200)
    assert learner.steps >= 1500
    learner.run()
    pd.testing.assert_frame_equal(learner.result().metrics, ref.metrics, check_exact=True)


def test_the_test_sets_are_those_of_the_seed():
    cfg = small()
    goals = sg.Learner(cfg, seed=2).test_set()["goals"]
    np.testing.assert_array_equal(goals, _core.Learner(cfg.core_dict(), *derive_seeds(2)).test_set()["goals"])
    assert not np.array_equal(goals, sg.Learner(cfg, seed=3).test_set()["goals"])
    assert sg.Learner(cfg, seed=2).seeds == derive_seeds(2)


@pytest.mark.parametrize("until", [-1, 2.5, True, "10"])
def test_bad_until_is_refused(until):
    with pytest.raises(ParameterError, match="'until' parameter of Learner.run"):
        sg.Learner(small(), 0).run(until=until)


def test_bad_config_is_refused():
    with pytest.raises(ParameterError, match="'config' parameter of Learner"):
        sg.Learner({"n_steps": 10})
    assert "steps=0 of 3000" in repr(sg.Learner(small(), 1))


def test_a_saved_checkpoint_resumes_to_the_run(tmp_path):
    cfg = small()
    ref = sg.run(cfg, seed=4)
    learner = sg.Learner(cfg, seed=4, threads=1)
    learner.run(until=1200)
    out = tmp_path / "run"
    ck = learner.save_checkpoint(out, checkpoint_every=1000)
    assert ck == sg.runs.checkpoint_dir(out) and sorted(p.name for p in ck.iterdir()) == ["checkpoint.json", "state.bin"]
    got = sg.resume(out)
    assert got.manifest["resumed_at_step"] == learner.steps and not ck.exists()
    for name in ("metrics", "goals", "attempts", "regions"):
        pd.testing.assert_frame_equal(getattr(got, name), getattr(ref, name), check_exact=True)


@pytest.mark.parametrize("every", [0, 1.5, True, None])
def test_bad_checkpoint_arguments_are_refused(every, tmp_path):
    with pytest.raises(ParameterError, match="'checkpoint_every' parameter of Learner.save_checkpoint"):
        sg.Learner(small(), 0).save_checkpoint(tmp_path / "r", every)
    with pytest.raises(ParameterError, match="not available with a user's environment"):
        sg.Learner(small(), 0, environment=sg.bodies.environments.PlanarArm()).save_checkpoint(tmp_path / "r", 1000)
    assert not any(tmp_path.iterdir())


def test_numpy_integers_stop_where_the_ints_they_stand_for_stop(tmp_path):
    """Learner.run(until=np.int64(1000)) ran the whole budget: the core read the numpy bool its
    stop test gave as "go on" (issue 33, item 2)."""
    cfg = small()
    plain, by_numpy = sg.Learner(cfg, 0, threads=1), sg.Learner(cfg, 0, threads=1)
    expected, stops = [], []
    for t in range(600, 3001, 600):
        plain.run(until=t)
        expected.append(plain.steps)
    for t in np.arange(600, 3001, 600):
        by_numpy.run(until=t)
        stops.append(by_numpy.steps)
    assert stops == expected and stops[0] < 1500 and stops[-1] == 3000
    pd.testing.assert_frame_equal(by_numpy.result().metrics, plain.result().metrics, check_exact=True)
    one = sg.Learner(cfg, 0, threads=1)
    one.run(until=1000)
    assert one.steps < 3000
    for kind in (np.int32, np.uint16, np.int64, np.uint64):
        other = sg.Learner(cfg, 0, threads=1)
        assert not other.run(until=kind(1000))
        assert other.steps == one.steps


def test_numpy_integers_for_checkpoints_seeds_and_threads(tmp_path):
    """run(checkpoint_every=np.int64(1000)) stopped at its first checkpoint with a TypeError
    (a numpy int does not go into checkpoint.json), losing the work done."""
    cfg = small()
    ref = sg.run(cfg, seed=3)
    got = sg.run(cfg, seed=np.uint32(3), out_dir=tmp_path / "r", checkpoint_every=np.int64(1000), threads=np.int8(1))
    pd.testing.assert_frame_equal(got.metrics, ref.metrics, check_exact=True)
    learner = sg.Learner(cfg, np.int16(3), threads=np.int64(1))
    learner.run(until=np.uint64(1000))
    learner.save_checkpoint(tmp_path / "c", np.int32(1000))
    pd.testing.assert_frame_equal(sg.resume(tmp_path / "c", threads=np.int64(1)).metrics, ref.metrics, check_exact=True)


@pytest.mark.parametrize("until", [np.float64(1000.0), np.bool_(True), np.int64(-1)])
def test_numpy_values_that_are_no_time_step_are_refused(until):
    with pytest.raises(ParameterError, match="'until' parameter of Learner.run must be an int >= 0"):
        sg.Learner(small(), 0).run(until=until)
