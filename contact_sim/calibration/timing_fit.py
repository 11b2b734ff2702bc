"""The robust least-squares fit of one law to recorded bounce sequences, on the impact times.

The unknowns are the damping λ (in ln λ), optionally the drag coefficient C_d (in ln C_d), and
per sequence the time t₁ and speed v₁ of its first recorded impact; the model is
``bounces.impact_sequence`` (closed-form drag flights, restitution fast path, contact duration,
first-order gravity during contact).  The residuals are predicted minus measured times in units of
the timing resolution, plus, for a sequence with a measured release height h (± ``height_error``),
(h(v₁) - h) / height_error.  ``scipy.optimize.least_squares`` minimises them with a robust loss
(soft-L1 by default) whose scale is three times the timing noise, itself estimated robustly
(1.4826 × median absolute residual of a first pass, never below the resolution / √12).
Confidence intervals come from the Jacobian of the weighted residuals at the optimum (covariance
s² (JᵀJ)⁻¹, Student t with N - P degrees of freedom), in ln λ and ln C_d; the Akaike criterion
is N ln(SSE / N) + 2P.
Units: SI.
"""
import math

import numpy as np
from scipy.optimize import least_squares

from contact_sim.calibration.bounces import impact_sequence, release_height, release_speed
from contact_sim.calibration.contact_tables import tabulated_restitution
from contact_sim.calibration.results import LawFit
from contact_sim.flight import AirDrag
from contact_sim.impact import damping_for_restitution, damping_from_group, robust_weights
from contact_sim.validation import InputError, require_positive

CD_BOUNDS = (1e-3, 10.0)     # a fitted drag coefficient stays inside (AirDrag's range)
HALF_WIDTH_MAX = 20.0        # a log-interval half width beyond this: the parameter is undetermined
SPAN_MAX = 100.0             # an interval wider than this factor (high / low): ill-determined
MAX_EVALUATIONS = 5000       # residual evaluations a solve may take (converging fits seen: <= 787)


def drag_coefficient_of(log_cd):
    """C_d from its fitted logarithm, clipped into ``CD_BOUNDS``: exp(log 10) is
    10.000000000000002, which ``AirDrag`` refuses.

    Parameters
    ----------
    log_cd : float
        ln C_d.

    Returns
    -------
    float
        C_d, ``CD_BOUNDS[0] <= C_d <= CD_BOUNDS[1]``.

    Examples
    --------
    >>> import math
    >>> from contact_sim.calibration.timing_fit import drag_coefficient_of
    >>> drag_coefficient_of(math.log(10.0))
    10.0
    """
    return min(max(math.exp(min(log_cd, 700.0)), CD_BOUNDS[0]), CD_BOUNDS[1])


def log_interval(name, value, half):
    """The interval value · exp(±half) of a parameter fitted in its logarithm, or why there
    is none.

    Parameters
    ----------
    name : str
        The parameter's name, for the reason.
    value : float
        The fitted value (> 0 to have an interval).
    half : float
        The half width in the logarithm (Student t times the standard error).

    Returns
    -------
    (tuple, str)
        ``(low, high)`` and ``''``; ``(low, high)`` and the reason when the interval spans
        more than a factor ``SPAN_MAX`` (ill-determined); or ``(nan, nan)`` and the reason
        when the interval is degenerate (zero width, a value at zero) or unbounded (the data
        do not determine it).
    """
    if not (math.isfinite(value) and value > 0.0):
        return (math.nan, math.nan), f'{name} collapsed to {value:g}: the data do not determine it'
    if not math.isfinite(half):
        return (math.nan, math.nan), f'{name} is undetermined: its standard error is not finite'
    if not half > 0.0:
        return (math.nan, math.nan), f'{name} has an interval of zero width: no degree of freedom'
    if not half < HALF_WIDTH_MAX:
        return (math.nan, math.nan), (f'{name} is undetermined: its interval spans more than a '
                                      f'factor exp({HALF_WIDTH_MAX:g})')
    low, high = value * math.exp(-half), value * math.exp(half)
    if 2.0 * half > math.log(SPAN_MAX):
        return (low, high), (f'{name} is ill-determined: its interval [{low:.3g}, {high:.3g}] '
                             f'spans a factor {math.exp(2.0 * half):.3g} (more than '
                             f'{SPAN_MAX:g})')
    return (low, high), ''


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
        cd = drag_coefficient_of(x[1]) if self.fit_drag else None
        t1 = x[self.offset:self.offset + self.n_seq]
        v1 = np.exp(np.minimum(x[self.offset + self.n_seq:], 700.0))
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
            # a backward step at the upper bound: the derivative from inside the range
            sign = -1.0 if x[1] + step > math.log(CD_BOUNDS[1]) else 1.0
            xs[1] += sign * step
            jac[:, 1] = (self.residuals(xs) - base) / (sign * step)
        return np.where(np.isfinite(jac), jac, 0.0)


