"""Argument checks shared by every constructor: each error names the field, the value and the range."""
import math


def _describe(value):
    return repr(value) if isinstance(value, str) else f'{value!r}'


def require_real(name, value):
    """Return ``value`` as a finite float, or raise ``ValueError`` naming ``name``."""
    if isinstance(value, bool):
        raise ValueError(f'{name} = {value!r} is not a number; it must be a finite real number')
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(
            f'{name} = {_describe(value)} is not a number; it must be a finite real number'
        ) from None
    if not math.isfinite(x):
        raise ValueError(f'{name} = {x!r} is not finite; it must be a finite real number')
    return x


def require_range(name, value, low=-math.inf, high=math.inf, *, low_open=False, high_open=False,
                  allow_inf=False):
    """Return ``value`` as a float inside the interval, else raise ``ValueError``.

    The message states the field, the value and the allowed range, e.g.
    ``poisson_ratio = 0.6 is out of range: allowed -1 < poisson_ratio < 0.5``.
    """
    if allow_inf and isinstance(value, (int, float)) and not isinstance(value, bool) \
            and value == math.inf:
        x = math.inf
    else:
        x = require_real(name, value)
    left = f'{low:g} {"<" if low_open else "<="} ' if low > -math.inf else ''
    right = f' {"<" if high_open else "<="} {high:g}' if high < math.inf else ''
    too_low = x < low or (low_open and x == low)
    too_high = x > high or (high_open and x == high)
    if too_low or too_high:
        raise ValueError(f'{name} = {x!r} is out of range: allowed {left}{name}{right}')
    return x


def require_positive(name, value, *, allow_inf=False):
    return require_range(name, value, 0.0, low_open=True, allow_inf=allow_inf)


def require_nonnegative(name, value):
    return require_range(name, value, 0.0)
