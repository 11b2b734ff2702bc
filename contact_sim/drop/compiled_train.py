"""Bounces on the fixed plate, a vibrating table or a commanded plate in compiled code: flight,
touch, contact phase, lift-off, flight, ... for as many bounces as fit before the end asked
(``run_train``, behind ``mode_train``).

Each piece is the one the Python modes use, called from here: the flight's touch time and apex
(``plate.compiled_ballistic``, ``plate.compiled_flight``), the plate's state (``sinusoid_state``,
``compiled_flight.commanded_state``) and its forcing pieces (``pieces.piece_forcing``), the phase's
scales, start, run and dense output (``phase.compiled_scales``, ``phase.start_phase``,
``phase.run_phase``, ``phase.phase_state_at``), and the energy bound of the rebound
(``bounded_rate``, which ``mode_contact`` uses too).  What the loop adds is the sequence: the
transitions ``touch`` -> ``impact``, ``knot`` -> ``go_on`` (a commanded plate's forcing changes:
the same contact restarts there, its record carried) and ``lift_off`` -> ``bounce`` of
``transitions.TRANSITIONS`` in vacuum (on a moving plate with its forcing, ``CarryWatch``'s runs
of steps and the test for the carried state left to Python: CARRY_TEST), the impact records
(``ImpactRecord``'s fields and the apex, a row each in ``imp``) and the points (``pts``).

It stops, with its state in ``tr`` (the layout ``TR_*``), where the Python modes take over or the
caller asked: the time ``t_stop`` (s), the step budget, a step whose energy fell below the
lift-off floor (``RestWatch`` decides whether the contact is permanent), a phase too stiff for the
compiled integrator (``phase.COMPILED_STIFF_DAMPING``, unforced: the ``touch`` or ``knot`` goes
to the Python path), or full buffers.  Units: SI; z > 0 penetration, ż > 0 approach.
"""
import math

from numba import njit

from contact_sim.drop.plate.compiled_ballistic import apex_height
from contact_sim.drop.plate.compiled_ballistic import touch_time as ballistic_touch_time
from contact_sim.drop.plate.compiled_flight import (NO_EXIT, commanded_state,
                                                   commanded_touch_time, piece_index,
                                                   sinusoid_touch_time)
from contact_sim.drop.plate.flights import rise_apex
from contact_sim.drop.plate.motions import sinusoid_state
from contact_sim.drop.plate.pieces import piece_forcing
from contact_sim.phase import (RUN_REASONS, compiled_scales, energy_stop, lift_off_of,
                               phase_state_at, phase_time, potential_of, pulls_out, results_of,
                               run_phase, set_constant_forcing, set_plate_forcing, start_phase)

_KW = dict(cache=True, nogil=True, error_model='numpy')
LIFTED_OFF, TIME_REACHED, BUDGET_SPENT, ENERGY_BELOW, BUFFER_FULL, STEP_TOO_SMALL = RUN_REASONS
STIFF_PHASE, CARRY_TEST, NO_EXIT_FOUND, STIFF_KNOT = 5, 6, 7, 8   # why ``run_train`` returned,
#                                                                beside the phase's reasons
MAX_STEPS = 2 ** 62

# -- the train's state (float64[NTR]) ------------------------------------------------------------
TR_FLIGHT = 0                 # 1.0 in flight, 0.0 in a contact phase
TR_START, TR_Y0, TR_V0, TR_TOUCH = 1, 2, 3, 4    # the flight: start (s), y, v (m, m/s), touch (s)
TR_GRAVITY, TR_FLOOR, TR_STIFF = 5, 6, 7   # g (m/s²), lift-off energy floor (J), ζ limit
TR_NPTS, TR_PHASE_ROW, TR_EMITTED = 8, 9, 10   # rows of pts: used, the phase's first, handed out
TR_NIMP, TR_STEPS, TR_KEEP = 11, 12, 13   # rows of imp used; steps of phases ended; keep points
TR_TIME = 14                  # the time reached (s)
TR_Z, TR_RATE = 15, 16        # (z, ż) at a touch left to the Python path (STIFF_PHASE)
TR_T0, TR_Z0, TR_RATE0 = 17, 18, 19   # the phase's first point
TR_STOP = 20                  # the energy (J) below which the phase stops for the floor's test
TR_K, TR_LAM, TR_MASS, TR_N, TR_P, TR_Q = 21, 22, 23, 24, 25, 26   # the contact and the sphere
TR_RAN = 27                   # 1.0: the call's last work was a run of the phase's steps
TR_MOVING = 28                # the plate: FIXED, TABLE or COMMANDED (below)
TR_AMP, TR_OMEGA, TR_PHASE = 29, 30, 31   # the table p = a sin(ω t + ϕ): a, ω, ϕ
TR_FORCE_AMP, TR_BOUND = 32, 33   # its acceleration's amplitude -a ω² (m/s²); g + max |p̈| (m/s²)
TR_CHUNK, TR_CHUNK_LEFT, TR_CHECKED = 34, 35, 36   # CarryWatch's run of steps, its steps left,
#                               and the phase's steps at the last test for the carried state
TR_KNOT = 37                  # the running phase's forcing ends (s): a commanded plate's knot
TR_REC_PEAK, TR_REC_DEPTH = 38, 39   # the impact's peak force (N), depth (m) before that phase
TR_F0 = 40                    # the force (N) at the impact's first point (t0, z0, ż0 above)
TR_VANISHES = 41              # 1.0: the law's force can vanish inside (n > p)
NTR = 42

