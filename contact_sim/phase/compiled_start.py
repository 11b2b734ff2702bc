"""A contact phase in compiled code as another kernel drives it: its start, its run, its results.

``CompiledPhase`` starts every phase with ``start_phase`` (after ``constant_parameters``), and so
does the drop's compiled bounce loop (``drop.compiled_train``) at each impact it meets, written
once for both: the per-phase slots of ``compiled``'s parameter vector from the phase's scales
(``compiled_scales``: ``scales.scales_of`` compiled), the state at σ = 0 and the force and peak
of the first point.  The loop then runs the phase with ``compiled.run`` (``run_phase``, its
reasons re-exported here) and reads its lift-off and peaks with ``lift_off_of`` and
``results_of``.  Units: SI.
"""
import math

import numpy as np
from numba import njit

from contact_sim.phase import compiled
from contact_sim.phase.compiled import (BUDGET_SPENT, BUFFER_FULL, ENERGY_BELOW, LIFTED_OFF,
                                        NPAR, P_AMPLITUDE, P_ATOL, P_DRAG1, P_DRAG2, P_OMEGA,
                                        P_PHASE, P_DAMPING, P_ENERGY_GRAVITY, P_GRAVITY,
                                        P_KIND, P_LENGTH, P_LIFT_EVENTS, P_MASS, P_N, P_P, P_Q,
                                        P_REST_POTENTIAL, P_RTOL, P_START, P_STIFFNESS, P_TIME,
                                        P_ZETA, S_DEPTH, S_END_RATE, S_END_T, S_END_Z, S_H,
                                        S_LIFTED, S_PEAK, S_S, S_STEPS, S_U, S_X, STEP_TOO_SMALL,
                                        TIME_REACHED)
from contact_sim.phase.scales import FIRST_STEP, scales_of, start_peak

_KW = dict(cache=True, nogil=True, error_model='numpy')

# ``compiled.run`` for a kernel that drives phases, and why it returns
run_phase = compiled.run
RUN_REASONS = (LIFTED_OFF, TIME_REACHED, BUDGET_SPENT, ENERGY_BELOW, BUFFER_FULL,
               STEP_TOO_SMALL)

compiled_scales = njit('UniTuple(float64, 4)(float64, float64, float64, float64, float64, '
                       'float64, float64, float64, float64)', **_KW)(scales_of)
_start_peak = njit('float64(float64, float64, float64, float64, float64, float64)',
                   **_KW)(start_peak)


def constant_parameters(contact, mass, rtol, atol, lift_events):
    """``compiled``'s parameter vector with the slots that hold for every phase of ``contact``
    filled (law, k, λ, m (kg), tolerances, the law's short form, ``lift_events`` 1 or 2); the
    forcing and the per-phase slots zero (``start_phase`` fills the latter)."""
    law = contact.law
    par = np.zeros(NPAR)
    par[P_N], par[P_P], par[P_Q] = law.n, law.p, law.q
    par[P_STIFFNESS], par[P_DAMPING], par[P_MASS] = contact.stiffness, contact.damping, mass
    par[P_RTOL], par[P_ATOL] = rtol, atol
    par[P_KIND], par[P_LIFT_EVENTS] = float(law.kernel), float(lift_events)
    return par


def phase_storage():
    """Empty integrator storage (st, K, F) of ``compiled``'s shapes."""
    return (np.zeros(compiled.NSTATE), np.zeros((compiled.A.shape[0], 2)),
            np.zeros((compiled.D.shape[0] + 3, 2)))


@njit('float64(float64[::1], float64[::1], float64[:, ::1], float64[:, ::1], float64, float64, '
      'float64, float64, float64, float64, float64)', **_KW)
def start_phase(par, st, K, F, start_time, penetration, penetration_rate, length, time, gamma,
                zeta):
    """Start a phase at ``start_time`` (s) from (z, ż) (m, m/s) with the scales (Z m, T s, γ, ζ):
    fill the per-phase slots of ``par`` (as ``constant_parameters`` left it, its forcing
    slots set by the caller), set (st, K, F) to the state at σ = 0; returns the phase's first
    peak force (N), ``scales.start_peak_force`` of the force there.

    The energy of rest is taken at the g the scales give back, m γ Z / T² / m (as the phase's
    energy test uses it)."""
    par[P_ZETA], par[P_GRAVITY] = zeta, gamma
    par[P_START], par[P_TIME], par[P_LENGTH] = start_time, time, length
    mass, k, n = par[P_MASS], par[P_STIFFNESS], par[P_N]
    mass_g = mass * gamma * length / (time * time)
    g = mass_g / mass
    z0 = (mass_g / k) ** (1.0 / n)
    par[P_ENERGY_GRAVITY] = g
    par[P_REST_POTENTIAL] = (k * (z0 if z0 > 0.0 else 0.0) ** (n + 1.0) / (n + 1.0)
                             - mass * g * z0)
    st[:] = 0.0
    K[:, :] = 0.0
    F[:, :] = 0.0
    st[S_X], st[S_U], st[S_H] = penetration / length, penetration_rate * time / length, FIRST_STEP
    peak = _start_peak(par[P_P], par[P_DAMPING], par[P_Q], penetration, penetration_rate,
                       compiled.contact_force(penetration, penetration_rate, par))
    st[S_PEAK], st[S_DEPTH] = peak, penetration
    return peak


