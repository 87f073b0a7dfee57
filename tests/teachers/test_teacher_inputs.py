"""Teachers check what they are given and what they replace: saving replaces only a teacher
file, sizes have stated bounds, strings, bools and extreme values are refused or kept finite. From the third newcomer audit (issue 27)."""

from __future__ import annotations

import functools
import os
from pathlib import Path

import numpy as np
import pytest

import saggriac
from saggriac import Config
from saggriac.errors import InputError, ParameterError, SaggriacError, StorageError
from tests.special_files import snapshot, special_files


TEACHERS = {kind: functools.partial(saggriac.testing.example_teacher, kind, 1) for kind in saggriac.teachers.available() if kind != "random"}





@pytest.mark.parametrize("kind", sorted(TEACHERS))
def test_teacher_save_replaces_only_its_own_files(tmp_path, kind):
    t = TEACHERS[kind]()
    specials = special_files(tmp_path)
    if os.path.exists(os.devnull):
        specials["devnull"] = Path(os.devnull)
    for name, path in specials.items():
        before = snapshot(path)
        with pytest.raises(StorageError):
            t.save(path, overwrite=True)
        assert snapshot(path) == before, name
    # Its own file is replaced, and only with overwrite=True (a real bool).
    own = t.save(tmp_path / "t.bin")
    with pytest.raises(StorageError, match="exists"):
        t.save(own)
    for bad in ("no", 1, None, "False"):
        with pytest.raises(ParameterError, match="overwrite"):
            t.save(own, overwrite=bad)
    t.save(own, overwrite=True)
    assert type(saggriac.load_selector(own)) is type(t)
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []


HUGE = [2**40, 2**62, 10**12]


@pytest.mark.parametrize(
    "make",
    [
        *(lambda v=v: saggriac.SaggRiacSelector([0.0], [1.0], zeta=v) for v in HUGE),
        *(lambda v=v: saggriac.SaggRiacSelector([0.0], [1.0], g_max=v) for v in HUGE),
        *(lambda v=v: saggriac.RiacSelector([0.0], [1.0], split_attempts=v) for v in HUGE),
        *(lambda v=v: saggriac.RiacSelector([0.0], [1.0], max_region_size=v) for v in HUGE),
        *(lambda v=v: saggriac.AlpGmmSelector([0.0], [1.0], fit_rate=v) for v in HUGE),
        *(lambda v=v: saggriac.AlpGmmSelector([0.0], [1.0], max_components=v) for v in (101, *HUGE)),
        *(lambda v=v: saggriac.CovarGmmSelector([0.0], [1.0], bootstrap=v) for v in HUGE),
        *(lambda v=v: saggriac.DiscreteLpSelector(v) for v in (2**31, *HUGE)),
        *(lambda v=v: saggriac.PlrSelector(v) for v in (2**31, *HUGE)),
        *(lambda v=v: saggriac.AdrSelector([0.0], [1.0], buffer_size=v) for v in HUGE),
        *(lambda v=v: Config(zeta=v) for v in HUGE),
        *(lambda v=v: Config(g_max=v) for v in HUGE),
    ],
)
def test_sizes_have_stated_bounds(make):
    with pytest.raises(ParameterError, match=r"must be an int in \[\d+, (\d+\]|2\*\*\d+\))"):
        make()


@pytest.mark.parametrize("n", [10**8, 2**40, 2**62])
def test_sample_batch_is_bounded(n):
    t = saggriac.SaggRiacSelector([0.0, 0.0], [1.0, 1.0])
    with pytest.raises(SaggriacError, match="n"):
        t.sample_batch(n)
    assert t.sample_batch(3).shape == (3, 2)


@pytest.mark.parametrize("kind", ["alp_gmm", "covar_gmm", "riac", "sagg_riac", "adr"])
@pytest.mark.parametrize("scale", [1e150, 1e300, -1e300])
def test_extreme_competences_are_refused_or_kept_finite(kind, scale):
    t = TEACHERS[kind]()
    rng = np.random.default_rng(0)
    for i in range(600):
        g = t.sample()
        try:
            t.update(g, scale * rng.uniform(-1, 1))
        except InputError as e:
            assert "1e100" in str(e)
            t.update(g, rng.uniform(-1, 0))
    assert np.all(np.isfinite(t.sample_batch(50)))





@pytest.mark.parametrize("kind", sorted(set(TEACHERS) - {"discrete_lp", "plr"}))
@pytest.mark.parametrize("goal, competence", [([0.5, 0.5], "0.5"), ([0.5, 0.5], True), (["0.5", "0.5"], -0.5), ([True, False], -0.5), ([0.5, 0.5], [-0.5, -0.5]), ([0.5, 0.5], None)])
def test_teachers_refuse_strings_and_bools(kind, goal, competence):
    t = TEACHERS[kind]()
    with pytest.raises(InputError):
        t.update(goal, competence)
    assert len(t.history()["told_competence"]) == 0


@pytest.mark.parametrize("low, high", [(["0", "0"], [1, 1]), ([False, False], [True, True]), ([0, 0], "11")])
def test_bounds_refuse_strings_and_bools(low, high):
    with pytest.raises(InputError):
        saggriac.SaggRiacSelector(low, high)
