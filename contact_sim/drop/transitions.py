"""The drop engine's transition table: which event of which mode leads to which mode.

``TRANSITIONS[(mode class, event name)]`` is the entry ``(sim, mode, event) -> next mode`` (the
same mode: no change), ``sim`` the ``DropSimulation``, ``mode`` the mode the event ended.  The
events a mode reports itself (``Mode.advance``): ``touch`` (flight), ``lift_off``, ``knot``,
``landed``, ``settled``, ``carried`` (contact), ``released`` (carried).  The changes from
outside, at the current time: ``set_contact`` (``event.contact`` is the new contact) and
``set_plate`` (the plate's motion has changed; (z, ż) are relative to the new plate).

Every successor is made here, from the event: no mode builds the one that follows it.  And what
the drop records of an event (an impact at a lift-off, the landing for good, the rest, the
carried state, a flight's apex) is written here, with the ledger's one method for it
(``records.Recorder``).

A contact given during a contact phase waits (``DropSimulation.pending_contact``) and is taken
by the next contact phase that starts (an impact or a resumed contact) or at a lift-off.
"""
from contact_sim.drop.mode_carried import Carried, carried_from
from contact_sim.drop.mode_contact import InContact
from contact_sim.drop.mode_flight import Flight
from contact_sim.drop.mode_rest import Rest, rest_after


def _take_pending_contact(sim):
    if sim.pending_contact is not None:
        sim.contact, sim.pending_contact = sim.pending_contact, None


def free_motion(sim, t, z, zdot, after_lift_off=False, resumed=False):
    """The motion from (t, z, ż) (s, m, m/s) with the contact force off: a contact phase at once
    if the force is already on (not after a lift-off), else a flight, its apex recorded."""
    if not after_lift_off and z > 0.0 and sim.contact.force_at(z, zdot) > 0.0:
        return _contact(sim, t, z, zdot, resumed)
    flight = Flight(sim.plate_motion, sim.gravity, t, z, zdot, sim.contact, sim.drag_rates,
                    after_lift_off)
    sim.recorder.apex(flight.apex)
    return flight


def _contact(sim, t, z, zdot, resumed):
    if sim.pending_contact is not None:
        _take_pending_contact(sim)
    return InContact(sim, t, z, zdot, resumed=resumed)


def impact(sim, mode, event):
    """A contact phase begins: an impact (recorded when it ends)."""
    return _contact(sim, event.time, event.penetration, event.penetration_rate, False)


def resume(sim, mode, event):
    """A contact phase begins with the sphere already inside: no impact of its own."""
    return _contact(sim, event.time, event.penetration, event.penetration_rate, True)


def go_on(sim, mode, event):
    """The same contact goes on in a new phase (the plate's forcing changed), its record carried."""
    return InContact(sim, event.time, event.penetration, event.penetration_rate,
                     resumed=event.resumed, record=event.record)


def bounce(sim, mode, event):
    """The flight after a lift-off, the impact recorded (a waiting contact is taken now, unless
    the phase was resumed)."""
    impact_point, peak_force, max_penetration = event.record
    sim.recorder.lift_off(impact_point, event.time, event.penetration_rate, peak_force,
                          max_penetration, event.resumed)
    if not event.resumed and sim.pending_contact is not None:
        _take_pending_contact(sim)
    return free_motion(sim, event.time, event.penetration, event.penetration_rate,
                       after_lift_off=True)


def land(sim, mode, event):
    """The contact phase became permanent: the same phase goes on, its landing for good
    recorded as an impact (unless the phase was resumed)."""
    if not event.resumed:
        sim.recorder.land(*event.record)
    return mode


def settle(sim, mode, event):
    """The phase settled: the closed-form rest from its state, the rest recorded (with the
    landing's final peaks, unless the phase was resumed)."""
    if event.resumed:
        sim.recorder.settle(event.time)
    else:
        sim.recorder.settle(event.time, *event.record, impact_time=mode.impact_point[0])
    return rest_after(sim, event.time, event.penetration, event.penetration_rate)


def carry(sim, mode, event):
    """The plate carries the sphere: the quasi-static state from here, the landing for good
    recorded at the contact's impact (unless one came before)."""
    sim.recorder.carry(mode.impact_point[0])
    return carried_from(sim, event.time)


def fly_on(sim, mode, event):
    """A flight re-entered from the current state (the force may be on at once)."""
    return free_motion(sim, event.time, event.penetration, event.penetration_rate,
                       resumed=True)


def new_contact(entry):
    """``entry`` with the new contact (``event.contact``) in use first."""
    def with_contact(sim, mode, event):
        sim.contact = event.contact
        return entry(sim, mode, event)
    return with_contact


def contact_waits(sim, mode, event):
    """During a contact phase a new contact waits for the next phase."""
    sim.pending_contact = event.contact
    return mode


def replant(sim, mode, event):
    """A change of plate in a contact phase: the same contact goes on with the new forcing
    (a waiting contact still waits), or, once the contact is permanent, a new resumed phase."""
    if mode.landed:
        return resume(sim, mode, event)
    return InContact(sim, event.time, event.penetration, event.penetration_rate,
                     resumed=mode.resumed, record=mode.record_until(event.time))


TRANSITIONS = {
    (Flight, 'touch'): impact,
    (Flight, 'set_contact'): new_contact(fly_on),
    (Flight, 'set_plate'): fly_on,
    (InContact, 'lift_off'): bounce,
    (InContact, 'knot'): go_on,
    (InContact, 'landed'): land,
    (InContact, 'settled'): settle,
    (InContact, 'carried'): carry,
    (InContact, 'set_contact'): contact_waits,
    (InContact, 'set_plate'): replant,
    (Rest, 'set_contact'): new_contact(resume),
    (Rest, 'set_plate'): resume,
    (Carried, 'released'): impact,
    (Carried, 'set_contact'): new_contact(resume),
    (Carried, 'set_plate'): resume,
}
