"""The plate's motions: the protocol ``PlateMotion``, the fixed plate, the vibrating table (and
``vibrating_table``, the table from its settings or ``None``), a switch from one motion to another
at a time (``CommandedPlate``, set-points, is in ``commanded``); and ``sphere_motion``, the
sphere's absolute height and velocity over a plate.

The plate's surface is at height p(t) (m, up positive), with velocity ṗ (m/s) and acceleration
p̈ (m/s²).  The drop engine (``drop.DropSimulation(..., plate=...)``) works in the relative
coordinate z = p - y (penetration of the sphere's lowest point y), so that during contact

    m z̈ = m (g + p̈(t)) - F(z, ż),

the plate's acceleration enters as forcing beside gravity (``forcing_piece``, a ``phase.Forcing``
that is exact on an interval).  The contact force F acts up on the sphere, its reaction -F on the
plate.

A plate motion is any object with the methods of ``PlateMotion``:

* ``state(t)`` -> (p, ṗ, p̈);
* ``acceleration_bound()`` -> an upper bound of |p̈| over all t (the flights' root bracket);
* ``acceleration_range(t0, t1)`` -> (min, max) of p̈ over [t0, t1] (the local bracket);
* ``forcing_piece(t)`` -> (Forcing, t_until): p̈ on [t, t_until) as a ``phase.Forcing``;
* ``next_acceleration_below(t, level)`` -> the first time >= t at which p̈ <= level (inf: never);
* ``speed_bound()`` -> an upper bound of |ṗ| over all t (the drop's depth check);
* ``moving``: False only for the fixed plate (a moving plate can carry the sphere, the fixed
  one lets it come to rest);
* ``plan_flight(flight, ...)``: the flight's touch time and apex (``flights``);
* ``samples(t)`` -> (p, ṗ, p̈) over an array of times, and ``states(t)`` -> (p, ṗ) arrays for
  the engine's vectorised tick ends, or ``None`` where only ``state`` gives the exact numbers;
  ``search_states(t)`` -> (p, ṗ) arrays for a flight's sampled root search (vectorised where
  the motion can be, equal to round-off).

Four are provided:

* ``FixedPlate()``: p = 0 for ever, answering in the engine's closed forms (touch time by the
  quadratic formula, no forcing, a contact exact for ever);
* ``SinusoidalPlate(amplitude a, frequency f, phase ϕ)``: p = a sin(2π f t + ϕ), so
  Γ = a (2π f)² / g is the table's peak acceleration in units of g;
* ``CommandedPlate(times, positions, velocities)``: set-points (tᵢ, pᵢ, vᵢ) joined by the C¹
  piecewise-quadratic interpolant with a knot at each interval's midpoint: constant acceleration
  on each half-interval, chosen so that p and ṗ match both set-points.  Constant accelerations
  make every piece an exact forcing of the compiled contact phase (no kernel change); the
  interpolant is C¹ (no velocity jump, hence no impulse on a carried sphere).  Outside the
  set-points the plate moves at constant velocity (zero acceleration): before t₀ it extrapolates
  (p₀, v₀) backwards, after the last set-point it holds the last velocity;
* ``SwitchedPlate(before, after, switch_time)``: one motion before the switch, another from it
  on (a change of motion at a time: what ``DropSimulation.set_plate`` does to a running drop).

``commands.table_transition`` joins the plate's current motion to a new vibrating table with a
C¹ bridge; ``commands.command_motion`` turns a trajectory command (timed set-points) into a
``CommandedPlate`` that starts from the plate's current state and brakes to rest after the last
point.
"""
import functools
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.drop.plate.flights import ballistic_flight, gap_flight, table_flight
from contact_sim.phase import Forcing
from contact_sim.validation import (InputError, require_instance, require_range, require_real,
                                    require_real_array)

# the vibrating table's ranges (the node's plate_* parameters, sweeps, every SinusoidalPlate)
TABLE_AMPLITUDE_MAX = 0.1         # m
TABLE_FREQUENCY_MAX = 1000.0      # Hz
TABLE_FREQUENCY_MIN = 1e-3        # Hz: else 0 (a period of 1/5e-324 s is no bridge length)
TABLE_PHASE_MAX = 2.0 * math.pi   # rad: -2π <= ϕ <= 2π
TABLE_ACCELERATION_MAX = 1000.0   # m/s²: the peak a (2π f)² (Γ ≈ 100)


