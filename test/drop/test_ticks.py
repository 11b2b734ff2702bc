"""``DropSimulation.advance_ticks`` (many tick times in one call, arrays out) against the slow
path: ``advance`` called at each tick time in turn, reading ``state`` after each."""
import math

import numpy as np
import pytest

from contact_sim import AZAD_FEATHERSTONE, LINEAR, AirDrag, Contact, DropSimulation, TickBatch
from contact_sim.drop.plate import CommandedPlate, SinusoidalPlate

MASS = 0.066
STEEL = Contact(AZAD_FEATHERSTONE, 1e10, 1e5)
LOSSY = Contact(AZAD_FEATHERSTONE, 1e10, 2e6)
FIELDS = ('time', 'penetration', 'penetration_rate', 'force', 'plate_position', 'plate_velocity')


def tick_by_tick(make, times):
    """Tick ends (rows of FIELDS), contact points (t, z, ż, F) with their tick, impacts."""
    sim = make()
    ends, points, impacts = [], [], []
    for i, t in enumerate(times):
        advance = sim.advance(float(t))
        s = advance.samples
        points += [(i, *row) for row in zip(s.time[:-1], s.penetration[:-1],
                                             s.penetration_rate[:-1], s.force[:-1])]
        impacts += [(i, r) for r in advance.impacts]
        state = sim.state
        ends.append([getattr(state, f) for f in FIELDS])
    return sim, np.array(ends), points, impacts


def batched(make, times, chunks, max_steps=None):
    """The same through advance_ticks, in calls of the given chunk sizes (cycled)."""
    sim = make()
    ends, points, impacts = [], [], []
    i, k = 0, 0
    while i < len(times):
        chunk = times[i:i + chunks[k % len(chunks)]]
        k += 1
        batch = sim.advance_ticks(chunk, max_steps=max_steps)
        assert isinstance(batch, TickBatch)
        ends += np.column_stack([getattr(batch, f) for f in FIELDS]).tolist()
        p = batch.points
        points += [(i + int(j), *row) for j, *row in zip(batch.point_tick, p.time, p.penetration,
                                                          p.penetration_rate, p.force)]
        impacts += [(i + int(j), r) for j, r in zip(batch.impact_tick, batch.impacts)]
        i += batch.ticks
    return sim, np.array(ends), points, impacts


def assert_same(slow, fast):
    sim0, ends0, points0, impacts0 = slow
    sim1, ends1, points1, impacts1 = fast
    assert ends1.shape == ends0.shape
    np.testing.assert_array_equal(ends1[:, 0], ends0[:, 0])          # the tick times
    # the same states to round-off (the closed forms evaluated over arrays)
    scale = np.max(np.abs(ends0), axis=0) + 1e-300
    assert np.all(np.abs(ends1 - ends0) <= 1e-13 * scale), np.max(np.abs(ends1 - ends0) / scale,
                                                                   axis=0)
    assert points1 == points0                                        # the same points, exactly
    assert impacts1 == impacts0
    assert sim1.impacts == sim0.impacts and sim1.apex_heights == sim0.apex_heights
    assert sim1.settle_time == sim0.settle_time
    assert sim1.permanent_contact_time == sim0.permanent_contact_time


@pytest.mark.parametrize('chunks', [(1,), (7, 300, 1, 64), (10_000,)], ids=['1', 'mixed', 'all'])
def test_a_whole_drop_bouncing_to_rest(chunks):
    make = lambda: DropSimulation(STEEL, MASS, 0.1)    # noqa: E731
    times = 0.01 * np.arange(1, 501)                   # 5 s at 100 Hz: bounces, settles, rests
    slow = tick_by_tick(make, times)
    assert slow[0].settle_time is not None and len(slow[0].impacts) > 10
    assert_same(slow, batched(make, times, chunks))


def test_with_air_drag():
    drag = AirDrag(radius=0.02, air_density=1.2)
    make = lambda: DropSimulation(STEEL, 0.0027, 0.3, drag=drag)   # noqa: E731
    times = 0.004 * np.arange(1, 501)
    slow = tick_by_tick(make, times)
    assert len(slow[0].impacts) > 2 and slow[0].apex_heights
    assert_same(slow, batched(make, times, (5, 50, 1000)))


@pytest.mark.parametrize('plate', [
    SinusoidalPlate(0.002, 20.0, 0.5),                                     # bouncing
    SinusoidalPlate(0.0005, 15.0),                                        # carried
    CommandedPlate([0.0, 0.5, 0.7, 0.9], [0.0, 0.0, 0.1, -0.1], [0.0, 0.0, 1.0, -3.0]),
], ids=['vibrating', 'carried', 'commanded'])
def test_with_a_moving_plate(plate):
    contact = Contact(LINEAR, 1e6, 400.0) if isinstance(plate, SinusoidalPlate) and \
        plate.amplitude < 0.001 else LOSSY
    make = lambda: DropSimulation(contact, MASS, 0.005, plate=plate)   # noqa: E731
    times = 0.002 * np.arange(1, 601)
    slow = tick_by_tick(make, times)
    assert np.any(slow[1][:, 4] != 0.0)            # the plate moves
    assert slow[0].carried == (contact.law.name == 'linear')   # (the carried case ends carried)
    assert_same(slow, batched(make, times, (3, 100, 1000)))


def test_a_step_budget_stops_at_a_tick_that_needs_integration_and_resumes():
    make = lambda: DropSimulation(STEEL, MASS, 0.1)    # noqa: E731
    times = 0.01 * np.arange(1, 301)
    sim0, ends0, points0, impacts0 = tick_by_tick(make, times)
    sim1, ends1, points1, impacts1 = batched(make, times, (300,), max_steps=20)
    np.testing.assert_array_equal(ends1[:, 0], ends0[:, 0])
    assert np.allclose(ends1, ends0, rtol=1e-13, atol=0.0)
    assert [r for _, r in impacts1] == [r for _, r in impacts0]
    # a call stopped inside a tick returns the state reached as a point, the last integrator
    # point again: without those repeats, the same points
    unique = [p for k, p in enumerate(points1) if k == 0 or p[1:] != points1[k - 1][1:]]
    assert [p[1:] for p in unique] == [p[1:] for p in points0]
    assert sim1.settle_time == sim0.settle_time


def test_budget_and_arguments():
    sim = DropSimulation(STEEL, MASS, 0.1)
    sim.advance(0.14)                           # the first contact is at t = 0.1428 s
    batch = sim.advance_ticks([0.15, 0.16], max_steps=3)
    assert batch.ticks == 0 and sim.time < 0.15 and batch.point_tick.tolist() == [0] * len(
        batch.points.time)
    assert batch.time.size == 0 and batch.points.time[-1] == sim.time
    with pytest.raises(ValueError, match='times'):
        sim.advance_ticks([0.1])
    with pytest.raises(ValueError, match='times'):
        sim.advance_ticks([0.2, 0.19])
    with pytest.raises(ValueError, match='times'):
        sim.advance_ticks([math.nan])
    empty = sim.advance_ticks([])
    assert empty.ticks == 0 and empty.points.time.size == 0
