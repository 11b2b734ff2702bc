"""A sphere dropped on a plate, bouncing until it rests: an event-driven, steppable engine.

The motion alternates between three kinds of phase:

* flight (the clamped force is zero): ballistic, z(t) = z₀ + ż₀ t + ½ g t², solved in closed form
  with no integrator steps, including the time at which the force switches on again;
* contact: integrated exactly by ``phase.PhaseIntegrator`` up to the located lift-off;
* rest: once the energy above static equilibrium is too small for the force ever to vanish again
  (permanent contact) and the oscillation amplitude about the static deflection
  z₀ = (m g / k)^(1/n) has decayed below ``settle_tolerance * z₀``, the motion is the linearised
  damped oscillator about z₀, in closed form, so a resting sphere costs nothing to advance.

``DropSimulation.advance(t)`` moves to time t and returns what happened on the way, so the same
engine serves a batch run (``simulate_drop``) and a real-time loop.  Units: SI; z > 0 is
penetration, ż > 0 is downward motion (approach), height above the plate is -z.
"""
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from contact_sim.drop import plate as plate_motion
from contact_sim.model import require_contact
from contact_sim.flight import FlightPath
from contact_sim.phase import PhaseIntegrator, contact_phase, lift_off_energy, phase_scales
from contact_sim.validation import (InputError, require_int, require_positive, require_range, require_real,
                         require_rtol)

DROP_RTOL = 1e-10

# The ranges of a drop's arguments (SI).  Outside them the doubles of the model overflow or the
# contact cannot be resolved in time; every bound is stated in the refusal.
MASS_RANGE = (1e-12, 1e9)            # kg
GRAVITY_MAX = 1e6                    # m/s²
HEIGHT_MAX = 1e6                     # m
VELOCITY_MAX = 1e5                   # m/s, either direction
DURATION_MAX = 1e9                   # s
SAMPLE_RATE_MAX = 1e7                # Hz
MAX_SAMPLES = 200_000                # trajectory samples of one simulate_drop call (~7 s)
MAX_STEPS = 100_000                  # integrator steps of one simulate_drop call (~10 s)
CONTACT_TIME_MIN = 1e-12             # s: the contact's time scale T
CONTACT_LENGTH_MAX = 1e3             # m: the contact's length scale Z (the depth it reaches)
DAMPING_GROUP_MAX = 1e8              # ζ: beyond it a contact is a creep that never ends in time


def _require_gravity_for(what, gravity):
    """Drag flights and a moving plate's flights are solved under gravity: g > 0."""
    if not gravity > 0.0:
        raise InputError('gravity', gravity, '{n[gravity]} = {value} is out of range with %s: '
                         'allowed 0 < {n[gravity]} (its flights are solved under gravity), or '
                         'no %s' % (what, what))


def _first_impact_speed(gravity, height, velocity):
    """Speed (m/s) at the first touch, √(v0² + 2 g h); 0 if the sphere never lands."""
    if gravity == 0.0:
        return max(velocity, 0.0)
    return math.sqrt(velocity * velocity + 2.0 * gravity * height)


def check_drop(contact, mass, gravity, height, velocity, radius=None, plate_speed=0.0):
    """Refuse a drop the engine cannot follow, or one outside the contact model's validity.

    With a moving plate of peak speed ``plate_speed`` (m/s, ``PlateMotion.speed_bound``) an
    impact can be faster by up to that: the checks below take v1 + ``plate_speed`` as the
    impact speed (a vibrating table that pumps the sphere higher still can exceed it).

    * the contact's time scale T (at the first impact, and at rest under gravity) must be at
      least ``CONTACT_TIME_MIN``, and its damping group ζ at most ``DAMPING_GROUP_MAX`` (a
      larger ζ is a creep of the sphere into the plate far slower than any drop);
    * with the sphere ``radius`` R (m): the undamped sphere must not sink deeper than R, where
      no contact law here applies.  The first impact at v1 = √(v0² + 2 g h) stops undamped at
      the depth z with k z^(n+1)/(n+1) = m v1²/2 + m g z, so z <= R holds when
      k >= (n+1)(m v1²/2 + m g R)/R^(n+1); damping only makes z smaller, so this bound is
      sufficient (and independent of λ).

    Raises ``InputError`` keyed ``stiffness`` or ``damping`` whose reason gives the bounds.
    """
    speed = _first_impact_speed(gravity, height, velocity) + plate_speed
    if speed == 0.0 and gravity == 0.0:
        return                      # never lands: nothing to check
    law, k, lam = contact.law, contact.stiffness, contact.damping
    n = law.n
    regimes = []
    try:
        if speed > 0.0:
            regimes.append(phase_scales(contact, mass, 0.0, 0.0, speed))
        if gravity > 0.0:
            z0 = contact.static_penetration(mass * gravity)
            regimes.append(phase_scales(contact, mass, gravity, z0, 0.0))
    except ArithmeticError:
        regimes = []
    deepest = max((sc.length for sc in regimes), default=math.inf)
    if not deepest <= CONTACT_LENGTH_MAX:
        # Z ∝ k^(-1/(n+1)) at an impact, (m g / k)^(1/n) at rest
        k_min = max(mass * speed ** 2 / CONTACT_LENGTH_MAX ** (n + 1.0),
                    mass * gravity / CONTACT_LENGTH_MAX ** n)
        raise InputError('stiffness', k, '{n[stiffness]} = {value} N/m^%g is too small for a '
                         '%.4g kg sphere: it would sink %s into the plate; allowed '
                         '{n[stiffness]} >= %.4g N/m^%g (contact length scale <= %g m)'
                         % (n, mass, 'without bound' if math.isinf(deepest) else
                            '~%.3g m' % deepest, k_min, n, CONTACT_LENGTH_MAX))
    shortest = min(sc.time for sc in regimes)
    if not shortest >= CONTACT_TIME_MIN:
        # T ∝ k^(-1/(n+1)) at an impact (Z = (m v²/k)^(1/(n+1)), T = Z/v), ∝ k^(-1/(2n)) at rest
        exponent = 1.0 / (n + 1.0) if speed > 0.0 else 0.5 / n
        k_max = k * (shortest / CONTACT_TIME_MIN) ** (1.0 / exponent)
        raise InputError('stiffness', k, '{n[stiffness]} = {value} N/m^%g is too large for a '
                         '%.4g kg sphere: its contact would last ~%.3g s, beyond what the engine '
                         'resolves; allowed {n[stiffness]} <= %.4g N/m^%g (contact time scale '
                         '>= %g s), or a larger {n[mass]}'
                         % (n, mass, shortest, k_max, n, CONTACT_TIME_MIN))
    largest = max(sc.damping for sc in regimes)
    if largest > DAMPING_GROUP_MAX:
        lam_max = lam * DAMPING_GROUP_MAX / largest
        raise InputError('damping', lam, '{n[damping]} = {value} is too large for this drop: '
                         'the damping group would be zeta = %.3g and the sphere would creep '
                         'into the plate for ages; allowed {n[damping]} <= %.4g (zeta <= %g)'
                         % (largest, lam_max, DAMPING_GROUP_MAX))
    if radius is None or speed == 0.0 and gravity == 0.0:
        return
    minimum = (n + 1.0) * (0.5 * mass * speed ** 2 + mass * gravity * radius) / radius ** (n + 1.0)
    if k >= minimum:
        return
    allowed = '{n[stiffness]} >= %.4g N/m^%g' % (minimum, n)
    # or, with this k, the highest drop: m v1²/2 <= k R^(n+1)/(n+1) - m g R
    top_speed_sq = 2.0 * (k * radius ** (n + 1.0) / (n + 1.0) - mass * gravity * radius) / mass
    if plate_speed > 0.0:   # the sphere's own share of the impact speed
        top_speed_sq = max(math.sqrt(max(top_speed_sq, 0.0)) - plate_speed, 0.0) ** 2
    if gravity > 0.0 and top_speed_sq > velocity ** 2:
        allowed += ' or {n[height]} <= %.4g m' % ((top_speed_sq - velocity ** 2) / (2.0 * gravity))
    if plate_speed > 0.0:
        allowed += ' (with the plate moving at up to %.4g m/s)' % plate_speed
    raise InputError('stiffness', k, '{n[stiffness]} = %.4g N/m^%g is too small for this drop: '
                     'a %.4g kg sphere hitting at %.4g m/s would sink more than its radius '
                     '(%g m) into the plate, where no contact law here applies; allowed %s'
                     % (k, n, mass, speed, radius, allowed))


