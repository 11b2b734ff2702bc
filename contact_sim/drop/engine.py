"""A sphere dropped on a plate, bouncing until it rests: ``DropSimulation``, the steppable
event-driven engine (an explicit state machine: its modes, its transition table and how to add a
mode are described in the ``drop`` package's docstring); ``simulate.simulate_drop`` is one
batch run of it. Units: SI; z > 0 is penetration, ż > 0 is downward motion (approach).
"""
import math
from operator import attrgetter

import numpy as np

from contact_sim.drop.limits import (DROP_RTOL, MAX_TICKS, TIME_MAX, check_drop,
                                     require_gravity, require_gravity_for, require_height,
                                     require_mass, require_radius, require_velocity)
from contact_sim.flight import AirDrag
from contact_sim.drop.mode import NO_POINTS, Event
from contact_sim.drop.mode_carried import CHUNK
from contact_sim.drop.plate import as_plate
from contact_sim.drop.records import AdvanceResult, DropState, Recorder, Samples, TickBatch
from contact_sim.drop.transitions import TRANSITIONS, free_motion
from contact_sim.model import require_contact
from contact_sim.phase import PhaseFactory
from contact_sim.validation import (InputError, require_instance, require_int, require_range,
                                    require_real, require_rtol)

def _recorded(name, doc):
    """A read-only attribute ``name`` of the drop's ``recorder`` (``records.Recorder``)."""
    return property(attrgetter('recorder.' + name), doc=doc)


MAX_STEPS_PER_CALL = 10 ** 12     # integrator steps one advance call may be given


def _samples_of(points):
    """``Samples`` of the engine's points: a list of (n, 4) arrays of rows (t, z, ż, F)."""
    return Samples.from_points(np.concatenate(points))


def _step_budget(max_steps):
    """``max_steps`` of an advance call: ``None`` (no bound) or an integer 0..MAX_STEPS_PER_CALL."""
    return None if max_steps is None else require_int('max_steps', max_steps, 0,
                                                      MAX_STEPS_PER_CALL)


