"""Detector glitches named before a bounce fit, and the clicks prepared for it.

Glitches are found by walking the clicks in order, each interval predicting the next single
flight (the last one times ē, the median of the interval ratios); each glitch is named once:

* a doubled click (an echo or the ball's rattle, within 0.1 of a flight after a click) or a
  spurious click (anywhere else): a click that splits an expected flight, so that the two parts
  together fit one or more flights better than the first part alone; it is left out, and the
  flight is judged whole;
* missed bounces: an interval close to (1 + ē + … + ē^m) times the one expected, for any m (no
  cap; ``_flights_in``); nothing is left out, the following clicks are numbered m bounces later;
* a growing interval: longer by more than 5 % than the flight before it with no missed click to
  explain it (bounce flights shrink); kept, and it predicts the next;
* a late start (the first impacts were missed): with a release height, a first interval that
  matches the flight of bounce j + 1 rather than the first (any j up to 100); the sequence is
  numbered from j.  Without a release height a late start cannot be told from a lower release;
* micro-bounces (``MicroBounceCut``): from the first flight shorter than ``min_flight``, or
  whose impact lasts more than ``ratio`` of it, the final clicks are left out: there the ball
  spends a sizeable part of each bounce in contact, gravity acts during the contact beyond the
  bounce model's first order (``bounces``), and the law's k matters more than its λ.  The
  contact time is the law's undamped one, τ_c = τ̂ Z / v (``impact.elastic_limits``), at the
  impact speed g T / 2 of the flight T before it; the default ratio 0.016 is G = gZ/v² = 0.01 for
  the n = 3/2 laws.  Both are the user's to change: a stiffness guessed too soft cuts too early.

Units: SI.
"""
import math
from dataclasses import dataclass

import numpy as np

from contact_sim.calibration.bounces import release_speed
from contact_sim.calibration.defaults import MICRO_BOUNCE_RATIO
from contact_sim.flight import flight_to_plate
from contact_sim.impact import elastic_limits, impact_scales
from contact_sim.validation import require_nonnegative, require_positive

MISSED_FLIGHT_SHARE = 0.01   # a flight shorter than this share of an interval: not counted
SPLIT_RATIO = 0.7        # an interval below this share of the expected flight: a split one
DOUBLED_SHARE = 0.1      # a split this close after the click before: a doubled click
GROWTH = 0.05            # an interval longer than the flight before by this share: growing
MAX_LATE = 100           # impacts missed before the first click, at most (late starts)
LEFT_OUT = ('doubled click', 'spurious click')


@dataclass(frozen=True)
class Glitch:
    """A detector glitch found in sequence ``sequence``: ``kind`` is 'doubled click', 'missed
    bounce', 'late start' or 'outlier'; ``time`` the click concerned (s); ``left_out`` whether
    that click was left out of the fit."""

    sequence: int
    kind: str
    time: float
    left_out: bool
    detail: str

    def describe(self):
        action = 'left out' if self.left_out else 'kept'
        return f'sequence {self.sequence + 1}: {self.kind} at t = {self.time:.6f} s ({action}): ' \
               f'{self.detail}'


@dataclass(frozen=True)
class MicroBounceCut:
    """Where the final micro-bounces of a sequence begin (module doc).

    Parameters
    ----------
    law : ContactLaw or None
        The law of ``stiffness`` (None: no contact-time test).
    stiffness : float or None
        Its k in N/m^n.
    mass : float or None
        The mass in kg.
    ratio : float
        Contact time / flight time beyond which the clicks are left out, > 0 (inf: never).
    min_flight : float
        Flights shorter than this (s) are micro-bounces, >= 0 (0: no such test).
    """

    law: object = None
    stiffness: float = None
    mass: float = None
    ratio: float = MICRO_BOUNCE_RATIO
    min_flight: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, 'ratio', require_positive('micro_bounce_ratio', self.ratio,
                                                           allow_inf=True))
        object.__setattr__(self, 'min_flight', require_nonnegative('min_flight',
                                                                   self.min_flight))

    def contact_time(self, speed):
        """The undamped contact duration (s) at impact ``speed`` (m/s), or None without a
        law."""
        if self.law is None or self.stiffness is None or self.mass is None:
            return None
        _, scale = impact_scales(self.law, self.stiffness, self.mass, speed)
        return elastic_limits(self.law)['duration'] * scale

    def first(self, flights, gravity):
        """The first flight (position in ``flights``, s) of the micro-bounces and why, or
        None."""
        speeds = 0.5 * gravity * flights
        contact = self.contact_time(speeds)
        for i, (flight, v) in enumerate(zip(flights, speeds)):
            if flight < self.min_flight:
                return i, f'flight {flight * 1e3:.3g} ms < min_flight {self.min_flight * 1e3:g} ms'
            if contact is not None and contact[i] > self.ratio * flight:
                return i, (f'impact at {v:.3g} m/s lasts {contact[i] * 1e3:.3g} ms, more than '
                           f'{self.ratio:g} of the flight of {flight * 1e3:.3g} ms before it '
                           f'({self.law.name}, k = {self.stiffness:.3g})')
        return None