@dataclass(frozen=True)
class DropState:
    """The sphere at one instant: time (s), penetration z (m), rate ż (m/s), force F (N).

    With a moving plate z = p - y is relative to the plate's surface at height p (m, moving at
    ṗ m/s): ``plate_position``, ``plate_velocity``; F acts up on the sphere, -F on the plate."""

    time: float
    penetration: float
    penetration_rate: float
    force: float
    plate_position: float = 0.0
    plate_velocity: float = 0.0

    @property
    def plate_force(self):
        """The contact's reaction on the plate (N, up positive): -F."""
        return -self.force

    @property
    def in_contact(self):
        return self.force > 0.0


@dataclass(frozen=True)
class Samples:
    """Sampled trajectory: equal-length arrays of t (s), z (m), ż (m/s) and F (N).

    F is the force on the sphere (up); ``plate_force`` = -F is its reaction on the plate.  With a
    moving plate, z and ż are relative to the plate; ``DropSimulation.plate_samples`` gives p, ṗ.
    """

    time: np.ndarray
    penetration: np.ndarray
    penetration_rate: np.ndarray
    force: np.ndarray

    @classmethod
    def from_points(cls, points):
        arr = np.asarray(points, dtype=float).reshape(-1, 4)
        return cls(*(arr[:, i].copy() for i in range(4)))

    @classmethod
    def concatenate(cls, parts):
        return cls(*(np.concatenate([getattr(p, f) for p in parts]) if parts else np.empty(0)
                     for f in ('time', 'penetration', 'penetration_rate', 'force')))

    @property
    def plate_force(self):
        """The reaction on the plate (N, up positive): -F."""
        return -self.force


@dataclass(frozen=True)
class ImpactRecord:
    """One contact phase: when it began (s), speeds (m/s), restitution, duration (s), peak (N).

    The final, permanent contact has rebound_speed = restitution = 0 and contact_duration = inf.
    """

    time: float
    impact_speed: float
    rebound_speed: float
    restitution: float
    contact_duration: float
    peak_force: float
    max_penetration: float

    @property
    def permanent(self):
        return math.isinf(self.contact_duration)


@dataclass(frozen=True)
class Advance:
    """What one ``DropSimulation.advance`` call produced."""

    samples: Samples
    impacts: tuple
    apex_heights: tuple = ()


@dataclass(frozen=True)
class TickBatch:
    """What one ``DropSimulation.advance_ticks`` call produced, as arrays (SI units).

    ``ticks`` tick times of the call were reached (the first ``ticks``; fewer than asked when the
    step budget ran out).  Per tick reached, its end's state: ``time`` (s), ``penetration`` z
    (m), ``penetration_rate`` ż (m/s), ``force`` F (N, on the sphere; -F on the plate),
    ``plate_position`` p (m) and ``plate_velocity`` ṗ (m/s) (0 for the fixed plate), the same
    numbers as ``DropSimulation.state`` after ``advance`` to that time.  ``points`` (``Samples``)
    are the contact points passed, in time order, without the tick ends; ``point_tick[i]`` is the
    index of the tick point i belongs to (``ticks`` for the points of the tick the budget stopped
    in: its last point is the state reached, as ``advance`` returns it).  ``impacts`` completed,
    with ``impact_tick`` (the same indexing), and the ``apex_heights`` of the flights begun.
    """

    ticks: int
    time: np.ndarray
    penetration: np.ndarray
    penetration_rate: np.ndarray
    force: np.ndarray
    plate_position: np.ndarray
    plate_velocity: np.ndarray
    points: Samples
    point_tick: np.ndarray
    impacts: tuple
    impact_tick: np.ndarray
    apex_heights: tuple = ()


def _rest_states(rest, t):
    """``_Rest.state`` over an array of times t (s), with the same operations."""
    dt = t - rest.start
    a, w0sq = rest.decay, rest.natural_sq
    disc = w0sq - a * a
    if disc > 0.0:
        w = math.sqrt(disc)
        e = np.exp(-a * dt)
        ec, es = e * np.cos(w * dt), e * np.sin(w * dt) / w
    elif disc < 0.0:
        w = math.sqrt(-disc)
        slow, fast = np.exp((w - a) * dt), np.exp(-(w + a) * dt)
        ec, es = 0.5 * (slow + fast), 0.5 * (slow - fast) / w
    else:
        e = np.exp(-a * dt)
        ec, es = e, e * dt
    y = rest.offset * ec + (rest.rate + a * rest.offset) * es
    v = rest.rate * ec - (a * rest.rate + w0sq * rest.offset) * es
    return rest.rest_depth + y, v


