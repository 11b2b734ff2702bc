"""One compliant contact advanced exactly over each step of a host simulator (no engine import).

The host (MuJoCo, PyBullet, Drake, ...) gives, at the start of each of its steps, the contact's
gap along its normal (m, > 0 apart), the gap's rate (m/s), the effective mass along the normal
(kg, 1 / (J M⁻¹ Jᵀ) at the contact point), the normal acceleration the rest of the system gives
the gap over the step (m/s², gravity, actuators) and the step dt (s).  ``NormalCoupling.step``
advances the contact exactly over the step with the package's own pieces: the closed-form
flight under that constant acceleration (``flight``), the compiled contact phase with its
located lift-off (``phase.contact_phase``), as many of each as the step holds, and returns the
impulse (N·s, along the normal, pushing apart) the host applies as the force impulse / dt over
that step, the impacts the step completed and the exact state it carries.

**How the host's state and the exact state are reconciled.**  Hosts that step positions with
the new velocity (semi-implicit Euler: MuJoCo's Euler and implicitfast, PyBullet, Drake's
discrete plant) move the gap by dt · v₁ in a step that ends at the normal velocity v₁.  The
impulse is chosen so that v₁ = (z_end - z_host) / dt: the host's gap at the end of the step is
then the exact one, at every step, in contact and out of it.  No energy enters or leaves through
the host's position update, and a resting sphere gets exactly m a dt (its weight) every step.
The host's velocity is then the mean velocity over its last step, as in a leapfrog; the exact
velocity is carried (with the phase in progress, which runs on over as many host steps as the
contact lasts, one contact) and the host's gap and velocity are compared with what the last
step made them.  Within ``tolerance`` the carried exact state goes on; beyond it (another
constraint, an actuator, a reset moved the bodies) the host's gap is taken and its unexplained
change of velocity added to the exact velocity, and the phase restarts there.  Far from
contact nothing is carried: the host's own flight under a constant acceleration samples the
exact parabola, whose velocity at the step's start is v + a dt / 2.

The impulse of a step is the contact force weighted by the triangle of two host steps centred
on the step's start (the leapfrog's window), so it is >= 0 and its sum over a contact is the
contact's impulse.

A host that integrates a given force over its step instead (``host='continuous'``: Drake's
continuous plant) gets the force impulse / dt + ``force_rate`` (t - t₀ - dt / 2), linear over the
step, whose two numbers bring both its gap and its velocity to the exact ones at the step's end;
its velocity is then the exact one.  Units: SI.
"""
import math
from dataclasses import dataclass

from contact_sim.coupling.flight import parabola, touch_time
from contact_sim.model import require_contact
from contact_sim.phase import Forcing, contact_phase
from contact_sim.validation import InputError, require_positive, require_real

# the carried exact state goes on while the host's gap and normal velocity are within these of
# what the last step made them (relative to the contact's scales, and absolute floors)
TOLERANCE = 1e-9
# a resting contact settles into exact rest once its energy above rest is below this fraction of
# m g z0 (its oscillation about z0 is then ~1e-6 z0 or less)
REST_ENERGY = 1e-12
# the host's acceleration counts as unchanged within this relative difference
ACCELERATION_RTOL = 1e-9
# how a host moves its positions over a step (``NormalCoupling``'s ``host``)
HOSTS = ('semi_implicit', 'continuous')


@dataclass(frozen=True)
class CoupledImpact:
    """One impact of a coupled contact, from touch to lift-off (exact).

    Attributes
    ----------
    time : float
        Touch time, s (the host's clock).
    speed_in : float
        Approach speed at touch, m/s, >= 0.
    speed_out : float
        Separation speed at lift-off, m/s, >= 0.
    peak_force : float
        Largest contact force, N.
    duration : float
        Touch to lift-off, s.
    max_penetration : float
        Deepest penetration, m.
    """

    time: float
    speed_in: float
    speed_out: float
    peak_force: float
    duration: float
    max_penetration: float

    @property
    def restitution(self):
        """speed_out / speed_in (nan for a touch at zero speed)."""
        return self.speed_out / self.speed_in if self.speed_in > 0.0 else math.nan


