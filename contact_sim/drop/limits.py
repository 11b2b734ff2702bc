"""The ranges of a drop's arguments and ``check_drop``: the drops the engine can follow, inside the
contact model's validity.  Units: SI; every bound is stated in the refusal (``InputError``)."""
import math

from contact_sim.model import require_contact
from contact_sim.phase import phase_scales
from contact_sim.impact import (CONTACT_LENGTH_MAX, CONTACT_TIME_MIN, ZETA_MAX, ZETA_MIN,
                                checked_scales)
from contact_sim import validation
from contact_sim.validation import (GRAVITY_MAX, HEIGHT_MAX, MASS_RANGE, InputError,  # noqa: F401 (GRAVITY_MAX: re-exported by drop)
                                    require_range)

DROP_RTOL = 1e-10

# The ranges of a drop's arguments (SI).  Outside them the doubles of the model overflow or the
# contact cannot be resolved in time; every bound is stated in the refusal.
VELOCITY_MAX = 1e5                   # m/s, either direction
DURATION_MAX = 1e9                   # s
SAMPLE_RATE_MAX = 1e7                # Hz
MAX_SAMPLES = 200_000                # trajectory samples of one simulate_drop call (~7 s)
MAX_STEPS = 100_000                  # integrator steps of one simulate_drop call (~10 s)
RADIUS_RANGE = (1e-9, 1e3)           # m: the sphere's radius R1 (R^(n+1) stays a normal double)
TIME_MAX = DURATION_MAX              # s: the latest time a drop is advanced to
MAX_TICKS = 1_000_000                # tick times of one advance_ticks call (6 x 8 MB of state)


def require_gravity_for(what, gravity):
    """Drag flights and a moving plate's flights are solved under gravity: g > 0."""
    if not gravity > 0.0:
        raise InputError('gravity', gravity, '{n[gravity]} = {value} is out of range with %s: '
                         'allowed 0 < {n[gravity]} (its flights are solved under gravity), or '
                         'no %s' % (what, what))


def _first_impact_speed(gravity, height, velocity):
    """Speed (m/s) at the first touch, √(v0² + 2 g h); 0 if the sphere never lands."""
    if gravity == 0.0:
        return max(velocity, 0.0)
    return math.sqrt(velocity * velocity + 2.0 * gravity * height)


def _refuse_slow_landing(contact, mass, gravity, height, velocity, plate_speed, speed):
    """A first impact too slow for its depth scale Z = (m v²/k)^(1/(n+1)) to be a double (a
    height of 5e-324 m): refused naming the argument it comes from, not a speed nobody gave."""
    v_min = math.sqrt(2.3e-308 * contact.stiffness / mass)   # m v²/k a normal double
    if plate_speed >= max(velocity, 0.0) and plate_speed * plate_speed >= 2.0 * gravity * height:
        key, value, unit = 'plate_speed', plate_speed, 'm/s'
    elif velocity * velocity >= 2.0 * gravity * height:
        key, value, unit = 'velocity', velocity, 'm/s'
    elif gravity < 1e-3:
        key, value, unit = 'gravity', gravity, 'm/s^2'
    else:
        key, value, unit = 'height', height, 'm'
    bound = ' ({n[height]} = 0 or >= %.3g m at this gravity)' % (v_min * v_min / (2.0 * gravity)) \
        if key == 'height' else ''
    raise InputError(key, value, '{n[%s]} = {value} %s gives a first impact at %.3g m/s, too slow '
                     'for its impact depth to be a double with {n[mass]} = %g kg and '
                     '{n[stiffness]} = %g: allowed a first impact at 0 or >= %.3g m/s%s'
                     % (key, unit, speed, mass, contact.stiffness, v_min, bound),
                     value=repr(value))