class PlateMotion:
    """The protocol of a prescribed plate motion (see the module docstring); a base class."""

    def state(self, t):
        raise NotImplementedError

    def acceleration_bound(self):
        raise NotImplementedError

    def forcing_piece(self, t):
        raise NotImplementedError

    def next_acceleration_below(self, t, level):
        raise NotImplementedError

    def acceleration_range(self, t0, t1):
        """(min, max) of p̈ over [t0, t1]; by default ± ``acceleration_bound()``."""
        bound = self.acceleration_bound()
        return -bound, bound

    def jerk(self, t):
        return 0.0

    def speed_bound(self):
        raise NotImplementedError

    @property
    def moving(self):
        return True

    def plan_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off):
        """Set ``flight``'s touch time (and drag path) from (z, ż) (m, m/s) by the first root of
        the gap (``flights.gap_flight``); returns the apex height (m) after a lift-off, or
        ``None``."""
        return gap_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off)

    def samples(self, t):
        """(p, ṗ, p̈) (m, m/s, m/s²) at the times t (s, an array), one ``state`` call each."""
        return tuple(np.array(v) for v in zip(*(self.state(float(ti)) for ti in t)))

    def states(self, t):
        """(p, ṗ) arrays at the times t (s) for vectorised closed forms; ``None``: ``state``
        alone gives the numbers of the scalar path."""
        return None

    def search_states(self, t):
        """(p, ṗ) arrays (m, m/s) at the times t (s, an array) for a flight's sampled root
        search (only the samples' signs are used; the root is refined with ``state``): numpy
        where the motion has a vectorised formula, one ``state`` call each otherwise."""
        rows = [self.state(float(ti))[:2] for ti in t]
        return np.array([r[0] for r in rows]), np.array([r[1] for r in rows])


@dataclass(frozen=True)
class FixedPlate(PlateMotion):
    """The plate that does not move: p = ṗ = p̈ = 0 for ever.  Its flights are planned in closed
    form (``flights.ballistic_flight``), its contacts have no forcing and stay exact for ever,
    and it carries nothing: a sphere on it comes to rest."""

    def state(self, t):
        return 0.0, 0.0, 0.0

    def acceleration_bound(self):
        return 0.0

    def speed_bound(self):
        return 0.0

    def forcing_piece(self, t):
        """No forcing beyond gravity (``None``), exact for ever."""
        return None, math.inf

    def next_acceleration_below(self, t, level):
        return t if 0.0 <= level else math.inf

    @property
    def moving(self):
        return False

    def plan_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off):
        """Set ``flight``'s touch time (and drag path) from (z, ż) (m, m/s) in closed form
        (``flights.ballistic_flight``); returns the apex height (m) after a lift-off, or
        ``None``."""
        return ballistic_flight(flight, z, zdot, contact, drag_rates, after_lift_off)

    def samples(self, t):
        return np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)

    def states(self, t):
        return np.zeros_like(t), np.zeros_like(t)


FIXED = FixedPlate()


@functools.lru_cache(maxsize=4096)
def constant_forcing(acceleration):
    """A constant acceleration as a ``phase.Forcing``: A sin(0·t + π/2) = A (made once for each
    value: a commanded plate asks for its pieces' at every contact and test for the carried
    state; a ``Forcing`` is frozen)."""
    return Forcing(acceleration_amplitude=acceleration, angular_frequency=0.0, phase=math.pi / 2)


def sinusoid_state(amplitude, angular_frequency, phase, t):
    """(p m, ṗ m/s, p̈ m/s²) of p = a sin(ω t + ϕ) at t (s): ``SinusoidalPlate.state``."""
    w, a = angular_frequency, amplitude
    th = w * t + phase
    s, c = math.sin(th), math.cos(th)
    return a * s, a * w * c, -a * w * w * s