@njit('float64(float64, float64[::1])', **_KW)
def energy_stop(stop_energy, par):
    """The energy (J) at which ``compiled.run`` stops for a caller's test at ``stop_energy``:
    a generous margin above it (1e-9 of it and 1e-12 of the phase's kinetic energy scale
    m (Z/T)²), so that the run stops a step before the caller's own test may agree, never
    after; -inf stays -inf."""
    if not stop_energy > -np.inf:
        return -np.inf
    v = par[P_LENGTH] / par[P_TIME]
    return stop_energy + abs(stop_energy) * 1e-9 + 1e-12 * par[P_MASS] * (v * v)


@njit('void(float64[::1], float64, float64, float64)', **_KW)
def set_plate_forcing(par, amplitude, omega, phase):
    """The forcing slots of ``par`` for a plate's acceleration A sin(Ω t + ϕ) alone (no drag),
    ``Forcing.dimensionless`` of it at the phase's start and scales, in compiled code."""
    time, length = par[P_TIME], par[P_LENGTH]
    par[P_AMPLITUDE] = amplitude * (time * time) / length
    par[P_OMEGA], par[P_PHASE] = omega * time, omega * par[P_START] + phase
    par[P_DRAG1] = par[P_DRAG2] = 0.0


@njit('void(float64[::1], float64, float64)', **_KW)
def set_constant_forcing(par, acceleration, lift_events):
    """The forcing slots of ``par`` for a constant acceleration A (m/s²) beyond gravity as
    ``CompiledPhase`` fills them from ``constant_forcing(A)`` (A sin(0 t + π/2), A ≠ 0; none
    for A = 0, the unforced phase ``contact_phase`` makes then), and the phase's lift-off events
    (1 or 2, ``force_can_vanish_inside``)."""
    if acceleration != 0.0:
        set_plate_forcing(par, acceleration, 0.0, math.pi / 2)
    else:
        par[P_AMPLITUDE:P_DRAG2 + 1] = 0.0
    par[P_LIFT_EVENTS] = lift_events


def step_too_small():
    """The error of a phase whose step size fell below the spacing of the doubles
    (``compiled.STEP_TOO_SMALL``)."""
    return RuntimeError('contact integration failed: Required step size is less than spacing '
                        'between numbers.')


@njit('float64(float64[::1], float64[::1])', **_KW)
def phase_time(st, par):
    """The time (s) the phase's integrator has reached."""
    return par[P_START] + par[P_TIME] * st[S_S] * st[S_S]


@njit('Tuple((boolean, float64, float64, float64))(float64[::1])', **_KW)
def lift_off_of(st):
    """(lifted off, t s, z m, ż m/s at the lift-off) of a phase's state."""
    return st[S_LIFTED] != 0.0, st[S_END_T], st[S_END_Z], st[S_END_RATE]


@njit('UniTuple(float64, 3)(float64[::1])', **_KW)
def results_of(st):
    """(peak force N, maximum penetration m, steps) of a phase's state so far."""
    return st[S_PEAK], st[S_DEPTH], st[S_STEPS]


@njit('UniTuple(float64, 2)(float64[::1], float64[:, ::1], float64[:, ::1], float64[::1], '
      'float64)', **_KW)
def phase_state_at(st, K, F, par, t):
    """(z m, ż m/s) of a phase at a time t (s) within its last step, from the step's dense
    output (``CompiledPhase.state_at``; the drop's compiled bounces restart a phase so at a
    commanded plate's knot)."""
    time, length = par[P_TIME], par[P_LENGTH]
    s = math.sqrt(max(t - par[P_START], 0.0) / time)
    x, u = compiled.state_in_last_step(st, K, F, par, s)
    return x * length, u * length / time