@dataclass
class _Flight:
    start: float
    penetration: float
    rate: float
    contact_time: float  # absolute time the force switches on again (inf: never)
    path: FlightPath = None  # with air drag: the closed-form flight (height y = -z)

    def state(self, t, gravity):
        dt = t - self.start
        if self.path is not None:
            y, v = self.path.state(dt)
            return -y, -v
        return (self.penetration + self.rate * dt + 0.5 * gravity * dt * dt,
                self.rate + gravity * dt)


@dataclass
class _Rest:
    """Linearised damped oscillation about the static deflection, in closed form."""

    start: float
    rest_depth: float
    offset: float
    rate: float
    decay: float      # a = c / 2m
    natural_sq: float  # ω₀² = k' / m

    def state(self, t):
        dt = t - self.start
        a, w0sq = self.decay, self.natural_sq
        disc = w0sq - a * a
        if disc > 0.0:                      # underdamped
            w = math.sqrt(disc)
            e = math.exp(-a * dt)
            ec, es = e * math.cos(w * dt), e * math.sin(w * dt) / w
        elif disc < 0.0:                    # overdamped: e^(-a t) cosh, sinh without overflow
            w = math.sqrt(-disc)            # w < a
            slow, fast = math.exp((w - a) * dt), math.exp(-(w + a) * dt)
            ec, es = 0.5 * (slow + fast), 0.5 * (slow - fast) / w
        else:                               # critically damped
            e = math.exp(-a * dt)
            ec, es = e, e * dt
        y = self.offset * ec + (self.rate + a * self.offset) * es
        v = self.rate * ec - (a * self.rate + w0sq * self.offset) * es
        return self.rest_depth + y, v


@dataclass
class _Contact:
    """A contact phase in progress: its integrator and what the drop engine knows of it."""

    integrator: PhaseIntegrator
    floor: float              # below this energy above rest the force can never vanish (J)
    permanent: bool = False
    rest: _Rest = None        # set when the oscillation has decayed: the closed form takes over
    resumed: bool = False     # started by set_contact with the sphere inside: not an impact
    record: int = None        # index in impacts of this phase's permanent-contact record
    # with a moving plate: the forcing is exact until ``valid_until`` (s), where the phase is
    # restarted; ``first_point``, ``peak`` and ``depth`` carry the contact's record across
    valid_until: float = math.inf
    first_point: tuple = None
    peak: float = 0.0
    depth: float = -math.inf

    @property
    def finish_time(self):
        """When the phase ends (lift-off or the switch to rest), or ``None`` if not yet known."""
        if self.integrator.lifted_off:
            return self.integrator.end[0]
        return self.rest.start if self.rest is not None else None


@dataclass
class _PlateFlight(_Flight):
    """A flight over a moving plate: the sphere's absolute path (lowest point at height y0 (m),
    moving up at v0 (m/s) at ``start``; drag if ``path``), and z = p(t) - y(t) relative."""

    plate: object = None
    y0: float = 0.0
    v0: float = 0.0

    def absolute(self, t, gravity):
        dt = t - self.start
        if self.path is not None:
            return self.path.state(dt)
        return self.y0 + self.v0 * dt - 0.5 * gravity * dt * dt, self.v0 - gravity * dt

    def state(self, t, gravity):
        y, v = self.absolute(t, gravity)
        p, pv, _ = self.plate.state(t)
        return p - y, pv - v


@dataclass
class _Carried:
    """The sphere carried by the plate (plate acceleration above -g/2): quasi-static, the depth
    z_s(t) = (m (g + p̈(t)) / k)^(1/n) at which the contact force carries the sphere along, until
    ``until`` (s): the plate's acceleration falls to -g/2, or a set-point knot changes it."""

    start: float
    until: float
    plate: object
    contact: object
    mass: float
    gravity: float

    def state(self, t):
        # the acceleration of the carried stretch: at ``until`` its left limit (a knot)
        _, _, acc = self.plate.state(min(t, math.nextafter(self.until, -math.inf)))
        load = self.mass * max(self.gravity + acc, 0.0)
        z = self.contact.static_penetration(load)
        jerk = self.plate.jerk(t) if hasattr(self.plate, 'jerk') else 0.0
        rate = z * jerk / (self.contact.law.n * (self.gravity + acc)) if load > 0.0 else 0.0
        return z, rate


def _first_upward_root(func, t_max, samples=64):
    """First t in (0, t_max] where ``func`` goes from <= 0 to > 0; ``None`` if none is seen."""
    ts = np.linspace(0.0, t_max, samples + 1)
    prev_t, prev_v = ts[0], func(ts[0])
    for t in ts[1:]:
        v = func(t)
        if v > 0.0 and prev_v <= 0.0:
            return brentq(func, prev_t, t, xtol=1e-18, rtol=1e-15)
        prev_t, prev_v = t, v
    return None


