"""The seed tree of saggriac.seeding is the one the code uses (issue 26, item 2)."""

from pathlib import Path

import numpy as np

import saggriac as sg
import saggriac.bodies.scale
from saggriac import _core
from saggriac.seeding import FIXED, derive_seeds, environment_seed, seed_tree, selector_seed

CORE = Path(__file__).resolve().parents[2] / "crates" / "saggriac-core" / "src"


def test_the_tree_holds_the_seeds_the_run_uses():
    t = seed_tree(7)
    assert (t["learner"], t["evaluation"]) == derive_seeds(7) == sg.Learner(sg.Config(n_steps=10), 7).seeds
    assert t["environment"] == environment_seed(7) and t["selector"] == selector_seed(7)
    assert len(set(t.values()) - {7}) == 6  # six distinct streams


def test_the_selector_stream_chooses_the_runs_goals():
    cfg = sg.Config.from_preset("exp1", n_steps=12000, n_evals=1, n_test_goals=5, n_test_configs=5)
    own = sg.run(cfg, seed=4)
    mine = sg.SaggRiacSelector(cfg.goal_low, cfg.goal_high, seed=seed_tree(4)["selector"])
    given = sg.run(cfg, seed=4, goal_selector=mine)
    cols = ["goal_x", "goal_y", "competence"]
    assert len(own.goals) >= 30
    np.testing.assert_array_equal(given.goals[cols].to_numpy(), own.goals[cols].to_numpy())


def test_the_fixed_streams_are_the_ones_in_the_code():
    core = "".join(p.read_text() for p in CORE.rglob("*.rs"))
    for name in ("min_norm_ik_restarts", "actuator_reset_cloud"):
        literal = f"0x{FIXED[name]:x}"
        assert f"{literal[:6]}_{literal[6:]}" in core, name
    assert sg.bodies.scale.CLOUD_SEED == FIXED["body_measure"]
    assert _core.child_seed(seed_tree(1)["learner"], 2) == seed_tree(1)["learning"]
