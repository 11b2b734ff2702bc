"""One contact phase in compiled code: the ``compiled`` kernels behind the phase interface.

The same mathematics as the reference (``reference.PhaseIntegrator``): DOP853 with scipy's step
control, the 7th-order dense output and Brent event location, all in numba, so that ``run``
takes any number of steps in one call.  A phase starts with ``start_phase`` (after
``constant_parameters``): the per-phase slots of ``compiled``'s parameter vector from the
phase's scales, the state at σ = 0 and the force and peak of the first point.
"""
import math

import numpy as np
from numba import njit

from contact_sim.phase import compiled
from contact_sim.phase.compiled import (BUFFER_FULL, MAX_STEPS, NPAR, P_AMPLITUDE, P_ATOL,
                                        P_DAMPING, P_DRAG1, P_DRAG2, P_ENERGY_GRAVITY, P_GRAVITY,
                                        P_KIND, P_LENGTH, P_LIFT_EVENTS, P_MASS, P_N, P_OMEGA,
                                        P_P, P_PHASE, P_Q, P_REST_POTENTIAL, P_RTOL, P_START,
                                        P_STIFFNESS, P_TIME, P_ZETA, S_DEPTH, S_END_RATE,
                                        S_END_T, S_END_Z, S_H, S_LIFTED, S_PEAK, S_S, S_STEPS,
                                        S_U, S_X, STEP_TOO_SMALL)
from contact_sim.phase.compiled import run as _run
from contact_sim.phase.forcing import NO_FORCING_TERMS
from contact_sim.phase.lift_off import force_can_vanish_inside
from contact_sim.phase.scales import (DEFAULT_ATOL, DEFAULT_RTOL, FIRST_STEP, PhaseScales,
                                      phase_scales, scales_of, start_peak)

_KW = dict(cache=True, nogil=True, error_model='numpy')

_start_peak = njit('float64(float64, float64, float64, float64, float64, float64)',
                   **_KW)(start_peak)
_scales_of = njit('UniTuple(float64, 4)(float64, float64, float64, float64, float64, float64, '
                  'float64, float64, float64)', **_KW)(scales_of)


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


TABLE_ROWS = 64     # the rows a phase that keeps its points starts with (doubled when full)
_SHAPES = (compiled.NSTATE, (compiled.A.shape[0], 2), (compiled.D.shape[0] + 3, 2))


def phase_storage(empty=np.empty, shapes=_SHAPES):
    """Integrator storage (st, K, F) of ``compiled``'s shapes, uninitialised (``start_phase``
    sets it).  (``empty`` and ``shapes`` bound once: a phase a bounce.)"""
    return empty(shapes[0]), empty(shapes[1]), empty(shapes[2])


_START = ('float64[::1], float64[::1], float64[:, ::1], float64[:, ::1], float64[:, ::1], '
          'float64, float64, float64, ')     # par, st, K, F, pts, t₀, z, ż
_TERMS = 'float64, float64, float64, float64, float64'  # ``Forcing.terms``


@njit('float64(' + _START + 'float64, float64, float64, float64, ' + _TERMS + ')', **_KW)
def start_phase(par, st, K, F, pts, start_time, penetration, penetration_rate, length, time,
                gamma, zeta, amplitude, omega, phase, drag1, drag2):
    """Start a phase at ``start_time`` (s) from (z, ż) (m, m/s) with the scales (Z m, T s, γ, ζ)
    and the forcing terms (A m/s², Ω rad/s, ϕ rad, c₁ N·s/m, c₂ N·s²/m², ``Forcing.terms``;
    zeros: gravity alone): fill the per-phase slots of ``par`` (as ``constant_parameters`` left
    it), the forcing's made dimensionless (A T²/Z, Ω T, Ω t₀ + ϕ, c₁ T/m, c₂ Z/m), set
    (st, K, F) to the state at σ = 0, write its first point (t, z, ż, peak) to row 0 of
    ``pts``; returns the phase's first peak force (N), ``scales.start_peak_force`` of the force
    there.

    The energy of rest is taken at the g the scales give back, m γ Z / T² / m (as the phase's
    energy test uses it)."""
    par[P_ZETA], par[P_GRAVITY] = zeta, gamma
    par[P_START], par[P_TIME], par[P_LENGTH] = start_time, time, length
    mass, k, n = par[P_MASS], par[P_STIFFNESS], par[P_N]
    par[P_AMPLITUDE] = amplitude * (time * time) / length
    par[P_OMEGA] = omega * time
    par[P_PHASE] = omega * start_time + phase
    par[P_DRAG1] = drag1 * time / mass
    par[P_DRAG2] = drag2 * length / mass
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
    pts[0, 0], pts[0, 1], pts[0, 2], pts[0, 3] = start_time, penetration, penetration_rate, peak
    return peak