class DropSimulation:
    """A sphere of mass ``mass`` (kg) released ``height`` (m) above a plate at ``velocity``
    (m/s, downward positive), under ``gravity`` (m/s²), with a ``Contact``.

    ``advance(t)`` integrates to time t; ``state`` is the state at the current time;
    ``set_contact`` changes the contact from the next contact phase on; ``reset`` restarts.

    ``drag`` (a ``flight.AirDrag``, default ``None``: vacuum) slows the flights, still in closed
    form (``flight.FlightPath``); it needs gravity > 0.  Drag is neglected during contact: its
    impulse there is at most κ v τc of the momentum (``flight.contact_drag_impulse_ratio``), e.g.
    2e-4 for a table-tennis ball at 3 m/s.

    ``plate`` (a ``plate.PlateMotion``: ``SinusoidalPlate``, ``CommandedPlate``; default
    ``None``, the fixed plate) moves the plate's surface to height p(t): ``height`` is then above
    p(0), ``velocity`` the sphere's own downward velocity, and z, ż are relative to the plate
    (``plate`` module).  Flights end at the first root of the gap, bracketed rigorously
    (``plate.first_gap_root``); contacts take the plate's acceleration as forcing (compiled
    engine); a sphere the plate carries is advanced quasi-statically (``_Carried``) while the
    plate's acceleration is above -g/2.  A plate that does not move is today's fixed plate.
    """

    def __init__(self, contact, mass, height, velocity=0.0, gravity=9.81, rtol=DROP_RTOL,
                 settle_tolerance=1e-3, radius=None, drag=None, plate=None):
        self.mass = require_range('mass', mass, *MASS_RANGE, unit='kg')
        self.gravity = require_range('gravity', gravity, 0.0, GRAVITY_MAX, unit='m/s^2')
        self.height = _height(height)
        self.velocity = _velocity(velocity)
        self.rtol = require_rtol('rtol', rtol)
        self.settle_tolerance = require_range('settle_tolerance', settle_tolerance, 0.0, 1.0,
                                              low_open=True)
        self.radius = None if radius is None else require_positive('radius', radius)
        self.drag = drag if drag is not None and drag.active else None
        if self.drag is not None:
            _require_gravity_for('air drag', self.gravity)
            self._drag_rates = self.drag.rates(self.mass, self.gravity)
        self.plate = plate_motion.plate_or_none(plate)
        if self.plate is not None:
            _require_gravity_for('a moving plate', self.gravity)
        self._initial_contact = require_contact(contact)
        self.reset()

    # -- public ---------------------------------------------------------------------------
    def reset(self, height=None, velocity=None, contact=None):
        """Restart at t = 0 (optionally from a new height, velocity or contact)."""
        height = self.height if height is None else _height(height)
        velocity = self.velocity if velocity is None else _velocity(velocity)
        contact = self._initial_contact if contact is None else require_contact(contact)
        self.check(contact, height, velocity)
        self.height, self.velocity, self._initial_contact = height, velocity, contact
        self.contact = self._initial_contact
        self._pending_contact = None
        self.time = 0.0
        self.steps = 0
        self.impacts = []
        self.apex_heights = []
        self.permanent_contact_time = None
        self.settle_time = None
        self._emitted = 0
        self._mode = None
        rate = self.velocity + (self.plate.state(0.0)[1] if self.plate is not None else 0.0)
        self._enter_free_motion(0.0, -self.height, rate)

    def check(self, contact, height=None, velocity=None, plate=False):
        """``check_drop`` of ``contact`` for this drop (its initial conditions by default) over
        ``plate`` (default: the drop's own plate; ``None``: the fixed plate)."""
        plate = self.plate if plate is False else plate
        check_drop(contact, self.mass, self.gravity, self.height if height is None else height,
                   self.velocity if velocity is None else velocity, self.radius,
                   plate.speed_bound() if plate is not None else 0.0)

    def check_plate(self, plate):
        """The checks ``set_plate`` makes of ``plate`` (gravity > 0 for a moving plate, and
        ``check`` with its peak speed, of the contact and of one waiting for the next contact
        phase); returns it as ``set_plate`` takes it (``None``: fixed)."""
        new = plate_motion.plate_or_none(plate)
        if new is not None:
            _require_gravity_for('a moving plate', self.gravity)
        for contact in (self.contact, self._pending_contact):
            if contact is not None:
                self.check(contact, plate=new)
        return new

    def set_plate(self, plate):
        """Move the plate as ``plate`` (a ``plate.PlateMotion``, or ``None``: fixed at p = 0)
        from the current time on.

        The sphere's absolute height and velocity are unchanged at the switch; its state relative
        to the plate is recomputed from the new plate's p, ṗ now (the same if the motion is
        continuous: ``plate.table_transition`` and ``plate.command_motion`` make it so).  In
        flight the flight is re-entered from the new relative state; in a contact phase the phase
        restarts with the new forcing, the running impact's record carried across (no new impact);
        a resting or carried sphere starts a contact phase (no impact recorded).  The new plate
        is checked as ``check`` does, with its peak speed.
        """
        new = self.check_plate(plate)
        t, mode = self.time, self._mode
        z, zdot = self._state_at(t)
        p, pv = self.plate.state(t)[:2] if self.plate is not None else (0.0, 0.0)
        q, qv = new.state(t)[:2] if new is not None else (0.0, 0.0)
        z, zdot = z + (q - p), zdot + (qv - pv)     # y = p - z and v = ṗ - ż unchanged
        if isinstance(mode, _Contact) and not mode.permanent and mode.rest is None:
            phase = mode.integrator
            kept = [pt for pt in phase.points if pt[0] <= t]
            self.steps += phase.steps
            record = (mode.first_point or phase.points[0],
                      max([mode.peak] + [pt[3] for pt in kept]),
                      max([mode.depth] + [pt[1] for pt in kept]))
            self.plate = new
            # the same contact phase goes on: a contact waiting for the next one still waits
            pending, self._pending_contact = self._pending_contact, None
            self._begin_contact(t, z, zdot, resumed=mode.resumed)
            self._pending_contact = pending
            fresh = self._mode
            fresh.first_point, fresh.peak, fresh.depth = record
            return
        if isinstance(mode, _Contact):
            self.steps += mode.integrator.steps
        self.plate = new
        if isinstance(mode, _Flight):
            self._enter_free_motion(t, z, zdot, resumed=True)
        else:       # resting, carried, or a permanent contact settling
            self._begin_contact(t, z, zdot, resumed=True)

    def set_contact(self, contact):
        """Use ``contact`` from the next contact phase on: at once in flight or at rest (a
        resting sphere then settles onto the new contact), after lift-off during a bounce.

        The new contact is checked (``check_drop``) against the drop's initial conditions,
        whose energy bounds the rest of the motion.  The contact phase a change starts while
        the sphere rests (or is inside the surface) is no impact and is not recorded as one.
        """
        contact = require_contact(contact)
        self.check(contact)
        mode = self._mode
        if isinstance(mode, (_Flight, _Rest, _Carried)):
            z, zdot = self._state_at(self.time)
            self.contact = contact
            if isinstance(mode, (_Rest, _Carried)):
                self._begin_contact(self.time, z, zdot, resumed=True)
            else:   # the new contact may push at once (after a lift-off at z > 0)
                self._enter_free_motion(self.time, z, zdot, resumed=True)
        else:
            self._pending_contact = contact

    @property
    def state(self):
        return DropState(*self._state_row(self.time))

    def _state_row(self, t):
        """(t, z, ż, F, p, ṗ) at a time t of the current mode, as floats."""
        z, zdot = self._state_at(t)
        p, pv = self.plate.state(t)[:2] if self.plate is not None else (0.0, 0.0)
        return (float(t), float(z), float(zdot), self.contact.force_at(z, zdot), float(p),
                float(pv))

    @property
    def in_contact(self):
        return isinstance(self._mode, (_Contact, _Rest, _Carried))

    @property
    def carried(self):
        """True while the plate carries the sphere (the quasi-static state)."""
        return isinstance(self._mode, _Carried)

    def plate_samples(self, samples):
        """(p, ṗ, p̈) of the plate (m, m/s, m/s²) at the times of ``samples`` (zeros if fixed)."""
        t = np.asarray(samples.time, dtype=float)
        if self.plate is None:
            return np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
        return tuple(np.array(v) for v in zip(*(self.plate.state(float(ti)) for ti in t)))

    def advance(self, t_end, max_steps=None):
        """Advance to ``t_end`` (s); return the contact points passed and the impacts completed.

        With ``max_steps``, stop early once that many integrator steps have been taken in this
        call (then ``time < t_end``; call again to go on): a bound on the work of one call.
        """
        t_end = require_real('t_end', t_end)
        if t_end < self.time:
            raise ValueError(f't_end = {t_end!r} is out of range: allowed t_end >= {self.time!r}')
        points = []
        n_impacts, n_apex = len(self.impacts), len(self.apex_heights)
        budget = math.inf if max_steps is None else max_steps
        while True:
            mode = self._mode
            if isinstance(mode, _Flight):
                if mode.contact_time > t_end:
                    break
                z, zdot = mode.state(mode.contact_time, self.gravity)
                self._begin_contact(mode.contact_time, max(z, 0.0), zdot)
            elif isinstance(mode, _Carried):
                if mode.until > t_end:
                    break
                z, zdot = mode.state(mode.until)
                self._begin_contact(mode.until, z, zdot)
            elif isinstance(mode, _Contact) and self.plate is not None:
                if budget <= 0 and not mode.integrator.lifted_off \
                        and mode.integrator.time < min(t_end, mode.valid_until):
                    t_end = mode.integrator.time    # out of budget: stop where the integrator is
                    points.extend(self._take_points(mode.integrator, t_end))
                    break
                taken = self._plate_contact(mode, t_end, points)
                if taken is None:
                    break
                budget -= taken
            elif isinstance(mode, _Contact):
                phase = mode.integrator
                points.extend(self._take_points(phase, t_end))
                finish = mode.finish_time
                if finish is not None:
                    if finish > t_end:
                        break
                    self._finish_contact(mode)
                    continue
                if phase.time >= t_end:
                    break
                if budget <= 0:
                    t_end = phase.time          # out of budget: stop where the integrator is
                    points.extend(self._take_points(phase, t_end))
                    break
                budget -= phase.run(t_end, budget, self._stop_energy(mode))
                self._check_rest(mode)
            else:
                break
        self.time = t_end
        state = self.state
        points.append((t_end, state.penetration, state.penetration_rate, state.force))
        impacts = tuple(self.impacts[n_impacts:])
        apexes = tuple(self.apex_heights[n_apex:])
        return Advance(Samples.from_points(points), impacts, apexes)

    def advance_ticks(self, times, max_steps=None):
        """Advance through the tick end times ``times`` (s, non-decreasing, >= ``time``) in one
        call; return a ``TickBatch``: each tick end's state, the contact points passed and the
        impacts completed, as arrays.

        The same motion, points and impacts as ``advance(t)`` called at each tick time in turn:
        a stretch of closed-form motion (flight, rest, carried, plate flight) up to its next
        event is evaluated for all its ticks at once, vectorised over numpy arrays (the fixed
        plate's flight and rest: the same operations as the scalar path, equal to round-off); a
        tick with a contact goes through ``advance``.  With ``max_steps``, stop at the first
        tick that needs integration once that many integrator steps have been taken in this
        call (or inside a tick, as ``advance`` does): ``ticks`` then says how far it got.
        """
        times = np.asarray(times, dtype=float)
        if times.ndim != 1 or not np.isfinite(times).all():
            raise ValueError('times must be a 1-D array of finite tick times (s)')
        if times.size and (times[0] < self.time or (times[1:] < times[:-1]).any()):
            raise ValueError(f'times = {times[0]!r} ... is out of range: allowed non-decreasing '
                             f'times >= {self.time!r}')
        n = times.size
        ends = np.zeros((6, n))
        pieces, piece_ticks, impacts, impact_ticks, apexes = [], [], [], [], []
        budget = math.inf if max_steps is None else max_steps
        i = 0
        while i < n:
            until = self._closed_form_until()
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

    def _closed_form_until(self):
        """The time (s) before which ``advance`` only evaluates the current closed-form motion
        (no mode change): the next touch in flight, the end of the carried stretch, never at
        rest; -inf in contact."""
        mode = self._mode
        if isinstance(mode, _Flight):
            return mode.contact_time
        if isinstance(mode, _Carried):
            return mode.until
        if isinstance(mode, _Rest):
            return math.inf
        return -math.inf

    def _closed_form_ends(self, t, out):
        """The states (t, z, ż, F, p, ṗ) at the times t (s) of the current closed-form motion,
        into the rows of ``out``: vectorised for the fixed plate's flight and rest (beyond 8
        ticks: fewer cost less one by one), tick by tick (scalar, as ``state``) otherwise."""
        mode = self._mode
        if self.plate is None and isinstance(mode, (_Flight, _Rest)) and t.size > 8:
            if isinstance(mode, _Rest):
                z, zdot = _rest_states(mode, t)
            elif mode.path is not None:
                y, v = mode.path.state(t - mode.start)
                z, zdot = -y, -v
            else:
                dt = t - mode.start
                z = mode.penetration + mode.rate * dt + 0.5 * self.gravity * dt * dt
                zdot = mode.rate + self.gravity * dt
            out[0], out[1], out[2] = t, z, zdot
            out[3] = self.contact.force(out[1], out[2])
            return
        for k, tk in enumerate(t.tolist()):
            out[:, k] = self._state_row(tk)

    @property
    def total_steps(self):
        """Integrator steps so far, the current contact phase included."""
        extra = self._mode.integrator.steps if isinstance(self._mode, _Contact) else 0
        return self.steps + extra

    # -- phases ---------------------------------------------------------------------------
    def _state_at(self, t):
        mode = self._mode
        if isinstance(mode, _Flight):
            return mode.state(t, self.gravity)
        if isinstance(mode, (_Rest, _Carried)):
            return mode.state(t)
        phase = mode.integrator
        if t == phase.start_time:
            return phase.points[0][1], phase.points[0][2]
        if t == phase.time:
            return phase.state
        return phase.state_at(t)

    def _take_points(self, phase, t_end):
        out = []
        pts = phase.points
        while self._emitted < len(pts) and pts[self._emitted][0] <= t_end:
            out.append(pts[self._emitted])
            self._emitted += 1
        return out

    def _begin_contact(self, t, z, zdot, resumed=False):
        if self._pending_contact is not None:
            self.contact, self._pending_contact = self._pending_contact, None
        if self.plate is not None:
            self._begin_plate_contact(t, z, zdot, resumed=resumed)
            return
        phase = contact_phase(self.contact, self.mass, self.gravity, t, z, zdot,
                              rtol=self.rtol, atol=self.rtol * 1e-2)
        floor = (lift_off_energy(self.contact, self.mass, self.gravity)
                 if self.gravity > 0.0 else -math.inf)
        self._mode = _Contact(phase, floor, resumed=resumed)
        self._emitted = 0

    def _stop_energy(self, mode):
        """The energy above rest (J) below which ``_check_rest`` has work: the contact phase
        runs its steps without returning until then (it stops at the first step below)."""
        if self.gravity <= 0.0:
            return -math.inf
        if not mode.permanent:
            return mode.floor
        if self.contact.law.q != 1.0:
            return -math.inf
        z0, k_lin, _ = self.contact.rest_linearisation(self.mass * self.gravity)
        return 0.5 * k_lin * (self.settle_tolerance * z0) ** 2

    def _check_rest(self, mode):
        """Mark permanent contact, and the switch to the closed-form rest solution."""
        phase = mode.integrator
        if self.gravity <= 0.0 or phase.lifted_off:
            return
        energy = phase.energy_above_rest()
        if not mode.permanent and (energy < mode.floor or self._creeps_to_rest(phase)):
            mode.permanent = True
            if not mode.resumed:    # the landing for good: report it as this phase's impact
                self.permanent_contact_time = phase.start_time
                mode.record = len(self.impacts)
                self.impacts.append(self._permanent_record(phase))
        law = self.contact.law
        if not mode.permanent or law.q != 1.0:
            return   # (q != 1 has no linear damping at rest: it is integrated all the way)
        z0, k_lin, c_lin = self.contact.rest_linearisation(self.mass * self.gravity)
        amplitude = math.sqrt(2.0 * max(energy, 0.0) / k_lin)
        if amplitude < self.settle_tolerance * z0:
            z, zdot = phase.state
            mode.rest = _Rest(phase.time, z0, z - z0, zdot, c_lin / (2.0 * self.mass),
                              k_lin / self.mass)

    def _creeps_to_rest(self, phase):
        """True if the sphere provably creeps down into its rest depth z0 without lift-off.

        For q = 1, above z0 (z < z0) moving down (ż >= 0): ż cannot turn negative before z0
        (at ż = 0 the net force m g - k zⁿ is down).  With b = λ zᵖ/m (zᵖ grows with z) and
        a = max slope of k zⁿ on [z, z0] / m, the region 0 <= ż <= c (z0 - z) is invariant when
        c² - b c + a <= 0 (check the boundary ż = c δ: z̈ + c ż <= δ (a - b c + c²)), which has a
        solution c = (b + √(b² - 4a))/2 when b² >= 4a.  Inside it the sphere reaches z0 only
        with ż = 0: the force k zⁿ + λ zᵖ ż stays positive for ever: permanent contact.
        """
        law, contact = self.contact.law, self.contact
        if law.q != 1.0:
            return False
        z, zdot = phase.state
        z0 = contact.static_penetration(self.mass * self.gravity)
        if not (0.0 < z < z0 and zdot >= 0.0):
            return False
        n, k = law.n, contact.stiffness
        a = n * k * max(z ** (n - 1.0), z0 ** (n - 1.0)) / self.mass
        b = contact.damping * z ** law.p / self.mass
        disc = b * b - 4.0 * a
        return disc >= 0.0 and zdot <= 0.5 * (b + math.sqrt(disc)) * (z0 - z)

    @staticmethod
    def _permanent_record(phase):
        impact_time, _, impact_rate, _ = phase.points[0]
        return ImpactRecord(impact_time, max(impact_rate, 0.0), 0.0, 0.0, math.inf,
                            phase.peak_force, phase.max_penetration)

    def _finish_contact(self, mode):
        phase = mode.integrator
        self.steps += phase.steps
        impact_time, _, impact_rate, _ = mode.first_point or phase.points[0]
        impact_speed = max(impact_rate, 0.0)
        if mode.resumed:        # a contact change moved the sphere: no impact to record
            if phase.lifted_off:
                self.permanent_contact_time = self.settle_time = None
                t, z, zdot = phase.end
                self._enter_free_motion(t, z, zdot, after_lift_off=True)
            else:
                self.settle_time = mode.rest.start
                self._mode = mode.rest
            return
        if phase.lifted_off:
            t, z, zdot = phase.end
            rebound = max(-zdot, 0.0)
            record = ImpactRecord(impact_time, impact_speed, rebound,
                                  rebound / impact_speed if impact_speed > 0.0 else 0.0,
                                  t - impact_time, max(phase.peak_force, mode.peak),
                                  max(phase.max_penetration, mode.depth))
            self.impacts.append(record)
            if self._pending_contact is not None:
                self.contact, self._pending_contact = self._pending_contact, None
            self._enter_free_motion(t, z, zdot, after_lift_off=True)
        else:   # the record made when the contact became permanent, with the final peaks
            self.impacts[mode.record] = self._permanent_record(phase)
            self.permanent_contact_time = impact_time
            self.settle_time = mode.rest.start
            self._mode = mode.rest

    def _enter_free_motion(self, t, z, zdot, after_lift_off=False, resumed=False):
        """Start a flight at (t, z, ż), or a contact at once if the force is already on."""
        if self.plate is not None:
            self._enter_plate_flight(t, z, zdot, after_lift_off, resumed)
            return
        contact, g = self.contact, self.gravity
        if not after_lift_off and z > 0.0 and contact.force_at(z, zdot) > 0.0:
            self._begin_contact(t, z, zdot, resumed=resumed)
            return
        dt = self._time_to_contact(z, zdot)
        self._mode = _Flight(t, z, zdot, t + dt)
        leaves = z <= 0.0 or (zdot < 0.0 and dt > self._surface_time(z, zdot))
        if self.drag is not None and leaves:
            # a flight above the plate (not the brief excursion inside the undeformed surface
            # after a lift-off at z > 0, which stays ballistic): closed form with drag
            path = FlightPath(-z, -zdot, g, *self._drag_rates)
            self._mode = _Flight(t, z, zdot, t + path.time_to_height(0.0), path)
            if after_lift_off:
                self.apex_heights.append(path.apex_height)
            return
        if after_lift_off and g > 0.0 and math.isfinite(dt):
            t_top = -zdot / g
            lowest = z - zdot * zdot / (2.0 * g) if 0.0 < t_top < dt else min(
                z, self._mode.state(t + dt, g)[0])
            self.apex_heights.append(-lowest)

    # -- a moving plate (``plate`` module) ------------------------------------------------------
    PLATE_CHUNK = 32    # contact steps between two tests for the carried state

    def _begin_plate_contact(self, t, z, zdot, record=None, resumed=False):
        """A contact phase on the moving plate from (t, z, ż), its forcing exact until the next
        knot of the plate's motion; ``record`` carries (first point, peak, depth) across knots."""
        forcing, until = self.plate.forcing_piece(t)
        phase = contact_phase(self.contact, self.mass, self.gravity, t, z, zdot,
                              rtol=self.rtol, atol=self.rtol * 1e-2, forcing=forcing)
        mode = _Contact(phase, -math.inf, valid_until=until, resumed=resumed)
        if record is not None:
            mode.first_point, mode.peak, mode.depth = record
        self._mode = mode
        self._emitted = 0

    def _plate_contact(self, mode, t_end, points):
        """One move of a contact on the moving plate: the integrator steps taken, or ``None`` when
        ``advance`` must stop."""
        phase, knot = mode.integrator, mode.valid_until
        points.extend(self._take_points(phase, min(t_end, knot)))
        if phase.lifted_off and phase.end[0] <= knot:
            if phase.end[0] > t_end:
                return None
            self._finish_contact(mode)
            return 0
        if (phase.lifted_off or phase.time >= knot) and knot <= t_end:
            # the forcing changes at the knot: restart there from the dense output (the last step
            # integrated the forcing continued smoothly past the knot: exact up to it)
            z, zdot = phase.state_at(knot)
            kept = [pt for pt in phase.points if pt[0] <= knot]
            self.steps += phase.steps
            record = (mode.first_point or phase.points[0],
                      max([mode.peak] + [pt[3] for pt in kept]),
                      max([mode.depth] + [pt[1] for pt in kept]))
            self._begin_plate_contact(knot, z, zdot, record, resumed=mode.resumed)
            return 0
        if phase.time >= t_end:
            return None
        if self._carry(mode):
            return 0
        return phase.run(min(t_end, knot), self.PLATE_CHUNK)

    def _carry(self, mode):
        """Switch to the carried state if the plate's acceleration is above -g/4 and the contact's
        oscillation about the quasi-static depth has decayed below ``settle_tolerance``."""
        phase = mode.integrator
        t = phase.time
        p_acc = self.plate.state(t)[2]
        if p_acc <= -0.25 * self.gravity:    # hysteresis: carried from -g/4, released at -g/2
            return False
        until = min(self.plate.next_acceleration_below(t, -0.5 * self.gravity),
                    self.plate.forcing_piece(t)[1])
        carried = _Carried(t, until, self.plate, self.contact, self.mass, self.gravity)
        z_s, rate_s = carried.state(t)
        z, zdot = phase.state
        law = self.contact.law
        k_lin = law.n * self.contact.stiffness * z_s ** (law.n - 1.0)
        deviation = math.hypot(z - z_s, (zdot - rate_s) * math.sqrt(self.mass / k_lin))
        if not deviation < self.settle_tolerance * z_s:
            return False
        self.steps += phase.steps
        if self.permanent_contact_time is None:
            self.permanent_contact_time = (mode.first_point or phase.points[0])[0]
        self._mode = carried
        return True

    def _enter_plate_flight(self, t, z, zdot, after_lift_off, resumed=False):
        """Free motion over the moving plate from (t, z, ż): a contact at once if the force is on
        (``resumed``: started by set_contact, no impact), else the flight to the next touch
        (``_plate_touch``)."""
        contact, g = self.contact, self.gravity
        if not after_lift_off and z > 0.0 and contact.force_at(z, zdot) > 0.0:
            self._begin_contact(t, z, zdot, resumed=resumed)
            return
        p, pv, _ = self.plate.state(t)
        y0, v0 = p - z, pv - zdot
        path = None
        if self.drag is not None:
            path = FlightPath(y0, v0, g, *self._drag_rates)
        flight = _PlateFlight(t, z, zdot, math.inf, path, self.plate, y0, v0)
        flight.contact_time = self._plate_touch(flight, t, z, zdot)
        self._mode = flight
        if after_lift_off and v0 > 0.0:
            top = path.apex_height if path is not None else y0 + 0.5 * v0 * v0 / g
            self.apex_heights.append(top)

    def _plate_touch(self, flight, t0, z0, zdot0):
        """Absolute time (s) at which the force switches on again over the moving plate.

        Above the plate (z <= 0) it is the first root of the gap G = y - p going down, rigorously
        bracketed (``plate.first_gap_root``, |G''| <= g + drag + max|p̈|); a tangent graze with G'
        >= 0 at the root (within rounding) is passed.  Inside the undeformed surface with zero
        force (after a lift-off at z > 0) the force returns when φ turns positive, searched on
        64 samples per stretch as for the fixed plate, unless the sphere leaves the surface first.
        """
        g = self.gravity
        v_up = max(flight.v0, 0.0)
        kappa, beta = self._drag_rates if self.drag is not None else (0.0, 0.0)
        bound = g + kappa * v_up * v_up + beta * v_up + self.plate.acceleration_bound()

        def gap(t):
            y, v = flight.absolute(t, g)
            p, pv, _ = self.plate.state(t)
            return y - p, v - pv, abs(y) + abs(p)

        def curvature(t, h):      # a lower bound of G'' = y'' - p̈ on [t, t + h]
            return -(g + kappa * v_up * v_up + beta * v_up) - self.plate.acceleration_range(
                t, t + h)[1]

        t = t0
        if z0 > 0.0:
            law, contact = self.contact.law, self.contact
            stretch = 2.0 * abs(zdot0) / g + 1e-9

            def inside(t):
                G, dG, scale = gap(t)
                return -G, -dG, scale

            def curvature_inside(t, h):   # a lower bound of -G'' = p̈ - y'' (y'' <= -g in vacuum,
                return self.plate.acceleration_range(t, t + h)[0] + (  # <= 0 with drag)
                    g if self.drag is None else 0.0)

            for _ in range(10000):
                out = plate_motion.first_gap_root(inside, t, bound, t + stretch,
                                                  local_curvature=curvature_inside)
                t_stop = out[0] if out is not None else t + stretch

                def phi(dt, start=t):
                    zz, rate = flight.state(start + dt, g)
                    return float(law.reduced_force(zz, rate, contact.stiffness, contact.damping))

                root = _first_upward_root(phi, t_stop - t)
                if root is not None:
                    return t + root
                t = t_stop
                if out is not None:
                    break
                stretch *= 2.0
            else:
                raise RuntimeError(f'no exit from the plate surface found after t = {t0!r}')
        while True:
            found = plate_motion.first_gap_root(gap, t, bound, local_curvature=curvature)
            t_root, G, dG = found
            if dG < 0.0:
                return t_root
            # a tangent graze (or the lift-off point itself): pass it, nudging until G > 0
            nudge = max(1e-12, 4.0 * plate_motion.EPS * abs(t_root))
            for _ in range(200):
                G2, dG2, scale = gap(t_root + nudge)
                if G2 > 16.0 * plate_motion.EPS * max(scale, 1e-9):
                    break
                if G2 < 0.0 and dG2 < 0.0:
                    return t_root + nudge
                nudge *= 2.0
            t = t_root + nudge

    def _surface_time(self, z, zdot):
        """Ballistic time (s) to rise from z > 0 to the undeformed surface (inf: never)."""
        disc = zdot * zdot - 2.0 * self.gravity * z
        return 2.0 * z / (-zdot + math.sqrt(disc)) if disc >= 0.0 and zdot < 0.0 else math.inf

    def _time_to_contact(self, z, zdot):
        """Flight time (s) until the clamped force switches on again (inf: never)."""
        g = self.gravity
        contact, law = self.contact, self.contact.law
        if z > 0.0:
            # Inside the undeformed surface with zero force (after a lift-off at z > 0): the
            # force returns when φ = k z^(n-p) + λ ż|ż|^(q-1) turns positive while z > 0.
            if g > 0.0:
                disc = zdot * zdot - 2.0 * g * z
                t_out = (2.0 * z / (-zdot + math.sqrt(disc))) if disc >= 0.0 and zdot < 0.0 \
                    else math.inf
                t_search = min(t_out, max(-zdot / g, 0.0))
            else:
                t_search = -z / zdot if zdot < 0.0 else 0.0
            if t_search > 0.0:
                def phi(dt):
                    zz = z + zdot * dt + 0.5 * g * dt * dt
                    return float(law.reduced_force(zz, zdot + g * dt, contact.stiffness,
                                                   contact.damping))
                root = _first_upward_root(phi, t_search)
                if root is not None:
                    return root
            if g == 0.0:
                return math.inf
            if t_search < t_out:
                return t_search          # ż reaches 0 with z > 0: the spring pushes again
            # the sphere leaves the undeformed surface: a flight from z = 0 going up
            return t_out + self._time_to_contact(0.0, zdot + g * t_out)
        if g > 0.0:
            disc = zdot * zdot - 2.0 * g * z
            if zdot >= 0.0:
                return 2.0 * -z / (zdot + math.sqrt(disc)) if z < 0.0 else 0.0
            return (-zdot + math.sqrt(disc)) / g
        return -z / zdot if zdot > 0.0 else math.inf


