"""A prescribed plate motion: the vibrating table and a plate commanded by timed set-points.

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
* ``speed_bound()`` -> an upper bound of |ṗ| over all t (the drop's depth check).

Three are provided:

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

``table_transition`` joins the plate's current motion to a new vibrating table with a C¹ bridge;
``command_motion`` turns a trajectory command (timed set-points) into a ``CommandedPlate`` that
starts from the plate's current state and brakes to rest after the last point.
"""
import bisect
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.phase import Forcing
from contact_sim.validation import InputError, require_nonnegative, require_range, require_real


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


def _constant_forcing(acceleration):
    """A constant acceleration as a ``phase.Forcing``: A sin(0·t + π/2) = A."""
    return Forcing(acceleration_amplitude=acceleration, angular_frequency=0.0, phase=math.pi / 2)


@dataclass(frozen=True)
class SinusoidalPlate(PlateMotion):
    """A table vibrating as p(t) = a sin(2π f t + ϕ): ``amplitude`` a >= 0 (m), ``frequency``
    f >= 0 (Hz), ``phase`` ϕ (rad).  a = 0 (or f = 0 with ϕ = 0) is the fixed plate."""

    amplitude: float = 0.0
    frequency: float = 0.0
    phase: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, 'amplitude', require_nonnegative('amplitude', self.amplitude))
        object.__setattr__(self, 'frequency', require_nonnegative('frequency', self.frequency))
        object.__setattr__(self, 'phase', require_real('phase', self.phase))

    @property
    def angular_frequency(self):
        return 2.0 * math.pi * self.frequency

    @property
    def moving(self):
        return self.amplitude > 0.0 and (self.frequency > 0.0 or math.sin(self.phase) != 0.0)

    def peak_acceleration_ratio(self, gravity=9.81):
        """Γ = a ω² / g."""
        return self.amplitude * self.angular_frequency ** 2 / gravity

    def state(self, t):
        w, a = self.angular_frequency, self.amplitude
        th = w * t + self.phase
        s, c = math.sin(th), math.cos(th)
        return a * s, a * w * c, -a * w * w * s

    def jerk(self, t):
        """d p̈ / dt (m/s³)."""
        w = self.angular_frequency
        return -self.amplitude * w ** 3 * math.cos(w * t + self.phase)

    def acceleration_bound(self):
        return self.amplitude * self.angular_frequency ** 2

    def speed_bound(self):
        """Peak |ṗ| = a ω (m/s)."""
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
        w = self.angular_frequency
        return Forcing(-self.amplitude * w * w, w, self.phase), math.inf

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


