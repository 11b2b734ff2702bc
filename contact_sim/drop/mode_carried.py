"""Carried by a moving plate: the quasi-static state while the plate's acceleration is above
-g/2 (the event ``released`` at its end); and ``CarryWatch``, the test a contact phase on a moving
plate makes between its runs of steps: has its oscillation about the quasi-static depth decayed
enough for the carried state to take over (the event ``carried``, see ``mode_contact``)?"""
import math

from contact_sim.drop.mode import Event, Mode

CHUNK = 32    # contact steps between two tests for the carried state


class Carried(Mode):
    """The sphere carried by the plate (plate acceleration above -g/2) from ``start`` (s):
    quasi-static, the depth z_s(t) = (m (g + p̈(t)) / k)^(1/n) (m) at which the contact force
    carries the sphere along, until ``until`` (s): the plate's acceleration falls to -g/2, or a
    set-point knot changes it.  ``plate``: its ``PlateMotion``; ``contact``, ``mass`` (kg),
    ``gravity`` (m/s²): the sphere's."""

    in_contact = True
    carried = True

    def __init__(self, start, until, plate, contact, mass, gravity):
        self.start, self.until, self.plate = start, until, plate
        self.contact, self.mass, self.gravity = contact, mass, gravity

    def state(self, t):
        # the acceleration of the carried stretch: at ``until`` its left limit (a knot)
        _, _, acc = self.plate.state(min(t, math.nextafter(self.until, -math.inf)))
        return quasi_static(self.contact, self.mass, self.gravity, acc, self.plate.jerk(t))

    def event_at_until(self):
        z, zdot = self.state(self.until)
        return Event('released', self.until, z, zdot)


def quasi_static(contact, mass, gravity, acceleration, jerk):
    """(z_s m, ż_s m/s): the depth at which ``contact`` carries ``mass`` (kg) along a plate
    accelerating at p̈ (m/s², ``acceleration``) under ``gravity`` (m/s²), and its rate with the
    plate's ``jerk`` (m/s³); (0, 0) once g + p̈ <= 0.  (``Carried.state``, and ``CarryWatch``'s
    test before a carried state exists.)"""
    load = mass * max(gravity + acceleration, 0.0)
    z = contact.static_penetration(load)
    rate = z * jerk / (contact.law.n * (gravity + acceleration)) if load > 0.0 else 0.0
    return z, rate


def carried_from(sim, t):
    """The ``Carried`` state of ``sim`` (a ``DropSimulation``) from t (s) on: until the plate's
    acceleration falls to -g/2 or its forcing piece ends."""
    plate, g = sim.plate_motion, sim.gravity
    until = min(plate.next_acceleration_below(t, -0.5 * g), plate.forcing_piece(t)[1])
    return Carried(t, until, plate, sim.contact, sim.mass, g)


class CarryWatch:
    """What a contact phase on a moving plate settles into: the ``Carried`` state.  It runs
    ``CHUNK`` steps at a time and tests before each run; it never lands for good."""

    landed = False
    settled = None

    def run(self, sim, phase, t_stop, budget):
        return phase.run(t_stop, CHUNK)

    def after_run(self, sim, contact):
        return False

    def before_run(self, sim, contact):
        """The event ``carried`` at the quasi-static state (z_s, ż_s) if the plate's
        acceleration is above -g/4 and the contact's oscillation about that state has decayed
        below ``settle_tolerance``."""
        plate, g = sim.plate_motion, sim.gravity
        phase = contact.integrator
        t = phase.time
        p_acc = plate.state(t)[2]
        if p_acc <= -0.25 * g:    # hysteresis: carried from -g/4, released at -g/2
            return None
        # ``carried_from(sim, t).state(t)`` without making the carried state: its stretch ends
        # after t (p̈ is above -g/2 at t, and a forcing piece holds at its start), so its state at
        # t is the quasi-static one at t's acceleration
        z_s, rate_s = quasi_static(sim.contact, sim.mass, g, p_acc, plate.jerk(t))
        z, zdot = phase.state
        law = sim.contact.law
        k_lin = law.n * sim.contact.stiffness * z_s ** (law.n - 1.0)
        deviation = math.hypot(z - z_s, (zdot - rate_s) * math.sqrt(sim.mass / k_lin))
        if not deviation < sim.settle_tolerance * z_s:
            return None
        return Event('carried', t, z_s, rate_s)
