"""Calibrating a contact from recorded bounce sequences: a robust least-squares fit on the impact
times themselves.

For each law, the unknowns are the damping λ (in ln λ), optionally the drag coefficient C_d (in
ln C_d), and per sequence the time t₁ and speed v₁ of its first recorded impact; the model is
``bounces.impact_sequence`` (closed-form drag flights, restitution fast path, contact duration,
first-order gravity during contact).  The residuals are predicted minus measured times in units of
the timing resolution, plus, for a sequence with a measured release height h (± ``height_error``),
(h(v₁) - h) / height_error.  ``scipy.optimize.least_squares`` minimises them with a robust loss
(soft-L1 by default) whose scale is three times the timing noise, itself estimated robustly
(1.4826 × median absolute residual of a first pass, never below the resolution / √12); points the
loss down-weights by more than half are reported.

Detector glitches are found before the fit from the intervals between clicks, which shrink by
about the restitution ē (the median of the interval ratios) at each bounce:

* a doubled click (an echo or the ball's rattle): an interval far shorter (< 0.4 ×) than the one
  expected; the later click is left out;
* a missed bounce: an interval close to (1 + ē) or (1 + ē + ē²) times the one expected; nothing is
  left out, the following clicks are numbered one or two bounces later;
* a late start (the first impact was missed): with a release height, a first interval that
  matches the second bounce's flight rather than the first; the sequence is numbered from 1.
  Without a release height a late start cannot be told from a lower release.

Laws have equal parameter counts, so they are ranked by the weighted rms timing residual; the
Akaike criterion N ln(SSE / N) + 2P is reported too (it ranks the same way then, and is the one to
compare when counts differ, e.g. with and without a fitted C_d).  The constant-restitution law is
the linear law (its e does not depend on speed); its stiffness, when not given, is chosen so that
its undamped contact lasts as long as the Hertz contact at the median impact speed.  The data are
said to support a speed-dependent restitution when the best speed-dependent law beats the constant
law by ΔAIC > 10.  Confidence intervals come from the Jacobian of the weighted residuals at the
optimum (covariance s² (JᵀJ)⁻¹, Student t with N - P degrees of freedom), in ln λ and ln C_d.
Units: SI.
"""
import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from contact_sim.calibration.bounces import contact_map, impact_sequence, release_height, release_speed
from contact_sim.model import Contact
from contact_sim.impact import robust_weights, damping_for_restitution, require_fit_options
from contact_sim.flight import AirDrag, flight_to_plate
from contact_sim.model import LAWS, get_law
from contact_sim.calibration.recordings import ImpactTimes
from contact_sim.impact import elastic_limits, impact_scales, restitution
from contact_sim.validation import InputError, require_positive

MICRO_BOUNCE_GROUP = 1e-2    # impacts with G = gT/v above this are left out (bounces doc)
DOUBLED_RATIO = 0.4          # an interval below this fraction of the expected one: doubled click
SUPPORT_DELTA_AIC = 10.0     # evidence needed to call the restitution speed dependent


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


def prepare_sequence(number, seq, gravity=9.81, kappa=0.0, stiffness=None, mass=None,
                     law_n=1.5):
    """Find glitches in one ``ImpactTimes``; returns (``PreparedSequence``, glitches).
    ``kappa`` (1/m): the quadratic drag rate c/m, used for the late-start test; with
    ``stiffness`` (N/m^n of a law with exponent ``law_n``) and ``mass`` (kg), the final
    micro-bounces beyond the model's validity are cut off."""
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
    # micro-bounces: cut where the gravity group of the impacts exceeds the model's range
    if stiffness is not None and mass is not None and dt.size > 2:
        v = gravity * dt / 2.0                       # impact speed at the end of each flight
        length = (mass * v * v / stiffness) ** (1.0 / (law_n + 1.0))
        group = gravity * length / (v * v)           # G = g T / v with T = Z / v
        over = np.flatnonzero(group > MICRO_BOUNCE_GROUP)
        if over.size and over[0] + 2 < kt.size:
            cut = int(over[0]) + 2
            glitches.append(Glitch(number, 'micro-bounces', float(kt[cut]), True,
                                   f'the last {kt.size - cut} click(s) left out: impacts at '
                                   f'{v[over[0]]:.3g} m/s and slower have G = gT/v > '
                                   f'{MICRO_BOUNCE_GROUP:g}, beyond the bounce model'))
            kt = kt[:cut]
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
        sums = [expected * sum(e_bar ** j for j in range(m + 1)) for m in range(3)]
        m = int(np.argmin([abs(math.log(dt[i] / s)) for s in sums]))
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


