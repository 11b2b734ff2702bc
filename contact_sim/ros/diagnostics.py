"""``/diagnostics``: how the node keeps up (diagnostic_msgs/DiagnosticArray, once a second),
measured over the last period of wall time.

One ``DiagnosticStatus`` named ``<node's fully qualified name>: simulation`` (hardware_id the
node's name), level OK, or WARN while a real-time run is more than ``LAG_WARN`` s behind; its
values (strings, as diagnostic_msgs has them; numbers in SI units, ``repr`` of a float):

* ``real_time_factor``: the one asked for (``inf`` as fast as possible);
* ``real_time_factor_achieved``: simulated s per wall s over the period;
* ``lag``: s of simulated time the run is behind its wall-clock schedule (0 as fast as possible);
* ``integrator_steps_per_second``: integrator steps of the contact phases per wall s;
* ``ticks_per_second``: ticks published per wall s;
* ``mode``: ``flight``, ``contact``, ``rest`` or ``carried`` (``mode_of``);
* ``paced_by_recorder``: ``true`` while a recorder paces the node (``pacing``);
* ``period``: s of wall time the rates are measured over (since the last message: about
  ``PERIOD``, more for a node that cannot keep up; ``Schedule``).
"""
import math
from dataclasses import dataclass

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from .messages import time_msg

PERIOD = 1.0      # s of wall time between messages
EARLY = 0.05      # s: a message may come this much before its time (a timer's jitter), no more
LAG_WARN = 0.5    # s of simulated time behind schedule before the level is WARN
KEYS = ('real_time_factor', 'real_time_factor_achieved', 'lag', 'integrator_steps_per_second',
        'ticks_per_second', 'mode', 'paced_by_recorder', 'period')


def mode_of(sim):
    """The drop's mode, by what ``DropSimulation`` reports: ``carried`` (the plate carries the
    sphere), ``rest`` (resting for good), ``contact`` or ``flight``."""
    if sim.carried:
        return 'carried'
    if sim.in_contact:
        return 'rest' if sim.settle_time is not None else 'contact'
    return 'flight'


class Schedule:
    """When /diagnostics is due: once every ``period`` s of wall time, on a grid (a late message
    does not move the next one), never twice within a period, whoever asks (the node's timer,
    which an executor flooded by a flat-out loop delivers late and in bursts, and the loop
    itself after each engine call).

    Parameters
    ----------
    start : float
        s (steady clock): the grid's origin; the first message is due a period later.
    period : float, optional
        s (default ``PERIOD``).

    Examples
    --------
    >>> schedule = Schedule(0.0)
    >>> [schedule.due(t) for t in (0.5, 0.97, 0.98, 1.5, 3.2, 3.25, 4.0, 4.2)]
    [False, True, False, False, True, False, False, True]
    """

    def __init__(self, start, period=PERIOD):
        self.period = period
        self._next = start + period

    def due(self, now):
        """Whether a message is due at ``now`` (s); if so, it counts as sent."""
        if now < self._next - EARLY:
            return False
        # the next on the grid; a run more than a period late starts a new grid from now
        self._next += self.period
        if self._next <= now:
            self._next = now + self.period
        return True


@dataclass(frozen=True)
class Progress:
    """What the node has done by a wall time: ``wall`` (s, steady clock), ``simulated`` (s of
    simulated time reached), ``steps`` (integrator steps), ``ticks`` (ticks published)."""

    wall: float
    simulated: float
    steps: int
    ticks: int


def rates(before, after):
    """(real-time factor achieved, integrator steps per s, ticks per s) between two
    ``Progress`` (per wall s; zeros over no wall time).

    Examples
    --------
    >>> rates(Progress(0.0, 0.0, 0, 0), Progress(2.0, 60.0, 100, 6000))
    (30.0, 50.0, 3000.0)
    """
    wall = after.wall - before.wall
    if not wall > 0.0:
        return 0.0, 0.0, 0.0
    return ((after.simulated - before.simulated) / wall, (after.steps - before.steps) / wall,
            (after.ticks - before.ticks) / wall)


def diagnostics_msg(ns, name, real_time_factor, achieved, lag, steps_per_second,
                    ticks_per_second, mode, paced, period=PERIOD):
    """The DiagnosticArray of one period.

    Parameters
    ----------
    ns : int
        Stamp, ns of simulated time.
    name : str
        The node's fully qualified name.
    real_time_factor, achieved : float
        The factor asked for (inf: as fast as possible) and the one achieved (-).
    lag : float
        s of simulated time behind schedule (>= 0).
    steps_per_second, ticks_per_second : float
        Integrator steps and ticks per wall s.
    mode : str
        ``mode_of`` the drop.
    paced : bool
        Whether a recorder paces the node.
    period : float, optional
        s of wall time the rates are measured over (default ``PERIOD``).

    Returns
    -------
    diagnostic_msgs.msg.DiagnosticArray

    Examples
    --------
    >>> msg = diagnostics_msg(10**9, '/contact_sim', 1.0, 0.99, 0.0, 120.0, 100.0, 'rest', False)
    >>> [v.key for v in msg.status[0].values][:2], msg.status[0].level == DiagnosticStatus.OK
    (['real_time_factor', 'real_time_factor_achieved'], True)
    """
    late = math.isfinite(real_time_factor) and real_time_factor > 0.0 and lag > LAG_WARN
    status = DiagnosticStatus(
        level=DiagnosticStatus.WARN if late else DiagnosticStatus.OK,
        name=f'{name}: simulation', hardware_id=name,
        message=(f'{lag:.3g} s behind real time' if late else
                 f'{achieved:.3g} x real time, {mode}'))
    values = (real_time_factor, achieved, lag, steps_per_second, ticks_per_second, mode,
              'true' if paced else 'false', period)
    status.values = [KeyValue(key=key, value=value if isinstance(value, str) else repr(
        float(value))) for key, value in zip(KEYS, values)]
    msg = DiagnosticArray(status=[status])
    msg.header.stamp = time_msg(ns)
    return msg
