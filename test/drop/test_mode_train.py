"""The compiled bounces (``mode_train.Bouncing``) against the Python modes they string together:
the same drops, stepping, changes from outside and hand-overs, on the fixed plate, vibrating
tables and commanded plates, with the trains switched off as the reference
(``trains_enabled(False)``)."""
import collections
import contextlib
import dataclasses
import doctest
import math
import random

import numpy as np
import pytest

import contact_sim as cs
from contact_sim.drop import mode_train
from contact_sim.drop.engine import DropSimulation
from contact_sim.drop.mode_contact import Contact
from contact_sim.drop.mode_train import Bouncing
from contact_sim.drop.plate import (CommandedPlate, SinusoidalPlate, SwitchedPlate, command_motion,
                                    pieces, table_transition)
from contact_sim.phase import CompiledPhase, lift_off, phase_scales, use_engine
from contact_sim.phase.reference import PhaseIntegrator

M = 0.066
CONTACTS = {
    'azad_featherstone': (cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5), 0.2),
    'hunt_crossley': (cs.Contact(cs.HUNT_CROSSLEY, 1e9, 2e8), 0.3),
    'lee_wang': (cs.Contact(cs.LEE_WANG, 1e9, 1e5), 0.3),
    'linear': (cs.Contact(cs.LINEAR, 1e6, 20.0), 0.3),
}
REL = 1e-9      # the same functions in the same order: equal but for the last bits of a machine


@contextlib.contextmanager
def trains(flag):
    previous = mode_train.trains_enabled(flag)
    try:
        yield
    finally:
        mode_train.trains_enabled(previous)


def both(run):
    """``run()`` with the Python modes (the reference) and with the trains."""
    with trains(False):
        reference = run()
    with trains(True):
        compiled = run()
    return reference, compiled


def assert_close(a, b):
    assert np.allclose(np.asarray(a, dtype=float), np.asarray(b, dtype=float), rtol=REL,
                       atol=0.0, equal_nan=True)