@dataclass(frozen=True)
class LawFit:
    """The fit of one law to all sequences (SI units)."""

    law: object
    stiffness: float
    damping: float
    damping_interval: tuple
    drag_coefficient: float
    drag_interval: tuple          # (nan, nan) when C_d was not fitted
    start_times: np.ndarray       # t₁ per sequence (s)
    first_speeds: np.ndarray      # v₁ per sequence (m/s)
    release_heights: np.ndarray   # h(v₁) per sequence (m)
    residuals: list               # per sequence, predicted - measured (s), kept clicks only
    weights: list                 # per sequence, the robust loss weights (1 = full weight)
    rms: float                    # weighted rms timing residual (s)
    aic: float
    parameters: int
    observations: int
    noise: float                  # estimated timing noise (s)
    success: bool
    message: str

    def contact(self):
        return Contact(self.law, self.stiffness, self.damping)


@dataclass(frozen=True)
class BounceFit:
    """``fit_bounces`` result: laws ranked best first, the glitches and the prepared data."""

    fits: list
    sequences: list
    glitches: list
    mass: float
    gravity: float
    drag: object
    fit_drag: bool
    confidence: float
    timing_resolution: float
    speed_dependent: bool = field(default=False)
    delta_aic: float = field(default=math.nan)

    @property
    def best(self):
        return self.fits[0]

    def downweighted(self, fit=None):
        """(sequence, time s, residual s, weight) of the clicks the robust loss down-weighted."""
        fit = fit or self.best
        out = []
        for j, (seq, r, w) in enumerate(zip(self.sequences, fit.residuals, fit.weights)):
            for t, ri, wi in zip(seq.times, r, w):
                if wi < 0.5:
                    out.append((j, float(t), float(ri), float(wi)))
        return out


def _linear_stiffness(hertz_law, hertz_k, mass, speed):
    """k of a linear spring whose undamped contact π √(m/k) lasts as long as the Hertz one."""
    tau_unit = elastic_limits(hertz_law)['duration']   # dimensionless τc at ζ -> 0
    length, _ = impact_scales(hertz_law, hertz_k, mass, speed)
    return mass * (math.pi * speed / (tau_unit * length)) ** 2


