"""Flight: the clamped force is zero and the sphere flies over the plate, in closed form, until
the force switches on again (the event ``touch``)."""
import math

from contact_sim.drop.mode import Event, Mode, Move


def ballistic(y0, v0, gravity, dt):
    """The height y (m) and upward velocity (m/s) dt (s, or an array) after leaving y0 (m) at v0
    (m/s) in vacuum under ``gravity`` (m/s²)."""
    return y0 + v0 * dt - 0.5 * gravity * dt * dt, v0 - gravity * dt


class Flight(Mode):
    """A flight over ``plate`` from time ``start`` (s) at (z, ż) (m, m/s) relative to it, under
    ``gravity`` (m/s²): the sphere's absolute lowest point starts at y0 = p - z (m), moving up at
    v0 = ṗ - ż (m/s), ballistic or along the drag ``path`` (a ``flight.FlightPath``).  The plate
    plans it (``PlateMotion.plan_flight``): ``contact_time`` (s, inf: never), and the
    ``apex`` height (m) of a flight after a lift-off (``None`` otherwise)."""

    def __init__(self, plate, gravity, start, z, zdot, contact, drag_rates,
                 after_lift_off=False):
        p, pv, _ = plate.state(start)
        self.plate, self.gravity, self.start = plate, gravity, start
        self.y0, self.v0 = p - z, pv - zdot
        self.path = None
        self.contact_time = math.inf
        self.apex = plate.plan_flight(self, z, zdot, contact, drag_rates, after_lift_off)

    @property
    def until(self):
        return self.contact_time

    def absolute(self, t):
        """The sphere's absolute height y (m) and upward velocity (m/s) at t (s, or an array)."""
        dt = t - self.start
        if self.path is not None:
            return self.path.state(dt)
        return ballistic(self.y0, self.v0, self.gravity, dt)

    def state(self, t):
        if self.path is None:       # ``absolute``'s ballistic flight, inline (a touch a bounce)
            g, dt = self.gravity, t - self.start
            y, v = self.y0 + self.v0 * dt - 0.5 * g * dt * dt, self.v0 - g * dt
        else:
            y, v = self.absolute(t)
        p, pv, _ = self.plate.state(t)
        return p - y, pv - v

    def states(self, t):
        plate = self.plate.states(t)
        if plate is None:
            return None
        y, v = self.absolute(t)
        return plate[0] - y, plate[1] - v

    def advance(self, sim, t_end, budget, points):
        """Closed form up to the touch (``Mode.advance`` without its lookups: a flight a
        bounce)."""
        touch = self.contact_time
        if touch > t_end:
            return Move(None, t_end, budget)
        return Move(self.event_at_until(), touch, budget)

    def event_at_until(self):
        z, zdot = self.state(self.contact_time)
        return Event('touch', self.contact_time, max(z, 0.0), zdot)