FIXED, TABLE, COMMANDED = 0.0, 1.0, 2.0     # tr[TR_MOVING]; a commanded plate's pieces: ``pc``
#                                   (``CommandedPlate.piece_arrays``), a (4, 1) dummy otherwise

# -- an impact record's row (float64[NREC]): ImpactRecord's fields, then the apex after it -------
NREC = 8
REC_APEX = 7

_potential = njit('float64(float64, float64, float64, float64, float64)', **_KW)(potential_of)
_sinusoid = njit('UniTuple(float64, 3)(float64, float64, float64, float64)',
                 **_KW)(sinusoid_state)
_rise_apex = njit('float64(float64, float64, float64)', **_KW)(rise_apex)
_piece_forcing = njit(**_KW)(piece_forcing)
_pulls_out = njit('boolean(float64, float64)', **_KW)(pulls_out)


@njit('float64(float64, float64, float64, float64, float64, float64, float64, float64)', **_KW)
def bounded_rate(k, n, mass, g, start_z, start_rate, z, zdot):
    """The rate ż (m/s) at a lift-off at (z, ż) on the fixed plate with the energy above rest
    no higher than at the phase's start (``start_z`` m, ``start_rate`` m/s): see
    ``mode_contact.energy_bounded_rate``."""
    e_start = 0.5 * mass * start_rate * start_rate + _potential(k, n, mass, g, start_z)
    potential = _potential(k, n, mass, g, z)
    if not 0.5 * mass * zdot * zdot + potential > e_start:
        return zdot
    return math.copysign(math.sqrt(max(2.0 * (e_start - potential) / mass, 0.0)), zdot)


@njit(**_KW)
def _pieces(pc):
    """A commanded plate's pieces as ``compiled_flight`` takes them: (starts, p, ṗ, p̈) rows."""
    return pc[0], pc[1], pc[2], pc[3]


@njit(**_KW)
def _plate(tr, pc, t):
    """(p m, ṗ m/s, p̈ m/s²) of the plate at t (s), as its ``state`` (zeros: fixed)."""
    if tr[TR_MOVING] == TABLE:
        return _sinusoid(tr[TR_AMP], tr[TR_OMEGA], tr[TR_PHASE], t)
    if tr[TR_MOVING] == COMMANDED:
        return commanded_state(t, _pieces(pc))
    return 0.0, 0.0, 0.0


@njit(**_KW)
def _forcing_at(tr, pc, t):
    """(A m/s², until s): the amplitude of the plate's forcing of a phase starting at t (s) and
    where it ends, as ``PlateMotion.forcing_piece`` gives them (a commanded piece's constant p̈;
    A = 0: no forcing)."""
    if tr[TR_MOVING] == TABLE:
        return tr[TR_FORCE_AMP], math.inf
    if tr[TR_MOVING] == COMMANDED:
        return _piece_forcing(pc[0], pc[3], piece_index(pc[0], t), t)
    return 0.0, math.inf


