"""The interface of the drop engine's modes, and what a mode's ``advance`` returns.

A mode (flight, contact, rest, carried, ...) is the motion of the sphere between two events.  It
knows its own state and how far it can go alone; it does not know what follows it: it reports
an ``Event`` and the engine looks the next mode up in ``transitions.TRANSITIONS``.
"""
import math
from typing import NamedTuple


class Event(NamedTuple):
    """What ended a mode, at ``time`` (s) with the sphere at ``penetration`` z (m) and
    ``penetration_rate`` ż (m/s) relative to the plate.

    ``name`` is the key of ``transitions.TRANSITIONS`` (with the mode's class); ``resumed``: a
    contact phase started by a change from outside (no impact of its own); ``record``: a contact's
    (first point (t, z, ż, F), peak force (N), depth (m)): carried into the phase that goes on
    from here (``knot``), or recorded (``lift_off``, ``landed``: the phase's own first point);
    ``contact``: a new ``Contact`` given from outside.  (Events and moves are named tuples: a
    few are made at every bounce.)"""

    name: str
    time: float
    penetration: float = 0.0
    penetration_rate: float = 0.0
    resumed: bool = False
    record: tuple = None
    contact: object = None


class Move(NamedTuple):
    """What ``Mode.advance`` did: the ``event`` that ended the mode (``None``: it stopped at
    ``time`` (s), the end asked or where the step budget ran out) and the ``budget`` of
    integrator steps left."""

    event: Event
    time: float
    budget: float


class Mode:
    """A mode of the drop: a base class stating the interface, with the defaults of a motion in
    closed form.

    * ``until``: the time (s) before which ``advance`` only evaluates this closed-form motion (no
      event): inf for ever, -inf for a mode that integrates;
    * ``state(t)`` -> (z, ż) (m, m/s) at a time t (s) the mode has reached;
    * ``states(t)`` -> (z, ż) over an array of times (s), vectorised with the operations of
      ``state``, or ``None`` (the engine then asks ``state`` tick by tick);
    * ``advance(sim, t_end, budget, points)`` -> ``Move``: go on until ``t_end`` (s) or the next
      event, with at most ``budget`` integrator steps, appending the contact points passed to
      ``points`` (a list, as (n, 4) arrays of rows (t, z, ż, F); ``NO_POINTS``: none
      gathered); ``sim`` is the ``DropSimulation`` (contact, mass, gravity, plate, recorder);
    * ``event_at_until()``: the event at ``until`` of a closed-form mode that has one (the
      default ``advance`` reports it once ``t_end`` reaches ``until``);
    * ``steps``: integrator steps taken in this mode so far (the engine adds them to the record
      when the mode ends); ``in_contact``, ``carried``: what ``DropSimulation`` reports.
    """

    in_contact = False
    carried = False
    steps = 0
    until = math.inf

    def state(self, t):
        raise NotImplementedError

    def states(self, t):
        return None

    def advance(self, sim, t_end, budget, points):
        """A closed-form motion up to ``until``: the event there, or a stop at ``t_end``."""
        if self.until > t_end:
            return Move(None, t_end, budget)
        return Move(self.event_at_until(), self.until, budget)

    def event_at_until(self):
        raise NotImplementedError


class _NoPoints:
    """A sink for the contact points that nobody reads: ``append`` drops them."""

    @staticmethod
    def append(rows):
        pass


NO_POINTS = _NoPoints()     # the ``points`` of an advance that gathers none (``run_to``)
