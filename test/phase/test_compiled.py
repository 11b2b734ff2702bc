"""The compiled contact phase against the reference path (scipy's DOP853 stepped from Python).

Stated tolerances, compiled vs reference: restitution within 1e-10; contact duration, peak force
and maximum depth within 1e-9 relative (durations only where e >= 0.05: near-plastic lift-off is
ill-conditioned, see README); the paper drop bounce for bounce.
"""
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import contact_sim as cs
from contact_sim import phase
from contact_sim.phase import compiled

ROOT = Path(__file__).resolve().parents[2]
LAWS = list(cs.LAWS.values())
IDS = [law.name for law in LAWS]
PAPER = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)


def _random_impacts(law, count, seed):
    """Random physical (k, m, v, λ) whose restitution (no gravity) lies in [0.01, 0.999]."""
    from contact_sim.impact.damping_fit import group_for_restitution
    rng = np.random.default_rng(seed)
    lo, hi = group_for_restitution(law, 0.999), group_for_restitution(law, 0.01)
    zeta = np.exp(rng.uniform(math.log(lo), math.log(hi), count))
    k = 10 ** rng.uniform(5, 11, count)
    m = 10 ** rng.uniform(-3, 1, count)
    v = 10 ** rng.uniform(-3, 1.5, count)
    return k, m, v, zeta / np.array([float(cs.damping_group(cs.Contact(law, ki, 1.0), mi, vi))
                                     for ki, mi, vi in zip(k, m, v)])


def test_the_compiled_engine_is_the_default_and_radau_keeps_the_stiff_phases():
    assert phase.get_engine() == 'compiled'
    assert isinstance(phase.contact_phase(PAPER, 0.066, 10.0, 0.0, 0.0, 1.0), phase.CompiledPhase)
    with phase.use_engine('scipy'):
        assert isinstance(phase.contact_phase(PAPER, 0.066, 10.0, 0.0, 0.0, 1.0),
                          phase.PhaseIntegrator)
    assert phase.get_engine() == 'compiled'
    # ζ > COMPILED_STIFF_DAMPING under gravity: scipy's Radau, whatever the engine
    heavy = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e9)
    stiff = phase.contact_phase(heavy, 0.066, 10.0, 0.0, 0.0, 1e-3)
    assert stiff.scales.zeta > phase.COMPILED_STIFF_DAMPING
    assert isinstance(stiff, phase.PhaseIntegrator)
    # between the two thresholds the compiled DOP853 takes the phase the reference gives Radau
    moderate = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 2.5e7)
    fast = phase.contact_phase(moderate, 0.066, 10.0, 0.0, 0.0, math.sqrt(20.0))
    assert phase.STIFF_DAMPING < fast.scales.zeta < phase.COMPILED_STIFF_DAMPING
    assert isinstance(fast, phase.CompiledPhase)
    with pytest.raises(ValueError, match='engine'):
        phase.set_engine('fortran')


@pytest.mark.parametrize('gravity', [0.0, 9.81])
@pytest.mark.parametrize('law', LAWS, ids=IDS)
def test_simulate_impact_compiled_equals_the_reference_at_random_points(law, gravity):
    k, m, v, lam = _random_impacts(law, 12, seed=23)
    for ki, mi, vi, li in zip(k, m, v, lam):
        contact = cs.Contact(law, ki, li)
        fast = cs.simulate_impact(contact, mi, vi, gravity=gravity, engine='compiled')
        ref = cs.simulate_impact(contact, mi, vi, gravity=gravity, engine='scipy')
        # a stiff phase (ζ > STIFF_DAMPING) is DOP853 here and Radau in the reference
        zeta = phase.phase_scales(contact, mi, gravity, 0.0, vi).zeta
        same_method = gravity == 0.0 or zeta <= phase.STIFF_DAMPING
        assert fast.status == ref.status
        assert abs(fast.restitution - ref.restitution) <= 1e-10
        if fast.status == 0:
            assert fast.peak_force == pytest.approx(ref.peak_force, rel=1e-9)
            assert fast.max_penetration == pytest.approx(ref.max_penetration, rel=1e-9)
            if ref.restitution >= 0.05:
                assert fast.contact_duration == pytest.approx(ref.contact_duration, rel=1e-9)
        else:
            # came to rest: a creeping sphere's deepest point and largest force are where the
            # energy test stopped each engine, at the end of a step: step ends differ slightly
            # with the same method, by up to a (long) Radau step with the other
            tol = 1e-6 if same_method else 1e-3
            assert fast.peak_force == pytest.approx(ref.peak_force, rel=tol)
            # the penetration where the test stopped a sphere still creeping in: defined to the
            # step the test fires on (lee_wang, zeta = 15, seed 23: 3e-4 apart between rtol
            # 1e-10 and 1e-12 on either engine; the engines 1.3e-6 apart at 1e-12, 797 steps
            # each, at the way in's atol / zeta^2 of a heavily damped n > p law)
            assert fast.max_penetration == pytest.approx(ref.max_penetration,
                                                         rel=10 * tol if same_method else tol)
        if same_method:
            assert abs(fast.steps - ref.steps) <= 2 + 0.01 * ref.steps