class _Problem:
    """Residuals of one law over all sequences (vectorised over sequences)."""

    def __init__(self, law, stiffness, mass, gravity, drag, fit_drag, sequences, resolution,
                 height_error):
        self.law, self.k, self.m, self.g = law, stiffness, mass, gravity
        self.drag, self.fit_drag = drag, fit_drag
        self.seqs = sequences
        self.res = resolution
        self.height_error = height_error
        self.count = max(int(s.index[-1]) for s in sequences) + 1
        self.n_seq = len(sequences)
        self.offset = 2 if fit_drag else 1
        self.rows = [(j, s.index) for j, s in enumerate(sequences)]
        self.n_times = sum(s.times.size for s in sequences)
        self.heights = [j for j, s in enumerate(sequences) if s.height is not None]

    def unpack(self, x):
        lam = math.exp(min(x[0], 700.0))
        cd = math.exp(min(x[1], math.log(CD_BOUNDS[1]))) if self.fit_drag else None
        t1 = x[self.offset:self.offset + self.n_seq]
        v1 = np.exp(x[self.offset + self.n_seq:])
        return lam, cd, t1, v1

    def rates(self, cd):
        if self.drag is None:
            return 0.0, 0.0
        drag = self.drag if cd is None else AirDrag(self.drag.air_density, cd,
                                                    self.drag.radius,
                                                    self.drag.linear_coefficient)
        return drag.rates(self.m, self.g)

    def _times(self, lam, v1, kappa, beta):
        """Relative touch times (rows, count) for per-row λ and v₁ (arrays of equal length)."""
        return impact_sequence(self.law, self.k, lam, self.m, self.g, v1, self.count,
                               kappa, beta)[0]

    def predicted(self, x):
        lam, cd, t1, v1 = self.unpack(x)
        kappa, beta = self.rates(cd)
        times = self._times(np.full(v1.size, lam), v1, kappa, beta)
        return [t1[j] + times[j, idx] for j, idx in self.rows], (kappa, beta), v1

    def _pack(self, pred, v1, kappa, beta):
        out = np.empty(self.n_times + len(self.heights))
        pos = 0
        for p, s in zip(pred, self.seqs):
            r = (p - s.times) / self.res
            out[pos:pos + r.size] = np.where(np.isfinite(r), r, 1e6)   # the ball stopped
            pos += r.size
        if self.heights:
            sel = np.array(self.heights)
            h = release_height(v1[sel], self.g, kappa, beta)
            target = np.array([self.seqs[j].height for j in self.heights])
            out[pos:] = np.where(np.isfinite(h), (h - target) / self.height_error, 1e6)
        return out

    def residuals(self, x):
        pred, (kappa, beta), v1 = self.predicted(x)
        return self._pack(pred, v1, kappa, beta)

    def jacobian(self, x):
        """Forward differences in ln λ and ln v₁ from one batched model call (the sequences
        are independent given λ), exact in t₁; C_d, when fitted, by one more call."""
        lam, cd, t1, v1 = self.unpack(x)
        kappa, beta = self.rates(cd)
        n, step = self.n_seq, 1e-7
        lams = np.concatenate([np.full(n, lam), np.full(n, lam * math.exp(step)),
                               np.full(n, lam)])
        v1s = np.concatenate([v1, v1, v1 * math.exp(step)])
        times = self._times(lams, v1s, kappa, beta)
        jac = np.zeros((self.n_times + len(self.heights), x.size))
        pos = 0
        for j, idx in self.rows:
            base = times[j, idx]
            rows = slice(pos, pos + idx.size)
            jac[rows, 0] = (times[n + j, idx] - base) / step / self.res
            jac[rows, self.offset + j] = 1.0 / self.res
            jac[rows, self.offset + n + j] = (times[2 * n + j, idx] - base) / step / self.res
            pos += idx.size
        for i, j in enumerate(self.heights):
            h0 = float(release_height(v1[j], self.g, kappa, beta))
            h1 = float(release_height(v1[j] * math.exp(step), self.g, kappa, beta))
            jac[pos + i, self.offset + n + j] = (h1 - h0) / step / self.height_error
        if self.fit_drag:   # the base residuals from the batch's first block: one call more
            base = self._pack([t1[j] + times[j, idx] for j, idx in self.rows], v1, kappa, beta)
            xs = np.array(x, dtype=float)
            xs[1] += step
            jac[:, 1] = (self.residuals(xs) - base) / step
        return np.where(np.isfinite(jac), jac, 0.0)


def _damping_guess(law, stiffness, mass, e, speed):
    """λ giving restitution ``e`` at ``speed``: read off the master curve's nodes (a start
    value, no root finding); the exact inverse for a law without a master curve."""
    from contact_sim.calibration.bounces import _tables
    from contact_sim.impact import damping_from_group
    tables = _tables(law)
    if tables is None:
        return damping_for_restitution(law, stiffness, mass, e, speed)
    nodes = tables.master[3, :, 0]                  # e at s0, s0 + h, ... (decreasing)
    s = tables.s0 + tables.h * np.arange(nodes.size)
    log_zeta = float(np.interp(-e, -nodes, s))
    return float(damping_from_group(law, stiffness, mass, speed, math.exp(log_zeta)))


