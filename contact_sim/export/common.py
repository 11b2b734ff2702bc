"""What every engine's export shares: the target (a contact, its mass and the speeds, with the
e(v) this library gives it), the export's frozen result, the minimax fit of one engine parameter,
and the contact frequency an engine's step can resolve."""
import math
import warnings
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from contact_sim.export.choices import MAX_TIMESTEP, MIN_TIMESTEP
from contact_sim.impact import contact_duration, max_penetration, peak_force, restitution
from contact_sim.model import Contact, require_contact
from contact_sim.validation import InputError, require_positive, require_range



@dataclass(frozen=True)
class Target:
    """The contact to reproduce and its e(v).

    Parameters
    ----------
    contact : Contact
        The target contact (any law of eq. 1).
    mass : float
        The (reduced) mass in kg.
    radius : float
        The sphere's radius in m (the engines' geometry).
    speeds : numpy.ndarray
        Impact speeds in m/s.
    restitution : numpy.ndarray
        The target's e at ``speeds`` (``contact_sim.impact.restitution``).
    """

    contact: object
    mass: float
    radius: float
    speeds: np.ndarray
    restitution: np.ndarray

    def as_dict(self):
        """The JSON ``target`` block: law, stiffness, damping, mass, radius (SI)."""
        return {'law': self.contact.law.name, 'stiffness': self.contact.stiffness,
                'damping': self.contact.damping, 'mass': self.mass, 'radius': self.radius}


def make_target(contact, mass, radius, speeds):
    """The ``Target`` of ``contact`` with ``mass`` (kg) and sphere ``radius`` (m) at ``speeds``
    (m/s, each > 0).

    Raises
    ------
    InputError
        If the contact, the mass, the radius or a speed is out of range.
    """
    require_contact(contact)
    mass = require_positive('mass', mass)
    radius = require_positive('radius', radius)
    speeds = np.asarray([require_positive('speed', v) for v in np.atleast_1d(speeds)], float)
    return Target(contact, mass, radius, speeds, np.asarray(restitution(contact, mass, speeds)))


@dataclass(frozen=True)
class EngineFit:
    """What one engine's export found: its ``parameters`` (the engine's own names), the
    ``snippet`` to paste, the e at the target's speeds, whether that e was ``'measured'`` (the
    engine run) or ``'predicted'`` (its law evaluated here), a ``note`` on what the parameters do
    to the contact, and the contact ``duration`` (s) and ``peak_force`` (N) the engine gives at
    each speed (measured or from its law, as e; None where neither is known); ``reach``, the
    (lowest, highest) e the engine's damping range gives at this step (None if not known), the
    ``scene.Scene`` (the claim with gravity) and the ``pitfalls``: what in a user's model
    changes the claim."""

    parameters: dict
    snippet: str
    restitution: np.ndarray
    source: str
    note: str
    duration: object = None
    peak_force: object = None
    reach: object = None
    scene: object = None
    pitfalls: tuple = ()


@dataclass(frozen=True)
class Export:
    """One engine's parameters for a target, and the e(v) the engine gives with them.

    ``engine_restitution_source`` is ``'measured'`` when the engine itself was run, ``'predicted'``
    when the engine's law was evaluated here; ``max_abs_error`` is max abs(engine e - target e) over
    the speeds: how far the best choice stays from the target.
    """

    engine: str
    engine_version: str
    target: Target
    parameters: dict
    snippet: str
    engine_restitution: np.ndarray
    engine_restitution_source: str
    note: str = ''   # what the parameters do to the contact's duration and depth (text only)
    engine_duration: object = None     # s at each speed, as the e (the text table only)
    engine_peak_force: object = None   # N at each speed, as the e (the text table only)
    reach: object = None       # (lowest, highest) e of the engine's damping range, this step
    scene: object = None       # scene.Scene: the claim checked with gravity on
    pitfalls: tuple = ()       # what in a user's model changes the claim (text)

    @property
    def max_abs_error(self):
        """The largest abs(engine e - target e) over the speeds."""
        return float(np.max(np.abs(self.engine_restitution - self.target.restitution)))

    def as_dict(self):
        """The ``--format json`` record, with exactly the issue's keys."""
        return {'engine': self.engine, 'engine_version': self.engine_version,
                'target': self.target.as_dict(), 'parameters': dict(self.parameters),
                'snippet': self.snippet, 'speeds': self.target.speeds.tolist(),
                'target_restitution': self.target.restitution.tolist(),
                'engine_restitution': self.engine_restitution.tolist(),
                'engine_restitution_source': self.engine_restitution_source,
                'max_abs_error': self.max_abs_error,
                'lowest_speed_with_gravity': (None if self.scene is None
                                              else self.scene.lowest_speed),
                'rest_sag': None if self.scene is None else self.scene.sag}

    def miss(self):
        """Why the best choice misses by ``max_abs_error`` (one line of text)."""
        half = float(np.ptp(self.target.restitution)) / 2.0
        if self.reach is None or self.max_abs_error <= half + 0.005:
            return f"the best choice misses by {self.max_abs_error:.4f} (half the target's " \
                   f'spread: {half:.4f})'
        low, high = self.reach
        target = self.target.restitution
        if float(np.min(target)) < low:
            why = 'the target is lossier'
        elif float(np.max(target)) > high:
            why = 'the target is livelier'
        else:
            why = "within that range no one damping follows the target's e(v)"
        return (f'the best choice misses by {self.max_abs_error:.4f}, more than half the '
                f"target's spread ({half:.4f}): at this step the engine's damping range gives "
                f'e from {low:.4f} to {high:.4f}; {why}')