def _reference_trajectory(law, zeta, s_end):
    """An independent reference for the unit phase x'' = -xⁿ - ζ xᵖ x'|x'|^(q-1), x(0) = 0,
    x'(0) = 1 (k = m = 1, no gravity): scipy's ``solve_ivp`` (DOP853, rtol 1e-12, atol 1e-14)
    in σ = √τ, where every term is smooth from touch on (see ``phase``), up to ``s_end``; the
    force unclamped past lift-off as in both engines.  Returns the dense output (x, x')(σ)."""
    from scipy.integrate import solve_ivp

    def rhs(s, y):
        x, u = y
        rate = math.copysign(abs(u) ** law.q, u)
        accel = -x ** law.n - zeta * x ** law.p * rate if x > 0.0 else 0.0
        return [2.0 * s * u, 2.0 * s * accel]

    sol = solve_ivp(rhs, (0.0, s_end), [0.0, 1.0], method='DOP853', rtol=1e-12, atol=1e-14,
                    dense_output=True, first_step=0.05)
    assert sol.success
    return sol.sol


@pytest.mark.parametrize('law', LAWS, ids=IDS)
@pytest.mark.parametrize('zeta', [1e-3, 0.3, 3.0])
def test_compiled_phase_records_the_same_points_as_the_reference(law, zeta):
    # Issue 16: the two engines do the same mathematics with different arithmetic (numba's
    # and numpy's pow/exp, possibly AVX-512 or another libm), so their step counts and the
    # last bits of their points may differ; the points are compared as trajectories.
    contact = cs.Contact(law, 1.0, zeta)
    runs = []
    for engine in phase.ENGINES:
        p = phase.contact_phase(contact, 1.0, 0.0, 0.0, 0.0, 1.0, engine=engine)
        while not p.lifted_off:
            p.step()
        runs.append(p)
    fast, ref = runs
    # A last-bit difference in the error estimate can flip one accept/reject decision of the
    # step-size controller where the estimate sits near the tolerance; each flip moves the
    # count by about one step: a couple of steps, or 1 % on long phases (as for whole impacts).
    assert abs(fast.steps - ref.steps) <= 2 + 0.01 * ref.steps
    # The located events do not depend on where the steps ended.
    np.testing.assert_allclose(fast.end, ref.end, rtol=1e-9, atol=1e-12)
    assert fast.peak_force == pytest.approx(ref.peak_force, rel=1e-10)
    assert fast.max_penetration == pytest.approx(ref.max_penetration, rel=1e-10)
    # Every recorded point (t, z, ż, F) lies on the true trajectory: z, ż and F at each
    # recorded t against the independent reference.  Both engines hold a local error of 1e-12
    # per step over some tens of steps, and the reference as much: the largest deviation seen
    # is 5e-12 of a column's largest magnitude, so 1e-9 of it leaves a margin of 200.
    s_end = math.sqrt(max(fast.end[0], ref.end[0])) * (1.0 + 1e-12)
    exact = _reference_trajectory(law, zeta, s_end)
    assert fast.points[0] == ref.points[0]      # the touch, (0, 0, v, F) by construction
    for run in runs:
        points = np.array(run.points[1:])
        t, z, zdot, force = points.T
        x, u = exact(np.minimum(np.sqrt(t), s_end))
        want_z, want_zdot = np.maximum(x, 0.0), u
        want_force = contact.force(want_z, want_zdot)
        for got, want in ((z, want_z), (zdot, want_zdot), (force, want_force)):
            scale = np.abs(want).max()
            assert np.abs(got - want).max() <= 1e-9 * scale