def assert_same_impacts(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert_close(dataclasses.astuple(x), dataclasses.astuple(y))


@pytest.mark.parametrize('law', sorted(CONTACTS))
def test_a_drop_with_trains_is_the_drop_of_the_python_modes(law):
    contact, height = CONTACTS[law]
    ref, new = both(lambda: cs.simulate_drop(contact, M, height, duration=5.0,
                                             sample_rate=2000.0))
    assert len(ref.impacts) > 5
    assert_same_impacts(ref.impacts, new.impacts)
    assert_close(ref.apex_heights, new.apex_heights)
    for name in ('time', 'penetration', 'penetration_rate', 'force'):
        assert_close(getattr(ref.trajectory, name), getattr(new.trajectory, name))
    assert_close([ref.permanent_contact_time, ref.settle_time],       # nan: not reached
                 [new.permanent_contact_time, new.settle_time])


def test_the_drop_runs_as_a_train_until_it_lands():
    contact, height = CONTACTS['azad_featherstone']
    sim = DropSimulation(contact, M, height)
    assert isinstance(sim._mode, Bouncing)
    sim.run_to(1.0)
    assert isinstance(sim._mode, Bouncing) and len(sim.impacts) > 3
    sim.run_to(5.0)
    assert not isinstance(sim._mode, Bouncing)         # landed: the Python modes go on
    assert sim.impacts[-1].contact_duration == math.inf
    with trains(False):
        assert not isinstance(DropSimulation(contact, M, height)._mode, Bouncing)


def stepped(contact, height, seed, kind):
    """A drop advanced in random calls; what each call returned and the state after it."""
    rng = random.Random(seed)
    sim = DropSimulation(contact, M, height)
    out = []
    t = 0.0
    for _ in range(250):
        t = max(t, sim.time) + rng.choice([0.0, 1e-5, 3e-4, 1e-3, 0.01, 0.05])
        if kind == 'advance':
            adv = sim.advance(t, max_steps=rng.choice([None, None, 0, 1, 7, 60]))
            out.append((adv.samples.time, adv.samples.force, [dataclasses.astuple(i) for i in
                                                              adv.impacts], adv.apex_heights))
        else:
            batch = sim.advance_ticks(np.linspace(sim.time, t, 5))
            out.append((batch.penetration, batch.points.time, batch.points.force,
                        batch.point_tick, [dataclasses.astuple(i) for i in batch.impacts]))
        out.append((sim.time, sim.state.penetration, sim.state.penetration_rate,
                    sim.in_contact))
    return out, sim


@pytest.mark.parametrize('kind', ['advance', 'ticks'])
def test_stepping_a_train_gives_the_python_modes_points_impacts_and_states(kind):
    contact, height = CONTACTS['azad_featherstone']
    (ref, ref_sim), (new, new_sim) = both(lambda: stepped(contact, height, 3, kind))
    assert len(ref) == len(new)
    for a, b in zip(ref, new):
        for x, y in zip(a, b):
            if isinstance(x, list) and x and isinstance(x[0], tuple):
                assert len(x) == len(y)
                for u, v in zip(x, y):
                    assert_close(u, v)
            else:
                assert_close(x, y)
    assert len(new_sim.impacts) == len(ref_sim.impacts) > 3
    assert new_sim.total_steps > 0


@pytest.mark.parametrize('when', ['flight', 'contact'])
def test_a_change_from_outside_hands_the_train_over(when):
    contact, height = CONTACTS['azad_featherstone']
    softer = cs.Contact(cs.AZAD_FEATHERSTONE, 5e9, 2e5)
    table = SinusoidalPlate(1e-3, 20.0, 0.0)

    def run():
        sim = DropSimulation(contact, M, height)
        sim.run_to(0.4)
        while sim.in_contact != (when == 'contact'):
            sim.advance(sim.time + 2e-5)
        was_train = isinstance(sim._mode, Bouncing)
        sim.set_contact(softer)
        sim.advance(sim.time + 0.3)
        sim.set_plate(table)
        sim.advance(sim.time + 0.3)
        return was_train, sim

    (ref_train, ref), (new_train, new) = both(run)
    assert new_train and not ref_train
    assert_same_impacts(ref.impacts, new.impacts)
    assert_close(ref.apex_heights, new.apex_heights)
    # (no step counts compared across the two paths: another CPU may round a step differently)
    assert_close([ref.time, ref.state.penetration], [new.time, new.state.penetration])


def test_a_phase_too_stiff_for_the_compiled_integrator_goes_to_the_python_path():
    # zeta far above COMPILED_STIFF_DAMPING: the touch is handed to transitions.impact
    contact = cs.Contact(cs.HUNT_CROSSLEY, 1e9, 1e13)
    assert phase_scales(contact, M, 9.81, 0.0, 1.0).damping > 200.0
    sim = DropSimulation(contact, M, 0.05)
    assert isinstance(sim._mode, Bouncing)
    sim.advance(0.1015)                         # the touch at 0.101 s
    assert isinstance(sim._mode, Contact)
    assert isinstance(sim._mode.integrator, PhaseIntegrator)
    ref, new = both(lambda: cs.simulate_drop(contact, M, 0.05, duration=0.3))
    assert_same_impacts(ref.impacts, new.impacts)


def test_full_buffers_are_emptied_and_grown_without_losing_a_point(monkeypatch):
    monkeypatch.setattr(mode_train, 'POINT_ROWS', 8)
    monkeypatch.setattr(mode_train, 'RECORD_ROWS', 1)
    contact, height = CONTACTS['linear']
    ref, new = both(lambda: cs.simulate_drop(contact, M, height, duration=3.0,
                                             sample_rate=500.0))
    assert_same_impacts(ref.impacts, new.impacts)
    assert_close(ref.apex_heights, new.apex_heights)
    (ref_s, _), (new_s, _) = both(lambda: stepped(contact, height, 8, 'advance'))
    assert len(ref_s) == len(new_s)
    for a, b in zip(ref_s[::2], new_s[::2]):
        assert_close(a[0], b[0])
        assert_close(a[1], b[1])


def test_a_train_hands_over_when_the_default_engine_changes():
    contact, height = CONTACTS['azad_featherstone']

    def run():
        sim = DropSimulation(contact, M, height)
        sim.run_to(0.3)
        with use_engine('scipy'):
            sim.run_to(0.9)
            mode = sim._mode
        return sim, mode

    (ref, _), (new, mode) = both(run)
    assert not isinstance(mode, Bouncing)
    assert_same_impacts(ref.impacts, new.impacts)
    assert len(new.impacts) >= 4


@pytest.mark.parametrize('table', [(0.002, 20.0, 0.0), (0.001, 10.0, 1.0)],
                         ids=['bouncing', 'carried'])
def test_a_table_train_is_the_python_modes_bounces_and_carried_state(table):
    contact, _ = CONTACTS['azad_featherstone']
    plate = SinusoidalPlate(*table)

    def run():
        sim = DropSimulation(contact, M, 0.05, plate=plate)
        was_train = isinstance(sim._mode, Bouncing)
        sim.run_to(10.0)
        return was_train, sim

    (ref_train, ref), (new_train, new) = both(run)
    assert new_train and not ref_train
    assert len(ref.impacts) > 20
    assert_same_impacts(ref.impacts, new.impacts)
    assert_close(ref.apex_heights, new.apex_heights)
    assert new.carried == ref.carried
    assert_close([ref.state.penetration], [new.state.penetration])


def test_stepping_a_table_train_gives_the_python_modes_points_and_states():
    contact, _ = CONTACTS['azad_featherstone']

    def run():
        rng = random.Random(4)
        sim = DropSimulation(contact, M, 0.05, plate=SinusoidalPlate(0.001, 10.0, 1.0))
        out = []
        for _ in range(200):
            t = sim.time + rng.choice([0.0, 1e-5, 3e-4, 1e-3, 0.01, 0.05])
            adv = sim.advance(t, max_steps=rng.choice([None, None, 0, 1, 7, 60]))
            out.append((adv.samples.time, adv.samples.force, sim.time, sim.carried))
        return out, sim

    (ref, ref_sim), (new, new_sim) = both(run)
    for a, b in zip(ref, new):
        for x, y in zip(a, b):
            assert_close(x, y)
    assert_same_impacts(ref_sim.impacts, new_sim.impacts)


def sampled_table(amplitude, frequency, phase, duration, per_period):
    """A ``CommandedPlate`` through the table a sin(2π f t + ϕ) sampled ``per_period`` times a
    period (its p and ṗ at each point)."""
    w = 2.0 * math.pi * frequency
    t = np.arange(int(duration * frequency * per_period) + 1) / (frequency * per_period)
    return CommandedPlate(tuple(t), tuple(amplitude * np.sin(w * t + phase)),
                          tuple(amplitude * w * np.cos(w * t + phase)))


COMMANDED = {
    'bouncing': sampled_table(0.002, 20.0, 0.0, 4.0, 20),      # Γ = 3.2: knots inside contacts
    'carried': sampled_table(0.0005, 10.0, 0.0, 4.0, 8),       # Γ = 0.2: carried, released
    'lifted': CommandedPlate((0.2, 0.5, 0.8, 1.2), (0.0, 0.004, 0.004, 0.0),
                             (0.0, 0.0, 0.0, 0.0)),             # still, up 4 mm, still, down
}


def knots_inside(plate, impacts):
    """How many of the plate's knots fall inside the impacts' contacts."""
    starts = plate.piece_arrays[0]
    return sum(int(np.sum((starts > i.time)
                          & (starts < i.time + i.contact_duration))) for i in impacts)


@pytest.mark.parametrize('law', ['azad_featherstone', 'linear'])
@pytest.mark.parametrize('name', sorted(COMMANDED))
def test_a_commanded_plate_train_is_the_python_modes_bounces_knots_and_carried_state(name, law):
    contact, _ = CONTACTS[law]
    plate = COMMANDED[name]

    def run():
        sim = DropSimulation(contact, M, 0.02, plate=plate)
        was_train = isinstance(sim._mode, Bouncing)
        advance = sim.advance(3.0)
        return was_train, sim, advance

    (ref_train, ref, ref_adv), (new_train, new, new_adv) = both(run)
    assert new_train and not ref_train
    assert len(ref.impacts) > 15
    assert_same_impacts(ref.impacts, new.impacts)
    assert_close(ref.apex_heights, new.apex_heights)
    for field in ('time', 'penetration', 'force'):
        assert_close(getattr(ref_adv.samples, field), getattr(new_adv.samples, field))
    assert new.carried == ref.carried
    assert_close([ref.state.penetration, ref.permanent_contact_time],
                 [new.state.penetration, new.permanent_contact_time])
    if name == 'bouncing':          # the restarts at knots inside a contact were met
        assert knots_inside(plate, ref.impacts) > 0
    if law == 'azad_featherstone' and name != 'bouncing':   # carried (the soft linear
        assert ref.permanent_contact_time is not None          # contact keeps bouncing)


def test_stepping_a_commanded_plate_train_gives_the_python_modes_points_and_states():
    contact, _ = CONTACTS['linear']
    plate = COMMANDED['bouncing']

    def run():
        rng = random.Random(5)
        sim = DropSimulation(contact, M, 0.02, plate=plate)
        out = []
        for _ in range(300):
            t = sim.time + rng.choice([0.0, 1e-5, 3e-4, 1e-3, 0.01])
            adv = sim.advance(t, max_steps=rng.choice([None, None, 0, 1, 7, 60]))
            out.append((adv.samples.time, adv.samples.force, sim.time,
                        sim.state.penetration, sim.in_contact))
        return out, sim

    (ref, ref_sim), (new, new_sim) = both(run)
    for a, b in zip(ref, new):
        for x, y in zip(a, b):
            assert_close(x, y)
    assert knots_inside(plate, ref_sim.impacts) > 0
    assert_same_impacts(ref_sim.impacts, new_sim.impacts)


def test_a_stiff_phase_after_a_knot_goes_to_the_python_path():
    # the plate accelerates down at 5 m/s² until 0.2 s, then moves on at constant velocity: the
    # forced phase is compiled, the unforced one after the knot too damped for DOP853
    contact = cs.Contact(cs.HUNT_CROSSLEY, 1e9, 1e15)
    plate = CommandedPlate((0.0, 0.2), (0.0, -0.1), (0.0, -1.0))

    def run():
        sim = DropSimulation(contact, M, 0.005, plate=plate)
        sim.run_to(0.19)
        in_train = isinstance(sim._mode, Bouncing) and sim.in_contact
        sim.run_to(0.3)
        return in_train, sim

    (_, ref), (in_train, new) = both(run)
    assert in_train
    assert isinstance(new._mode, Contact) and isinstance(new._mode.integrator, PhaseIntegrator)
    assert_close([ref.time, ref.state.penetration, ref.state.penetration_rate],
                 [new.time, new.state.penetration, new.state.penetration_rate])
    assert_same_impacts(ref.impacts, new.impacts)


def test_the_pieces_examples_run():
    for module in (pieces, lift_off):
        assert doctest.testmod(module).failed == 0


@pytest.mark.parametrize('after', ['table', 'commanded', 'stopped'])
def test_a_switch_runs_as_a_train_once_passed_where_its_new_motion_moves(after):
    contact, _ = CONTACTS['azad_featherstone']
    table = SinusoidalPlate(0.001, 10.0, 1.0)
    plate = {'table': table_transition(0.3, None, SinusoidalPlate(0.002, 20.0, 0.0)),
             'commanded': SwitchedPlate(table, command_motion(
                 0.5, *table.state(0.5)[:2], [0.7, 0.9, 1.4], [0.0, 0.004, -0.002]).motion, 0.5),
             'stopped': table_transition(0.3, table, None, 10.0)}[after]

    def run():
        sim = DropSimulation(contact, M, 0.02, plate=plate)
        modes = []
        for t in np.arange(0.05, 3.0, 0.05):
            sim.run_to(t)
            modes.append(isinstance(sim._mode, Bouncing) and sim.time >= plate.switch_time)
        return any(modes), sim

    (ref_train, ref), (new_train, new) = both(run)
    assert not ref_train and new_train == (after != 'stopped')
    assert len(ref.impacts) > 10
    assert_same_impacts(ref.impacts, new.impacts)
    assert_close(ref.apex_heights, new.apex_heights)
    assert_close([ref.time, ref.state.penetration], [new.time, new.state.penetration])


def test_a_phase_tested_for_the_carried_state_is_viewed_from_python_once(monkeypatch):
    # each test (every CHUNK steps) asks the running phase's Contact of Python: made once a
    # phase and brought up to date, not rebuilt with all its points (quadratic in a long phase)
    counts = collections.Counter()
    adopt, run = CompiledPhase.adopt.__func__, mode_train.ct.run_train

    def counted_adopt(cls, *args, **kwargs):
        counts['views'] += 1
        return adopt(cls, *args, **kwargs)

    def counted_run(*args):
        reason, taken = run(*args)
        counts['carry tests'] += reason == mode_train.ct.CARRY_TEST
        return reason, taken

    monkeypatch.setattr(CompiledPhase, 'adopt', classmethod(counted_adopt))
    monkeypatch.setattr(mode_train.ct, 'run_train', counted_run)
    contact = cs.Contact(cs.HUNT_CROSSLEY, 1e9, 1e13)
    plate = CommandedPlate((0.0, 0.2), (0.0, 0.1), (0.0, 1.0))     # up at 5 m/s²: carried

    def run_drop():
        sim = DropSimulation(contact, M, 0.005, plate=plate)
        sim.run_to(0.15)
        return sim

    ref, new = both(run_drop)
    assert counts['carry tests'] > 20 and counts['views'] == 1
    assert new.carried and ref.carried
    assert_close([ref.time, ref.state.penetration, ref.permanent_contact_time],
                 [new.time, new.state.penetration, new.permanent_contact_time])