@dataclass(frozen=True)
class SinusoidalPlate(PlateMotion):
    """A table vibrating as p(t) = a sin(2π f t + ϕ), in the ranges a table has.

    Parameters
    ----------
    amplitude : float
        a, 0 to ``TABLE_AMPLITUDE_MAX`` (m).
    frequency : float
        f, 0 or ``TABLE_FREQUENCY_MIN`` (1e-3) to ``TABLE_FREQUENCY_MAX`` (1000) Hz.
    phase : float
        ϕ, -``TABLE_PHASE_MAX`` to ``TABLE_PHASE_MAX`` (rad).

    a = 0 (or f = 0 with ϕ = 0) is the fixed plate.

    Raises
    ------
    InputError
        Keyed ``amplitude``, ``frequency`` or ``phase``: a value out of its range, or a peak
        acceleration a (2π f)² above ``TABLE_ACCELERATION_MAX`` (m/s²).

    See Also
    --------
    DropSimulation.set_plate : Move a drop's plate so.

    Examples
    --------
    >>> from contact_sim.drop import SinusoidalPlate
    >>> table = SinusoidalPlate(amplitude=0.001, frequency=20.0)
    >>> print(f"Gamma = {table.peak_acceleration_ratio():.4f}, peak speed "
    ...       f"{table.speed_bound():.4f} m/s")
    Gamma = 1.6097, peak speed 0.1257 m/s
    >>> position, velocity, acceleration = table.state(0.0125)   # a quarter period
    >>> print(f"{position:.4f} m, {acceleration:.3f} m/s^2")
    0.0010 m, -15.791 m/s^2
    """

    amplitude: float = 0.0
    frequency: float = 0.0
    phase: float = 0.0

    def __post_init__(self):
        a = require_range('amplitude', self.amplitude, 0.0, TABLE_AMPLITUDE_MAX, unit='m')
        f = require_range('frequency', self.frequency, 0.0, TABLE_FREQUENCY_MAX, unit='Hz')
        if 0.0 < f < TABLE_FREQUENCY_MIN:
            raise InputError('frequency', f, '{n[frequency]} = {value} Hz is out of range: allowed '
                             '{n[frequency]} = 0 (the fixed plate) or %g <= {n[frequency]} <= %g '
                             'Hz' % (TABLE_FREQUENCY_MIN, TABLE_FREQUENCY_MAX), value=repr(f))
        ph = require_range('phase', self.phase, -TABLE_PHASE_MAX, TABLE_PHASE_MAX, unit='rad')
        object.__setattr__(self, 'amplitude', a)
        object.__setattr__(self, 'frequency', f)
        object.__setattr__(self, 'phase', ph)
        peak = self.acceleration_bound()
        if peak > TABLE_ACCELERATION_MAX:
            raise InputError('amplitude', a, '{n[amplitude]} = {value} m at {n[frequency]} = %g '
                             'Hz shakes the plate at %.4g m/s^2: allowed a (2 pi f)^2 <= %g '
                             'm/s^2, i.e. {n[amplitude]} <= %.4g m at this frequency'
                             % (f, peak, TABLE_ACCELERATION_MAX,
                                TABLE_ACCELERATION_MAX / self.angular_frequency ** 2))

    @property
    def angular_frequency(self):
        """ω = 2π f, rad/s."""
        return 2.0 * math.pi * self.frequency

    @property
    def moving(self):
        return self.amplitude > 0.0 and (self.frequency > 0.0 or math.sin(self.phase) != 0.0)

    def peak_acceleration_ratio(self, gravity=9.81):
        """The table's peak acceleration over gravity, Γ = a ω² / g.

        Parameters
        ----------
        gravity : float, optional
            Gravity g, m/s² (default 9.81).

        Returns
        -------
        float
            Γ, dimensionless (the sphere can leave a table only with Γ > 1).
        """
        return self.amplitude * self.angular_frequency ** 2 / gravity

    def state(self, t):
        return sinusoid_state(self.amplitude, self.angular_frequency, self.phase, t)

    def plan_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off):
        """In vacuum the touch time comes from compiled code (``flights.table_flight``), with
        drag from ``flights.gap_flight`` (the reference path of both)."""
        if drag_rates is None:
            return table_flight(self, flight, z, zdot, contact, after_lift_off)
        return gap_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off)

    def search_states(self, t):
        w, a = self.angular_frequency, self.amplitude
        th = w * np.asarray(t, dtype=float) + self.phase
        return a * np.sin(th), a * w * np.cos(th)

    def jerk(self, t):
        """d p̈ / dt (m/s³)."""
        w = self.angular_frequency
        return -self.amplitude * w ** 3 * math.cos(w * t + self.phase)

    def acceleration_bound(self):
        return self.amplitude * self.angular_frequency ** 2

    def speed_bound(self):
        """Peak abs(ṗ) = a ω (m/s)."""
        return self.amplitude * self.angular_frequency

    def acceleration_range(self, t0, t1):
        """(min, max) of p̈ over [t0, t1] (exact: the extremes of sin on the phase interval)."""
        w, aw2 = self.angular_frequency, self.amplitude * self.angular_frequency ** 2
        a0, a1 = self.state(t0)[2], self.state(t1)[2]
        lo, hi = min(a0, a1), max(a0, a1)
        th0, th1 = w * t0 + self.phase, w * t1 + self.phase
        two_pi = 2.0 * math.pi
        if math.floor((th1 - 1.5 * math.pi) / two_pi) > math.floor((th0 - 1.5 * math.pi) / two_pi):
            hi = aw2                            # sin = -1 inside
        if math.floor((th1 - 0.5 * math.pi) / two_pi) > math.floor((th0 - 0.5 * math.pi) / two_pi):
            lo = -aw2                           # sin = +1 inside
        return lo, hi

    def forcing_piece(self, t):
        return self._forcing, math.inf

    @functools.cached_property
    def _forcing(self):
        """The table's acceleration as a ``Forcing``, the same at every t (built once)."""
        w = self.angular_frequency
        return Forcing(-self.amplitude * w * w, w, self.phase)

    def next_acceleration_below(self, t, level):
        """First t' >= t with p̈(t') = -a ω² sin(ω t' + ϕ) <= level (closed form)."""
        aw2 = self.amplitude * self.angular_frequency ** 2
        if aw2 == 0.0 or self.frequency == 0.0:
            return t if self.state(t)[2] <= level else math.inf
        s = -level / aw2                       # need sin θ >= s
        if s > 1.0:
            return math.inf
        w = self.angular_frequency
        th = w * t + self.phase
        if math.sin(th) >= s:
            return t
        lo = math.asin(s)                      # the window [lo, π - lo] (mod 2π)
        k = math.ceil((th - lo) / (2.0 * math.pi))
        return max(t, (lo + 2.0 * math.pi * k - self.phase) / w)