def test_paper_drop_is_the_reference_bounce_for_bounce():
    results = {}
    for engine in phase.ENGINES:
        with phase.use_engine(engine):
            results[engine] = cs.simulate_drop(PAPER, 0.066, 1.0, gravity=10.0, duration=5.0)
    fast, ref = results['compiled'], results['scipy']
    # 37 bounces + permanent contact: an exact count, with a margin far beyond rounding (the
    # same 38 impacts and 26 microscopic bounces for heights 1 m ± 1e-6 relative, issue 16)
    assert len(fast.impacts) == len(ref.impacts) == 38
    # step counts differ by the controller's flipped accept/reject decisions (see above), over
    # 38 phases and their flights: a couple of steps a phase, or 1 % (issue 16)
    assert abs(fast.steps - ref.steps) <= 2 * len(ref.impacts) + 0.01 * ref.steps
    for a, b in zip(fast.impacts, ref.impacts):
        assert a.time == pytest.approx(b.time, rel=1e-10)
        assert a.impact_speed == pytest.approx(b.impact_speed, rel=1e-9, abs=1e-12)
        assert a.rebound_speed == pytest.approx(b.rebound_speed, rel=1e-9, abs=1e-12)
        assert abs(a.restitution - b.restitution) <= 1e-9
        assert a.contact_duration == pytest.approx(b.contact_duration, rel=1e-8)
        assert a.peak_force == pytest.approx(b.peak_force, rel=1e-9)
        assert a.max_penetration == pytest.approx(b.max_penetration, rel=1e-9)
    np.testing.assert_allclose(fast.apex_heights, ref.apex_heights, rtol=1e-8, atol=1e-15)
    assert fast.permanent_contact_time == pytest.approx(ref.permanent_contact_time, rel=1e-10)
    assert fast.settle_time == pytest.approx(ref.settle_time, rel=1e-8)


def test_sampled_trajectory_matches_the_reference_dense_output():
    # sampling asks state_at() inside steps: the compiled dense output against scipy's
    trajs = {}
    for engine in phase.ENGINES:
        with phase.use_engine(engine):
            trajs[engine] = cs.simulate_drop(PAPER, 0.066, 1.0, gravity=10.0, duration=0.9,
                                             sample_rate=20_000.0).trajectory
    fast, ref = trajs['compiled'], trajs['scipy']
    assert fast.time.shape == ref.time.shape
    np.testing.assert_allclose(fast.time, ref.time, rtol=1e-12, atol=0)
    scale = np.abs(ref.penetration).max()
    assert np.abs(fast.penetration - ref.penetration).max() <= 1e-9 * scale
    assert np.abs(fast.force - ref.force).max() <= 1e-8 * ref.force.max()


def test_peers_problem_bounces_378_times_as_the_reference():
    # steel ball (R = 12.7 mm) on cast iron, Hertz stiffness, Hunt-Crossley with e(1 m/s) = 0.8,
    # dropped 1 m under 9.81 m/s² for 5 s: the reference solution has 378 bounces
    radius = 0.0127
    mass = cs.sphere_mass(cs.get_material('steel').density, radius)
    hertz = cs.Contact.from_materials(cs.HUNT_CROSSLEY, 'steel', 'cast_iron', radius)
    lam = cs.damping_for_restitution(cs.HUNT_CROSSLEY, hertz.stiffness, mass, 0.8, 1.0)
    contact = cs.Contact(cs.HUNT_CROSSLEY, hertz.stiffness, lam)
    fast = cs.simulate_drop(contact, mass, 1.0, gravity=9.81, duration=5.0)
    # an exact count with a margin: the last apex comes 0.9 ms before the 5 s end, the impact
    # times agree to 1e-10 relative across paths, and 1 m ± 1e-9 gives 378 too (issue 16)
    assert len(fast.apex_heights) == 378
    with phase.use_engine('scipy'):
        ref = cs.simulate_drop(contact, mass, 1.0, gravity=9.81, duration=2.5)
    for a, b in zip(fast.impacts, ref.impacts):
        assert a.time == pytest.approx(b.time, rel=1e-10)
        assert abs(a.restitution - b.restitution) <= 1e-9
        assert a.peak_force == pytest.approx(b.peak_force, rel=1e-9)
    assert len(ref.impacts) > 5