@dataclass(frozen=True)
class PreparedSequence:
    """Clicks kept for the fit and the bounce number (from 0) each one is assigned."""

    times: np.ndarray
    index: np.ndarray
    height: float
    name: str
    restitution_guess: float


def _interval_restitution(dt):
    ratios = dt[1:] / dt[:-1]
    good = ratios[(ratios > 0.2) & (ratios < 1.0)]
    return float(np.clip(np.median(good) if good.size else 0.7, 0.1, 0.995))


def _flights_in(interval, expected, e_bar):
    """How many clicks are missing from ``interval`` (s), whose first flight is expected to
    last ``expected`` s: the m whose m + 1 flights expected (1 + ē + … + ē^m) come closest in
    ratio.  No cap: the candidates run until their sum passes the interval, or until one more
    flight would add less than ``MISSED_FLIGHT_SHARE`` of it (the sums no longer differ)."""
    sums, m = [expected], 0
    while sums[-1] < interval and expected * e_bar ** (m + 1) > MISSED_FLIGHT_SHARE * interval:
        m += 1
        sums.append(sums[-1] + expected * e_bar ** m)
    return int(np.argmin([abs(math.log(interval / total)) for total in sums]))


def _walk(t, e_bar, split=True):
    """Number the clicks ``t`` by the physics: each interval predicts the next single flight
    (the last one times ``e_bar``).  Returns the clicks kept, their bounce numbers and the
    glitches found as (kind, time, detail):

    * a click that splits an expected flight in two (the two parts together fit one or more
      flights better than the first part alone) is left out: a 'doubled click' when it comes
      within ``DOUBLED_SHARE`` of a flight after the click before (an echo, a rattle), else a
      'spurious click';
    * an interval of m + 1 expected flights (any m) holds m 'missed bounce' clicks;
    * an interval longer by more than ``GROWTH`` than the flight before it, with no missed
      click to explain it, is a 'growing interval' (kept; it becomes the next prediction).

    ``split=False``: no click is left out (the numbering after the micro-bounce cut).
    """
    kept, index, found = [0], [0], []
    last = None           # the last single flight (s)
    i = 1
    while i < t.size:
        dt = t[i] - t[kept[-1]]
        if last is None:
            # the first interval: against the next one, unless that one holds a miss
            nxt = t[i + 1] - t[i] if i + 1 < t.size else dt
            expected = nxt / e_bar if nxt <= dt * (1.0 + 0.5 * e_bar) else dt
            if nxt < SPLIT_RATIO * e_bar * dt and i + 2 < t.size:
                expected = dt   # the next click splits the second flight: judged there
        else:
            expected = last * e_bar
        if split and dt < SPLIT_RATIO * expected:
            merged = (t[i + 1] - t[kept[-1]]) if i + 1 < t.size else None
            alone = abs(math.log(dt / expected))
            m_merged = _flights_in(merged, expected, e_bar) if merged is not None else 0
            fits = merged is not None and abs(math.log(
                merged / _flight_sum(expected, e_bar, m_merged))) < alone
            if fits or merged is None:
                kind = 'doubled click' if dt < DOUBLED_SHARE * expected else 'spurious click'
                found.append((kind, t[i], f'{dt * 1e3:.2f} ms after the click before, expected '
                                          f'a flight of about {expected * 1e3:.1f} ms'))
                i += 1
                continue
        m = _flights_in(dt, expected, e_bar)
        if m:
            found.append(('missed bounce', t[i], f'interval {dt * 1e3:.1f} ms is about {1 + m} '
                                                 f'flights of {expected * 1e3:.1f} ms, {m} '
                                                 'click(s) missing before it'))
            single = dt * e_bar ** m / _flight_sum(1.0, e_bar, m)    # the last of the m + 1
        else:
            single = dt
            if last is not None and dt > (1.0 + GROWTH) * last:
                found.append(('growing interval', t[i], f'interval {dt * 1e3:.1f} ms is longer '
                                                        f'than the flight of {last * 1e3:.1f} ms'
                                                        ' before it: bounce flights shrink'))
        kept.append(i)
        index.append(index[-1] + 1 + m)
        last = single
        i += 1
    return t[kept], np.array(index, dtype=int), found