def _initial_guess(problem, drag_coefficient):
    law, k, m, g = problem.law, problem.k, problem.m, problem.g
    kappa, beta = problem.rates(drag_coefficient)
    t1, v1, speeds, es = [], [], [], []
    for s in problem.seqs:
        dt = np.diff(s.times) / np.diff(s.index)        # rough single flights
        e = s.restitution_guess
        first_flight = dt[0]
        if s.height is not None:
            v = float(release_speed(s.height, g, kappa, beta))
            v_first = v * e ** s.index[0]
        else:
            v_first = g * first_flight / 2.0 / e
            v = v_first / e ** s.index[0]
        t_first = s.times[0] - sum(2.0 * v * e ** (i + 1) / g for i in range(s.index[0]))
        t1.append(t_first)
        v1.append(v)
        speeds.extend(g * dt / 2.0)
        es.append(e)
    v_med = float(np.median(speeds))
    e_med = float(np.median(es))
    lam0 = _damping_guess(law, k, m, e_med, v_med)
    x0 = [math.log(max(lam0, 1e-300))]
    if problem.fit_drag:
        x0.append(math.log(drag_coefficient))
    x0 = np.array(x0 + t1 + [math.log(v) for v in v1])
    # each sequence's start time: the median offset of the predicted from the measured clicks
    pred = problem.predicted(x0)[0]
    for j, (p, s) in enumerate(zip(pred, problem.seqs)):
        offset = np.median((s.times - p)[np.isfinite(p)]) if np.any(np.isfinite(p)) else 0.0
        x0[problem.offset + j] += offset
    return x0, v_med


CD_BOUNDS = (1e-3, 10.0)     # a fitted drag coefficient stays inside (AirDrag's range)


def _solve(problem, x0, loss, scale):
    bounds = (-np.inf, np.inf)
    if problem.fit_drag:
        low, high = np.full(x0.size, -np.inf), np.full(x0.size, np.inf)
        low[1], high[1] = (math.log(b) for b in CD_BOUNDS)
        x0 = x0.copy()
        x0[1] = min(max(x0[1], low[1] + 1e-9), high[1] - 1e-9)
        bounds = (low, high)
    # many sequences: the iterative trust-region solver (no SVD of the whole Jacobian)
    solver = 'lsmr' if x0.size > 12 else 'exact'
    return least_squares(problem.residuals, x0, jac=problem.jacobian, loss=loss, bounds=bounds,
                         tr_solver=solver,
                         f_scale=scale, x_scale='jac', method='trf', xtol=1e-8, ftol=1e-8,
                         gtol=1e-8, max_nfev=100)


def _fit_law(law, k, problem, x0, loss, confidence):
    from scipy.special import stdtrit
    res_unit = problem.res
    # pass 1: plain least squares (quick from afar); its median residual estimates the noise
    first = _solve(problem, x0, 'linear', 1.0)
    r = first.fun[:problem.n_times] * res_unit
    noise = max(1.4826 * float(np.median(np.abs(r - np.median(r)))), res_unit / math.sqrt(12.0))
    scale = 3.0 * noise / res_unit
    result = _solve(problem, first.x, loss, scale) if loss != 'linear' else first
    x = result.x
    n_obs, n_par = result.fun.size, x.size
    dof = max(n_obs - n_par, 1)
    weights = robust_weights(loss, (result.fun / scale) ** 2)
    weighted_sse = float(np.sum(weights * result.fun ** 2)) * res_unit ** 2
    s2 = float(np.sum(weights * result.fun ** 2)) / dof
    jac = result.jac.toarray() if hasattr(result.jac, 'toarray') else np.asarray(result.jac)
    jw = jac * np.sqrt(weights)[:, None] if loss != 'linear' else jac
    normal = jw.T @ jw
    try:
        cov = s2 * np.linalg.inv(normal)
        if not np.all(np.isfinite(np.diag(cov))):
            raise np.linalg.LinAlgError('singular')
    except np.linalg.LinAlgError:
        cov = s2 * np.linalg.pinv(normal)
    q = float(stdtrit(dof, 0.5 + confidence / 2.0))
    lam, cd, t1, v1 = problem.unpack(x)
    half = min(q * math.sqrt(max(cov[0, 0], 0.0)), 50.0)
    lam_ci = (lam * math.exp(-half), lam * math.exp(half))
    if problem.fit_drag:
        half_cd = min(q * math.sqrt(max(cov[1, 1], 0.0)), 50.0)
        cd_ci = (cd * math.exp(-half_cd), cd * math.exp(half_cd))
    else:
        cd = problem.drag.drag_coefficient if problem.drag is not None else 0.0
        cd_ci = (math.nan, math.nan)
    pred, (kappa, beta), _ = problem.predicted(x)
    residuals, weights_seq, pos = [], [], 0
    for p, s in zip(pred, problem.seqs):
        residuals.append(p - s.times)
        weights_seq.append(weights[pos:pos + s.times.size])
        pos += s.times.size
    n_times = problem.n_times
    rms = math.sqrt(float(np.sum(weights[:n_times] * (result.fun[:n_times] * res_unit) ** 2))
                    / float(np.sum(weights[:n_times])))
    aic = n_obs * math.log(max(weighted_sse, 1e-300) / n_obs) + 2.0 * n_par
    heights = release_height(v1, problem.g, kappa, beta)
    return LawFit(law, k, lam, lam_ci, cd, cd_ci, np.asarray(t1), v1, np.asarray(heights),
                  residuals, weights_seq, rms, aic, n_par, n_obs, noise, bool(result.success),
                  str(result.message))