@dataclass(frozen=True)
class DropResult:
    """Outcome of ``simulate_drop``; ``trajectory`` is ``None`` unless a sample rate was given."""

    impacts: tuple
    apex_heights: tuple
    permanent_contact_time: float
    settle_time: float
    steps: int
    duration: float
    trajectory: Samples = None


def simulate_drop(contact, mass, height, gravity=9.81, duration=5.0, sample_rate=None,
                  velocity=0.0, rtol=DROP_RTOL, settle_tolerance=1e-3, radius=None,
                  max_steps=MAX_STEPS, drag=None, plate=None):
    """Drop a sphere from ``height`` (m) and follow it for ``duration`` (s).

    With ``sample_rate`` (Hz) the result carries a trajectory sampled on that grid plus every
    contact phase's own integrator points, so that no force peak is lost.
    ``permanent_contact_time`` and ``settle_time`` are ``nan`` if not reached.  With the sphere's
    ``radius`` (m) a contact too soft for the drop is refused (see ``check_drop``).  The work
    is bounded: at most ``MAX_SAMPLES`` samples, and ``max_steps`` integrator steps, beyond
    which an ``InputError`` on ``duration`` says how far the drop got.
    ``drag``: a ``flight.AirDrag`` for the flights (default ``None``, vacuum).
    ``plate``: a ``plate.PlateMotion`` (default ``None``, the fixed plate; see ``DropSimulation``).
    """
    duration = require_range('duration', duration, 0.0, DURATION_MAX, low_open=True, unit='s')
    max_steps = require_int('max_steps', max_steps, 1, 10 ** 9)
    if sample_rate is not None:
        rate = require_range('sample_rate', sample_rate, 0.0, SAMPLE_RATE_MAX, low_open=True,
                             unit='Hz')
        if duration * rate > MAX_SAMPLES:
            raise InputError('sample_rate', rate, '{n[sample_rate]} = {value} Hz over '
                             '{n[duration]} = %g s makes %.4g samples: allowed at most %d '
                             '(%s x %s <= %d)' % (duration, duration * rate, MAX_SAMPLES,
                                                  '{n[sample_rate]}', '{n[duration]}',
                                                  MAX_SAMPLES))
    sim = DropSimulation(contact, mass, height, velocity=velocity, gravity=gravity, rtol=rtol,
                         settle_tolerance=settle_tolerance, radius=radius, drag=drag,
                         plate=plate)

    def advance(t):
        part = sim.advance(t, max_steps=max_steps - sim.total_steps)
        if sim.time < t:
            raise InputError('duration', duration, '{n[duration]} = {value} s needs more than '
                             '%d integrator steps (max_steps; reached t = %.6g s): allowed a '
                             'shorter {n[duration]}' % (max_steps, sim.time))
        return part

    trajectory = None
    if sample_rate is None:
        advance(duration)
    else:
        grid = np.arange(1, int(math.floor(duration * rate + 1e-9)) + 1) / rate
        if grid.size == 0 or grid[-1] < duration:
            grid = np.append(grid, duration)
        first = sim.state
        parts = [Samples.from_points([(0.0, first.penetration, first.penetration_rate,
                                       first.force)])]
        parts.extend(advance(t).samples for t in grid)
        trajectory = Samples.concatenate(parts)
    nan = math.nan
    return DropResult(tuple(sim.impacts), tuple(sim.apex_heights),
                      sim.permanent_contact_time if sim.permanent_contact_time is not None
                      else nan, sim.settle_time if sim.settle_time is not None else nan,
                      sim.total_steps, duration, trajectory)


def _height(height):
    """Release height of the lowest point above the plate (m): 0 <= h <= HEIGHT_MAX."""
    return require_range('height', height, 0.0, HEIGHT_MAX, unit='m')


def _velocity(velocity):
    return require_range('velocity', velocity, -VELOCITY_MAX, VELOCITY_MAX, unit='m/s')
