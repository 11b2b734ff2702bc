"""A string is not a sequence of values to sweep (issue 17; found by scripts/hostile_inputs.py:
the function was called on each character, TypeError: bad operand type for abs())."""
import pytest

import contact_sim as cs
from contact_sim.drop import sweep


@pytest.mark.parametrize('values', ['abc', b'abc'])
def test_sweep_refuses_text_as_values(values):
    with pytest.raises(cs.InputError, match='^values = .* is not a sequence'):
        sweep(abs, values, max_workers=1)