class DropSimulation:
    """A sphere dropped on a plate, bouncing until it rests: the steppable engine.

    Drag is neglected during contact (its impulse is at most κ v τc of the momentum,
    ``flight.contact_drag_impulse_ratio``: 2e-4 for a table-tennis ball at 3 m/s).  Also public:
    ``plate_motion`` (``plate.FIXED``: fixed), ``drag_rates`` (κ, β; ``None``: vacuum),
    ``pending_contact``, ``recorder`` (the ``records.Recorder`` behind ``impacts``, ...).

    Parameters
    ----------
    contact : Contact
        The contact (law, k, λ).
    mass, height : float
        The sphere's (reduced) mass, kg, 1e-12 to 1e9; its release height (lowest point above
        the plate, or above p(0) for a moving plate), m, 0 <= h <= 1e6.
    velocity, gravity : float, optional
        Release velocity (m/s, down, abs(v) <= 1e5; default 0) and g (m/s², 0 to 1e6; 9.81).
    rtol, settle_tolerance : float, optional
        The integrator's relative tolerance (1e-14 to 1e-3), and the amplitude about the static
        depth z0, as a share of z0, below which the rest is in closed form (0 < tol <= 1).
    radius, drag : optional
        The sphere's radius R1 (m: a contact too soft for it is refused, ``check_drop``); an
        ``AirDrag`` in flight, in closed form (needs g > 0; ``None``: vacuum).
    plate : PlateMotion, optional
        The plate's motion p(t) (``SinusoidalPlate``, ``CommandedPlate``; needs g > 0), z and
        ż then relative to it; ``None``: the fixed plate.

    Raises
    ------
    InputError
        Keyed by the argument out of its range (``limits``), or a drop ``check_drop`` refuses.

    Examples
    --------
    >>> import contact_sim as cs
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> sim = cs.DropSimulation(contact, cs.build_mass(sphere='steel', radius=0.0127), 0.1)
    >>> print(f"e = {sim.advance(0.2).impacts[0].restitution:.4f}, z = {sim.state.penetration:.4f}")
    e = 0.7236, z = -0.0419
    """

    PLATE_CHUNK = CHUNK     # contact steps between two tests for the carried state

    def __init__(self, contact, mass, height, velocity=0.0, gravity=9.81, rtol=DROP_RTOL,
                 settle_tolerance=1e-3, radius=None, drag=None, plate=None):
        self.mass = require_mass(mass)
        self.gravity = require_gravity(gravity)
        self.height = require_height(height)
        self.velocity = require_velocity(velocity)
        self.rtol = require_rtol('rtol', rtol)
        self.settle_tolerance = require_range('settle_tolerance', settle_tolerance, 0.0, 1.0,
                                              low_open=True)
        self.radius = None if radius is None else require_radius(radius)
        if drag is not None:
            require_instance('drag', drag, AirDrag, 'None or an AirDrag(air_density, '
                             'drag_coefficient, radius)')
        self.drag = drag if drag is not None and drag.active else None
        self.drag_rates = None
        if self.drag is not None:
            require_gravity_for('air drag', self.gravity)
            self.drag_rates = self.drag.rates(self.mass, self.gravity)
        self.plate_motion = self._moving_or_fixed(plate)
        self._initial_contact = require_contact(contact)
        self._phases = None
        self.reset()

    # -- public ---------------------------------------------------------------------------
    @property
    def plate(self):
        """The plate's motion (a ``plate.PlateMotion``), or ``None`` for the fixed plate."""
        return self.plate_motion if self.plate_motion.moving else None

    def reset(self, height=None, velocity=None, contact=None):
        """Restart at t = 0, optionally from a new height, velocity or contact.

        Parameters
        ----------
        height, velocity, contact : optional
            New release height (m), velocity (m/s, down) or ``Contact``; default: as before.
        """
        height = self.height if height is None else require_height(height)
        velocity = self.velocity if velocity is None else require_velocity(velocity)
        contact = self._initial_contact if contact is None else require_contact(contact)
        self.check(contact, height, velocity)
        self.height, self.velocity, self._initial_contact = height, velocity, contact
        self.contact = self._initial_contact
        self.pending_contact = None
        self.time = 0.0
        self.recorder = Recorder()
        rate = self.velocity + self.plate_motion.state(0.0)[1]
        self._mode = free_motion(self, 0.0, -self.height, rate)

    def phase_factory(self):
        """The maker of this drop's contact phases, for the contact in use.

        Returns
        -------
        PhaseFactory
            ``phase.PhaseFactory`` of ``contact``, the drop's mass, gravity and tolerances (made
            again when the contact changes).
        """
        factory = self._phases
        if factory is None or factory.contact is not self.contact:
            factory = self._phases = PhaseFactory(self.contact, self.mass, self.gravity,
                                                  self.rtol, self.rtol * 1e-2)
        return factory

    def check(self, contact, height=None, velocity=None, plate=False):
        """``check_drop`` of ``contact`` for this drop (its ``InputError``), changing nothing.

        Parameters
        ----------
        contact : Contact
            The contact to check.
        height, velocity : float, optional
            Release height (m) and velocity (m/s); default: the drop's initial conditions.
        plate : PlateMotion or None, optional
            The plate (default: the drop's own; ``None``: the fixed plate).
        """
        motion = self.plate_motion if plate is False else as_plate(plate)
        check_drop(contact, self.mass, self.gravity, self.height if height is None else height,
                   self.velocity if velocity is None else velocity, self.radius,
                   motion.speed_bound())

    def check_plate(self, plate):
        """The checks ``set_plate`` makes of ``plate`` (g > 0 if it moves, ``check`` with its peak
        speed of the contact and of one pending), changing nothing.

        Parameters
        ----------
        plate : PlateMotion or None
            The plate's motion; ``None``: the fixed plate.

        Returns
        -------
        PlateMotion or None
            ``plate`` as ``set_plate`` takes it (``None``: fixed).
        """
        new = self._moving_or_fixed(plate)
        for contact in (self.contact, self.pending_contact):
            if contact is not None:
                self.check(contact, plate=new)
        return new if new.moving else None

    def set_plate(self, plate):
        """Move the plate as ``plate`` from the current time on.

        The sphere's absolute height and velocity are unchanged at the switch; its state relative
        to the plate is recomputed from the new plate's p, ṗ now (the same if the motion is
        continuous: ``plate.table_transition`` and ``plate.command_motion`` make it so).  In
        flight the flight is re-entered from the new relative state; in a contact phase the phase
        restarts with the new forcing, the running impact's record carried across (no new impact);
        a resting or carried sphere starts a contact phase (no impact recorded).  The new plate
        is checked as ``check_plate`` does.

        Parameters
        ----------
        plate : PlateMotion or None
            The plate's motion; ``None``: fixed at p = 0.
        """
        self.check_plate(plate)
        new = as_plate(plate)
        t = self.time
        z, zdot = self._mode.state(t)
        p, pv = self.plate_motion.state(t)[:2]
        q, qv = new.state(t)[:2]
        z, zdot = z + (q - p), zdot + (qv - pv)     # y = p - z and v = ṗ - ż unchanged
        self.plate_motion = new
        self._follow(Event('set_plate', t, z, zdot))

    def set_contact(self, contact):
        """Use ``contact`` from the next contact phase on.

        At once in flight or at rest (a resting sphere then settles onto it), after lift-off
        during a bounce; checked (``check_drop``) against the drop's initial conditions, whose
        energy bounds the motion.  A contact phase it starts at rest is not recorded as an impact.

        Parameters
        ----------
        contact : Contact
            The new contact.
        """
        contact = require_contact(contact)
        self.check(contact)
        z, zdot = self._mode.state(self.time)
        self._follow(Event('set_contact', self.time, z, zdot, contact=contact))

    @property
    def state(self):
        """The ``DropState`` at the current ``time``."""
        return DropState(*self._state_row(self.time))

    def _state_row(self, t):
        """(t, z, ż, F, p, ṗ) at a time t of the current mode, as floats."""
        z, zdot = self._mode.state(t)
        p, pv = self.plate_motion.state(t)[:2]
        return (float(t), float(z), float(zdot), self.contact.force_at(z, zdot), float(p),
                float(pv))

    @property
    def in_contact(self):
        """True while a contact phase or the rest holds the sphere on the plate."""
        return self._mode.in_contact

    @property
    def carried(self):
        """True while the plate carries the sphere (the quasi-static state)."""
        return self._mode.carried

    impacts = _recorded('impacts', 'The ``ImpactRecord`` of each contact phase completed (a list).')
    apex_heights = _recorded('apex_heights', 'The apex height (m) of each flight begun after a '
                             'lift-off (a list).')
    steps = _recorded('steps', 'Integrator steps of the contact phases ended (``total_steps``: the '
                      'current one too).')
    permanent_contact_time = _recorded('permanent_contact_time', 'When the landing for good '
                                       'began (s), or ``None``.')
    settle_time = _recorded('settle_time', 'When the closed-form rest took over (s), or ``None``.')

    @property
    def total_steps(self):
        """Integrator steps so far, the current contact phase included."""
        return self.recorder.steps + self._mode.steps

    def plate_samples(self, samples):
        """The plate's motion at the times of ``samples``.

        Parameters
        ----------
        samples : Samples
            Samples of this drop.

        Returns
        -------
        tuple of numpy.ndarray
            (p m, ṗ m/s, p̈ m/s²) per sample (zeros for the fixed plate).
        """
        return self.plate_motion.samples(np.asarray(samples.time, dtype=float))

    def advance(self, t_end, max_steps=None):
        """Advance to ``t_end``; return the contact points passed and the impacts completed.

        Parameters
        ----------
        t_end : float
            The time to reach, s, ``time`` <= t_end <= 1e9.
        max_steps : int, optional
            Integrator steps allowed in this call, 0 to ``MAX_STEPS_PER_CALL`` (default: no
            bound): stop early once they are taken (then ``time < t_end``; call again to go on).

        Returns
        -------
        AdvanceResult
            The contact points passed (the state reached last), impacts completed, apexes.

        Raises
        ------
        InputError
            Keyed ``t_end`` (before ``time`` or beyond 1e9 s) or ``max_steps``.
        """
        points = []
        n_impacts, n_apex = len(self.impacts), len(self.apex_heights)
        self._advance(t_end, max_steps, points)
        state = self.state
        points.append(np.array(((self.time, state.penetration, state.penetration_rate,
                                 state.force),)))
        impacts = tuple(self.impacts[n_impacts:])
        apexes = tuple(self.apex_heights[n_apex:])
        return AdvanceResult(_samples_of(points), impacts, apexes)

    def run_to(self, t_end, max_steps=None):
        """``advance`` without gathering the contact points passed: for a caller that reads only
        the impacts, apexes and state (``simulate_drop`` without ``sample_rate``, the vibrating
        table's orbits), which then does not pay for them.

        Parameters
        ----------
        t_end : float
            The time to reach, s, ``time`` <= t_end <= 1e9.
        max_steps : int, optional
            Integrator steps allowed in this call, as in ``advance``.

        Raises
        ------
        InputError
            Keyed ``t_end`` or ``max_steps``, as in ``advance``.

        Examples
        --------
        >>> import contact_sim as cs
        >>> from contact_sim.drop import DropSimulation
        >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
        ...                                     radius=0.0127, damping_factor=8.87e5)
        >>> sim = DropSimulation(contact, cs.build_mass(sphere='steel', radius=0.0127), 0.1)
        >>> sim.run_to(0.5)
        >>> print(f"{len(sim.impacts)} impacts by t = {sim.time:.1f} s")
        2 impacts by t = 0.5 s
        """
        self._advance(t_end, max_steps, NO_POINTS)

    def _advance(self, t_end, max_steps, points):
        """``advance``'s motion: the contact points passed go to ``points`` (a list, as (n, 4)
        arrays of rows; ``NO_POINTS``: none gathered)."""
        t_end = require_real('t_end', t_end)
        if not self.time <= t_end <= TIME_MAX:
            allowed = ('{n[t_end]} >= %r' % self.time if t_end < self.time
                       else '{n[t_end]} <= %g s' % TIME_MAX)
            raise InputError('t_end', t_end, '{n[t_end]} = {value} is out of range: allowed '
                             + allowed)
        max_steps = _step_budget(max_steps)
        budget = math.inf if max_steps is None else max_steps
        while True:
            move = self._mode.advance(self, t_end, budget, points)
            if move.event is None:
                break
            budget = move.budget
            self._follow(move.event)
        self.time = move.time

    def _tick_times(self, times):
        """``times`` of ``advance_ticks`` as a float array (1-D, <= ``MAX_TICKS``, finite,
        non-decreasing, ``time`` to ``TIME_MAX`` s), or ``InputError`` keyed ``times``."""
        try:
            arr = np.asarray(times, dtype=float)
        except (TypeError, ValueError):
            arr = None
        if arr is None or arr.ndim != 1 or not np.isfinite(arr).all():
            raise InputError('times', times, '{n[times]} must be a 1-D array of finite tick times '
                             '(s)')
        if arr.size > MAX_TICKS:
            raise InputError('times', arr.size, '{n[times]} has %d tick times: allowed at most %d '
                             'a call' % (arr.size, MAX_TICKS))
        if arr.size and (arr[0] < self.time or arr[-1] > TIME_MAX
                         or (arr[1:] < arr[:-1]).any()):
            raise InputError('times', float(arr[0]), '{n[times]} = %.17g ... %.17g is out of range: '
                             'allowed non-decreasing times with %.17g <= {n[times]} <= %g s'
                             % (arr[0], arr[-1], self.time, TIME_MAX))
        return arr

    def _follow(self, event):
        """The mode that ``event`` of the current mode leads to (``transitions.TRANSITIONS``);
        the integrator steps of a mode left go to the record."""
        mode = self._mode
        new = TRANSITIONS[type(mode), event.name](self, mode, event)
        if new is not mode:
            steps = mode.steps
            if steps:
                self.recorder.left(steps)
            self._mode = new

    def advance_ticks(self, times, max_steps=None):
        """Advance through many tick end times in one call, as arrays.

        The same motion, points and impacts as ``advance(t)`` at each tick time in turn: a
        stretch of closed-form motion (flight, rest, carried, plate flight) up to its next event
        is evaluated for all its ticks at once (the fixed plate's flight and rest: the same
        operations as the scalar path, equal to round-off); a tick with a contact goes through
        ``advance``.

        Parameters
        ----------
        times : array_like of float
            Tick end times, s, 1-D, non-decreasing, from ``time`` to 1e9, at most 1e6 a call.
        max_steps : int, optional
            Integrator steps allowed in this call, 0 to 1e12 (default: no bound): stop at the
            first tick that needs integration once they are taken (or inside a tick, as
            ``advance`` does); ``TickBatch.ticks`` says how far it got.

        Returns
        -------
        TickBatch
            Each tick end's state, the contact points passed and the impacts completed.
        """
        times = self._tick_times(times)
        n = times.size
        ends = np.zeros((6, n))
        pieces, piece_ticks, impacts, impact_ticks, apexes = [], [], [], [], []
        max_steps = _step_budget(max_steps)
        budget = math.inf if max_steps is None else max_steps
        i = 0
        while i < n:
            until = self._mode.until
            j = i + int(np.searchsorted(times[i:], until, side='left'))
            if j > i:
                self._closed_form_ends(times[i:j], ends[:, i:j])
                self.time = float(times[j - 1])
                i = j
                continue
            if budget <= 0:
                break
            before = self.total_steps
            advance = self.advance(float(times[i]), max_steps=None if math.isinf(budget)
                                   else budget)
            budget -= self.total_steps - before
            samples = advance.samples
            reached = self.time >= times[i]
            m = samples.time.size - 1 if reached else samples.time.size
            if m:
                pieces.append(np.stack([samples.time[:m], samples.penetration[:m],
                                        samples.penetration_rate[:m], samples.force[:m]]))
                piece_ticks.append(np.full(m, i))
            impacts.extend(advance.impacts)
            impact_ticks.extend([i] * len(advance.impacts))
            apexes.extend(advance.apex_heights)
            if not reached:
                break
            ends[:, i] = self._state_row(self.time)
            i += 1
        points = np.concatenate(pieces, axis=1) if pieces else np.empty((4, 0))
        return TickBatch(i, *(ends[k, :i] for k in range(6)), Samples(*points),
                         np.concatenate(piece_ticks) if piece_ticks else np.empty(0, int),
                         tuple(impacts), np.array(impact_ticks, dtype=int), tuple(apexes))

    def _closed_form_ends(self, t, out):
        """States (t, z, ż, F, p, ṗ) at times t of the closed-form motion, into ``out``'s rows:
        vectorised (``Mode.states``, ``PlateMotion.states``) beyond 8 ticks, else one by one."""
        states = self._mode.states(t) if t.size > 8 else None
        plate = self.plate_motion.states(t) if states is not None else None
        if plate is not None:
            out[0], out[1], out[2] = t, states[0], states[1]
            out[3] = self.contact.force(out[1], out[2])
            out[4], out[5] = plate
            return
        for k, tk in enumerate(t.tolist()):
            out[:, k] = self._state_row(tk)

    def _moving_or_fixed(self, plate):
        """``plate`` as the engine takes it (``plate.as_plate``); a moving plate needs g > 0."""
        motion = as_plate(plate)
        if motion.moving:
            require_gravity_for('a moving plate', self.gravity)
        return motion