@njit(**_KW)
def _set_forcing(tr, par, amplitude):
    """The forcing slots of the phase just started (its start and scales in ``par``): the
    table's sinusoid, or a commanded piece's constant A with the lift-off events of
    ``force_can_vanish_inside``."""
    if tr[TR_MOVING] == TABLE:
        set_plate_forcing(par, amplitude, tr[TR_OMEGA], tr[TR_PHASE])
    elif tr[TR_MOVING] == COMMANDED:
        vanishes = tr[TR_VANISHES] != 0.0 or _pulls_out(tr[TR_GRAVITY], amplitude)
        set_constant_forcing(par, amplitude, 2.0 if vanishes else 1.0)


@njit(**_KW)
def _start(tr, st, K, F, par, pts, pc, t, z, zdot):
    """Start a contact phase at t (s) from (z, ż) (m, m/s) with the plate's forcing there, as
    ``contact_phase`` does; False, with (z, ż) in ``tr``, where it is unforced and too stiff for
    the compiled integrator (``contact_phase`` hands it to ``PhaseIntegrator``)."""
    length, time, gamma, zeta = compiled_scales(tr[TR_K], tr[TR_LAM], tr[TR_MASS],
                                                tr[TR_GRAVITY], tr[TR_N], tr[TR_P], tr[TR_Q], z,
                                                zdot)
    amplitude, until = _forcing_at(tr, pc, t)
    if zeta > tr[TR_STIFF] and amplitude == 0.0:      # a forced phase is always compiled
        tr[TR_Z], tr[TR_RATE] = z, zdot
        return False
    peak = start_phase(par, st, K, F, t, z, zdot, length, time, gamma, zeta)
    _set_forcing(tr, par, amplitude)
    tr[TR_KNOT] = until
    tr[TR_CHUNK_LEFT], tr[TR_CHECKED] = 0.0, -1.0
    if tr[TR_KEEP] == 0.0:               # nobody reads the points of the phases ended
        tr[TR_NPTS] = tr[TR_EMITTED] = 0.0
    row = int(tr[TR_NPTS])
    pts[row, 0], pts[row, 1], pts[row, 2], pts[row, 3] = t, z, zdot, peak
    tr[TR_PHASE_ROW], tr[TR_NPTS] = row, row + 1
    tr[TR_STOP] = energy_stop(tr[TR_FLOOR], par)
    tr[TR_FLIGHT] = 0.0
    return True


@njit(**_KW)
def _touch(tr, st, K, F, par, pts, pc):
    """The flight touches at ``tr[TR_TOUCH]``: start the contact phase there (``impact``), or
    leave it to the Python path (False) if it is stiff."""
    g, t = tr[TR_GRAVITY], tr[TR_TOUCH]
    dt = t - tr[TR_START]
    y = tr[TR_Y0] + tr[TR_V0] * dt - 0.5 * g * dt * dt          # as Flight.absolute
    p, pv, _ = _plate(tr, pc, t)
    z, zdot = p - y, pv - (tr[TR_V0] - g * dt)
    if 0.0 > z:                                                  # as Flight.event_at_until
        z = 0.0
    if not _start(tr, st, K, F, par, pts, pc, t, z, zdot):
        return False
    tr[TR_T0], tr[TR_Z0], tr[TR_RATE0] = t, z, zdot
    tr[TR_F0] = pts[int(tr[TR_PHASE_ROW]), 3]
    tr[TR_REC_PEAK], tr[TR_REC_DEPTH] = 0.0, -math.inf      # as a new Contact's record
    return True


@njit(**_KW)
def _knot(tr, st, K, F, par, pts, pc):
    """The forcing changes at the knot ``tr[TR_KNOT]``: the same contact restarts there from the
    dense output (``Contact.advance``'s ``knot``, ``transitions.go_on``), its record carried
    (``Contact.record_until``: the peak force and depth of the points up to the knot), the
    points after the knot dropped; False, with the knot's (z, ż) in ``tr``, where the new phase
    is the Python path's (stiff)."""
    knot = tr[TR_KNOT]
    z, zdot = phase_state_at(st, K, F, par, knot)
    peak, depth = tr[TR_REC_PEAK], tr[TR_REC_DEPTH]
    end = int(tr[TR_NPTS])
    for row in range(int(tr[TR_PHASE_ROW]), int(tr[TR_NPTS])):
        if pts[row, 0] > knot:
            end = row
            break
        peak, depth = max(peak, pts[row, 3]), max(depth, pts[row, 1])
    tr[TR_REC_PEAK], tr[TR_REC_DEPTH] = peak, depth
    tr[TR_NPTS] = end
    tr[TR_EMITTED] = min(tr[TR_EMITTED], end)
    tr[TR_STEPS] += results_of(st)[2]                   # the phase ended (Mode's steps)
    tr[TR_TIME] = knot
    return _start(tr, st, K, F, par, pts, pc, knot, z, zdot)