def require_timestep(timestep, continuous=False):
    """``timestep`` (s) if ``MIN_TIMESTEP`` <= timestep <= ``MAX_TIMESTEP`` (0 too if the
    engine has a ``continuous`` plant), else ``InputError`` keyed ``timestep``."""
    if continuous and timestep == 0.0:
        return 0.0
    try:
        return require_range('timestep', timestep, MIN_TIMESTEP, MAX_TIMESTEP, unit='s')
    except InputError as error:
        if not continuous:
            raise
        raise InputError('timestep', timestep, error.template + ', or 0 (the continuous plant)',
                         **error.params) from None


def target_frequency(target):
    """The angular frequency (rad/s) of a linear spring whose elastic contact lasts as long as
    the target's at the geometric middle of the speeds: pi / duration."""
    middle = math.sqrt(target.speeds.min() * target.speeds.max())
    return math.pi / float(contact_duration(target.contact, target.mass, [middle])[0])


def resolved_frequency(target, timestep, steps_per_radian):
    """The target's frequency, lowered to 1 / (``steps_per_radian`` ``timestep``) when the
    engine's step cannot resolve it (rad/s)."""
    return min(target_frequency(target), 1.0 / (steps_per_radian * timestep))


def linear_contact_note(target, frequency):
    """What a linear contact of angular ``frequency`` w (rad/s) does, beside the target: it
    lasts about pi / w and sinks about v / w at the top speed v."""
    top = float(target.speeds.max())
    middle = math.sqrt(target.speeds.min() * top)
    duration = float(contact_duration(target.contact, target.mass, [middle])[0])
    depth = float(max_penetration(target.contact, target.mass, [top])[0])
    return (f'the engine\'s contact lasts about {math.pi / frequency:.3g} s (the target: '
            f'{duration:.3g} s at {middle:.3g} m/s) and sinks about {top / frequency:.3g} m at '
            f'{top:g} m/s (the target: {depth:.3g} m)')


def fit_minimax(engine_restitution, target, low, high):
    """The parameter x in [low, high] that minimises max abs(engine_restitution(x) - target e).

    Parameters
    ----------
    engine_restitution : callable
        x -> the engine's e at ``target.speeds`` (numpy array).
    target : Target
    low, high : float
        The bracket of x.

    Returns
    -------
    (float, numpy.ndarray)
        The best x and the engine's e there.
    """
    def worst(x):
        return float(np.max(np.abs(engine_restitution(x) - target.restitution)))
    best = minimize_scalar(worst, bounds=(low, high), method='bounded',
                           options={'xatol': 1e-5 * (high - low)})
    return float(best.x), np.asarray(engine_restitution(best.x))


def law_contact(law, stiffness, damping, mass, speeds):
    """(contact duration in s, peak force in N) at ``speeds`` (m/s) of ``law`` with
    ``stiffness`` and ``damping``, ``mass`` (kg), exactly: an engine whose law is of eq. 1."""
    contact = Contact(law, stiffness, damping)
    with warnings.catch_warnings():   # the exact path is expected here
        warnings.simplefilter('ignore', RuntimeWarning)
        return (np.asarray(contact_duration(contact, mass, speeds)),
                np.asarray(peak_force(contact, mass, speeds)))


def law_restitution(law, stiffness, mass, speeds):
    """The function x -> e at ``speeds`` (m/s) of ``law`` with ``stiffness`` and damping x, with
    ``mass`` (kg), exactly (eq. 1): the e(v) of an engine whose law is a member of eq. 1."""
    def engine_restitution(damping):
        with warnings.catch_warnings():   # the exact path is expected here
            warnings.simplefilter('ignore', RuntimeWarning)
            return np.asarray(restitution(Contact(law, stiffness, damping), mass, speeds))
    return engine_restitution
