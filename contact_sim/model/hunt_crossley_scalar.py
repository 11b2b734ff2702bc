"""The exact restitution of the Hunt-Crossley law for one ζ, in plain float arithmetic: called
as it is for one impact, and compiled by ``closed_form_kernels`` for arrays."""
import math

# 1/23, 1/21, ..., 1/3: the series of (atanh y - y) / y³ to |y| = 1/7 (|x| = 1/4) within 1e-17
_ATANH_TAIL = tuple(1.0 / k for k in range(23, 2, -2))
# a guess of e with a relative error below this is finished by one Newton step (quadratic: the
# next step would be below 1e-16 of the iterate, under round-off)
ONE_STEP_GUESS_RTOL = 1e-8


def hunt_crossley_restitution_scalar(zeta, guess=0.0):
    """``hunt_crossley_restitution`` for one float in plain Python (a few µs).

    Newton's method on a convex function from the side where it converges monotonically:
    in s = 1 - u from s = √(2c) when c < 1, in u from u = exp(-1 - c) otherwise, until a step
    is below 1e-14 of the iterate (quadratic convergence: the next would be far below
    round-off; a bound of 1e-16 was never met where the steps dither by an ulp, which then ran
    all 60 iterations).  Below ζ = 1e-6 the series 1 - 2ζ/3 + 4ζ²/9 (error O(ζ³) < 1e-18).

    ``guess`` > 0 is an estimate of e within ``ONE_STEP_GUESS_RTOL`` (the compiled kernel's
    table, ``closed_form_kernels``): the iteration starts from it (s = ζ e, or u = exp(-c - ζ e)
    from u = exp(u - 1 - c), which turns an absolute error of u into a relative one) and takes
    one step.
    """
    if zeta < 1e-6:
        return 1.0 - zeta * (2.0 / 3.0 - zeta * 4.0 / 9.0)
    # c = g(ζ), g(x) = x - ln(1 + x); where |x| < 1/4 by g = x y - 2 y³ (1/3 + y²/5 + ...),
    # y = x / (2 + x) (ln(1 + x) = 2 atanh y), which does not cancel as x - log1p(x) does
    # (3e-13 relative near ζ = 1e-3); the same below for g(-s)
    if zeta < 0.25:
        y = zeta / (2.0 + zeta)
        y2 = y * y
        tail = 0.0
        for a in _ATANH_TAIL:
            tail = tail * y2 + a
        c = zeta * y - 2.0 * y * y2 * tail
    else:
        c = zeta - math.log1p(zeta)
    steps = 1 if guess > 0.0 else 60
    if c < 1.0:
        s = zeta * guess if guess > 0.0 else min(math.sqrt(2.0 * c), 0.95)
        for _ in range(steps):
            if s < 0.25:                   # g(-s), as c above
                y = s / (2.0 - s)
                y2 = y * y
                tail = 0.0
                for a in _ATANH_TAIL:
                    tail = tail * y2 + a
                f = s * y + 2.0 * y * y2 * tail - c
            else:
                f = -s - math.log1p(-s) - c
            step = f * (1.0 - s) / s
            s -= step
            if abs(step) <= 1e-14 * s:
                break
        return s / zeta
    u = math.exp(-c - zeta * guess) if guess > 0.0 else math.exp(-1.0 - c)
    if u == 0.0:                      # u underflows: e = (1 - u) / ζ = 1 / ζ to the last bit
        return 1.0 / zeta
    for _ in range(steps):
        step = (u - math.log(u) - 1.0 - c) / (1.0 - 1.0 / u)
        u -= step
        if abs(step) <= 1e-14 * u:
            break
    return (1.0 - u) / zeta
