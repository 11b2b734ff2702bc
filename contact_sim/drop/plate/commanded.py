"""A plate commanded by timed set-points: ``CommandedPlate``, the C¹ piecewise-quadratic
interpolant through them, and the checks of set-point arrays that ``command_motion`` shares."""
import bisect
import functools
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.drop.plate.flights import commanded_flight, gap_flight
from contact_sim.drop.plate.motions import PlateMotion, constant_forcing
from contact_sim.drop.plate.pieces import piece_forcing, piece_state
from contact_sim.validation import InputError, require_real_array


@dataclass(frozen=True)
class CommandedPlate(PlateMotion):
    """A plate through set-points, C¹, with constant acceleration on each half-interval.

    The interpolation is stated in the module docstring (constant velocity outside the points).

    Attributes
    ----------
    times : tuple of float
        tᵢ, s, strictly increasing, at least one.
    positions : tuple of float
        pᵢ, m, one per time.
    velocities : tuple of float
        vᵢ, m/s, one per time.

    Raises
    ------
    InputError
        Keyed by the field: lengths that differ, non-finite values, or times not strictly
        increasing.

    Examples
    --------
    >>> from contact_sim.drop import CommandedPlate
    >>> plate = CommandedPlate((0.0, 0.5), (0.0, 0.01), (0.0, 0.0))   # up 1 cm in 0.5 s
    >>> [round(x, 6) for x in plate.state(0.25)]                     # p m, v m/s, a m/s^2
    [0.005, 0.04, -0.16]
    """

    times: tuple
    positions: tuple
    velocities: tuple

    def __post_init__(self):
        times = set_point_times(self.times)
        n = times.size
        arrays = {'times': times,
                  'positions': finite_array('positions', self.positions, n, bounded=True),
                  'velocities': finite_array('velocities', self.velocities, n, bounded=True)}
        for name, arr in arrays.items():
            object.__setattr__(self, name, tuple(arr.tolist()))
        t, p, v = arrays['times'], arrays['positions'], arrays['velocities']
        h = 0.5 * np.diff(t)
        with np.errstate(all='ignore'):   # too close points: refused just below
            dv = (v[1:] - v[:-1]) / h if n > 1 else np.empty(0)
            a1 = 0.5 * (2.0 * (p[1:] - p[:-1] - 2.0 * v[:-1] * h) / h ** 2 - dv) if n > 1 \
                else np.empty(0)
            a2 = dv - a1
        _require_gentle(t, a1, a2)
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

    @functools.cached_property
    def piece_arrays(self):
        """The pieces (rows: start times s, positions m, velocities m/s, accelerations m/s²; the
        last piece runs to +inf with zero acceleration) as one C-contiguous float64 array of
        shape (4, pieces), built once: the commanded plate as the compiled flight search takes it
        (each row a contiguous array)."""
        return np.array(self._pieces, dtype=np.float64)

    @functools.cached_property
    def piece_rows(self):
        """The four rows of ``piece_arrays`` (start times, positions, velocities,
        accelerations), each a contiguous array, as a tuple made once: the arguments of the
        compiled flight search (``flights.commanded_flight``, one a flight)."""
        return tuple(self.piece_arrays)

    def plan_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off):
        """In vacuum the touch time comes from compiled code (``flights.commanded_flight``),
        with drag from ``flights.gap_flight`` (the reference path of both)."""
        if drag_rates is None:
            return commanded_flight(self, flight, z, zdot, contact, after_lift_off)
        return gap_flight(self, flight, z, zdot, contact, drag_rates, after_lift_off)

    def _piece(self, t):
        i = bisect.bisect_right(self._pieces[0], t) - 1
        return i if i > 0 else 0

    def state(self, t):
        pieces = self._pieces       # ``_piece`` inline (a few times a bounce)
        i = bisect.bisect_right(pieces[0], t) - 1
        return piece_state(*pieces, i if i > 0 else 0, t)

    def jerk(self, t):
        """d p̈ / dt (m/s³): zero inside every piece."""
        return 0.0

    def acceleration_bound(self):
        return self._peak_acceleration

    @functools.cached_property
    def _peak_acceleration(self):
        """max abs(p̈) over the pieces (m/s²), found once: every flight's bracket asks for it."""
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
        """Peak abs(ṗ) (m/s): ṗ is piecewise linear, so at a piece's ends."""
        return self._peak_speed

    @functools.cached_property
    def _peak_speed(self):
        """max abs(ṗ) over the set-points and pieces (m/s), found once: every drop's check asks
        for it (about 1 ms for 8000 set-points)."""
        return max(abs(v) for v in self.velocities + self._pieces[2])

    def acceleration_range(self, t0, t1):
        """(min, max) of p̈ over [t0, t1]: over the pieces it overlaps."""
        starts, acc = self._pieces[0], self._pieces[3]
        values = [0.0] if t0 < starts[0] else []
        if t1 >= starts[0]:
            values += acc[self._piece(max(t0, starts[0])):self._piece(t1) + 1]
        return min(values), max(values)

    def forcing_piece(self, t):
        starts = self._pieces[0]
        i = bisect.bisect_right(starts, t) - 1
        acceleration, until = piece_forcing(starts, self._pieces[3], i if i > 0 else 0, t)
        return constant_forcing(acceleration), until

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


