"""InContact: a contact phase integrated exactly (``phase.PhaseFactory``), with the plate's
acceleration as forcing, until one of its events: ``lift_off`` (the force vanished), ``knot``
(the plate's forcing changes: the same contact goes on from there), ``landed`` (the contact
became permanent: the same phase goes on), ``settled`` (the fixed plate's rest took over) or
``carried`` (a moving plate carries the sphere).  (The mode is ``InContact``, the model's
``Contact`` the law with its k and λ.)"""
import math

from contact_sim.drop.mode import NO_POINTS, Event, Mode, Move
from contact_sim.drop.mode_carried import CarryWatch
from contact_sim.drop.mode_rest import RestWatch
from contact_sim.phase import potential_at

def energy_bounded_rate(sim, start, z, zdot):
    """The rate ż (m/s) at a lift-off at (z, ż) on the fixed plate, with the energy above rest
    (½ m ż² + ``phase.potential_at``) no higher than at the phase's ``start`` point (t, z, ż, F).

    On the fixed plate the damper only dissipates and gravity and the spring conserve: the
    energy cannot grow during a contact.  The integrator's error (about rtol a phase) can make
    it grow a little, which an elastic contact would turn into e > 1 and a rebound above the
    release; the speed is then taken from the energy at the start instead (the sign kept).
    Unchanged wherever the energy did not grow.
    """
    contact, mass, g = sim.contact, sim.mass, sim.gravity
    e_start = 0.5 * mass * start[2] * start[2] + potential_at(contact, mass, g, start[1])
    potential = potential_at(contact, mass, g, z)
    if not 0.5 * mass * zdot * zdot + potential > e_start:
        return zdot
    return math.copysign(math.sqrt(max(2.0 * (e_start - potential) / mass, 0.0)), zdot)


class InContact(Mode):
    """A contact phase of ``sim`` (a ``DropSimulation``) from time t (s) at (z, ż) (m, m/s).

    The forcing is the plate's on [t, ``valid_until``) (``PlateMotion.forcing_piece``: none and
    for ever on the fixed plate); ``watch`` is what the phase settles into, by the plate: a
    ``RestWatch`` on the fixed plate, a ``CarryWatch`` on a moving one.  ``resumed``: started by
    a change from outside with the sphere inside (no impact of its own); ``record``: the
    (first point, peak force (N), depth (m)) of the same contact before a restart (a knot, a
    change of plate), carried into this phase's impact record."""

    in_contact = True
    until = -math.inf
    first_point, peak, depth = None, 0.0, -math.inf     # no record carried in
    emitted = 0             # the points handed out (an index into the integrator's)
    passed = -math.inf      # and the points up to this time (s), passed

    def __init__(self, sim, t, z, zdot, resumed=False, record=None):
        plate = sim.plate_motion
        forcing, self.valid_until = plate.forcing_piece(t)
        phases = sim.phase_factory()
        self.integrator = phase = phases.start(t, z, zdot, forcing=forcing)
        self.start_point = phase.points[0]      # (t, z, ż, F) at the phase's start
        self.moving = moving = plate.moving
        self.watch = CarryWatch() if moving else RestWatch(phases.energy_floor)
        self.resumed = resumed
        if record is not None:
            self.first_point, self.peak, self.depth = record

    @property
    def steps(self):
        return self.integrator.steps

    @property
    def landed(self):
        """True once the contact is permanent (on the fixed plate): a change of plate then starts
        a new contact phase rather than carrying this one's record on."""
        return self.watch.landed

    @property
    def impact_point(self):
        """(t, z, ż, F) at the start of the contact (before any restart)."""
        return self.first_point or self.start_point

    def record_until(self, t):
        """(first point, peak force (N), depth (m)) of the contact up to t (s), to carry on."""
        phase = self.integrator
        kept = [pt for pt in phase.points if pt[0] <= t]
        return (self.impact_point, max([self.peak] + [pt[3] for pt in kept]),
                max([self.depth] + [pt[1] for pt in kept]))

    def state(self, t):
        phase = self.integrator
        if t == phase.start_time:
            return self.start_point[1], self.start_point[2]
        if t == phase.time:
            return phase.state
        return phase.state_at(t)

    def hand_out(self, points, t_end):
        """Append the integrator's points up to ``t_end`` (s) not handed out yet to ``points``,
        as one (n, 4) array of rows (t, z, ż, F); to ``NO_POINTS`` none: they are passed."""
        if points is NO_POINTS:
            if t_end > self.passed:
                self.passed = t_end
            return
        start = self.emitted
        rows, self.emitted = self.integrator.points_after(start, self.passed, t_end)
        if self.emitted > start:
            points.append(rows)

    def advance(self, sim, t_end, budget, points):
        phase, knot, watch = self.integrator, self.valid_until, self.watch
        stop = min(t_end, knot)
        spent = False
        while True:
            # the end within the forcing piece: lift-off, or the switch to rest
            if phase.lifted_off:
                finish = phase.end[0] if phase.end[0] <= knot else None
            else:
                finish = watch.settled[0] if watch.settled is not None else None
            if finish is not None:
                move = (Move(None, t_end, budget) if finish > t_end
                        else Move(self._finish(sim), finish, budget))
                break
            if knot <= t_end and (phase.lifted_off or phase.time >= knot):
                # the forcing changes at the knot: restart there from the dense output (the last
                # step integrated the forcing continued smoothly past the knot: exact up to it)
                z, zdot = phase.state_at(knot)
                move = Move(Event('knot', knot, z, zdot, resumed=self.resumed,
                                  record=self.record_until(knot)), knot, budget)
                break
            if phase.time >= t_end:
                move = Move(None, t_end, budget)
                break
            if budget <= 0:         # out of budget: stop where the integrator is
                move, spent = Move(None, phase.time, budget), True
                break
            event = watch.before_run(sim, self)
            if event is not None:
                move = Move(event, event.time, budget)
                break
            budget -= watch.run(sim, phase, stop, budget)
            if watch.after_run(sim, self):     # landed for good
                move = Move(Event('landed', phase.time, resumed=self.resumed,
                                  record=(self.start_point, phase.peak_force,
                                          phase.max_penetration)), phase.time, budget)
                break
        # the points up to ``stop`` handed out once, whatever ended the loop (they are the same
        # points, in the same order, as handed out before each of its checks)
        if points is NO_POINTS:             # hand_out's pass, inline (a phase a bounce)
            if stop > self.passed:
                self.passed = stop
        else:
            self.hand_out(points, stop)
        if spent:
            self.hand_out(points, phase.time)
        return move

    def _finish(self, sim):
        """The event at the end of the phase: ``lift_off`` (the rebound's rate bounded by the
        energy on the fixed plate, the impact's record) or ``settled`` (the state where the
        closed-form rest takes over)."""
        phase = self.integrator
        if not phase.lifted_off:
            t, z, zdot = self.watch.settled
            return Event('settled', t, z, zdot, resumed=self.resumed,
                         record=(self.start_point, phase.peak_force, phase.max_penetration))
        t, z, zdot = phase.end
        if not self.moving:
            zdot = energy_bounded_rate(sim, self.start_point, z, zdot)
        return Event('lift_off', t, z, zdot, self.resumed,     # (resumed, record)
                     (self.impact_point, max(phase.peak_force, self.peak),
                      max(phase.max_penetration, self.depth)))
