"""Rest on the fixed plate: the linearised damped oscillation about the static deflection, in
closed form, for ever; and ``RestWatch``, the test a contact phase on the fixed plate makes after
each run of steps: has it become permanent (the energy above rest below the lift-off floor, or a
provable creep into the rest depth: the event ``landed``), and has its oscillation decayed enough
for the closed form to take over (the event ``settled``, see ``mode_contact``)?"""
import math

import numpy as np

from contact_sim.drop.mode import Mode


class Rest(Mode):
    """The linearised damped oscillation about the static deflection ``rest_depth`` z0 (m) from
    ``start`` (s), with ``offset`` z - z0 (m) and ``rate`` ż (m/s) then, ``decay`` a = c / 2m
    (1/s) and ``natural_sq`` ω₀² = k' / m (1/s²) of the linearisation."""

    in_contact = True

    def __init__(self, start, rest_depth, offset, rate, decay, natural_sq):
        self.start, self.rest_depth, self.offset, self.rate = start, rest_depth, offset, rate
        self.decay, self.natural_sq = decay, natural_sq

    def _oscillation(self, t, exp, cos, sin):
        """(z, ż) at the times t with the functions ``exp``, ``cos``, ``sin`` of ``math`` (a
        float t) or ``numpy`` (an array)."""
        dt = t - self.start
        a, w0sq = self.decay, self.natural_sq
        disc = w0sq - a * a
        if disc > 0.0:                      # underdamped
            w = math.sqrt(disc)
            e = exp(-a * dt)
            ec, es = e * cos(w * dt), e * sin(w * dt) / w
        elif disc < 0.0:                    # overdamped: e^(-a t) cosh, sinh without overflow
            w = math.sqrt(-disc)            # w < a
            slow, fast = exp((w - a) * dt), exp(-(w + a) * dt)
            ec, es = 0.5 * (slow + fast), 0.5 * (slow - fast) / w
        else:                               # critically damped
            e = exp(-a * dt)
            ec, es = e, e * dt
        y = self.offset * ec + (self.rate + a * self.offset) * es
        v = self.rate * ec - (a * self.rate + w0sq * self.offset) * es
        return self.rest_depth + y, v

    def state(self, t):
        return self._oscillation(t, math.exp, math.cos, math.sin)

    def states(self, t):
        return self._oscillation(t, np.exp, np.cos, np.sin)


def rest_after(sim, t, z, zdot):
    """The ``Rest`` of ``sim`` (a ``DropSimulation``) from the state (z, ż) (m, m/s) at t (s):
    its contact's linearisation about the static depth (``Contact.rest_linearisation``)."""
    z0, k_lin, c_lin = sim.contact.rest_linearisation(sim.mass * sim.gravity)
    return Rest(t, z0, z - z0, zdot, c_lin / (2.0 * sim.mass), k_lin / sim.mass)


class RestWatch:
    """What a contact phase on the fixed plate settles into: permanent contact, then rest.

    ``floor``: below this energy above rest (J) the force can never vanish again
    (``phase.PhaseFactory.energy_floor``); ``permanent``
    once it is so; ``settled``: (t s, z m, ż m/s) where the oscillation has decayed below
    ``settle_tolerance`` of the rest depth and the closed-form ``Rest`` takes over (laws linear
    in the rate only: the others are integrated all the way), ``None`` before."""

    settled = None

    def __init__(self, floor):
        self.floor = floor
        self.permanent = False

    @property
    def landed(self):
        """True once the contact is permanent (the sphere never leaves the plate again)."""
        return self.permanent

    def before_run(self, sim, contact):
        return None

    def run(self, sim, phase, t_stop, budget):
        """Steps until ``t_stop`` (s), ``budget`` or the energy at which ``after_run`` has work."""
        return phase.run(t_stop, budget, self.floor if not self.permanent
                         else self._rest_energy(sim))

    def _rest_energy(self, sim):
        """The energy above rest (J) below which a permanent contact settles: the phase runs its
        steps without returning until then, as it does down to ``floor`` before (it stops at
        the first step below); -inf where no closed-form rest takes over."""
        if sim.gravity <= 0.0 or not sim.contact.law.linear_in_rate:
            return -math.inf
        z0, k_lin, _ = sim.contact.rest_linearisation(sim.mass * sim.gravity)
        return 0.5 * k_lin * (sim.settle_tolerance * z0) ** 2

    def after_run(self, sim, contact):
        """Mark permanent contact, and where the closed-form rest takes over (``settled``);
        returns True if the contact has become permanent now (the landing for good, reported as
        the event ``landed``)."""
        phase = contact.integrator
        if sim.gravity <= 0.0 or phase.lifted_off:
            return False
        energy = phase.energy_above_rest()
        landed = not self.permanent and self.lands(sim, phase, energy)
        if landed:
            self.permanent = True
        if not self.permanent or not sim.contact.law.linear_in_rate:
            return landed   # (no linear damping at rest: it is integrated all the way)
        z0, k_lin, _ = sim.contact.rest_linearisation(sim.mass * sim.gravity)
        amplitude = math.sqrt(2.0 * max(energy, 0.0) / k_lin)
        if amplitude < sim.settle_tolerance * z0:
            self.settled = (phase.time, *phase.state)
        return landed

    def lands(self, sim, phase, energy):
        """True if the running ``phase`` (not lifted off, at the ``energy`` above rest (J) its
        integrator reached) can never leave the plate again: below the lift-off floor, or in a
        provable creep into the rest depth."""
        return energy < self.floor or _creeps_to_rest(sim, phase)


def _creeps_to_rest(sim, phase):
    """True if the sphere provably creeps down into its rest depth z0 without lift-off.

    For q = 1, above z0 (z < z0) moving down (ż >= 0): ż cannot turn negative before z0
    (at ż = 0 the net force m g - k zⁿ is down).  With b = λ zᵖ/m (zᵖ grows with z) and
    a = max slope of k zⁿ on [z, z0] / m, the region 0 <= ż <= c (z0 - z) is invariant when
    c² - b c + a <= 0 (check the boundary ż = c δ: z̈ + c ż <= δ (a - b c + c²)), which has a
    solution c = (b + √(b² - 4a))/2 when b² >= 4a.  Inside it the sphere reaches z0 only
    with ż = 0: the force k zⁿ + λ zᵖ ż stays positive for ever: permanent contact.
    """
    contact, mass = sim.contact, sim.mass
    law = contact.law
    if not law.linear_in_rate:
        return False
    z, zdot = phase.state
    z0 = contact.static_penetration(mass * sim.gravity)
    if not (0.0 < z < z0 and zdot >= 0.0):
        return False
    n, k = law.n, contact.stiffness
    a = n * k * max(z ** (n - 1.0), z0 ** (n - 1.0)) / mass
    b = contact.damping * z ** law.p / mass
    disc = b * b - 4.0 * a
    return disc >= 0.0 and zdot <= 0.5 * (b + math.sqrt(disc)) * (z0 - z)