@dataclass(frozen=True)
class CommandedPlate(PlateMotion):
    """A plate through set-points: ``times`` tᵢ (s, strictly increasing), ``positions`` pᵢ (m),
    ``velocities`` vᵢ (m/s), equal lengths >= 1; the interpolation is stated in the module
    docstring (C¹, constant acceleration on each half-interval, constant velocity outside)."""

    times: tuple
    positions: tuple
    velocities: tuple

    def __post_init__(self):
        times = _set_point_times(self.times)
        n = times.size
        arrays = {'times': times, 'positions': _finite_array('positions', self.positions, n),
                  'velocities': _finite_array('velocities', self.velocities, n)}
        for name, arr in arrays.items():
            object.__setattr__(self, name, tuple(arr.tolist()))
        t, p, v = arrays['times'], arrays['positions'], arrays['velocities']
        h = 0.5 * np.diff(t)
        dv = (v[1:] - v[:-1]) / h if n > 1 else np.empty(0)
        a1 = 0.5 * (2.0 * (p[1:] - p[:-1] - 2.0 * v[:-1] * h) / h ** 2 - dv) if n > 1 \
            else np.empty(0)
        a2 = dv - a1
        # pieces: start time, position, velocity, acceleration (the last runs to +inf)
        starts, pos, vel, acc = [], [], [], []
        for i in range(n - 1):
            mid_p = p[i] + v[i] * h[i] + 0.5 * a1[i] * h[i] ** 2
            starts += [t[i], t[i] + h[i]]
            pos += [p[i], mid_p]
            vel += [v[i], v[i] + a1[i] * h[i]]
            acc += [a1[i], a2[i]]
        starts.append(t[-1])
        pos.append(p[-1])
        vel.append(v[-1])
        acc.append(0.0)
        object.__setattr__(self, '_pieces', tuple(tuple(float(x) for x in seq)
                                                  for seq in (starts, pos, vel, acc)))

    def _piece(self, t):
        starts = self._pieces[0]
        return max(bisect.bisect_right(starts, t) - 1, 0)

    def state(self, t):
        starts, pos, vel, acc = self._pieces
        if t < starts[0]:
            return pos[0] + vel[0] * (t - starts[0]), vel[0], 0.0
        i = self._piece(t)
        dt = t - starts[i]
        return pos[i] + vel[i] * dt + 0.5 * acc[i] * dt * dt, vel[i] + acc[i] * dt, acc[i]

    def jerk(self, t):
        """d p̈ / dt (m/s³): zero inside every piece."""
        return 0.0

    def acceleration_bound(self):
        return max(abs(a) for a in self._pieces[3])

    def position_range(self):
        """(min, max) of p (m) from the first set-point on: at the knots, and at a piece's
        turning point (ṗ = 0 inside it)."""
        starts, pos, vel, acc = self._pieces
        values = list(pos)
        for i in range(len(starts) - 1):
            h = starts[i + 1] - starts[i]
            values.append(pos[i] + vel[i] * h + 0.5 * acc[i] * h * h)
            if acc[i] != 0.0 and 0.0 < -vel[i] / acc[i] < h:
                values.append(pos[i] - 0.5 * vel[i] * vel[i] / acc[i])
        if vel[-1] != 0.0:      # constant velocity after the last set-point: unbounded
            values.append(math.copysign(math.inf, vel[-1]))
        return min(values), max(values)

    def speed_bound(self):
        """Peak |ṗ| (m/s): ṗ is piecewise linear, so at a piece's ends."""
        return max(abs(v) for v in self.velocities + self._pieces[2])

    def acceleration_range(self, t0, t1):
        """(min, max) of p̈ over [t0, t1]: over the pieces it overlaps."""
        starts, acc = self._pieces[0], self._pieces[3]
        values = [0.0] if t0 < starts[0] else []
        if t1 >= starts[0]:
            values += acc[self._piece(max(t0, starts[0])):self._piece(t1) + 1]
        return min(values), max(values)

    def forcing_piece(self, t):
        starts, acc = self._pieces[0], self._pieces[3]
        if t < starts[0]:
            return _constant_forcing(0.0), starts[0]
        i = j = self._piece(t)
        while j + 1 < len(starts) and abs(acc[j + 1] - acc[i]) <= 1e-12 * abs(acc[i]):
            # knots that change nothing (up to the rounding of the interpolant's coefficients)
            j += 1
        return _constant_forcing(acc[i]), (starts[j + 1] if j + 1 < len(starts) else math.inf)

    def next_acceleration_below(self, t, level):
        starts, acc = self._pieces[0], self._pieces[3]
        if t < starts[0]:
            if 0.0 <= level:
                return t
            t = starts[0]
        for i in range(self._piece(t), len(starts)):
            if acc[i] <= level:
                return max(t, starts[i])
        return math.inf

@dataclass(frozen=True)
class SwitchedPlate(PlateMotion):
    """``before`` (a ``PlateMotion``) for t < ``switch_time`` (s), ``after`` from it on.

    The protocol is the parts', cut at the switch: a forcing piece of ``before`` ends at the
    switch at the latest.  The caller makes the switch continuous where it must be (a switch in
    p or ṗ is a teleport or an impulse of the plate): ``table_transition`` and
    ``command_motion`` start ``after`` from ``before``'s state at the switch.
    """

    before: PlateMotion
    after: PlateMotion
    switch_time: float

    def __post_init__(self):
        for name in ('before', 'after'):
            if not isinstance(getattr(self, name), PlateMotion):
                raise ValueError(f'{name} = {getattr(self, name)!r} is invalid: allowed a '
                                 'plate.PlateMotion')
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


# -- changes of motion at a time: the table's bridge, trajectory commands -----------------------
BRIDGE_TIME = 0.5           # s: the bridge's length when no table frequency gives one
BRIDGE_SPEED_MAX = 0.5      # m/s: a bridge is no faster than this, the plate now or the table
COMMAND_STOP_TIME = 0.2     # s: after a command's last point the plate brakes to rest over this
COMMAND_POSITION_MAX = 1.0  # m: commanded |p|
COMMAND_VELOCITY_MAX = 10.0  # m/s: commanded (or estimated) |ṗ|
COMMAND_ACCELERATION_MAX = 1000.0  # m/s²: |p̈| of the commanded motion (the interpolant's)
COMMAND_HORIZON = 600.0     # s: the last point at most this long after now


