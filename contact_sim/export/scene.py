"""The real scene: an export's claim (its e measured with gravity off) checked with gravity on,
the ball dropped on the plate and left to rest there, at the exported parameters.

The rest sag (the ball's depth in the plate at rest) is compared with its radius: a contact
that sinks the ball by its radius or more cannot hold it up, and the export refuses it.  The
e with gravity is compared with the claim at each speed: the claim holds with gravity from the
lowest speed at and above which every speed is within ``CLAIM_TOLERANCE`` of it."""
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.validation import InputError

GRAVITY = 9.81          # m/s^2: the scene's gravity
CLAIM_TOLERANCE = 0.01  # largest abs(e with gravity - e claimed) for the claim to hold
# the export's own check is held to this fraction of the tolerance, at each of its phases, so
# that a drop at any other phase of the step stays within the tolerance
CHECK_FRACTION = 0.5


@dataclass(frozen=True)
class Scene:
    """The claim checked with gravity on.

    Parameters
    ----------
    sag : float
        The ball's depth in the plate at rest, m.
    radius : float
        The ball's radius, m.
    restitution : numpy.ndarray
        e with gravity at the target's speeds, the mean over the impact's phases within a step
        (0 where the ball did not leave the plate).
    lowest_speed : float or None
        The lowest of the speeds (m/s) at and above which every speed's e with gravity is
        within ``CLAIM_TOLERANCE`` of the claim; None if the fastest misses.
    suggested_timestep : float or None
        A step (s) at which the claim would hold at every speed (the error with gravity
        scaled with the step); None if every speed holds or no step helps.
    source : str
        ``'measured'`` (the engine run) or ``'predicted'`` (the engine's law integrated here).
    """

    sag: float
    radius: float
    restitution: np.ndarray
    lowest_speed: object
    suggested_timestep: object
    source: str

    def lines(self, speeds):
        """What the scene says, as text lines (no '#')."""
        out = [f'with gravity ({GRAVITY:g} m/s^2, {self.source}): the ball rests '
               f'{self.sag:.3g} m deep in the plate, {self.sag / self.radius:.3g} of its '
               f'radius {self.radius:g} m']
        if self.lowest_speed is None:
            out.append(f'the claim does not hold with gravity at any of the speeds (abs(error) > '
                       f'{CLAIM_TOLERANCE:g} up to {float(np.max(speeds)):g} m/s)')
        elif self.lowest_speed <= float(np.min(speeds)):
            out.append(f'the claim holds with gravity within {CLAIM_TOLERANCE:g} at every speed '
                       f'(from {self.lowest_speed:g} m/s)')
        else:
            out.append(f'the claim holds with gravity within {CLAIM_TOLERANCE:g} from '
                       f'{self.lowest_speed:g} m/s up only; below, the e with gravity is the '
                       'column "e, gravity"')
        if self.suggested_timestep is not None:
            out.append(f'a step of {self.suggested_timestep:.2g} s would make it hold down to '
                       f'{float(np.min(speeds)):g} m/s (estimated: the error with gravity '
                       'scaled with the step)')
        return out


def worst_errors(claimed, with_gravity):
    """max abs(e with gravity - e claimed) at each speed, over the phases (the columns of a
    2-D ``with_gravity``)."""
    with_gravity = np.asarray(with_gravity, float)
    if with_gravity.ndim == 1:
        with_gravity = with_gravity[:, None]
    return np.max(np.abs(with_gravity - np.asarray(claimed, float)[:, None]), axis=1)


def lowest_holding_speed(speeds, claimed, with_gravity):
    """The lowest of ``speeds`` (m/s) at and above which abs(with_gravity - claimed) <=
    ``CHECK_FRACTION`` ``CLAIM_TOLERANCE`` at every speed (and every phase, the columns of a
    2-D ``with_gravity``), or None if the fastest misses."""
    errors = worst_errors(claimed, with_gravity)
    lowest = None
    for i in np.argsort(speeds)[::-1]:
        if errors[i] > CHECK_FRACTION * CLAIM_TOLERANCE:
            break
        lowest = float(speeds[i])
    return lowest


def assess(target, claimed, with_gravity, sag, timestep, step_floor, source, engine,
           spring_sag):
    """The ``Scene`` of a claim, or ``InputError`` keyed ``timestep`` if the contact cannot
    hold the ball up (sag >= radius).

    Parameters
    ----------
    target : common.Target
    claimed : numpy.ndarray
        e at the target's speeds, gravity off (the claim).
    with_gravity : numpy.ndarray
        e at the target's speeds with gravity, one column a phase of the impact within a step
        (or one value a speed); the claim must hold at every phase.
    sag : float
        The ball's depth at rest, m (inf if it fell through).
    timestep : float
        The step, s (0: a continuous plant).
    step_floor : float
        The step (s) below which the engine's stiffness no longer grows (its stiffness is then
        the target's own): 0 if the step does not set the stiffness.
    source : str
        ``'measured'`` or ``'predicted'``.
    engine : str
        The engine's name, for the message.
    spring_sag : float
        The sag of the engine's spring alone, m g / k (m): where the ball fell through, the
        largest step that holds it is estimated from it.

    Raises
    ------
    InputError
        Keyed ``timestep``, if ``sag`` >= the ball's radius.
    """
    radius = target.radius
    step_sets_stiffness = timestep > 0.0 and timestep > step_floor
    if not sag < radius:   # inf or nan included: the ball fell through
        depth = 'falls through the plate' if not math.isfinite(sag) else f'sinks {sag:.3g} m'
        if step_sets_stiffness:
            basis = sag if math.isfinite(sag) else spring_sag
            largest = timestep * math.sqrt(radius / basis) * 0.99   # the sag grows as step^2
            allowed = f'allowed a step below {largest:.2g} s for this contact'
        else:
            allowed = 'no step holds it: the contact itself is too soft for its mass'
        raise InputError('timestep', timestep, '{n[timestep]} = {value} s makes ' + engine
                         + "'s contact unusable: with gravity the ball " + depth + ' at rest, '
                         f'its radius is {radius:g} m, so it cannot hold the ball up: ' + allowed,
                         value=f'{timestep:g}')
    lowest = lowest_holding_speed(target.speeds, claimed, with_gravity)
    suggested = None
    errors = worst_errors(claimed, with_gravity)
    if step_sets_stiffness and np.any(errors > CHECK_FRACTION * CLAIM_TOLERANCE):
        step = timestep * CHECK_FRACTION * CLAIM_TOLERANCE / float(errors.max())
        suggested = step if step >= step_floor else None
    with_gravity = np.asarray(with_gravity, float)
    mean = with_gravity.mean(axis=1) if with_gravity.ndim == 2 else with_gravity
    return Scene(float(sag), radius, mean, lowest, suggested, source)