# The set-points any CommandedPlate takes (a command of the node is held to far less,
# ``commands.COMMAND_POSITION_MAX`` ...): beyond them the pieces' doubles overflow or lose
# every digit (points 1e-300 s apart need accelerations of 1e300 m/s²).
SET_POINT_MAX = {'times': 1e9, 'positions': 1e3, 'velocities': 1e3}   # s, m, m/s
SET_POINT_UNITS = {'times': 's', 'positions': 'm', 'velocities': 'm/s'}
PIECE_ACCELERATION_MAX = 1e9   # m/s²: the interpolant's, between two points


def finite_array(name, values, count=None, bounded=False):
    """``values`` as a flat float array: real numbers (no text, booleans or complex numbers:
    ``validation.require_real_array``), finite, within +-``SET_POINT_MAX[name]`` when
    ``bounded``, and ``count`` of them when given."""
    arr = require_real_array(name, values).ravel()
    bound = SET_POINT_MAX.get(name) if bounded else None
    if bound is not None and arr.size and float(np.max(np.abs(arr))) > bound:
        worst = float(arr[np.argmax(np.abs(arr))])
        raise InputError(name, worst, '{n[%s]} holds {value}: allowed -%g <= {n[%s]} <= %g %s'
                         % (name, bound, name, bound, SET_POINT_UNITS[name]), value=repr(worst))
    if count is not None and arr.size != count:
        raise InputError(name, values, '{n[%s]} has %d values: allowed one per point (%d)'
                         % (name, arr.size, count), value=repr(arr.tolist()))
    return arr


def _require_gentle(t, a1, a2):
    """Refuse pieces whose acceleration is not finite or above ``PIECE_ACCELERATION_MAX``
    (points too close in time for the change of position or velocity between them)."""
    worst = np.maximum(np.abs(a1), np.abs(a2))
    bad = np.flatnonzero(~(worst <= PIECE_ACCELERATION_MAX))
    if bad.size:
        i = int(bad[0])
        raise InputError('times', float(t[i + 1] - t[i]), '{n[times]}[%d] and [%d] are {value} s '
                         'apart: the motion between them needs |acceleration| = %.3g m/s^2; '
                         'allowed <= %g m/s^2 (points further apart in time or closer in '
                         'position and velocity)' % (i, i + 1, float(worst[i]),
                                                     PIECE_ACCELERATION_MAX))


def set_point_times(times, bounded=True):
    """Set-point times (s) as an array: at least one, finite, strictly increasing (and within
    +-``SET_POINT_MAX['times']`` when ``bounded``)."""
    t = finite_array('times', times, bounded=bounded)
    if t.size == 0:
        raise InputError('times', times, '{n[times]} is empty: allowed at least one point',
                         value='[]')
    if np.any(np.diff(t) <= 0.0):
        raise InputError('times', times, '{n[times]} = {value} is out of range: allowed strictly '
                         'increasing times', value=repr(t.tolist()))
    return t