def fit_bounces(sequences, mass, stiffness, laws=None, gravity=9.81, drag=None, fit_drag=False,
                timing_resolution=1.0 / 48000.0, height_error=0.01, loss='soft_l1',
                confidence=0.95):
    """Fit λ (and optionally C_d) of each law to recorded bounce sequences; see module doc.

    ``sequences``: ``recordings.ImpactTimes`` values (or arrays of times); ``mass`` in kg;
    ``stiffness``: one k for the n = 1.5 laws or a mapping law name -> k (for 'linear' a
    missing k is derived, see module doc); ``drag``: an ``AirDrag`` (its C_d the start value
    when ``fit_drag``); ``timing_resolution`` (s): the clock's resolution, 1/48000 s for a phone;
    ``height_error`` (m): the uncertainty of a measured release height.  Returns ``BounceFit``.
    """
    mass = require_positive('mass', mass)
    gravity = require_positive('gravity', gravity)
    resolution = require_positive('timing_resolution', timing_resolution)
    height_error = require_positive('height_error', height_error)
    confidence, loss = require_fit_options(confidence, loss)
    if fit_drag and (drag is None or drag.air_density == 0.0):
        raise ValueError('drag is missing: fitting the drag coefficient needs an AirDrag with '
                         'the air density and the sphere radius')
    if drag is not None and fit_drag and drag.drag_coefficient <= 0.0:
        drag = AirDrag(drag.air_density, 0.47, drag.radius, drag.linear_coefficient)
    if not sequences:
        raise ValueError('sequences is empty: allowed one or more recorded sequences')
    seqs = [s if isinstance(s, ImpactTimes)
            else ImpactTimes(np.asarray(s), None, f'sequence {i + 1}')
            for i, s in enumerate(sequences)]
    chosen = [get_law(name) for name in (laws if laws is not None else LAWS)]
    if isinstance(stiffness, dict):
        ks = dict(stiffness)
        if laws is None:      # every law with a k, and the constant law (k derivable)
            chosen = [law for law in chosen if law.name in ks or law.name == 'linear']
    else:
        ks = {law.name: require_positive('stiffness', stiffness) for law in chosen
              if law.n == 1.5}
    # the softest contact given decides where the micro-bounces begin
    cut_law, cut_k = min(((get_law(name), k) for name, k in ks.items()),
                         key=lambda lk: lk[1] ** (1.0 / (lk[0].n + 1.0)), default=(None, None))
    prepared, glitches = [], []
    kappa0 = drag.rates(mass, gravity)[0] if drag is not None else 0.0
    for j, s in enumerate(seqs):
        p, g = prepare_sequence(j, s, gravity, kappa0, cut_k, mass,
                                cut_law.n if cut_law is not None else 1.5)
        prepared.append(p)
        glitches.extend(g)
    speeds = np.concatenate([gravity * np.diff(p.times) / np.diff(p.index) / 2.0
                             for p in prepared])
    v_med = float(np.median(speeds))
    fits = []
    for law in chosen:
        k = ks.get(law.name)
        if k is None and law.name == 'linear':
            hertz = next((name for name in ks if get_law(name).n == 1.5), None)
            if hertz is None:
                raise InputError('stiffness', None, '{n[stiffness]} is missing for law linear: '
                                 'give its k (N/m), or fit a Hertz law beside it to derive it from')
            k = _linear_stiffness(get_law(hertz), ks[hertz], mass, v_med)
        if k is None:
            raise InputError('stiffness', None, '{n[stiffness]} is missing for law %s: allowed '
                             'a k for every law fitted' % law.name)
        problem = _Problem(law, require_positive('stiffness', k), mass, gravity, drag,
                           fit_drag, prepared, resolution, height_error)
        x0, _ = _initial_guess(problem, drag.drag_coefficient if drag is not None else None)
        fits.append(_fit_law(law, k, problem, x0, loss, confidence))
    fits.sort(key=lambda f: f.rms)
    # outliers the robust loss down-weighted (after the named glitches)
    best = fits[0]
    for j, (seq, r, w) in enumerate(zip(prepared, best.residuals, best.weights)):
        for t, ri, wi in zip(seq.times, r, w):
            if wi < 0.5:
                glitches.append(Glitch(j, 'outlier', float(t), False,
                                       f'residual {ri * 1e3:+.3f} ms, weight {wi:.2f} in the '
                                       f'robust fit of {best.law.name}'))
    constant = [f for f in fits if f.law.name == 'linear']
    varying = [f for f in fits if f.law.name != 'linear']
    delta = math.nan
    if constant and varying:
        delta = constant[0].aic - min(f.aic for f in varying)
    return BounceFit(fits, prepared, glitches, mass, gravity, drag, fit_drag, confidence,
                     resolution, bool(delta > SUPPORT_DELTA_AIC), delta)