@njit('UniTuple(float64, 5)(' + _START + 'float64, ' + _TERMS + ')', **_KW)
def start_scaled(par, st, K, F, pts, start_time, penetration, penetration_rate, gravity,
                 amplitude, omega, phase, drag1, drag2):
    """``start_phase`` with the phase's scales found here (``scales.scales_of`` of the law, k,
    λ and m in ``par`` and ``gravity`` m/s²): returns (peak force N, Z m, T s, γ, ζ); nothing
    started where Z <= 0 (no motion and no gravity, ``phase_scales`` refuses it)."""
    length, time, gamma, zeta = _scales_of(par[P_STIFFNESS], par[P_DAMPING], par[P_MASS],
                                           gravity, par[P_N], par[P_P], par[P_Q], penetration,
                                           penetration_rate)
    if not length > 0.0:
        return math.nan, length, time, gamma, zeta
    peak = start_phase(par, st, K, F, pts, start_time, penetration, penetration_rate, length,
                       time, gamma, zeta, amplitude, omega, phase, drag1, drag2)
    return peak, length, time, gamma, zeta


def step_too_small():
    """The error of a phase whose step size fell below the spacing of the doubles
    (``compiled.STEP_TOO_SMALL``)."""
    return RuntimeError('contact integration failed: Required step size is less than spacing '
                        'between numbers.')


@njit('UniTuple(float64, 2)(float64[::1], float64[:, ::1], float64[:, ::1], float64[::1], '
      'float64)', **_KW)
def phase_state_at(st, K, F, par, t):
    """(z m, ż m/s) of a phase at a time t (s) within its last step, from the step's dense
    output (``CompiledPhase.state_at``)."""
    time, length = par[P_TIME], par[P_LENGTH]
    s = math.sqrt(max(t - par[P_START], 0.0) / time)
    x, u = compiled.state_in_last_step(st, K, F, par, s)
    return x * length, u * length / time


