"""What the host adapters share about their pairs (no engine import): the rows read from the
user's ``pairs``, the refusal of a pair named twice and of two pairs pushing at once along
coupled lines, and the tangent plane of the friction impulse.  Units: SI."""
import math

import numpy as np

from contact_sim.coupling.friction import friction_impulse
from contact_sim.validation import InputError

# two pairs pushing in one step whose normal responses couple beyond this fraction of
# sqrt(w₁ w₂) are refused (``refuse_stack``)
COUPLED = 1e-9


def pair_rows(pairs, shape):
    """The user's ``pairs`` as a non-empty list of tuples; ``shape`` names a row in the errors.

    Raises
    ------
    InputError
        Keyed ``pairs``: not a sequence, or empty.
    """
    try:
        rows = [tuple(p) for p in pairs]
    except TypeError:
        raise InputError('pairs', pairs, '{n[pairs]} = {value} is not a sequence: allowed '
                         + shape + ' rows') from None
    if not rows:
        raise InputError('pairs', pairs, '{n[pairs]} is empty: allowed one or more ' + shape
                         + ' rows')
    return rows


def refuse_repeated(keys, rows):
    """Refuse a pair whose two sides (``keys[i]``, a frozenset) another pair named already.

    Raises
    ------
    InputError
        Keyed ``pairs``.
    """
    seen = {}
    for index, key in enumerate(keys):
        if key in seen:
            raise InputError('pairs', rows[index][:2], '{n[pairs]}[%d] = {value} names the two '
                             'sides of pairs[%d] twice: allowed each pair once'
                             % (index, seen[key]))
        seen[key] = index


def refuse_stack(first, second, cross, w_first, w_second):
    """Refuse pairs ``first`` and ``second`` (indices) pushing in one step when the velocity one
    gives the other's gap per unit impulse, ``cross`` (1/kg), is beyond ``COUPLED`` of their own
    (``w_first``, ``w_second``): each pair is integrated alone, and together they would pump
    energy in (a stack of balls).

    Raises
    ------
    InputError
        Keyed ``pairs``.
    """
    if abs(cross) > COUPLED * math.sqrt(w_first * w_second):
        raise InputError('pairs', (first, second), '{n[pairs]}[%d] and pairs[%d] push at once on '
                         "a body along lines that move each other's gap (a stack): allowed "
                         'pairs whose contacts at one time are independent (one contact per '
                         'body, or normals at right angles on a sphere)' % (first, second))


def refuse_tunnel(index, gap, reach):
    """Refuse pair ``index`` found penetrating (``gap`` < 0, m) right after a step it was out of
    ``reach`` (m): its touch fell in a step nobody looked at.

    Raises
    ------
    InputError
        Keyed ``reach``.
    """
    raise InputError('reach', reach, '{n[reach]} = {value} m: pairs[%d] closed from beyond it '
                     'to %.3g m deep in one step, and its touch was missed: allowed a reach above '
                     'the distance its bodies close in one step' % (index, -gap))


def tangential_impulse(normal_impulse, free, normal, inverse, friction):
    """Coulomb's impulse (N·s, world, shape (3,)) on the sliding side, from the contact point's
    relative velocity the step would end with without friction (``free``, m/s), the unit
    ``normal``, the 3x3 inverse mass at the point (1/kg) and μ (``friction_impulse`` in the
    tangent plane; zero when the point does not slide)."""
    slide = free - float(free @ normal) * normal
    if not float(slide @ slide) > 0.0:
        return np.zeros(3)
    basis = tangents(normal)
    return basis.T @ friction_impulse(normal_impulse, basis @ free, basis @ inverse @ basis.T,
                                      friction)


def tangents(normal):
    """Two unit tangents (rows) orthogonal to the normal and to each other (plain arithmetic:
    numpy's cross costs tens of µs a call)."""
    x, y, z = (float(v) for v in normal)
    if abs(x) < 0.9:        # n × (1, 0, 0)
        a, b, c = 0.0, z, -y
    else:                   # n × (0, 1, 0)
        a, b, c = -z, 0.0, x
    norm = math.sqrt(a * a + b * b + c * c)
    a, b, c = a / norm, b / norm, c / norm
    return np.array([[a, b, c], [y * c - z * b, z * a - x * c, x * b - y * a]])