def _rebound_for_flight(flight, gravity, kappa, beta):
    """Rebound speed (m/s) whose flight from the plate back to it lasts ``flight`` s: Newton on
    the closed form (monotone, concave), from the vacuum value 1/2 g T, which lies below."""
    u = 0.5 * gravity * flight
    for _ in range(50):
        t, _ = flight_to_plate(u, gravity, kappa, beta)
        dt = (float(flight_to_plate(u * (1.0 + 1e-7), gravity, kappa, beta)[0]) - float(t)) \
            / (1e-7 * u)
        step = (float(t) - flight) / dt
        u -= step
        if abs(step) <= 1e-13 * u:
            break
    return u, dt


def corrected_restitution_table(fit, law_fit=None):
    """The drag- and duration-corrected restitution read from the measured flights: a list of
    (sequence, impact speed v m/s, e, σ_e), one per pair of consecutive single flights.

    A flight (click to click) minus the fitted law's contact time at its impact speed is
    turned into the rebound speed that gives it under the fitted drag (closed form, inverted by
    Newton's method); its arrival speed is the next impact speed.  e = u / v, with v from the
    flight before (or from the fit for the first recorded impact); σ_e propagates the timing
    noise √2 σ_t of each interval."""
    lf = law_fit or fit.best
    law, k, lam, m, g = lf.law, lf.stiffness, lf.damping, fit.mass, fit.gravity
    kappa, beta = (0.0, 0.0)
    if fit.drag is not None:
        kappa, beta = AirDrag(fit.drag.air_density, lf.drag_coefficient, fit.drag.radius,
                              fit.drag.linear_coefficient).rates(m, g)
    sigma = math.sqrt(2.0) * lf.noise
    rows = []
    for j, (seq, v1) in enumerate(zip(fit.sequences, lf.first_speeds)):
        predicted = impact_sequence(law, k, lam, m, g, v1, int(seq.index[-1]) + 1,
                                    kappa, beta)[1][0]
        v_known, sv = None, 0.0
        for i in range(seq.times.size - 1):
            if seq.index[i + 1] - seq.index[i] != 1:
                v_known = None
                continue
            v = v_known if v_known is not None else float(predicted[seq.index[i]])
            if not (math.isfinite(v) and v > 0.0):
                break
            _, tau, _ = contact_map(law, k, lam, m, g, v, kappa, beta)
            u, dt_du = _rebound_for_flight(float(seq.times[i + 1] - seq.times[i]) - tau, g,
                                           kappa, beta)
            su = sigma / dt_du
            e = u / v
            rows.append((j, v, e, e * math.hypot(su / u, sv / v)))
            v_known = float(flight_to_plate(u, g, kappa, beta)[1])
            sv = su * v_known / u
    return rows


def restitution_curve(law_fit, mass, speeds):
    """e(v) of a fitted law (no gravity) at ``speeds`` (m/s)."""
    return restitution(law_fit.contact(), mass, np.asarray(speeds, dtype=float))