@njit(**_KW)
def _lift_off(tr, st, imp, pc):
    """The phase lifted off: record the impact (``Contact._finish``, its record carried over
    the knots), plan the flight after it (``bounce``: ``Flight`` and the plate's
    ``plan_flight``)."""
    g, k, lam, n, p, q = tr[TR_GRAVITY], tr[TR_K], tr[TR_LAM], tr[TR_N], tr[TR_P], tr[TR_Q]
    _, t, z, end_rate = lift_off_of(st)
    peak, depth, steps = results_of(st)
    zdot = end_rate if tr[TR_MOVING] != FIXED else bounded_rate(k, n, tr[TR_MASS], g, tr[TR_Z0],
                                                              tr[TR_RATE0], z, end_rate)
    speed, rebound = max(tr[TR_RATE0], 0.0), max(-zdot, 0.0)
    row = int(tr[TR_NIMP])
    imp[row, 0], imp[row, 1], imp[row, 2] = tr[TR_T0], speed, rebound
    imp[row, 3] = rebound / speed if speed > 0.0 else 0.0
    imp[row, 4] = t - tr[TR_T0]
    imp[row, 5], imp[row, 6] = max(peak, tr[TR_REC_PEAK]), max(depth, tr[TR_REC_DEPTH])
    tr[TR_NIMP] = row + 1
    tr[TR_STEPS] += steps
    plate, plate_rate, _ = _plate(tr, pc, t)
    y0, v0 = plate - z, plate_rate - zdot                                # as Flight.__init__
    tr[TR_START], tr[TR_Y0], tr[TR_V0] = t, y0, v0
    tr[TR_FLIGHT] = 1.0
    if tr[TR_MOVING] != FIXED:          # as flights.table_flight and commanded_flight
        if tr[TR_MOVING] == TABLE:
            touch = sinusoid_touch_time(t, y0, v0, g, z, zdot, tr[TR_AMP], tr[TR_OMEGA],
                                        tr[TR_PHASE], k, lam, n - p, q, tr[TR_BOUND])
        else:
            touch = commanded_touch_time(t, y0, v0, g, z, zdot, pc[0], pc[1], pc[2], pc[3], k,
                                         lam, n - p, q, tr[TR_BOUND])
        imp[row, REC_APEX] = _rise_apex(y0, v0, g) if v0 > 0.0 else math.nan
        tr[TR_TOUCH] = touch
        return touch != NO_EXIT
    flight_time = ballistic_touch_time(z, zdot, g, k, lam, n - p, q)
    imp[row, REC_APEX] = (apex_height(t, flight_time, z, zdot, g) if math.isfinite(flight_time)
                          else math.nan)
    tr[TR_TOUCH] = t + flight_time
    return True


@njit(**_KW)
def _stop_before_run(tr, st, par, t_stop, max_steps, taken):
    """Where ``Contact.advance`` stops before a run of the phase's steps: TIME_REACHED once the
    phase reached ``t_stop`` (s), BUDGET_SPENT once ``max_steps`` are taken (at the phase's
    time), else -1; the time in ``tr[TR_TIME]``."""
    now = phase_time(st, par)
    if now >= t_stop:
        tr[TR_TIME] = t_stop
        return TIME_REACHED
    if taken >= max_steps:
        tr[TR_TIME] = now
        return BUDGET_SPENT
    return -1


