"""``~/query_restitution``: request names -> answers, with the core library's fast path (no ROS)."""
import math

import numpy as np

import contact_sim as cs
from contact_sim.validation import require_positive

from .refusals import shorten

QUERY_QUANTITIES = ('restitution', 'contact_duration', 'peak_force', 'max_penetration')
MAX_NAMES = 1000   # names a request: more would stall the node's ticks (100,000: 1.9 s)


def parse_query(name):
    """``'2.5'`` or ``'peak_force:2.5'`` -> (quantity, speed in m/s); ValueError says why not."""
    if not isinstance(name, str):
        raise ValueError(f'name = {name!r} is not a string')
    prefix, colon, text = name.rpartition(':')
    quantity = prefix.strip() if colon else 'restitution'
    if quantity not in QUERY_QUANTITIES:
        raise ValueError(f'prefix {shorten(repr(quantity))} is unknown: allowed none or one of '
                         f'{", ".join(q + ":" for q in QUERY_QUANTITIES)}')
    try:
        speed = float(text)
    except ValueError:
        raise ValueError(f'impact speed {shorten(repr(text.strip()))} is not a number (m/s, '
                         'e.g. 2.5)') from None
    return quantity, require_positive('impact speed', speed)


def answer_queries(names, contact, mass):
    """Answer every name; returns [(value or None, reason or None)] in request order.

    Valid names are grouped by quantity and answered with one vectorised call of the library's
    fast path (``cs.restitution`` etc., zero gravity, one impact); if a group's call fails, its
    names are answered one by one so that only the failing ones go unanswered.
    """
    answers = [None] * len(names)
    groups = {}
    for i, name in enumerate(names):
        try:
            quantity, speed = parse_query(name)
        except ValueError as error:
            answers[i] = (None, str(error))
            continue
        groups.setdefault(quantity, []).append((i, speed))
    with np.errstate(all='ignore'):  # extreme speeds: every result is checked for finiteness
        _answer_groups(groups, answers, contact, mass)
    return answers


def _answer_groups(groups, answers, contact, mass):
    for quantity, items in groups.items():
        function = getattr(cs, quantity)
        speeds = np.array([speed for _, speed in items])
        try:
            values = np.asarray(function(contact, mass, speeds), dtype=float).reshape(-1)
            if values.shape != speeds.shape:
                raise ValueError(f'{quantity} returned {values.size} values for '
                                 f'{speeds.size} speeds')
        except Exception:  # isolate the failing speeds: answer one at a time
            values = []
            for i, speed in items:
                try:
                    values.append(float(function(contact, mass, speed)))
                except Exception as error:  # the engine's reason, reported per name
                    values.append(None)
                    answers[i] = (None, f'{quantity} at {speed:g} m/s failed: {error}')
        for (i, speed), value in zip(items, values):
            if answers[i] is not None:
                continue
            if value is None or not math.isfinite(value):
                answers[i] = (None, f'{quantity} at {speed:g} m/s is not finite')
            else:
                answers[i] = (float(value), None)