def _flight_sum(first, e_bar, m):
    """first (1 + ē + … + ē^m): the time of m + 1 flights, the first ``first`` s long."""
    return first * sum(e_bar ** j for j in range(m + 1))


def prepare_sequence(number, seq, gravity=9.81, kappa=0.0, cut=MicroBounceCut()):
    """Find the glitches in one recorded sequence (module doc).

    Parameters
    ----------
    number : int
        The sequence's number (from 0), recorded in each ``Glitch``.
    seq : ImpactTimes
        The click times (s) and, if known, the release height (m).
    gravity : float
        g in m/s^2.
    kappa : float
        The quadratic drag rate c/m in 1/m, used for the late-start test.
    cut : MicroBounceCut
        Where the final micro-bounces begin (default: no law, so no flight is cut).

    Returns
    -------
    (PreparedSequence, list of Glitch)
    """
    t = np.asarray(seq.times, dtype=float)
    glitches = []
    # doubled and spurious clicks, by the physics: the clicks kept after the walk
    kt, _, found = _walk(t, _interval_restitution(np.diff(t)))
    glitches.extend(Glitch(number, kind, float(when), True, detail)
                    for kind, when, detail in found if kind in LEFT_OUT)
    dt = np.diff(kt)
    # micro-bounces: the final clicks from the first flight the cut names
    over = cut.first(dt, gravity) if dt.size > 2 else None
    if over is not None and over[0] + 2 < kt.size:
        end = over[0] + 2          # the impact that ends that flight is the last click kept
        glitches.append(Glitch(number, 'micro-bounces', float(kt[end]), True,
                               f'the last {kt.size - end} click(s) left out: {over[1]}'))
        kt = kt[:end]
        dt = np.diff(kt)
    e_bar = _interval_restitution(dt)
    # missed bounces and growing intervals: each interval predicts the next
    kt, index, found = _walk(kt, e_bar, split=False)
    dt = np.diff(kt)
    glitches.extend(Glitch(number, kind, float(when), kind in LEFT_OUT, detail)
                    for kind, when, detail in found)
    # late start: the first flight against the fall from the release height, with the
    # restitution's trend over the first bounces extrapolated back (it can change with speed)
    if seq.height is not None and dt.size:
        singles = np.flatnonzero(np.diff(index) == 1)
        at, est = [], []
        for a, b in zip(singles[:-1], singles[1:]):
            if b == a + 1:                  # flights after impacts a and a + 1: e of a + 1
                at.append(index[b])
                est.append(dt[b] / dt[a])
        at, est = np.array(at[:6], dtype=float), np.array(est[:6])
        if est.size >= 3:
            slope, offset = np.polyfit(at, est, 1)
        else:
            slope, offset = 0.0, e_bar

        def e_at(j):
            return float(np.clip(offset + slope * j, 0.05, 0.999))

        first = dt[0] if index[1] == 1 else dt[0] / sum(e_bar ** j for j in range(index[1]))
        options = []
        released = float(release_speed(seq.height, gravity, kappa))
        late = 0
        while late <= MAX_LATE:     # bounce 1, 2, ... until its flight is far below the first
            v = released
            for j in range(-late, 0):
                v = float(flight_to_plate(e_at(j) * v, gravity, kappa)[1])
            options.append(float(flight_to_plate(e_at(0) * v, gravity, kappa)[0]))
            if options[-1] < 0.5 * first:
                break
            late += 1
        late = int(np.argmin([abs(math.log(first / s)) for s in options]))
        if late:
            index = index + late
            glitches.append(Glitch(number, 'late start', float(kt[0]), False,
                                   f'first interval {dt[0] * 1e3:.1f} ms fits bounce {late + 1} '
                                   f'of a release from {seq.height:g} m, not bounce 1: the first '
                                   f'{late} impact(s) were not recorded'))
    return PreparedSequence(kt, index, seq.height, seq.name, e_bar), glitches