def test_the_drag_slot_of_the_forcing_is_a_damper_in_closed_form():
    # linear spring, no contact damping, linear drag d: x'' = -x - d x' from (0, 1) until x = 0
    # again: duration π/ω and rebound e^(-dπ/2ω), ω = √(1 - d²/4)
    d = 0.3
    p = phase.contact_phase(cs.Contact(cs.LINEAR, 1.0, 0.0), 1.0, 0.0, 0.0, 0.0, 1.0,
                            forcing=phase.Forcing(linear_drag=d))
    assert p._par[compiled.P_DRAG1] == d
    p.run()
    omega = math.sqrt(1.0 - d * d / 4.0)
    t_end, z_end, rate_end = p.end
    assert t_end == pytest.approx(math.pi / omega, rel=1e-10)
    assert -rate_end == pytest.approx(math.exp(-d * math.pi / (2.0 * omega)), rel=1e-10)


def test_the_harmonic_slot_of_the_forcing_at_zero_frequency_is_gravity():
    ref = phase.CompiledPhase(PAPER, 0.066, 10.0, 0.0, 0.0, 0.5)
    alt = phase.CompiledPhase(PAPER, 0.066, 10.0, 0.0, 0.0, 0.5)   # same scales as ref
    alt._par[compiled.P_AMPLITUDE] = alt._par[compiled.P_GRAVITY]
    alt._par[compiled.P_GRAVITY] = 0.0
    alt._par[compiled.P_PHASE] = math.pi / 2.0
    ref.run()
    alt.run()
    # the same forcing to the last bit only if sin(π/2) rounds to 1: a step or two either way
    # (a flipped accept/reject of the step controller) where it does not (issue 16)
    assert abs(alt.steps - ref.steps) <= 2
    np.testing.assert_allclose(alt.end, ref.end, rtol=1e-13)


def test_harmonic_forcing_is_phased_in_absolute_time():
    # a phase starting at t0 with phase ϕ moves as one starting at 0 with phase ϕ + Ω t0
    omega, t0 = 2.0e4, 0.37
    a = phase.contact_phase(PAPER, 0.066, 10.0, t0, 0.0, 0.5,
                            forcing=phase.Forcing(5e3, omega, 0.3))
    b = phase.contact_phase(PAPER, 0.066, 10.0, 0.0, 0.0, 0.5,
                            forcing=phase.Forcing(5e3, omega, 0.3 + omega * t0))
    a.run()
    b.run()
    assert a.end[0] - t0 == pytest.approx(b.end[0], rel=1e-9)
    assert a.end[2] == pytest.approx(b.end[2], rel=1e-9)
    plain = phase.contact_phase(PAPER, 0.066, 10.0, 0.0, 0.0, 0.5)
    plain.run()
    assert abs(plain.end[2] - b.end[2]) > 1e-3 * abs(plain.end[2])   # the forcing acts


def test_forcing_is_validated_and_needs_the_compiled_engine():
    with pytest.raises(ValueError, match='linear_drag'):
        phase.Forcing(linear_drag=-1.0)
    with pytest.raises(ValueError, match='angular_frequency'):
        phase.Forcing(angular_frequency=float('nan'))
    with pytest.raises(ValueError, match='forcing'):
        phase.contact_phase(PAPER, 0.066, 10.0, 0.0, 0.0, 0.5, engine='scipy',
                            forcing=phase.Forcing(quadratic_drag=0.1))


