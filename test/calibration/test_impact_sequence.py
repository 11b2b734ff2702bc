"""The impacts among detected clicks (calibration.impact_sequence): each rule on click lists made
here, with their loudness, so that every rejection and its reason can be checked."""
import numpy as np
import pytest

from contact_sim.calibration.impact_sequence import KINDS, isolation, select_impacts, summary


def bounces(e=0.9, first=0.5, count=25, start=1.0):
    flights = first * e ** np.arange(count - 1)
    times = start + np.concatenate([[0.0], np.cumsum(flights)])
    return times, 1.0 * e ** np.arange(count)          # loudness follows the impact speed


def select(clicks):
    clicks = sorted(clicks)
    t = np.array([c[0] for c in clicks])
    s = np.array([c[1] for c in clicks])
    kept, rejected = select_impacts(t, s)
    return t[kept], {round(r.time, 6): r for r in rejected}


def test_isolation_is_the_time_to_the_nearest_louder_click():
    iso, near = isolation(np.array([0.0, 0.1, 0.15, 0.5]), np.array([1.0, 0.5, 0.7, 0.2]))
    assert iso.tolist() == pytest.approx([np.inf, 0.05, 0.15, 0.35])
    assert near.tolist() == [-1, 2, 0, 2]


def test_echoes_ringing_and_precursors_are_rejected_with_their_reason():
    t, s = bounces()
    clicks = list(zip(t, s))
    clicks += [(x + 0.007, 0.8 * y) for x, y in zip(t, s)]            # an echo at 7 ms
    clicks += [(x + 0.003 * k, 0.1 * y / k) for x, y in zip(t, s) for k in range(2, 6)]  # ring
    clicks += [(x - 0.002, 0.01 * y) for x, y in zip(t, s)]            # a precursor
    kept, rejected = select(clicks)
    assert kept.tolist() == pytest.approx(t.tolist())
    echo = rejected[round(t[3] + 0.007, 6)]
    assert echo.kind == 'echo or ringing' and f'{t[3]:.4f} s' in echo.reason
    assert rejected[round(t[3] - 0.002, 6)].kind == 'precursor'
    assert rejected[round(t[3] + 0.009, 6)].kind == 'echo or ringing'
    assert len(rejected) == len(clicks) - t.size


def test_an_echo_as_loud_as_the_late_impacts_is_told_by_its_fixed_lag():
    # late in the sequence the flights (down to 17 ms) come near twice the echo lag (7 ms):
    # there only the lag, the same after every impact, tells the echo
    t, s = bounces(e=0.93, first=0.3, count=42)
    assert np.diff(t)[-1] < 0.018
    clicks = list(zip(t, s)) + [(x + 0.007, 0.95 * y) for x, y in zip(t, s)]
    kept, rejected = select(clicks)
    assert kept.tolist() == pytest.approx(t.tolist())
    assert all(r.kind == 'echo or ringing' for r in rejected.values())
    assert "echo lag of the recording (7.0 ms" in rejected[round(t[-2] + 0.007, 6)].reason


def test_spurious_clicks_before_after_and_between_the_impacts():
    t, s = bounces()
    before, after = t[0] - 1.7, t[-1] + 0.6
    between = 0.5 * (t[6] + t[7])
    clicks = list(zip(t, s)) + [(before, 0.02), (after, 0.5), (between, 0.9 * s[6])]
    kept, rejected = select(clicks)
    assert kept.tolist() == pytest.approx(t.tolist())
    assert rejected[round(before, 6)].kind == 'before the sequence'
    assert rejected[round(after, 6)].kind == 'after the sequence'
    assert rejected[round(between, 6)].kind in ('off the sequence', 'precursor',
                                                'echo or ringing')


def test_a_missed_bounce_is_bridged_and_a_steady_sequence_kept_whole():
    t, s = bounces(e=0.98, first=0.2, count=80)       # a long sequence of high restitution
    kept, rejected = select(list(zip(t, s)))
    assert kept.size == t.size and not rejected
    heard = np.delete(np.arange(t.size), 30)           # one quiet bounce not heard
    kept, rejected = select(list(zip(t[heard], s[heard])))
    assert kept.tolist() == pytest.approx(t[heard].tolist()) and not rejected


def test_the_summary_counts_each_kind():
    t, s = bounces()
    clicks = list(zip(t, s)) + [(x + 0.007, 0.8 * y) for x, y in zip(t, s)] + [(0.1, 0.01)]
    kept, rejected = select(clicks)
    line = summary(len(clicks), kept.size, list(rejected.values()))
    assert line == (f'{len(clicks)} onset(s) found, {t.size} kept as impacts, {t.size + 1} '
                    f'rejected ({t.size} echo or ringing, 1 before the sequence)')
    assert set(KINDS) >= {r.kind for r in rejected.values()}


def test_the_work_is_bounded_on_clicks_that_all_sound_alike():
    # every click as loud as the others: no isolation tells them apart, and every click could
    # follow any other; the chain still visits each click's 32 nearest only (a regular train
    # of equal clicks is a sequence of restitution 1)
    t = np.arange(3000) * 0.01
    kept, rejected = select_impacts(t, np.ones(t.size))
    assert kept.size == t.size and not rejected


def test_bad_click_lists_are_refused_by_name():
    import contact_sim as cs
    with pytest.raises(cs.InputError, match=r'times\[1\] = nan is not finite'):
        select_impacts([0.0, np.nan, 1.0], [1.0, 1.0, 1.0])
    with pytest.raises(cs.InputError, match='hold 3 and 2 values: allowed as many, times '
                                            'increasing'):
        select_impacts([0.0, 0.5, 1.0], [1.0, 1.0])
    with pytest.raises(cs.InputError, match='allowed as many, times increasing'):
        select_impacts([0.0, 1.0, 0.5], [1.0, 1.0, 1.0])
    with pytest.raises(cs.InputError, match='share = 0.0 is out of range'):
        select_impacts([0.0, 0.5, 1.0], [1.0, 1.0, 1.0], share=0.0)
