"""Which detected clicks are the impacts of a bounce sequence, and why the others are not.

A recording of bounces holds many more sharp, loud sounds than impacts: the echo of each impact
from a nearby surface, the ringing of a hollow ball or of the plate (a new "click" every few ms
for as long as it rings), the filter's and the microphone's response just before a loud crack,
a hand or a voice before the drop.  The onset detector (``audio``) hears them all.  The impacts
are found as the bounce sequence those clicks hold, by three rules argued from the physics of
a bounce, none fitted to one ball, room or microphone:

1. **an impact is the loudest sound for about a flight** (its *isolation*, the time to the
   nearest louder click, is at least ``share`` = 1/2 of the flights beside it).  Its loudness
   follows its impact speed, which changes by the restitution e from one bounce to the next,
   while its echo, its ringing or a rattle follow it at a lag shorter than the flight and are
   weaker: their isolation is at most that lag.  Loudness is the strength of the click's crack
   (``audio``'s innovation energy).
2. **flights shrink by the restitution**: each flight is between ``low`` (1/4) and ``high``
   (1.1: timing jitter) times the one before it, or up to ``missed`` (2.1) times, e(1 + e), when
   a bounce between was too quiet to be heard (a missed bounce costs ``penalty`` = 1.5 clicks:
   a chain that leaves a click out is preferred to one that needs a missed bounce).
3. **the sequence is the longest chain of clicks obeying 1 and 2** (dynamic programming over
   the clicks' pairs; ties go to the louder clicks).  A click the chain leaves out is named: an
   **echo or ringing** (its isolation, to a louder click just before it, is under ``share`` of
   the flight there), a **precursor** (the same, to a louder click just after it), **before the
   sequence** or **after the sequence** (outside the chain's span), or **off the sequence**
   (loud enough, but it would break rule 2, as a spurious click between impacts does).

4. **an echo comes back at a nearly fixed lag**.  Where the flights are long, the clicks that
   follow the impacts are told from them by rule 1; the lags at which a weaker click follows
   at least half of those impacts (within ``ECHO_JITTER``, 1 ms) are the room's echo lags.
   Where the flights shrink towards those lags, rule 1 can no longer tell an echo from the
   next impact; there a click at an echo lag after a louder impact is an **echo or ringing**
   unless the sequence needs it: the chain is found again with such clicks counting
   ``ECHO_WEIGHT`` (-1/4) of a click, so that one is kept only where leaving it out would cost a
   missed bounce (an impact whose flight equals the echo lag coincides with the echo).

Then a click far quieter (below ``quiet`` = 1/10 of the strength) than the impact after it at
the start of the chain is **before the sequence** too (the first impacts are the fastest and
loudest).  Each rejected click is returned with its kind and reason (``Rejected``).
"""
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.validation import InputError, require_range, require_real_array

SHARE = 0.5      # an impact is the loudest click within this share of the flights beside it
LOW, HIGH, MISSED = 0.25, 1.1, 2.1     # a flight over the one before: shrinking, or one missed
PENALTY = 1.5    # a missed bounce costs this many clicks
ECHO_JITTER = 1e-3   # s: an echo's lag varies this little from impact to impact
ECHO_SHARE = 0.5     # an echo lag: a weaker click follows at least this share of the impacts
ECHO_WEIGHT = -0.25  # a click at an echo lag counts this much in the chain (1: any other)
PREDECESSORS = 32   # the nearest clicks a click may follow in the chain (bounds the work),
CONTINUED = 8       # and the best chains ending at a click that are continued from it
QUIET = 0.1      # a first click below this share of the next one's strength: before the sequence
KINDS = ('echo or ringing', 'precursor', 'before the sequence', 'after the sequence',
         'off the sequence')


@dataclass(frozen=True)
class Rejected:
    """A click that is not an impact: its onset ``time`` (s), ``kind`` (one of ``KINDS``) and
    the ``reason`` in words."""

    time: float
    kind: str
    reason: str


def isolation(times, strength):
    """Time from each click to the nearest strictly louder one.

    Parameters
    ----------
    times : numpy.ndarray
        Click onsets in s, increasing.
    strength : numpy.ndarray
        Their loudness, as many.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        The time (s) to the nearest louder click (inf if none) and that click's index (-1 if
        none).

    Examples
    --------
    >>> import numpy as np
    >>> iso, near = isolation(np.array([0.0, 0.1, 0.15]), np.array([1.0, 0.5, 0.7]))
    >>> np.round(iso, 3).tolist(), near.tolist()
    ([inf, 0.05, 0.15], [-1, 2, 0])
    """
    n = times.size
    iso, near = np.full(n, np.inf), np.full(n, -1)
    for order in (range(n), range(n - 1, -1, -1)):      # previous, then next, louder click
        stack = []
        for i in order:
            while stack and strength[stack[-1]] <= strength[i]:
                stack.pop()
            if stack and abs(times[i] - times[stack[-1]]) < iso[i]:
                iso[i], near[i] = abs(times[i] - times[stack[-1]]), stack[-1]
            stack.append(i)
    return iso, near