def test_chunked_runs_equal_one_run():
    whole = phase.CompiledPhase(PAPER, 0.066, 10.0, 0.0, 0.0, 2.0)
    whole.run()
    parts = phase.CompiledPhase(PAPER, 0.066, 10.0, 0.0, 0.0, 2.0)
    while not parts.lifted_off:
        parts.run(max_steps=3)
    assert parts.steps == whole.steps
    assert parts.points == whole.points
    assert parts.end == whole.end


def test_kernels_load_from_the_on_disk_cache():
    # setup.sh (and any earlier import) wrote the cache: a new process must load, not compile
    code = 'import contact_sim.phase.compiled'
    env = dict(os.environ, NUMBA_DEBUG_CACHE='1')
    subprocess.run([sys.executable, '-c', code], cwd=ROOT, env=env, check=True,
                   capture_output=True)
    out = subprocess.run([sys.executable, '-c', code], cwd=ROOT, env=env, check=True,
                         capture_output=True, text=True).stdout
    assert "data loaded from" in out and 'compiled.run-' in out
    assert 'data saved to' not in out


def test_the_colcon_symlink_install_loads_the_same_cache():
    # scripts/setup.sh's `colcon build --symlink-install` links build/contact_sim/contact_sim to
    # the sources; imported from there (as ros2 run would), the kernels come from the same cache
    linked = ROOT / 'build' / 'contact_sim'
    if not (linked / 'contact_sim').is_dir():
        pytest.skip(f'no colcon --symlink-install build at {linked} (scripts/setup.sh leaves '
                    'one; a colcon workspace builds elsewhere)')
    code = ('import sys; '
            'sys.meta_path[:] = [f for f in sys.meta_path if "editable" not in repr(f).lower()]; '
            f'sys.path.insert(0, {str(linked)!r}); '
            'import contact_sim.phase.compiled as c; print(c.__file__)')
    env = dict(os.environ, NUMBA_DEBUG_CACHE='1')
    out = subprocess.run([sys.executable, '-c', code], cwd=ROOT, env=env, check=True,
                         capture_output=True, text=True).stdout
    assert out.strip().splitlines()[-1] == str(linked / 'contact_sim' / 'phase' / 'compiled.py')
    assert "data loaded from" in out and 'data saved to' not in out


@pytest.mark.parametrize('lam', [1e7, 2.5e7, 5e7])    # first phase ζ = 40, 100, 200
def test_moderately_stiff_phases_compiled_dop853_equals_the_reference_radau(lam):
    contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, lam)
    speed = math.sqrt(20.0)
    fast = cs.simulate_impact(contact, 0.066, speed, gravity=10.0, engine='compiled')
    ref = cs.simulate_impact(contact, 0.066, speed, gravity=10.0, engine='scipy')
    assert fast.status == ref.status
    assert abs(fast.restitution - ref.restitution) <= 1e-9
    results = {}
    for engine in phase.ENGINES:
        with phase.use_engine(engine):
            results[engine] = cs.simulate_drop(contact, 0.066, 1.0, gravity=10.0, duration=1.5)
    a, b = results['compiled'], results['scipy']
    assert len(a.impacts) == len(b.impacts)
    for x, y in zip(a.impacts, b.impacts):
        assert abs(x.restitution - y.restitution) <= 1e-9
        # the final, permanent contact creeps into rest: its largest force and depth are where
        # each engine's steps ended when it switched to rest
        tol = 1e-6 if x.permanent else 1e-9
        assert x.peak_force == pytest.approx(y.peak_force, rel=tol)
        assert x.max_penetration == pytest.approx(y.max_penetration, rel=tol)
    assert a.permanent_contact_time == pytest.approx(b.permanent_contact_time, rel=1e-10)
    # the switch to the closed-form rest happens at the end of the first step that qualifies:
    # Radau's steps are long, so the two settle times differ by up to a step
    assert a.settle_time == pytest.approx(b.settle_time, rel=1e-3)


def test_the_lift_off_examples_run():
    import doctest
    from contact_sim.phase import lift_off
    assert doctest.testmod(lift_off).failed == 0
