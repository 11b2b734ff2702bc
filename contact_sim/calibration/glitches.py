"""Detector glitches named before a bounce fit, and the clicks prepared for it.

Glitches are found from the intervals between clicks, which shrink by about the restitution ē
(the median of the interval ratios) at each bounce:

* a doubled click (an echo or the ball's rattle): an interval far shorter (< 0.4 ×) than the one
  expected; the later click is left out;
* missed bounces: an interval close to (1 + ē + … + ē^m) times the one expected, for any m (no
  cap; ``_flights_in``); nothing is left out, the following clicks are numbered m bounces later;
* a late start (the first impact was missed): with a release height, a first interval that
  matches the second bounce's flight rather than the first; the sequence is numbered from 1.
  Without a release height a late start cannot be told from a lower release;
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
from contact_sim.flight import flight_to_plate
from contact_sim.impact import elastic_limits, impact_scales
from contact_sim.validation import require_nonnegative, require_positive

MICRO_BOUNCE_RATIO = 0.016   # contact time / flight time beyond which clicks are left out
MISSED_FLIGHT_SHARE = 0.01   # a flight shorter than this share of an interval: not counted
DOUBLED_RATIO = 0.4          # an interval below this fraction of the expected one: doubled click


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
    keep = np.ones(t.size, dtype=bool)
    # doubled clicks: drop the later click of an interval far shorter than both neighbours'
    # expectation, repeatedly (the expectation comes from the kept clicks)
    changed = True
    while changed and keep.sum() >= 4:
        changed = False
        kt = t[keep]
        dt = np.diff(kt)
        e_bar = _interval_restitution(dt)
        for i in range(dt.size):
            prev_dt = dt[i - 1] * e_bar if i > 0 else None
            next_dt = dt[i + 1] / e_bar if i + 1 < dt.size else None
            ref = [x for x in (prev_dt, next_dt) if x is not None]
            if ref and dt[i] < DOUBLED_RATIO * min(ref):
                # the echo (or rattle) is the later click of the pair
                j = np.flatnonzero(keep)[i + 1]
                keep[j] = False
                glitches.append(Glitch(number, 'doubled click', float(t[j]), True,
                                       f'{dt[i] * 1e3:.2f} ms after the click before, '
                                       f'expected about {min(ref) * 1e3:.1f} ms'))
                changed = True
                break
    kt = t[keep]
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
    index = np.zeros(kt.size, dtype=int)
    # missed bounces: number the clicks so that each interval is one or more bounce flights
    last = None     # the last single-bounce flight time
    for i in range(dt.size):
        if last is None:
            # the first interval: compare with the next one (if any)
            expected = dt[i + 1] / e_bar if i + 1 < dt.size else dt[i]
            if i + 1 < dt.size and dt[i + 1] > dt[i] * (1.0 + 0.5 * e_bar):
                expected = dt[i]   # the next interval is the one that holds a miss
        else:
            expected = last * e_bar
        m = _flights_in(dt[i], expected, e_bar)
        index[i + 1] = index[i] + 1 + m
        if m:
            glitches.append(Glitch(number, 'missed bounce', float(kt[i + 1]), False,
                                   f'interval {dt[i] * 1e3:.1f} ms is about {1 + m} flights of '
                                   f'{expected * 1e3:.1f} ms, {m} click(s) missing before it'))
        last = dt[i] * e_bar ** m / sum(e_bar ** j for j in range(m + 1))
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
        for late in range(3):
            v = released
            for j in range(-late, 0):
                v = float(flight_to_plate(e_at(j) * v, gravity, kappa)[1])
            options.append(float(flight_to_plate(e_at(0) * v, gravity, kappa)[0]))
        late = int(np.argmin([abs(math.log(first / s)) for s in options]))
        if late:
            index = index + late
            glitches.append(Glitch(number, 'late start', float(kt[0]), False,
                                   f'first interval {dt[0] * 1e3:.1f} ms fits bounce {late + 1} '
                                   f'of a release from {seq.height:g} m, not bounce 1: the first '
                                   f'{late} impact(s) were not recorded'))
    return PreparedSequence(kt, index, seq.height, seq.name, e_bar), glitches
