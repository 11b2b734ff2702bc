"""Changes of the plate's motion at a time: the vibrating table's C¹ bridge
(``table_transition``) and trajectory commands (``command_motion``)."""
from dataclasses import dataclass

import numpy as np

from contact_sim.drop.plate.commanded import (SET_POINT_MAX, CommandedPlate, finite_array,
                                              set_point_times)
from contact_sim.drop.plate.motions import (TABLE_ACCELERATION_MAX, SinusoidalPlate,
                                            SwitchedPlate)
from contact_sim.validation import InputError, require_range, require_real

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
    (by factors of 1.25) until the bridge's abs(p̈) is within ``TABLE_ACCELERATION_MAX`` and its
    abs(ṗ) within the larger of ``BRIDGE_SPEED_MAX``, the plate's speed now and the table's peak
    speed, so that a change far from the plate's state is no slam.

    Parameters
    ----------
    now : float
        The drop's time of the change, s.
    current : PlateMotion or None
        The plate's motion until now (``None``: fixed at p = 0).
    table : SinusoidalPlate or None
        The new table (``None`` or one that does not move: the table stops).
    previous_frequency : float, optional
        The old table's frequency, Hz (the bridge's length when the table stops).

    Returns
    -------
    SwitchedPlate or None
        The bridge, then the table; ``None`` when the plate stays fixed.

    Raises
    ------
    InputError
        Keyed ``now``: not a finite number.

    Examples
    --------
    >>> from contact_sim.drop import SinusoidalPlate, table_transition
    >>> plate = table_transition(0.0, None, SinusoidalPlate(0.001, 20.0))
    >>> plate.switch_time                  # bridged over one period of 20 Hz, s
    0.05
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
    not strictly increasing, abs(positions) > ``COMMAND_POSITION_MAX``, abs(velocities) (given
    or estimated) > ``COMMAND_VELOCITY_MAX``, an interpolant with abs(p̈) >
    ``COMMAND_ACCELERATION_MAX``.

    Parameters
    ----------
    now : float
        The drop's time, s.
    position, velocity : float
        The plate's state at ``now``: p in m, ṗ in m/s.
    times : array_like of float
        The points' times, s (the drop's time), strictly increasing.
    positions : array_like of float
        The points' positions, m.
    velocities : array_like of float, optional
        The points' velocities, m/s (default: estimated by finite differences).

    Returns
    -------
    Command
        The plate's ``motion`` from now on (``None`` if no point is left) and the number of
        points ``dropped``.

    Raises
    ------
    InputError
        Naming the field and the allowed range, as listed above.

    Examples
    --------
    >>> from contact_sim.drop import command_motion
    >>> command = command_motion(0.0, 0.0, 0.0, times=[0.5, 1.0], positions=[0.01, 0.0])
    >>> command.dropped, command.motion.times
    (0, (0.0, 0.5, 1.0))
    """
    now = require_range('now', now, -SET_POINT_MAX['times'], SET_POINT_MAX['times'], unit='s')
    position, velocity = require_real('position', position), require_real('velocity', velocity)
    t = set_point_times(times, bounded=False)   # the horizon below: the stricter bound
    p = finite_array('positions', positions, t.size)
    _require_magnitude('positions', p, COMMAND_POSITION_MAX, 'm')
    v = None if velocities is None else finite_array('velocities', velocities, t.size)
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