@njit(**_KW)
def _carried_run(tr, st, K, F, par, pts, pc, t_stop, max_steps, taken, cap):
    """A contact phase on a moving plate as ``Contact.advance`` runs it with a ``CarryWatch``:
    the tests before a run of ``TR_CHUNK`` steps (the time, the budget, the carried state, which
    Python makes where p̈ > -g/4: CARRY_TEST), then the run up to the knot at the latest (the
    budget does not cut it).  Returns (reason to return, or -1 to go on, steps taken)."""
    if tr[TR_CHUNK_LEFT] <= 0.0:
        stop = _stop_before_run(tr, st, par, t_stop, max_steps, taken)
        if stop >= 0:
            return stop, taken
        now = phase_time(st, par)
        steps = results_of(st)[2]
        if _plate(tr, pc, now)[2] > -0.25 * tr[TR_GRAVITY] and tr[TR_CHECKED] != steps:
            tr[TR_CHECKED] = steps
            tr[TR_TIME] = now
            return CARRY_TEST, taken
        tr[TR_CHUNK_LEFT] = tr[TR_CHUNK]
    npts = int(tr[TR_NPTS])
    if npts >= cap:
        return BUFFER_FULL, taken
    reason, added, steps = run_phase(st, K, F, par, pts[npts:], min(t_stop, tr[TR_KNOT]),
                                     int(tr[TR_CHUNK_LEFT]), -math.inf)
    taken += steps
    tr[TR_NPTS] = npts + added
    if reason == BUFFER_FULL:            # the same run goes on at the next call
        tr[TR_CHUNK_LEFT] -= steps
        return BUFFER_FULL, taken
    tr[TR_CHUNK_LEFT] = 0.0
    if reason == STEP_TOO_SMALL:
        return reason, taken
    return -1, taken


@njit('UniTuple(int64, 2)(float64[::1], float64[::1], float64[:, ::1], float64[:, ::1], '
      'float64[::1], float64[:, ::1], float64[:, ::1], float64[:, ::1], float64, int64)', **_KW)
def run_train(tr, st, K, F, par, pts, imp, pc, t_stop, max_steps):
    """Bounce until ``t_stop`` (s) or another stop (module docstring), with at most
    ``max_steps`` integrator steps; returns (reason, steps taken): TIME_REACHED (in flight, or
    the phase reached ``t_stop`` or lifts off after it), BUDGET_SPENT, ENERGY_BELOW, BUFFER_FULL
    (``pts`` or ``imp``: make room and call again), STEP_TOO_SMALL, STIFF_PHASE or STIFF_KNOT
    (the touch or knot at ``tr[TR_TIME]``, (z, ż) in ``tr``, is the Python path's); the time
    reached in ``tr[TR_TIME]``, and in ``tr[TR_RAN]`` whether the phase's steps ran last
    (``Contact.advance`` tests the phase for permanence after each run, not at a stop before
    one)."""
    taken = 0
    cap = pts.shape[0] - 4
    tr[TR_RAN] = 0.0
    while True:
        if tr[TR_FLIGHT] != 0.0:
            if tr[TR_TOUCH] > t_stop:                       # as Mode.advance
                tr[TR_TIME] = t_stop
                return TIME_REACHED, taken
            if tr[TR_NPTS] >= cap:
                return BUFFER_FULL, taken
            if not _touch(tr, st, K, F, par, pts, pc):
                tr[TR_TIME] = tr[TR_TOUCH]
                return STIFF_PHASE, taken
            tr[TR_RAN] = 0.0
            continue
        lifted, end_time, _, _ = lift_off_of(st)
        knot = tr[TR_KNOT]
        if lifted and end_time <= knot:                     # as Contact.advance
            if end_time > t_stop:
                tr[TR_TIME] = t_stop
                return TIME_REACHED, taken
            if tr[TR_NIMP] >= imp.shape[0]:
                return BUFFER_FULL, taken
            if not _lift_off(tr, st, imp, pc):
                return NO_EXIT_FOUND, taken
            continue
        if (lifted or phase_time(st, par) >= knot) and knot <= t_stop:
            if not _knot(tr, st, K, F, par, pts, pc):
                return STIFF_KNOT, taken
            tr[TR_RAN] = 0.0
            continue
        if lifted:                  # beyond a knot beyond t_stop: the phase's time is past it
            tr[TR_TIME] = t_stop
            return TIME_REACHED, taken
        if tr[TR_MOVING] != FIXED:
            reason, taken = _carried_run(tr, st, K, F, par, pts, pc, t_stop, max_steps, taken,
                                         cap)
            if reason >= 0:
                return reason, taken
            continue
        stop = _stop_before_run(tr, st, par, t_stop, max_steps, taken)
        if stop >= 0:
            return stop, taken
        npts = int(tr[TR_NPTS])
        if npts >= cap:
            return BUFFER_FULL, taken
        reason, added, steps = run_phase(st, K, F, par, pts[npts:], t_stop, max_steps - taken,
                                         tr[TR_STOP])
        taken += steps
        tr[TR_NPTS] = npts + added
        tr[TR_RAN] = 1.0
        if reason == ENERGY_BELOW or reason == STEP_TOO_SMALL:
            tr[TR_TIME] = phase_time(st, par)
            return reason, taken
