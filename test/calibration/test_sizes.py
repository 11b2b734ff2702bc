"""Bounded sizes in calibration (issue 17): each refused with its limit, before the work.
Found: ``bounces`` with 10 million times killed at 120 s (3.1 GB), ``fit_damping`` with 1e6
points > 120 s."""
import numpy as np
import pytest

import contact_sim as cs
from contact_sim.calibration import ImpactTimes, fit_bounces, parse_impact_times
from contact_sim.calibration import recordings
from contact_sim.validation import InputError


def test_ten_million_times_are_refused_with_the_limit():
    times = np.cumsum(np.full(10_000_000, 1e-3))
    with pytest.raises(InputError, match='times has 10000000 values: allowed at most '
                                         '5000') as info:
        fit_bounces(2e8, 0.046, [times])
    assert info.value.field == 'times'


def test_sequences_too_many_in_all_are_refused():
    one = ImpactTimes(0.3 + np.cumsum(0.4 * 0.9 ** np.arange(30)), 0.8)
    with pytest.raises(InputError, match=r'sequences hold 6000 impact times in all: allowed at '
                                         r'most 5000 in one fit'):
        fit_bounces(2e8, 0.046, [one] * 200)
    with pytest.raises(InputError, match='sequences holds 201 sequences: allowed at most 200'):
        fit_bounces(2e8, 0.046, [one] * 201)


def test_a_csv_of_too_many_lines_or_bytes_is_refused(tmp_path):
    text = 'time\n' + '\n'.join(str(0.001 * i) for i in range(1, 100_001))
    with pytest.raises(InputError, match='data = .* has 100001 lines: allowed at most 100000'):
        parse_impact_times(text, source='big.csv')
    path = tmp_path / 'huge.csv'
    with open(path, 'wb') as f:
        f.truncate(recordings.MAX_BYTES + 1)
    with pytest.raises(InputError, match='holds 67108865 bytes: allowed at most 67108864'):
        recordings.read_impact_times(path)


def test_fit_damping_with_a_million_points_is_refused_at_once():
    v = np.linspace(0.5, 3.0, 1_000_000)
    with pytest.raises(InputError, match='speeds has 1000000 values: allowed at most 2000'):
        cs.fit_damping(cs.HUNT_CROSSLEY, 2e8, 0.046, v, np.full(v.size, 0.8))
