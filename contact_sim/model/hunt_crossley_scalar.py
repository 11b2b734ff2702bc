"""The exact restitution of the Hunt-Crossley law for one ζ, in plain float arithmetic: called
as it is for one impact, and compiled by ``closed_form_kernels`` for arrays."""
import math


def hunt_crossley_restitution_scalar(zeta):
    """``hunt_crossley_restitution`` for one float in plain Python (a few µs).

    Newton's method on a convex function from the side where it converges monotonically:
    in s = 1 - u from s = √(2c) when c < 1, in u from u = exp(-1 - c) otherwise, until a step
    is below 1e-14 of the iterate (quadratic convergence: the next would be far below
    round-off; a bound of 1e-16 was never met where the steps dither by an ulp, which then ran
    all 60 iterations).  Below ζ = 1e-6 the series 1 - 2ζ/3 + 4ζ²/9 (error O(ζ³) < 1e-18).
    """
    if zeta < 1e-6:
        return 1.0 - zeta * (2.0 / 3.0 - zeta * 4.0 / 9.0)
    c = (zeta * zeta * (0.5 - zeta * (1 / 3 - zeta * (0.25 - zeta * (0.2 - zeta / 6)))))
    if zeta >= 1e-3:
        c = zeta - math.log1p(zeta)
    if c < 1.0:
        s = min(math.sqrt(2.0 * c), 0.95)
        for _ in range(60):
            f = (s * s * (0.5 + s * (1 / 3 + s * (0.25 + s * (0.2 + s / 6)))) if s < 1e-3
                 else -s - math.log1p(-s)) - c
            step = f * (1.0 - s) / s
            s -= step
            if abs(step) <= 1e-14 * s:
                break
        return s / zeta
    u = math.exp(-1.0 - c)
    if u == 0.0:                      # u underflows: e = (1 - u) / ζ = 1 / ζ to the last bit
        return 1.0 / zeta
    for _ in range(60):
        step = (u - math.log(u) - 1.0 - c) / (1.0 - 1.0 / u)
        u -= step
        if abs(step) <= 1e-14 * u:
            break
    return (1.0 - u) / zeta