class CompiledPhase:
    """One contact phase integrated in compiled code (``compiled``): the same interface and the
    same mathematics as ``PhaseIntegrator`` (DOP853 with scipy's step control, the 7th-order dense
    output, Brent event location), but ``run`` takes any number of steps in one call.

    ``peak_force``, ``max_penetration``, ``steps``, ``lifted_off`` and ``end`` are plain
    attributes, brought up to date after every ``step``/``run``; ``points`` too, read as a list
    of (t, z, ż, F) tuples when asked for (the rows a run adds are kept as arrays until then).
    With ``keep_points=False`` only the first point is kept (a caller that wants the outcome
    alone).  ``forcing`` (a ``Forcing``) adds forcing terms to gravity.
    """

    def __init__(self, contact, mass, gravity, start_time, penetration, penetration_rate,
                 rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL, scales=None, keep_points=True,
                 forcing=None):
        sc = scales if scales is not None else phase_scales(
            contact, mass, gravity, penetration, penetration_rate)
        # the layout of compiled.P_*; the forcing: gravity, and the terms of ``forcing``
        par = constant_parameters(contact, mass, rtol, atol,
                                  2 if force_can_vanish_inside(contact.law, gravity, forcing)
                                  else 1)
        st, k, f = phase_storage()
        table = np.empty((TABLE_ROWS if keep_points else compiled.POINT_BUFFER, 4))
        peak = start_phase(par, st, k, f, table, start_time, penetration, penetration_rate,
                           sc.length, sc.time, sc.gamma, sc.zeta,
                           *(NO_FORCING_TERMS if forcing is None else forcing.terms))
        self._started(contact, mass, par, (st, k, f), start_time, penetration, penetration_rate,
                      peak, sc, table if keep_points else None, table)

    # the state of a phase just started (``_started``), until its runs say otherwise
    lifted_off = False
    steps = 0
    end = None          # (t, z, ż) at lift-off
    _s = 0.0            # σ = sqrt((t - start) / T) reached
    _count = 1          # the rows of ``_table`` written

    def _started(self, contact, mass, par, storage, start_time, penetration, penetration_rate,
                 peak, scales, table, buffer=None):
        """The phase ``start_phase`` started in ``par`` (its own), ``storage`` (st, K, F) and
        ``table``, its first ``peak`` force (N), with its ``scales`` (a ``PhaseScales``, or its
        fields (Z m, T s, γ, ζ) as a tuple): its attributes.  ``table``: the rows of its points, the first written by
        ``start_phase``, the rest by the runs (``None``: no points kept: the runs write to
        ``buffer``, (POINT_BUFFER, 4) rows that phases run one at a time may share)."""
        self._scales = scales
        self._length_scale, self._time_scale = (scales[:2] if isinstance(scales, tuple)
                                                else (scales.length, scales.time))
        self.contact, self.mass = contact, mass
        self.start_time = start_time
        self._par, (self._st, self._k, self._f) = par, storage
        self._table, self._buffer = table, buffer
        self.peak_force = peak
        self.max_penetration = penetration
        self._points = [(start_time, penetration, penetration_rate, peak)]  # ``points``' cache

    @property
    def scales(self):
        """The phase's ``PhaseScales`` (Z m, T s, γ, ζ)."""
        if isinstance(self._scales, tuple):
            self._scales = PhaseScales(*self._scales)
        return self._scales

    @property
    def points(self):
        """The points (t s, z m, ż m/s, F N) so far, a list of tuples: the start, then each
        step's end and the peak, deepest point and lift-off located in it."""
        points = self._points
        if len(points) < self._count:
            points.extend(map(tuple, self._table[len(points):self._count].tolist()))
        return points

    def points_after(self, first, after, until):
        """(rows, end): the points of index ``first`` on with times in (``after``, ``until``]
        (s), an (n, 4) array of rows (t, z, ż, F) (a view: rows once written do not change),
        and the index after the last of them.  (Times increase: the ``bisect_right``s of
        ``points`` over their times, on the array.)"""
        n, table = self._count, self._table
        if table is None:
            table = np.array(self._points)
        start = first
        if start < n and table.item(start, 0) <= after:
            start += int(table[start:n, 0].searchsorted(after, 'right'))
        end = (n if table.item(n - 1, 0) <= until
               else start + int(table[start:n, 0].searchsorted(until, 'right')))
        return table[start:end], end

    def run(self, t_stop=math.inf, max_steps=None, stop_energy=-math.inf):
        """Step until lift-off, until ``time >= t_stop`` (s), for ``max_steps`` steps, or until a
        step that did not lift off ends with ``energy_above_rest() < stop_energy`` (J) (the
        compiled test uses a margin of 1e-12 of the phase's kinetic energy scale, so it may stop
        a step before the caller's own test agrees, never after).  Returns the steps taken."""
        budget = MAX_STEPS if max_steps is None else int(min(max_steps, MAX_STEPS))
        stop = self._energy_stop(stop_energy) if stop_energy > -math.inf else -math.inf
        st, k, f, par, table = self._st, self._k, self._f, self._par, self._table
        t_stop = float(t_stop)
        taken = 0
        while True:
            if table is None:       # no points kept: the shared rows
                reason, _, n = _run(st, k, f, par, self._buffer, t_stop, budget - taken, stop)
            else:                   # straight into the rows left (a view)
                reason, npts, n = _run(st, k, f, par, table[self._count:], t_stop,
                                       budget - taken, stop)
                self._count += npts
            taken += n
            if reason != BUFFER_FULL:
                break
            if table is not None:   # twice the rows, those written kept
                table = np.empty((2 * table.shape[0], 4))
                table[:self._count] = self._table[:self._count]
                self._table = table
        values = st.tolist()            # the results of the steps taken
        self._s = values[S_S]
        self.steps = int(values[S_STEPS])
        self.peak_force = values[S_PEAK]
        self.max_penetration = values[S_DEPTH]
        if values[S_LIFTED]:
            self.lifted_off = True
            self.end = (values[S_END_T], values[S_END_Z], values[S_END_RATE])
        if reason == STEP_TOO_SMALL:
            raise step_too_small()
        return taken

    def _energy_stop(self, stop_energy):
        """The energy (J) at which ``compiled.run`` stops for a caller's test at ``stop_energy``:
        a generous margin above it (1e-9 of it and 1e-12 of the phase's kinetic energy scale
        m (Z/T)²), so that the run stops a step before the caller's own test may agree, never
        after (for a finite ``stop_energy``: ``run`` passes -inf and nan on as -inf)."""
        v = self._length_scale / self._time_scale
        return stop_energy + abs(stop_energy) * 1e-9 + 1e-12 * self.mass * (v * v)

    def step(self):
        """Take one integrator step; locate peak, maximum penetration and lift-off in it."""
        self.run(max_steps=1)

    @property
    def time(self):
        """Time (s) reached by the integrator (the end of its last step)."""
        s = self._s             # σ reached (read from the compiled state by ``run``)
        return self.start_time + self._time_scale * s * s

    @property
    def state(self):
        """(z m, ż m/s) at the integrator's time, as floats."""
        st, length = self._st, self._length_scale
        return st.item(S_X) * length, st.item(S_U) * length / self._time_scale

    def state_at(self, t):
        """(z, ż) at a time t within the last step, from the dense output."""
        return phase_state_at(self._st, self._k, self._f, self._par, t)

    def energy_above_rest(self):
        """Mechanical energy (J) above static equilibrium at the integrator's current state
        (``energy_above_rest``, evaluated in compiled code)."""
        return compiled.energy_above_rest(self._st, self._par)