@dataclass(frozen=True)
class CouplingStep:
    """What one host step of a coupled contact gives back.

    Attributes
    ----------
    impulse : float
        The normal impulse over the step, N·s, >= 0, pushing the bodies apart: the host
        applies impulse / dt as a force for the step.
    impacts : tuple of CoupledImpact
        The impacts that ended (lifted off) inside the step.
    penetration, penetration_rate : float
        The exact z (m) and ż (m/s) at the step's end (z > 0 penetration, ż > 0 approach).
    in_contact : bool
        Whether the contact force is on at the step's end.
    touched : bool
        Whether the contact force was on at any time in the step.
    force_rate : float
        N/s, a ``'continuous'`` host's only (0 otherwise): the force over the step is
        impulse / dt + force_rate (t - t₀ - dt / 2), t₀ the step's start, which moves such a
        host's gap and velocity to the exact ones at the step's end.
    remainder : float
        N·s, >= 0, a semi-implicit host's only (0 otherwise): the part of the contact force's
        impulse inside this step that the next step's impulse carries (the force weighted by
        (t - t₀) / dt, the second half of the triangle).  An adapter whose contact Jacobian turns
        within a step applies it along the direction it had in this step.
    """

    impulse: float
    impacts: tuple
    penetration: float
    penetration_rate: float
    in_contact: bool
    touched: bool
    force_rate: float = 0.0
    remainder: float = 0.0


# flights and contact phases one host step may hold before it is refused as stuck
MAX_SEGMENTS = 100_000


class _Carried:
    """The exact state a coupled contact carries between host steps."""

    __slots__ = ('time', 'z', 'zdot', 'mode', 'phase', 'acceleration', 'host_z', 'host_v',
                 'touch', 'speed_in', 'peak', 'depth', 'leaving')

    def __init__(self, time, z, zdot, mode, acceleration, host_z, host_v):
        self.time, self.z, self.zdot, self.mode, self.phase = time, z, zdot, mode, None
        self.acceleration, self.host_z, self.host_v = acceleration, host_z, host_v
        self.touch, self.speed_in, self.peak, self.depth = time, max(zdot, 0.0), 0.0, 0.0
        self.leaving = False