def bridge_time(table, previous_frequency=0.0):
    """The bridge's length T (s): one period of the new table's frequency; when the table stops
    (or has f = 0), one period of the ``previous_frequency`` (Hz); else ``BRIDGE_TIME``."""
    if table is not None and table.moving and table.frequency > 0.0:
        return 1.0 / table.frequency
    if previous_frequency > 0.0:
        return 1.0 / previous_frequency
    return BRIDGE_TIME


def table_transition(now, current, table, previous_frequency=0.0):
    """The plate's motion from ``now`` (s) on when the vibrating table becomes ``table``.

    ``current``: the plate's motion until now (``None``: fixed at p = 0); ``table``: a
    ``SinusoidalPlate`` (``None`` or one that does not move: the table stops, at rest at p = 0).
    The plate is bridged C¹ from its state (p, ṗ) at ``now`` to the new motion's state at
    now + T (a 2-point ``CommandedPlate``), T from ``bridge_time``: one period of the new
    frequency, or of ``previous_frequency`` when the table stops, or ``BRIDGE_TIME``, made longer
    (by factors of 1.25) until the bridge's |p̈| is within ``TABLE_ACCELERATION_MAX`` and its
    |ṗ| within the larger of ``BRIDGE_SPEED_MAX``, the plate's speed now and the table's peak
    speed, so that a change far from the plate's state is no slam.  Returns a
    ``SwitchedPlate`` (bridge, then the table), or ``None`` when the plate stays fixed.
    """
    now = require_real('now', now)
    p, pv = current.state(now)[:2] if current is not None else (0.0, 0.0)
    target = table if table is not None and table.moving else SinusoidalPlate()
    if current is None and not target.moving:
        return None
    duration = bridge_time(table, previous_frequency)
    speed_max = max(abs(pv), target.speed_bound(), BRIDGE_SPEED_MAX)
    for _ in range(400):    # longer until the bridge is as gentle as a table may be
        end = now + duration
        pt, vt, _ = target.state(end)
        bridge = CommandedPlate((now, end), (p, pt), (pv, vt))
        if bridge.acceleration_bound() <= TABLE_ACCELERATION_MAX \
                and bridge.speed_bound() <= speed_max:
            return SwitchedPlate(bridge, target, end)
        duration *= 1.25
    raise RuntimeError(f'no gentle bridge from p = {p!r} m, pdot = {pv!r} m/s to {target!r}')


@dataclass(frozen=True)
class Command:
    """What ``command_motion`` made of a command: the plate's ``motion`` from now on (``None``
    when no point was left), and how many points it ``dropped`` (at or before now)."""

    motion: object
    dropped: int