def vibrating_table(amplitude, frequency, phase):
    """A ``SinusoidalPlate`` from settings in its ranges (``SinusoidalPlate``: 0 <= a <=
    ``TABLE_AMPLITUDE_MAX`` m, 0 <= f <= ``TABLE_FREQUENCY_MAX`` Hz, abs(ϕ) <= ``TABLE_PHASE_MAX``,
    peak acceleration a (2π f)² <= ``TABLE_ACCELERATION_MAX``), or ``None`` if it does not vibrate
    (a = 0 or f = 0: the fixed plate, not a plate held at a sin ϕ).  ``InputError`` keyed
    ``amplitude``, ``frequency`` or ``phase``."""
    table = SinusoidalPlate(amplitude, frequency, phase)
    return table if table.amplitude > 0.0 and table.frequency > 0.0 else None


@dataclass(frozen=True)
class SwitchedPlate(PlateMotion):
    """``before`` (a ``PlateMotion``) for t < ``switch_time`` (s), ``after`` from it on.

    The protocol is the parts', cut at the switch: a forcing piece of ``before`` ends at the
    switch at the latest.  The caller makes the switch continuous where it must be (a switch in
    p or ṗ is a teleport or an impulse of the plate): ``table_transition`` and
    ``command_motion`` start ``after`` from ``before``'s state at the switch.

    Attributes
    ----------
    before : PlateMotion
        The motion until the switch.
    after : PlateMotion
        The motion from the switch on.
    switch_time : float
        The switch, s.

    Examples
    --------
    >>> from contact_sim.drop import FIXED, SinusoidalPlate, SwitchedPlate
    >>> plate = SwitchedPlate(FIXED, SinusoidalPlate(0.001, 20.0), switch_time=1.0)
    >>> plate.state(0.5)
    (0.0, 0.0, 0.0)
    >>> print(f"{plate.state(1.0125)[0]:.4f} m")
    0.0010 m
    """

    before: PlateMotion
    after: PlateMotion
    switch_time: float

    def __post_init__(self):
        for name in ('before', 'after'):
            require_instance(name, getattr(self, name), PlateMotion, 'a plate.PlateMotion')
        object.__setattr__(self, 'switch_time', require_real('switch_time', self.switch_time))

    def _part(self, t):
        return self.before if t < self.switch_time else self.after

    @property
    def moving(self):
        return self.before.moving or self.after.moving

    def state(self, t):
        return self._part(t).state(t)

    def jerk(self, t):
        return self._part(t).jerk(t)

    def acceleration_bound(self):
        return max(self.before.acceleration_bound(), self.after.acceleration_bound())

    def speed_bound(self):
        return max(self.before.speed_bound(), self.after.speed_bound())

    def acceleration_range(self, t0, t1):
        ts = self.switch_time
        if t1 < ts:
            return self.before.acceleration_range(t0, t1)
        if t0 >= ts:
            return self.after.acceleration_range(t0, t1)
        lo0, hi0 = self.before.acceleration_range(t0, ts)
        lo1, hi1 = self.after.acceleration_range(ts, t1)
        return min(lo0, lo1), max(hi0, hi1)

    def plan_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off):
        """A flight from the switch on is ``after``'s alone: planned as ``after`` plans it (in
        compiled code where it can) if ``after`` moves; one that starts before the switch, or
        over a fixed ``after`` (whose closed-form plan would differ from the engine's plan of a
        moving plate in the apex and the drag path), by the first root of the gap over both
        parts (``flights.gap_flight``)."""
        if flight.start >= self.switch_time and self.after.moving:
            return self.after.plan_flight(flight, z, zdot, contact, drag_rates, after_lift_off)
        return gap_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off)

    def forcing_piece(self, t):
        if t < self.switch_time:
            forcing, until = self.before.forcing_piece(t)
            return forcing, min(until, self.switch_time)
        return self.after.forcing_piece(t)

    def next_acceleration_below(self, t, level):
        if t < self.switch_time:
            found = self.before.next_acceleration_below(t, level)
            if found < self.switch_time:
                return found
            t = self.switch_time
        return self.after.next_acceleration_below(t, level)