def check_drop(contact, mass, gravity, height, velocity, radius=None, plate_speed=0.0):
    """Refuse a drop the engine cannot follow, or one outside the contact model's validity.

    With a moving plate of peak speed ``plate_speed`` (m/s, ``PlateMotion.speed_bound``) an
    impact can be faster by up to that: the checks below take v1 + ``plate_speed`` as the
    impact speed (a vibrating table that pumps the sphere higher still can exceed it).

    * the contact's time scale T (at the first impact, and at rest under gravity) must be at
      least ``CONTACT_TIME_MIN``, and its damping group ζ at most ``impact.ZETA_MAX`` (a
      larger ζ is a creep of the sphere into the plate far slower than any drop);
    * with the sphere ``radius`` R (m): the undamped sphere must not sink deeper than R, where
      no contact law here applies.  The first impact at v1 = √(v0² + 2 g h) stops undamped at
      the depth z with k z^(n+1)/(n+1) = m v1²/2 + m g z, so z <= R holds when
      k >= (n+1)(m v1²/2 + m g R)/R^(n+1); damping only makes z smaller, so this bound is
      sufficient (and independent of λ).

    The arguments are checked first, in the ranges ``DropSimulation`` takes them (``MASS_RANGE``
    kg, 0 <= g <= ``GRAVITY_MAX``, 0 <= h <= ``HEIGHT_MAX``, abs(v0) <= ``VELOCITY_MAX``,
    ``RADIUS_RANGE`` m, 0 <= ``plate_speed`` <= ``VELOCITY_MAX``).

    Parameters
    ----------
    contact : Contact
        The contact (law, k, λ).
    mass : float
        The sphere's (reduced) mass, kg, within ``MASS_RANGE`` (1e-12 to 1e9).
    gravity : float
        Gravity g, m/s², 0 <= g <= ``GRAVITY_MAX`` (1e6).
    height : float
        Release height of the lowest point above the plate, m, 0 <= h <= ``HEIGHT_MAX`` (1e6).
    velocity : float
        Release velocity, m/s, downward positive, abs(v0) <= ``VELOCITY_MAX`` (1e5).
    radius : float, optional
        The sphere's radius R1, m, within ``RADIUS_RANGE``; ``None``: the depth is not checked.
    plate_speed : float, optional
        The moving plate's peak speed, m/s, >= 0 (default 0: the fixed plate).

    Returns
    -------
    None
        The drop is accepted.

    Raises
    ------
    InputError
        Keyed by the argument out of its range, or ``stiffness`` or ``damping`` whose reason
        gives the bounds.

    See Also
    --------
    DropSimulation : Makes these checks when built and at each change of contact or plate.

    Examples
    --------
    >>> import contact_sim as cs
    >>> mass = cs.build_mass(sphere='steel', radius=0.0127)
    >>> contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1.0952e10, 9.996e4)
    >>> cs.check_drop(contact, mass, 9.81, 0.1, 0.0, radius=0.0127) is None    # accepted
    True
    >>> soft = cs.Contact(cs.AZAD_FEATHERSTONE, 1e3, 0.0)
    >>> cs.check_drop(soft, mass, 9.81, 1.0, 0.0, radius=0.0127)
    Traceback (most recent call last):
        ...
    contact_sim.validation.InputError: stiffness = 1000 N/m^1.5 is too small for this drop: a 0.06735 kg sphere hitting at 4.429 m/s would sink more than its radius (0.0127 m) into the plate, where no contact law here applies; allowed stiffness >= 9.203e+04 N/m^1.5
    """
    contact = require_contact(contact)
    mass = require_mass(mass)
    gravity = require_gravity(gravity)
    height, velocity = require_height(height), require_velocity(velocity)
    radius = None if radius is None else require_radius(radius)
    plate_speed = require_range('plate_speed', plate_speed, 0.0, VELOCITY_MAX, unit='m/s')
    speed = _first_impact_speed(gravity, height, velocity) + plate_speed
    if speed == 0.0 and gravity == 0.0:
        return                      # never lands: nothing to check
    law, k, lam = contact.law, contact.stiffness, contact.damping
    n = law.n
    if speed > 0.0:   # the first impact, by the impact layer's ranges (T, Z, tiny ζ; k or λ)
        try:
            checked_scales(contact, mass, speed, 'speed', zeta_max=math.inf,   # large ζ: below
                           zeta_min=ZETA_MIN)
        except InputError as error:
            if error.field != 'speed':
                raise
            _refuse_slow_landing(contact, mass, gravity, height, velocity, plate_speed, speed)
    regimes = []
    if speed > 0.0:
        regimes.append(_scales_or_none(lambda: phase_scales(contact, mass, 0.0, 0.0, speed)))
    if gravity > 0.0:
        regimes.append(_scales_or_none(lambda: phase_scales(
            contact, mass, gravity, contact.static_penetration(mass * gravity), 0.0)))
    if None in regimes:   # a regime whose scales overflow: say so by the others, if any
        regimes = [sc for sc in regimes if sc is not None] if regimes[0] is not None else []
    deepest = max((sc.length for sc in regimes), default=math.inf)
    if not deepest <= CONTACT_LENGTH_MAX:
        # Z ∝ k^(-1/(n+1)) at an impact, (m g / k)^(1/n) at rest
        k_min = max(mass * speed ** 2 / CONTACT_LENGTH_MAX ** (n + 1.0),
                    mass * gravity / CONTACT_LENGTH_MAX ** n)
        raise InputError('stiffness', k, '{n[stiffness]} = {value} N/m^%g is too small for a '
                         '%.4g kg sphere: it would sink %s into the plate; allowed '
                         '{n[stiffness]} >= %.4g N/m^%g (contact length scale <= %g m)'
                         % (n, mass, 'without bound' if math.isinf(deepest) else
                            '~%.3g m' % deepest, k_min, n, CONTACT_LENGTH_MAX))
    shortest = min(sc.time for sc in regimes)
    if not shortest >= CONTACT_TIME_MIN:
        # T ∝ k^(-1/(n+1)) at an impact (Z = (m v²/k)^(1/(n+1)), T = Z/v), ∝ k^(-1/(2n)) at rest
        exponent = 1.0 / (n + 1.0) if speed > 0.0 else 0.5 / n
        k_max = k * (shortest / CONTACT_TIME_MIN) ** (1.0 / exponent)
        raise InputError('stiffness', k, '{n[stiffness]} = {value} N/m^%g is too large for a '
                         '%.4g kg sphere: its contact would last ~%.3g s, beyond what the engine '
                         'resolves; allowed {n[stiffness]} <= %.4g N/m^%g (contact time scale '
                         '>= %g s), or a larger {n[mass]}'
                         % (n, mass, shortest, k_max, n, CONTACT_TIME_MIN))
    largest = max(sc.zeta for sc in regimes)
    if largest > ZETA_MAX:
        lam_max = lam * (ZETA_MAX / largest)
        raise InputError('damping', lam, '{n[damping]} = {value} is too large for this drop: '
                         'the damping group would be zeta = %.3g and the sphere would creep '
                         'into the plate for ages; allowed {n[damping]} <= %.4g (zeta <= %g)'
                         % (largest, lam_max, ZETA_MAX))
    if radius is None or speed == 0.0 and gravity == 0.0:
        return
    minimum = (n + 1.0) * (0.5 * mass * speed ** 2 + mass * gravity * radius) / radius ** (n + 1.0)
    if k >= minimum:
        return
    allowed = '{n[stiffness]} >= %.4g N/m^%g' % (minimum, n)
    # or, with this k, the highest drop: m v1²/2 <= k R^(n+1)/(n+1) - m g R
    top_speed_sq = 2.0 * (k * radius ** (n + 1.0) / (n + 1.0) - mass * gravity * radius) / mass
    if plate_speed > 0.0:   # the sphere's own share of the impact speed
        top_speed_sq = max(math.sqrt(max(top_speed_sq, 0.0)) - plate_speed, 0.0) ** 2
    if gravity > 0.0 and top_speed_sq > velocity ** 2:
        allowed += ' or {n[height]} <= %.4g m' % ((top_speed_sq - velocity ** 2) / (2.0 * gravity))
    if plate_speed > 0.0:
        allowed += ' (with the plate moving at up to %.4g m/s)' % plate_speed
    raise InputError('stiffness', k, '{n[stiffness]} = %.4g N/m^%g is too small for this drop: '
                     'a %.4g kg sphere hitting at %.4g m/s would sink more than its radius '
                     '(%g m) into the plate, where no contact law here applies; allowed %s'
                     % (k, n, mass, speed, radius, allowed))




def _scales_or_none(scales):
    """``scales()``, or None where the doubles of the model overflow or underflow."""
    try:
        return scales()
    except (ArithmeticError, ValueError):
        return None


def require_mass(mass):
    """The sphere's (reduced) mass (kg), within ``MASS_RANGE``."""
    return require_range('mass', mass, *MASS_RANGE, unit='kg')


def require_gravity(gravity):
    """Gravity (m/s²): 0 <= g <= ``GRAVITY_MAX`` (``validation.require_gravity``)."""
    return validation.require_gravity(gravity)


def require_radius(radius):
    """The sphere's radius R1 (m), within ``RADIUS_RANGE``."""
    return require_range('radius', radius, *RADIUS_RANGE, unit='m')


def require_height(height):
    """Release height of the lowest point above the plate (m): 0 <= h <= HEIGHT_MAX."""
    return require_range('height', height, 0.0, HEIGHT_MAX, unit='m')


def require_velocity(velocity):
    """Release velocity (m/s, downward positive): |v| <= VELOCITY_MAX."""
    return require_range('velocity', velocity, -VELOCITY_MAX, VELOCITY_MAX, unit='m/s')
