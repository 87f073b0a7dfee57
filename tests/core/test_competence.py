"""saggriac.competence (Eq. 7) refuses positions that mean nothing. From the third newcomer audit (issue 27)."""

from __future__ import annotations

import numpy as np
import pytest

import saggriac
from saggriac.errors import InputError


@pytest.mark.parametrize("bad", [[np.nan, 0.0], ["1", "2"], [True, False]])
def test_competence_refuses_nonsense_positions(bad):
    with pytest.raises(InputError):
        saggriac.competence(bad, [1.0, 1.0], [0.0, 0.0])