def as_plate(plate):
    """The motion ``plate`` as the engine takes it: ``FIXED`` for ``None`` or a plate that does not
    move (the fixed plate), else ``plate`` itself; ``InputError`` for anything but a
    ``PlateMotion``."""
    if plate is None:
        return FIXED
    if not isinstance(plate, PlateMotion):
        raise InputError('plate', plate, '{n[plate]} = {value} is invalid: allowed None, a '
                         'SinusoidalPlate, a CommandedPlate or another plate.PlateMotion',
                         value=repr(plate))
    return plate if plate.moving else FIXED


def sphere_motion(radius, penetration, penetration_rate, plate_position=0.0,
                  plate_velocity=0.0):
    """The sphere's centre height p + R1 - z (m) and upward velocity ṗ - ż (m/s) in the frame
    where the plate's surface at rest is at height 0, from the penetration z (m) and its rate ż
    (m/s) relative to the plate at p (m), moving at ṗ (m/s); floats or numpy arrays.
    ``InputError`` naming the argument that is not a finite real number (or array of them)."""
    args = (radius, penetration, penetration_rate, plate_position, plate_velocity)
    if all(type(a) is float for a in args):   # the node's per-tick call: plain floats
        height, velocity = plate_position + radius - penetration, plate_velocity - penetration_rate
        if math.isfinite(height) and math.isfinite(velocity):
            return height, velocity
    elif not any(isinstance(a, (bool, str, bytes)) for a in args):   # numbers, not as numbers
        try:
            with np.errstate(all='ignore'):
                height = plate_position + radius - penetration
                velocity = plate_velocity - penetration_rate
        except TypeError:
            height = velocity = None
        if height is not None and all(np.asarray(x).dtype.kind in 'iuf' for x in args) \
                and np.all(np.isfinite(height)) and np.all(np.isfinite(velocity)):
            return height, velocity
    names = ('radius', 'penetration', 'penetration_rate', 'plate_position', 'plate_velocity')
    for name, value in zip(names, args):
        require_real_array(name, value)
    raise InputError('radius', radius, 'the sphere\'s height p + R1 - z or velocity overflows '
                     'for {n[radius]} = {value}, penetration = %r, plate_position = %r: allowed '
                     'values whose sums are finite' % (penetration, plate_position))