def _chain(times, strength, iso, share, weight=None):
    """The longest chain of clicks obeying rules 1 and 2 (module doc), as sorted indices; a
    click counts ``weight`` (default 1) in its length."""
    n = times.size
    weight = np.ones(n) if weight is None else weight
    reach = np.minimum(iso / share, times[-1] - times[0] + 1.0)   # the longest flight beside
    tie = 1e-3 * np.log(strength / strength.max() + 1e-300) / max(math.log(1e300), 1.0)
    # states (i, j, m), i < j: the best chain ending ..., h, i, j, with m = 1 when a bounce was
    # missed between i and j (the flight is then half the interval), else 0;
    # best[(i, j, m)] = (score, (h, m of (h, i)))
    incoming = [[] for _ in range(n)]      # per j: (flight from i to j, score, i, m)
    best = {}
    for j in range(n):
        lo = np.searchsorted(times, times[j] - 2.0 * reach[j], side='left')
        before = np.arange(lo, j)
        d_all = times[j] - times[before]
        before = before[(d_all > 0) & (d_all <= 2.0 * reach[before])][-PREDECESSORS:]
        for i in before:
            d = times[j] - times[i]
            found = [[-math.inf, None], [-math.inf, None]]
            if d <= min(reach[i], reach[j]):
                found[0] = [weight[i] + weight[j] + tie[i] + tie[j], None]
            for f0, s0, h, m0 in incoming[i]:
                r = d / f0
                if r < LOW or r > MISSED:
                    continue
                m = int(r > HIGH)
                f = 0.5 * d if m else d
                if max(f0, f) > reach[i] or f > reach[j]:
                    continue
                score = s0 + weight[j] + tie[j] - PENALTY * m
                if score > found[m][0]:
                    found[m] = [score, (h, m0)]
            for m, (score, back) in enumerate(found):
                if score > -math.inf:
                    best[(i, j, m)] = (score, back)
                    incoming[j].append((0.5 * d if m else d, score, i, m))
        incoming[j] = sorted(incoming[j], key=lambda entry: -entry[1])[:CONTINUED]
    if not best:
        return [int(np.argmax(strength))] if n else []
    state = max(best, key=lambda key: best[key][0])
    i, j, m = state
    chain = [j, i]
    while best[(i, j, m)][1] is not None:
        h, m0 = best[(i, j, m)][1]
        chain.append(h)
        i, j, m = h, i, m0
    return sorted(chain)


def _reason(k, times, iso, near, chain, share):
    """Why click ``k`` is not in the chain (sorted indices): (kind, reason)."""
    t = times[k]
    c = np.asarray(chain)
    if t < times[c[0]] or t > times[c[-1]]:
        first = t < times[c[0]]
        edge = times[c[0]] if first else times[c[-1]]
        kind = 'before the sequence' if first else 'after the sequence'
        if near[k] >= 0 and iso[k] < share * _flight(times, c, t):
            return _echo(k, times, iso, near, share, _flight(times, c, t))
        which = 'before the first' if first else 'after the last'
        return kind, f'{abs(t - edge) * 1e3:.1f} ms {which} impact of the sequence ({edge:.4f} s)'
    flight = _flight(times, c, t)
    if iso[k] < share * flight:
        return _echo(k, times, iso, near, share, flight)
    return 'off the sequence', (f'the loudest click within {iso[k] * 1e3:.1f} ms, but taking it '
                                f'would break the shrinking flights (about {flight * 1e3:.1f} ms '
                                'here)')


def _echo_lags(times, strength, chain):
    """Rule 4: the echo lags (s) of the recording, from the impacts of ``chain`` whose flight
    after them is at least 4 jitters long (the lag of the loudest weaker click in the first
    half of that flight, where at least half of them agree), and the clicks at those lags after
    a louder impact of the chain ({index: (kind, reason)})."""
    loudest = []            # per impact: the lag of the loudest weaker click in its half-flight
    for a, b in zip(chain[:-1], chain[1:]):
        half = 0.5 * (times[b] - times[a])
        j = np.arange(a + 1, np.searchsorted(times, times[a] + half))
        j = j[strength[j] < strength[a]]
        if half >= 4 * ECHO_JITTER and j.size:
            loudest.append(times[j[np.argmax(strength[j])]] - times[a])
    loudest = np.sort(np.array(loudest))
    if loudest.size < 3:
        return [], {}
    agree = np.array([np.sum(np.abs(loudest - lag) <= ECHO_JITTER) for lag in loudest])
    if agree.max() < ECHO_SHARE * loudest.size:
        return [], {}
    lag = float(np.median(loudest[np.abs(loudest - loudest[np.argmax(agree)]) <= ECHO_JITTER]))
    echoes = {}
    for p in chain:
        lo = np.searchsorted(times, times[p] + lag - ECHO_JITTER)
        hi = np.searchsorted(times, times[p] + lag + ECHO_JITTER, side='right')
        for k in range(lo, hi):
            if strength[k] < strength[p]:
                echoes[k] = ('echo or ringing', f'{(times[k] - times[p]) * 1e3:.1f} ms after the '
                             f'impact at {times[p]:.4f} s, at the echo lag of the recording '
                             f'({lag * 1e3:.1f} ms, the loudest click after '
                             f'{int(agree.max())} of {loudest.size} impacts)')
    return [lag], echoes