def _finite_array(name, values, count=None):
    try:
        arr = np.asarray(values, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InputError(name, values, '{n[%s]} = {value} is invalid: allowed a sequence of '
                         'finite numbers' % name, value=repr(values)) from None
    if not np.all(np.isfinite(arr)):
        raise InputError(name, values, '{n[%s]} = {value} is out of range: allowed finite '
                         'numbers' % name, value=repr(arr.tolist()))
    if count is not None and arr.size != count:
        raise InputError(name, values, '{n[%s]} has %d values: allowed one per point (%d)'
                         % (name, arr.size, count), value=repr(arr.tolist()))
    return arr


def _set_point_times(times):
    """Set-point times (s) as an array: at least one, finite, strictly increasing."""
    t = _finite_array('times', times)
    if t.size == 0:
        raise InputError('times', times, '{n[times]} is empty: allowed at least one point',
                         value='[]')
    if np.any(np.diff(t) <= 0.0):
        raise InputError('times', times, '{n[times]} = {value} is out of range: allowed strictly '
                         'increasing times', value=repr(t.tolist()))
    return t


def _require_magnitude(name, arr, bound, unit, where=''):
    worst = float(np.max(np.abs(arr))) if arr.size else 0.0
    if worst > bound:
        raise InputError(name, worst, '{n[%s]} reaches |%s| = %.6g %s%s: allowed -%g <= {n[%s]} '
                         '<= %g %s' % (name, name, worst, unit, where, bound, name, bound, unit))


def command_motion(now, position, velocity, times, positions, velocities=None):
    """A trajectory command as the plate's motion from ``now`` (s, the drop's time) on.

    ``position``, ``velocity``: the plate's state at now (m, m/s); ``times`` (s, the drop's time,
    strictly increasing), ``positions`` (m) and ``velocities`` (m/s, or ``None``) of the points.
    The rules (those of a ros2_control JointTrajectoryController, as far as they apply):

    * points at or before ``now`` are dropped (``Command.dropped``); none left: ``motion`` is
      ``None`` (the command is ignored);
    * the motion starts at (now, position, velocity), so a jump in the command is followed C¹,
      never teleported, and runs through the points (``CommandedPlate``: C¹, constant
      acceleration on each half-interval);
    * velocities not given are estimated by finite differences over the points (the first
      point counts the current state): the central difference (pᵢ₊₁ - pᵢ₋₁)/(tᵢ₊₁ - tᵢ₋₁)
      inside, zero at the last point; accelerations are not taken (the interpolant sets them);
    * after the last point the plate brakes to rest at constant deceleration over
      ``COMMAND_STOP_TIME`` s and stays there: when commands stop, the plate stops.

    Refused (``InputError`` naming the field and the allowed range): non-finite values, times
    not strictly increasing, |positions| > ``COMMAND_POSITION_MAX``, |velocities| (given or
    estimated) > ``COMMAND_VELOCITY_MAX``, an interpolant with |p̈| > ``COMMAND_ACCELERATION_MAX``.
    """
    now = require_real('now', now)
    position, velocity = require_real('position', position), require_real('velocity', velocity)
    t = _set_point_times(times)
    p = _finite_array('positions', positions, t.size)
    _require_magnitude('positions', p, COMMAND_POSITION_MAX, 'm')
    v = None if velocities is None else _finite_array('velocities', velocities, t.size)
    if v is not None:
        _require_magnitude('velocities', v, COMMAND_VELOCITY_MAX, 'm/s')
    if t[-1] > now + COMMAND_HORIZON:
        raise InputError('times', float(t[-1]), '{n[times]} reach %.6g s after now: allowed up '
                         'to %g s ahead (stamps are simulated time, the node\'s /clock, not '
                         'wall time)' % (t[-1] - now, COMMAND_HORIZON))
    keep = t > now
    dropped = int(np.count_nonzero(~keep))
    if not np.any(keep):
        return Command(None, dropped)
    tt = np.concatenate(([now], t[keep]))
    pp = np.concatenate(([position], p[keep]))
    if v is None:
        vv = np.zeros_like(tt)
        vv[1:-1] = (pp[2:] - pp[:-2]) / (tt[2:] - tt[:-2])
        _require_magnitude('velocities', vv[1:], COMMAND_VELOCITY_MAX, 'm/s')
    else:
        vv = np.concatenate(([0.0], v[keep]))
    vv[0] = velocity
    if vv[-1] != 0.0:       # brake to rest: Δp = v T / 2 at constant deceleration v / T
        tt = np.append(tt, tt[-1] + COMMAND_STOP_TIME)
        pp = np.append(pp, pp[-1] + 0.5 * vv[-1] * COMMAND_STOP_TIME)
        vv = np.append(vv, 0.0)
    motion = CommandedPlate(tuple(tt), tuple(pp), tuple(vv))
    low, high = motion.position_range()
    _require_magnitude('positions', np.array([low, high]), COMMAND_POSITION_MAX, 'm',
                       ' (the motion through the points, braking to rest after the last)')
    peak = motion.acceleration_bound()
    if peak > COMMAND_ACCELERATION_MAX:
        raise InputError('accelerations', peak, 'the commanded motion (from the plate\'s state '
                         'at now through the points) needs |acceleration| = %.6g m/s^2: allowed '
                         '<= %g m/s^2 (points further apart in time or closer in position)'
                         % (peak, COMMAND_ACCELERATION_MAX))
    return Command(motion, dropped)

# -- the vibrating table's settings (the node's parameters) ------------------------------------
TABLE_AMPLITUDE_MAX = 0.1         # m
TABLE_FREQUENCY_MAX = 1000.0      # Hz
TABLE_PHASE_MAX = 2.0 * math.pi   # rad: -2π <= ϕ <= 2π
TABLE_ACCELERATION_MAX = 1000.0   # m/s²: the peak a (2π f)² (Γ ≈ 100)


def vibrating_table(amplitude, frequency, phase):
    """A ``SinusoidalPlate`` from settings in the stated ranges (0 <= a <= ``TABLE_AMPLITUDE_MAX``
    m, 0 <= f <= ``TABLE_FREQUENCY_MAX`` Hz, |ϕ| <= ``TABLE_PHASE_MAX``, peak acceleration
    a (2π f)² <= ``TABLE_ACCELERATION_MAX``), or ``None`` if it does not vibrate (a = 0 or
    f = 0: the fixed plate, not a plate held at a sin ϕ).  ``InputError`` keyed ``amplitude``,
    ``frequency`` or ``phase``."""
    a = require_range('amplitude', amplitude, 0.0, TABLE_AMPLITUDE_MAX, unit='m')
    f = require_range('frequency', frequency, 0.0, TABLE_FREQUENCY_MAX, unit='Hz')
    ph = require_range('phase', phase, -TABLE_PHASE_MAX, TABLE_PHASE_MAX, unit='rad')
    table = SinusoidalPlate(a, f, ph)
    peak = table.acceleration_bound()
    if peak > TABLE_ACCELERATION_MAX:
        raise InputError('amplitude', a, '{n[amplitude]} = {value} m at {n[frequency]} = %g Hz '
                         'shakes the plate at %.4g m/s^2: allowed a (2 pi f)^2 <= %g m/s^2, i.e. '
                         '{n[amplitude]} <= %.4g m at this frequency'
                         % (f, peak, TABLE_ACCELERATION_MAX,
                            TABLE_ACCELERATION_MAX / table.angular_frequency ** 2))
    return table if a > 0.0 and f > 0.0 else None


def sphere_motion(radius, penetration, penetration_rate, plate_position=0.0,
                  plate_velocity=0.0):
    """The sphere's centre height p + R1 - z (m) and upward velocity ṗ - ż (m/s) in the frame
    where the plate's surface at rest is at height 0, from the penetration z (m) and its rate ż
    (m/s) relative to the plate at p (m), moving at ṗ (m/s); floats or numpy arrays."""
    return plate_position + radius - penetration, plate_velocity - penetration_rate


def plate_or_none(plate):
    """``None`` for no plate or a plate that does not move (today's fixed plate)."""
    if plate is None:
        return None
    if not isinstance(plate, PlateMotion):
        raise ValueError(f'plate = {plate!r} is invalid: allowed None, a SinusoidalPlate, a '
                         'CommandedPlate or another plate.PlateMotion')
    if not plate.moving:
        return None
    return plate


# -- flights: the first root of the gap, rigorously bracketed ----------------------------------
EPS = np.finfo(float).eps


def _quadratic_positive(g, dg, curvature, h):
    """True if g + dg s + ½ curvature s² > 0 for every s in [0, h]."""
    if g + dg * h + 0.5 * curvature * h * h <= 0.0:
        return False
    if curvature > 0.0 and dg < 0.0 and -dg / curvature < h:
        return g - 0.5 * dg * dg / curvature > 0.0      # the vertex inside
    return True


def first_gap_root(gap, t0, curvature_bound, t_max=math.inf, max_steps=100000,
                   local_curvature=None):
    """First t in [t0, t_max] where the gap G(t) reaches <= ~0, with no root skipped.

    ``gap(t)`` returns (G, G', scale): the gap (m), its rate (m/s) and a length scale of the
    operands (for the rounding tolerance).  With |G''| <= M = ``curvature_bound`` on the whole
    interval, G(t + s) >= G + G' s - ½ M s² > 0 for 0 <= s < h = (G' + √(G'² + 2 M G)) / M:
    each step to t + h is safe (no root inside), and converges quadratically to a transversal
    root, geometrically to a tangent one.  ``local_curvature(t, h)``, a lower bound of G'' on
    [t, t + h], allows longer safe steps (twice the last one, tried once while the steps are not
    shrinking; the global step is the fallback): where G'' >= 0 nearby, e.g. just after a release,
    where G grows like s³.
    Returns (t, G, G') at the first point where G <= tolerance (16 eps × scale), or ``None`` past
    ``t_max``.
    """
    t = t0
    M = max(curvature_bound, 1e-300)
    trial = 0.0
    for _ in range(max_steps):
        G, dG, scale = gap(t)
        if G <= 16.0 * EPS * max(scale, 1e-9):
            return t, G, dG
        disc = math.sqrt(dG * dG + 2.0 * M * G)
        h = (dG + disc) / M if dG >= 0.0 else 2.0 * G / (disc - dG)
        if local_curvature is not None and h >= 0.5 * trial:
            # the steps are not shrinking (no root ahead yet): try twice the last one, once
            trial = 2.0 * max(trial, h)
            if _quadratic_positive(G, dG, local_curvature(t, trial), trial):
                h = trial
        trial = h
        t_next = t + h
        if t_next == t:
            return t, G, dG
        if t_next > t_max:
            return None
        t = t_next
    raise RuntimeError(f'flight search did not converge in {max_steps} steps from t = {t0!r}')