def _damping_guess(law, stiffness, mass, e, speed):
    """λ giving restitution ``e`` at ``speed``: read off the master curve's nodes (a start
    value, no root finding); the exact inverse for a law without a master curve."""
    nodes = tabulated_restitution(law)
    if nodes is None:
        return damping_for_restitution(law, stiffness, mass, e, speed)
    s, e_nodes = nodes
    log_zeta = float(np.interp(-e, -e_nodes, s))
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
    lam0 = _damping_guess(law, k, m, float(np.median(es)), float(np.median(speeds)))
    x0 = [math.log(max(lam0, 1e-300))]
    if problem.fit_drag:
        x0.append(math.log(drag_coefficient))
    x0 = np.array(x0 + t1 + [math.log(v) for v in v1])
    # each sequence's start time: the median offset of the predicted from the measured clicks
    pred = problem.predicted(x0)[0]
    for j, (p, s) in enumerate(zip(pred, problem.seqs)):
        offset = np.median((s.times - p)[np.isfinite(p)]) if np.any(np.isfinite(p)) else 0.0
        x0[problem.offset + j] += offset
    return x0


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
                         gtol=1e-8, max_nfev=MAX_EVALUATIONS)


def fit_law(law, stiffness, mass, gravity, drag, fit_drag, sequences, resolution, height_error,
            loss, confidence):
    """Fit λ (and C_d with ``fit_drag``) of one law to the prepared sequences (module doc).

    Parameters
    ----------
    law : ContactLaw
    stiffness : float
        k in N/m^n.
    mass, gravity : float
        kg, m/s^2.
    drag : AirDrag or None
        The air drag in flight (its C_d the start value when ``fit_drag``); None: vacuum.
    fit_drag : bool
        Fit C_d too.
    sequences : list of PreparedSequence
    resolution, height_error : float
        The timing resolution (s) and the uncertainty of a measured release height (m).
    loss : str
        The ``least_squares`` loss.
    confidence : float
        The level of the intervals, 0 < confidence < 1.

    Returns
    -------
    LawFit

    Raises
    ------
    InputError
        If ``stiffness`` is not positive, or the start value of the fit is not finite (a
        stiffness and mass no damping fits).
    ValueError
        If there are no more observations (clicks and heights) than fitted parameters.
    """
    problem = _Problem(law, require_positive('stiffness', stiffness), mass, gravity, drag,
                       fit_drag, sequences, resolution, height_error)
    x0 = _initial_guess(problem, drag.drag_coefficient if drag is not None else None)
    n_obs = problem.n_times + len(problem.heights)
    if n_obs <= x0.size:
        raise ValueError(f'data holds {problem.n_times} click(s) and {len(problem.heights)} '
                         f'release height(s), {n_obs} observation(s) for {x0.size} fitted '
                         'parameters (lambda, C_d if fitted, and per sequence its start time '
                         'and first speed): allowed more observations than parameters (more '
                         'clicks, or the release heights)')
    if not np.all(np.isfinite(x0)):      # scipy: 'Initial guess is outside of provided bounds'
        raise InputError('stiffness', stiffness, 'no start value for the fit of %s: with '
                         '{n[stiffness]} = {value} and {n[mass]} = %r the restitution the '
                         'flights show (%.3g) has no finite damping: allowed a stiffness and '
                         'mass of this ball' % (law.name, mass, float(np.median(
                             [s.restitution_guess for s in problem.seqs]))))
    return _solved_fit(law, stiffness, problem, x0, loss, confidence)


def _solved_fit(law, k, problem, x0, loss, confidence):
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
    dof = n_obs - n_par      # > 0: fit_law refuses fewer observations
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
    failed, bound, weak = [], [], []   # why it failed; C_d at a bound; ill-determined

    def interval(name, value, variance):
        ci, why = log_interval(name, value, q * math.sqrt(max(variance, 0.0)))
        (failed if not (math.isfinite(value) and value > 0.0) else weak).append(why)
        return ci
    lam_ci = interval('lambda', lam, cov[0, 0])
    if problem.fit_drag:
        cd_ci = interval('C_d', cd, cov[1, 1])
        if not CD_BOUNDS[0] * (1.0 + 1e-6) < cd < CD_BOUNDS[1] * (1.0 - 1e-6):
            bound.append(f'C_d = {cd:.6g} is at a bound of its range [{CD_BOUNDS[0]:g}, '
                          f'{CD_BOUNDS[1]:g}]: this law needs an implausible drag')
    else:
        cd = problem.drag.drag_coefficient if problem.drag is not None else 0.0
        cd_ci = (math.nan, math.nan)
    if problem.n_times <= n_par:
        weak.append(f'{problem.n_times} clicks for {n_par} fitted parameters: the fit and its '
                    'rank rest on the release heights, not on the timing')
    if not result.success:
        failed.insert(0, f'the solver did not converge in {result.nfev} evaluations '
                         f'({result.message})')
    failed, bound, weak = ([p for p in kind if p] for kind in (failed, bound, weak))
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
    status = ('FAILED' if failed else 'at-bound' if bound else 'ill-determined' if weak
              else 'converged')
    problems = failed + bound + weak
    return LawFit(law, k, lam, lam_ci, cd, cd_ci, np.asarray(t1), v1, np.asarray(heights),
                  residuals, weights_seq, rms, aic, n_par, n_obs, noise, not problems,
                  '; '.join(problems) or str(result.message), status)