def _flight(times, chain, t):
    """The chain's flight at time ``t``: the interval of the chain that holds ``t``, or the one
    nearest."""
    k = int(np.clip(np.searchsorted(times[chain], t), 1, len(chain) - 1))
    return float(times[chain[k]] - times[chain[k - 1]])


def _echo(k, times, iso, near, share, flight):
    after = times[near[k]] < times[k]
    kind = 'echo or ringing' if after else 'precursor'
    return kind, (f'{iso[k] * 1e3:.1f} ms {"after" if after else "before"} a louder click '
                  f'({times[near[k]]:.4f} s), less than {share:g} of the flight there '
                  f'({flight * 1e3:.1f} ms)')


def select_impacts(times, strength, share=SHARE, quiet=QUIET):
    """The impacts among detected clicks (module doc).

    Parameters
    ----------
    times : array_like
        Onsets of the detected clicks in s, increasing.
    strength : array_like
        Their loudness, > 0 (any scale: the ratios matter), as many.
    share : float
        An impact is the loudest click within this share of the flights beside it, > 0.
    quiet : float
        A first click below this share of the next one's strength is before the sequence,
        0 <= quiet < 1.

    Returns
    -------
    (numpy.ndarray, list of Rejected)
        The indices of the impacts (increasing) and the clicks rejected, in time order.

    Raises
    ------
    InputError
        Times or strengths not finite, not as many, times not increasing, a strength below 0,
        or ``share`` or ``quiet`` out of range (named).

    Examples
    --------
    >>> import numpy as np
    >>> from contact_sim.calibration.impact_sequence import select_impacts
    >>> t = np.array([0.5, 0.9, 0.907, 1.26, 1.584, 1.876])    # an echo 7 ms after an impact
    >>> kept, rejected = select_impacts(t, np.array([1.0, 0.9, 0.6, 0.8, 0.7, 0.6]))
    >>> t[kept].tolist(), [r.kind for r in rejected]
    ([0.5, 0.9, 1.26, 1.584, 1.876], ['echo or ringing'])
    """
    times = require_real_array('times', times).ravel()
    strength = require_real_array('strength', strength).ravel()
    if strength.size != times.size or np.any(np.diff(times) < 0) or np.any(strength < 0):
        raise InputError('times', None, '{n[times]} and {n[strength]} hold %d and %d values: '
                         'allowed as many, times increasing, strengths >= 0'
                         % (times.size, strength.size))
    share = require_range('share', share, 0.0, low_open=True)
    quiet = require_range('quiet', quiet, 0.0, 1.0, high_open=True)
    strength = np.maximum(strength, 1e-300)
    if times.size < 3:
        return np.arange(times.size), []
    iso, near = isolation(times, strength)
    chain = _chain(times, strength, iso, share)
    lags, echoes = _echo_lags(times, strength, chain)
    if echoes:
        weight = np.ones(times.size)
        weight[list(echoes)] = ECHO_WEIGHT
        chain = _chain(times, strength, iso, share, weight)
    while len(chain) > 2 and strength[chain[0]] < quiet * strength[chain[1]]:
        chain = chain[1:]        # a quiet click before the loud first impacts
    inside = set(chain)
    rejected = [Rejected(float(times[k]), *(echoes[k] if k in echoes else
                                            _reason(k, times, iso, near, chain, share)))
                for k in range(times.size) if k not in inside]
    return np.array(chain, dtype=int), rejected


def summary(found, kept, rejected):
    """One line: how many onsets were found, kept and rejected, and why (counts per kind).

    Parameters
    ----------
    found : int
        The clicks heard.
    kept : int
        The impacts kept.
    rejected : list of Rejected
        The clicks rejected.

    Returns
    -------
    str

    Examples
    --------
    >>> summary(3, 2, [Rejected(0.507, 'echo or ringing', '7 ms after the impact at 0.5 s')])
    '3 onset(s) found, 2 kept as impacts, 1 rejected (1 echo or ringing)'
    """
    counts = [(kind, sum(r.kind == kind for r in rejected)) for kind in KINDS]
    why = ', '.join(f'{n} {kind}' for kind, n in counts if n)
    return f'{found} onset(s) found, {kept} kept as impacts, {len(rejected)} rejected' + \
           (f' ({why})' if why else '')