class NormalCoupling:
    """One contact between two bodies along a normal, advanced exactly over each host step.

    Parameters
    ----------
    contact : Contact
        The contact law with its k and λ (any law of the package, or a custom ``ContactLaw``).
    tolerance : float, optional
        Relative tolerance (of the contact's length and speed scales) within which the host's
        gap and velocity count as the ones the last step made; default ``TOLERANCE``.
    host : str, optional
        How the host moves its positions over a step: ``'semi_implicit'`` (default: with the
        step's new velocity, as MuJoCo, PyBullet and Drake's discrete plant do) or
        ``'continuous'`` (an integrator that follows a force given over the step, as Drake's
        continuous plant: the step then also gives ``force_rate``).

    Raises
    ------
    InputError
        Keyed ``contact`` (not a ``Contact``), ``tolerance`` (not a number > 0) or ``host``.

    Examples
    --------
    A steel ball (66 g) resting on cast iron under g = 9.81 gets exactly its weight:

    >>> import contact_sim as cs
    >>> from contact_sim.coupling import NormalCoupling
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> coupling = NormalCoupling(contact)
    >>> z0 = contact.static_penetration(0.066 * 9.81)
    >>> out = coupling.step(0.0, -z0, 0.0, 0.066, -9.81, 1e-3)
    >>> print(f"{out.impulse / 1e-3:.6f} N")
    0.647460 N
    """

    def __init__(self, contact, tolerance=TOLERANCE, host='semi_implicit'):
        self.contact = require_contact(contact)
        self.tolerance = require_positive('tolerance', tolerance)
        if host not in HOSTS:
            raise InputError('host', host, '{n[host]} = {value} is unknown: allowed one of '
                             + ', '.join(repr(h) for h in HOSTS))
        self.host = host
        # the exact velocity at a step's start from a flying host's: the semi-implicit host's is
        # the mean over its last step, v + a dt / 2 (see the module doc)
        self._lead = 0.5 if host == 'semi_implicit' else 0.0
        self.impacts = []
        self._carried = None

    def reset(self):
        """Forget the carried state and the impacts (the host was reset)."""
        self.impacts = []
        self._carried = None

    @property
    def carrying(self):
        """Whether an exact state is carried into the next step."""
        return self._carried is not None

    def step(self, time, gap, gap_rate, mass, gap_acceleration, dt):
        """Advance the contact exactly over one host step.

        Parameters
        ----------
        time : float
            The host's time at the step's start, s.
        gap : float
            The gap along the normal, m (> 0 apart, < 0 penetrating).
        gap_rate : float
            d(gap)/dt from the host's velocities, m/s (< 0 approaching).
        mass : float
            The effective mass along the normal, kg, > 0.
        gap_acceleration : float
            d²(gap)/dt² the rest of the system gives over the step, m/s² (-9.81 for a ball
            above a floor under gravity).
        dt : float
            The host's step, s, > 0.

        Returns
        -------
        CouplingStep
            The impulse (N·s) over the step, the impacts it ended, the exact state at its end.

        Raises
        ------
        InputError
            Keyed ``time``, ``gap``, ``gap_rate``, ``gap_acceleration`` (not finite), ``mass``
            or ``dt`` (not a finite number > 0).
        """
        if not _plain(time, gap, gap_rate, gap_acceleration) or not _plain_positive(mass, dt):
            time, gap, gap_rate, mass, gap_acceleration, dt = _checked(
                time, gap, gap_rate, mass, gap_acceleration, dt)
        zh, vh, a = -gap, -gap_rate, -gap_acceleration
        c = self._carried
        if c is not None and not math.isclose(c.time, time, rel_tol=1e-12, abs_tol=1e-3 * dt):
            c = self._carried = None            # the host's clock jumped: start again
        if c is None:
            if not self._touches_from_host(zh, vh, a, dt):    # the host's own flight is exact
                z, zdot = parabola(zh, vh + self._lead * a * dt, a, dt)
                return CouplingStep(0.0, (), z, zdot, False, False)
            c = self._carried = self._from_host(time, zh, vh, a, dt)
        else:
            self._reconcile(c, zh, vh, a, mass)
        touched = c.mode != 'flight'
        z_start, zdot_start = c.z, c.zdot
        new_impacts = []
        t_end = time + dt
        t = time
        for segment in range(MAX_SEGMENTS + 1):
            if segment == MAX_SEGMENTS:
                self._carried = None
                raise RuntimeError(f'coupled contact stuck: {MAX_SEGMENTS} flights and contact '
                                   f'phases inside one step at t = {t!r} s, z = {c.z!r} m, '
                                   f'rate = {c.zdot!r} m/s')
            if c.mode == 'rest':
                break
            if c.mode == 'contact':
                t = self._run_phase(c, mass, t, t_end, new_impacts)
                if c.mode == 'contact' or t >= t_end:
                    break
                continue
            horizon = t_end - t
            t_touch = touch_time(self.contact, c.z, c.zdot, a, horizon, c.leaving)
            c.leaving = False
            if not t_touch <= horizon:
                c.z, c.zdot = parabola(c.z, c.zdot, a, horizon)
                break
            c.z, c.zdot = parabola(c.z, c.zdot, a, t_touch)
            t += t_touch
            touched = True
            self._start_phase(c, mass, t)
        c.time = t_end
        rate = remainder = 0.0
        if self._lead:
            if touched:     # ∫F (t - t₀)/dt = ∫F - ∫F (t₀ + dt - t)/dt, from the exact states
                remainder = max(mass * (a * dt + zdot_start - c.zdot) - mass * (
                    z_start + zdot_start * dt + 0.5 * a * dt * dt - c.z) / dt, 0.0)
            host_v = (c.z - zh) / dt
            impulse = mass * (vh + a * dt - host_v)
            if impulse < 0.0:       # a contact cannot pull: the host goes its own way
                impulse, host_v = 0.0, vh + a * dt
            c.host_z, c.host_v = zh + dt * host_v, host_v
        else:                       # a force linear over the step: both z and ż exact
            impulse = mass * (vh + a * dt - c.zdot)
            moment = mass * (zh + vh * dt + 0.5 * a * dt * dt - c.z)
            rate = (0.5 * impulse * dt - moment) * 12.0 / (dt * dt * dt)
            c.host_z, c.host_v = c.z, c.zdot
            if impulse < 0.0:
                impulse, rate = 0.0, 0.0
                c.host_z, c.host_v = zh + vh * dt + 0.5 * a * dt * dt, vh + a * dt
        self.impacts.extend(new_impacts)
        out = CouplingStep(impulse, tuple(new_impacts), c.z, c.zdot, c.mode != 'flight',
                           touched, rate, remainder)
        if c.mode == 'flight' and not touched and math.isinf(
                touch_time(self.contact, c.z, c.zdot, a, 2.0 * dt)):
            self._carried = None        # out of reach: the host's own flight is exact
        return out

    # -- the pieces ---------------------------------------------------------------------------
    def _force_on(self, z, zdot, a):
        """Whether the contact force is on (or about to be, at rest on the surface)."""
        return touch_time(self.contact, z, zdot, a, 0.0) == 0.0

    def _touches_from_host(self, zh, vh, a, dt):
        """Whether a flight from the host's state (no state carried) touches within the step;
        a state already in contact counts."""
        return math.isfinite(touch_time(self.contact, zh, vh + self._lead * a * dt, a, dt))

    def _from_host(self, time, zh, vh, a, dt):
        """The exact state from the host's alone: in flight the host's velocity is the mean over
        its last step (exact velocity v + a dt / 2); in contact it is taken as it is."""
        if self._force_on(zh, vh, a):
            return _Carried(time, zh, vh, 'contact', a, zh, vh)
        return _Carried(time, zh, vh + self._lead * a * dt, 'flight', a, zh, vh)

    def _reconcile(self, c, zh, vh, a, mass):
        """Go on with the carried state if the host is where the last step put it; else move the
        exact state by the host's unexplained change, and restart its phase."""
        dz, dv = zh - c.host_z, vh - c.host_v
        z_scale, v_scale = self._scales(c, mass, a)
        tol = self.tolerance
        moved = abs(dz) > tol * z_scale + 1e-15 or abs(dv) > tol * v_scale + 1e-15
        if moved:
            c.z, c.zdot = c.z + dz, c.zdot + dv
        same_a = math.isclose(a, c.acceleration, rel_tol=ACCELERATION_RTOL, abs_tol=1e-12)
        if moved or not same_a:
            c.phase = None
            if c.mode == 'rest' or (c.mode == 'contact' and not self._force_on(c.z, c.zdot, a)):
                c.mode = 'contact' if self._force_on(c.z, c.zdot, a) else 'flight'
        c.acceleration = a

    def _scales(self, c, mass, a):
        """(length m, speed m/s) scales of the tolerance: the contact's static depth under the
        load m|a| or the carried penetration, whichever is larger, and the speed of a flight
        of one such depth."""
        law, k = self.contact.law, self.contact.stiffness
        depth = max((mass * abs(a) / k) ** (1.0 / law.n), abs(c.z) if math.isfinite(c.z)
                    else 0.0, 1e-12)
        return depth, max(abs(c.zdot), math.sqrt(depth * abs(a)), 1e-9)

    def _start_phase(self, c, mass, t):
        """A contact starts at t (s) from the carried (z, ż): a touch."""
        c.mode, c.phase = 'contact', None
        c.touch, c.speed_in, c.peak, c.depth = t, max(c.zdot, 0.0), 0.0, 0.0

    def _ensure_phase(self, c, mass, t):
        """The contact phase from t (s) at the carried (z, ż) under the carried acceleration,
        unless one runs already."""
        if c.phase is not None:
            return
        a, z = c.acceleration, max(c.z, 0.0)
        if a >= 0.0:
            c.phase = contact_phase(self.contact, mass, a, t, z, c.zdot, keep_points=False)
        else:       # pulled apart: gravity 0 and a constant forcing a, lift-off tested inside
            c.phase = contact_phase(self.contact, mass, 0.0, t, z, c.zdot, keep_points=False,
                                    engine='compiled', forcing=Forcing(
                                        acceleration_amplitude=a, phase=0.5 * math.pi))

    def _run_phase(self, c, mass, t, t_end, new_impacts):
        """Run the contact phase from t to the lift-off or to t_end; returns the time reached."""
        if t >= t_end:          # a touch at the step's very end: the phase starts next step
            return t_end
        self._ensure_phase(c, mass, t)
        phase = c.phase
        if not phase.lifted_off and phase.time < t_end:
            phase.run(t_stop=t_end)
        c.peak, c.depth = max(c.peak, phase.peak_force), max(c.depth, phase.max_penetration)
        if phase.lifted_off and phase.end[0] <= t_end:
            t_off, z, zdot = phase.end
            if not self.contact.law.force_vanishes_inside and c.acceleration >= 0.0:
                z = min(z, 0.0)         # it leaves at the surface: z > 0 there is round-off
            new_impacts.append(CoupledImpact(c.touch, c.speed_in, max(-zdot, 0.0), c.peak,
                                             t_off - c.touch, c.depth))
            c.mode, c.z, c.zdot, c.phase, c.leaving = 'flight', z, zdot, None, True
            return t_off
        c.z, c.zdot = phase.state_at(t_end)
        if c.acceleration > 0.0 and self._settled(c, mass):
            c.mode, c.phase = 'rest', None
            c.z, c.zdot = self.contact.static_penetration(mass * c.acceleration), 0.0
        return t_end

    def _settled(self, c, mass):
        """Whether the contact's energy above static rest is negligible (``REST_ENERGY``)."""
        law, k = self.contact.law, self.contact.stiffness
        w = mass * c.acceleration
        z0 = (w / k) ** (1.0 / law.n)
        z = max(c.z, 0.0)
        energy = (0.5 * mass * c.zdot * c.zdot + k * z ** (law.n + 1.0) / (law.n + 1.0) - w * z
                  - (k * z0 ** (law.n + 1.0) / (law.n + 1.0) - w * z0))
        return energy < REST_ENERGY * w * z0



def _plain(*values):
    """Whether every value is a finite float (the host's usual input: no checks needed)."""
    return all(type(v) is float and math.isfinite(v) for v in values)


def _plain_positive(*values):
    return all(type(v) is float and 0.0 < v < math.inf for v in values)


def _checked(time, gap, gap_rate, mass, gap_acceleration, dt):
    """The step's arguments as floats, each refused by an ``InputError`` naming it."""
    return (require_real('time', time), require_real('gap', gap),
            require_real('gap_rate', gap_rate), require_positive('mass', mass),
            require_real('gap_acceleration', gap_acceleration), require_positive('dt', dt))
