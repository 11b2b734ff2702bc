"""Argument checks shared by every constructor: each error names the field, the value and the range.

Every refusal is an ``InputError`` (a ``ValueError``) that carries the canonical key of the field
it is about (the core argument name: ``mass``, ``height``, ``stiffness``, ...), the value, and a
message template in which every field name is a placeholder ``{n[key]}``.  ``str(error)`` spells
the fields with their core names; a front end renders the same message in its own words with
``error.render(names)``, e.g. ``{'mass': '--mass'}`` in the command line or
``{'mass': 'sphere_mass'}`` in the ROS node, so its users read the names they typed.
"""
import math
import numbers


class _Names(dict):
    """Field key -> the front end's name for it (the key itself when not mapped)."""

    def __missing__(self, key):
        return key


class InputError(ValueError):
    """A refused input: ``field`` (canonical key), ``value`` and a message naming the range.

    ``template`` is a ``str.format`` template; ``{n[key]}`` stands for the name of field ``key``
    and every other ``{name}`` is filled from ``params`` (``{value}``: the value's repr unless
    given).  A ``ValueError``, so ``except ValueError`` catches it too.

    Parameters
    ----------
    field : str
        The canonical key of the field refused (the core argument name, e.g. ``'mass'``).
    value : object
        The value refused.
    template : str
        The message, with ``{n[key]}`` for each field named and ``{value}`` for the value.
    **params
        The template's other fields; ``value`` defaults to the value's repr.

    Attributes
    ----------
    field : str
        The canonical key of the field refused.
    value : object
        The value refused.
    template : str
        The message template.
    params : dict
        The template's fields.

    Examples
    --------
    >>> import contact_sim as cs
    >>> error = cs.InputError('mass', -1.0, '{n[mass]} = {value} is out of range: '
    ...                       'allowed 0 < {n[mass]}')
    >>> print(error)
    mass = -1.0 is out of range: allowed 0 < mass
    >>> print(error.render({'mass': '--mass'}))
    --mass = -1.0 is out of range: allowed 0 < --mass
    >>> try:
    ...     cs.Material('x', 1e9, 0.6, 1000.0)
    ... except cs.InputError as refused:
    ...     print(refused.field, refused.value)
    poisson_ratio 0.6
    """

    def __init__(self, field, value, template, /, **params):
        self.field = field
        self.value = value
        self.template = template
        params.setdefault('value', _describe(value))
        self.params = params
        super().__init__(self.render())

    def render(self, names=None):
        """The message with each field spelled as a front end names it.

        Parameters
        ----------
        names : dict, optional
            Field key -> the front end's name for it (e.g. ``{'mass': '--mass'}``); unmapped
            keys are spelled as is.

        Returns
        -------
        str
            The message.

        Examples
        --------
        >>> import contact_sim as cs
        >>> try:
        ...     cs.Material('x', 1e9, 0.6, 1000.0)
        ... except cs.InputError as error:
        ...     print(error.render({'poisson_ratio': 'sphere_poisson_ratio'}))
        sphere_poisson_ratio = 0.6 is out of range: allowed -1 < sphere_poisson_ratio < 0.5
        """
        return self.template.format(n=_Names(names or {}), **self.params)

    def rekeyed(self, field):
        """The same refusal about another field (``material`` -> ``sphere``, say).

        Parameters
        ----------
        field : str
            The new canonical key.

        Returns
        -------
        InputError
            A new error whose ``field`` and template name ``field``.

        Examples
        --------
        >>> import contact_sim as cs
        >>> try:
        ...     cs.get_material('wood')
        ... except cs.InputError as error:
        ...     print(error.rekeyed('sphere').field)
        sphere
        """
        old = '{n[%s]}' % self.field
        return InputError(field, self.value, self.template.replace(old, '{n[%s]}' % field),
                          **self.params)

    def __reduce__(self):   # keep pickling (multiprocessing) working for a custom __init__
        return (_rebuild, (self.field, self.value, self.template, self.params))


def _rebuild(field, value, template, params):
    return InputError(field, value, template, **params)


def _plain(value):
    """A numpy scalar as the Python number it holds (so no message shows ``np.float64(...)``)."""
    item = getattr(value, 'item', None)
    if item is not None and getattr(value, 'shape', None) == ():
        try:
            return item()
        except (TypeError, ValueError):
            return value
    return value


def _describe(value):
    value = _plain(value)
    if isinstance(value, (str, bool, int, float, complex)) or value is None:
        return repr(value)
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + '...'


def _fmt(x):
    return f'{x:g}'


TEXT = (str, bytes, bytearray, memoryview)   # float() reads these; a number argument does not


def require_real(name, value):
    """Return ``value`` as a finite float, or raise ``InputError`` naming ``name``.

    Refused: booleans, text (``str``, ``bytes``: ``'9.81'``, ``b'1'``, ``'\u0669'`` are not
    numbers here, whatever ``float()`` makes of them), complex numbers, masked or non-numeric
    arrays, and non-finite values."""
    if isinstance(value, TEXT):
        raise InputError(name, value, '{n[%s]} = {value} is not a number (it is text); it must '
                         'be a finite real number' % name, value=_describe(value))
    if isinstance(value, bool):
        raise InputError(name, value, '{n[%s]} = {value} is not a number; it must be a finite '
                         'real number' % name, value=repr(value))
    if isinstance(value, complex) or getattr(getattr(value, 'dtype', None), 'kind', 'f') \
            not in 'iuf' or getattr(value, 'mask', None) is not None:
        raise InputError(name, value, '{n[%s]} = {value} is not a real number; it must be a '
                         'finite real number' % name, value=_describe(value))
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(name, value, '{n[%s]} = {value} is not a number; it must be a finite '
                         'real number' % name, value=_describe(value)) from None
    if not math.isfinite(x):
        raise InputError(name, x, '{n[%s]} = {value} is not finite; it must be a finite real '
                         'number' % name, value=repr(x))
    return x


def number_from_text(name, text):
    """A number written as ``text`` (a cell of a data file) as a float, else ``InputError``
    naming ``name``: the one place that reads text as a number (``require_real`` refuses
    text).  Non-finite spellings (``nan``, ``inf``) are returned for the range check to refuse."""
    try:
        return float(text)
    except (TypeError, ValueError):
        raise InputError(name, text, '{n[%s]} = {value} is not a number; it must be a finite '
                         'real number' % name, value=_describe(text)) from None


MAX_VALUES = 10_000_000   # values of one array argument (80 MB of doubles)


def require_real_array(name, values, max_size=MAX_VALUES, finite=True):
    """``values`` (a number or an array-like of them) as a float ndarray of finite reals.

    Refused, as an ``InputError`` on ``name``: strings, ``None``, booleans, complex numbers
    (their imaginary part would be lost), dates and times (``datetime64``, ``timedelta64``),
    masked arrays (their mask would be ignored), ragged or object arrays, non-finite values and
    more than ``max_size`` values; non-finite values unless ``finite`` is false (the caller
    then states its range).
    """
    import numpy as np   # here, so that parsing a command line does not import numpy
    if values is None or isinstance(values, (*TEXT, bool, complex)) \
            or getattr(values, 'mask', None) is not None:
        what = 'a masked array' if getattr(values, 'mask', None) is not None else None
        raise InputError(name, values, '{n[%s]} = {value} is not a real number or an array of '
                         'them: allowed finite real numbers' % name,
                         value=what or _describe(values))
    try:
        size = np.size(values)
    except Exception:   # noqa: BLE001  (ragged input: numpy's own error)
        size = None
    if size is not None and size > max_size:
        raise InputError(name, size, '{n[%s]} has {value} values: allowed at most %d'
                         % (name, max_size), value=str(size))
    try:
        raw = np.asarray(values)
    except Exception:   # noqa: BLE001
        raw = None
    if raw is not None and isinstance(values, (list, tuple)) \
            and any(isinstance(v, (bool, *TEXT)) for v in values):
        raw = np.asarray([True])   # a boolean (or text) among numbers: not a number
    if raw is None or raw.dtype.kind not in 'iuf':
        kind = {'c': 'complex numbers', 'M': 'dates', 'm': 'time differences',
                'b': 'booleans', 'U': 'text', 'S': 'text'}.get(
                    getattr(getattr(raw, 'dtype', None), 'kind', 'O'), 'values that are not numbers')
        raise InputError(name, None, '{n[%s]} holds %s: allowed finite real numbers (a number '
                         'or an array of them)' % (name, kind))
    x = raw.astype(float)
    if finite and not np.all(np.isfinite(x)):
        bad = float(x[~np.isfinite(x)].flat[0])
        where = '' if x.ndim == 0 else '[%d]' % int(np.flatnonzero(~np.isfinite(x.ravel()))[0])
        raise InputError(name, bad, '{n[%s]}%s = {value} is not finite: allowed finite real '
                         'numbers' % (name, where), value=repr(bad))
    return x


def range_text(name, low=-math.inf, high=math.inf, *, low_open=False, high_open=False):
    """The allowed range as a template, e.g. ``0 < {n[mass]} <= 1e+09``."""
    left = f'{_fmt(low)} {"<" if low_open else "<="} ' if low > -math.inf else ''
    right = f' {"<" if high_open else "<="} {_fmt(high)}' if high < math.inf else ''
    return f'{left}{{n[{name}]}}{right}'


def require_range(name, value, low=-math.inf, high=math.inf, *, low_open=False, high_open=False,
                  allow_inf=False, unit=''):
    """Return ``value`` as a float inside the interval, else raise ``InputError``.

    The message states the field, the value and the allowed range, e.g.
    ``poisson_ratio = 0.6 is out of range: allowed -1 < poisson_ratio < 0.5``.
    """
    if type(value) is float and math.isfinite(value) \
            and (low < value if low_open else low <= value) \
            and (value < high if high_open else value <= high):
        return value    # a plain finite float in range: what the checks below return for it
    if allow_inf and isinstance(value, (int, float)) and not isinstance(value, bool) \
            and value == math.inf:
        x = math.inf
    else:
        x = require_real(name, value)
    too_low = x < low or (low_open and x == low)
    too_high = x > high or (high_open and x == high)
    if too_low or too_high:
        allowed = range_text(name, low, high, low_open=low_open, high_open=high_open)
        raise InputError(name, x, '{n[%s]} = {value} is out of range: allowed %s%s'
                         % (name, allowed, f' ({unit})' if unit else ''), value=repr(x))
    return x


def require_positive(name, value, *, allow_inf=False):
    return require_range(name, value, 0.0, low_open=True, allow_inf=allow_inf)


def require_nonnegative(name, value):
    return require_range(name, value, 0.0)


def require_int(name, value, low, high):
    """Return ``value`` as an int with low <= value <= high, else raise ``InputError``."""
    if isinstance(value, bool) or not isinstance(value, (numbers.Integral, float)) \
            or isinstance(value, float) and not value.is_integer():
        raise InputError(name, value, '{n[%s]} = {value} is not an integer: allowed %s'
                         % (name, range_text(name, low, high)), value=_describe(value))
    x = int(value)
    if not low <= x <= high:
        raise InputError(name, x, '{n[%s]} = {value} is out of range: allowed %s'
                         % (name, range_text(name, low, high)), value=repr(x))
    return x


def require_instance(name, value, kind, what):
    """Return ``value`` if it is a ``kind``, else raise ``InputError`` saying ``what`` it must be."""
    if not isinstance(value, kind):
        raise InputError(name, value, '{n[%s]} = {value} is not %s' % (name, what),
                         value=_describe(value))
    return value


# The (reduced) mass of every path (impacts, drops, fits, the node): outside it the doubles of
# the model overflow (a 1e308 kg sphere gives a contact of 5e119 s).
MASS_RANGE = (1e-12, 1e9)   # kg


GRAVITY_MAX = 1e6   # m/s²
HEIGHT_MAX = 1e6    # m: a release height


def require_gravity(value, name='gravity'):
    """Gravity g in m/s², 0 <= g <= ``GRAVITY_MAX``: the one rule of every path (impacts, drops,
    fits, the command line, the node)."""
    return require_range(name, value, 0.0, GRAVITY_MAX, unit='m/s^2')


def require_mass(value, name='mass'):
    """A (reduced) mass in kg within ``MASS_RANGE``."""
    return require_range(name, value, *MASS_RANGE, unit='kg')


# Tolerances of the exact integrators: looser than 1e-3 gives wrong results without warning
# (rtol = 1 makes e = 0.8665 where it is 0.7246), tighter than 1e-14 cannot be met in doubles.
RTOL_RANGE = (1e-14, 1e-3)


def require_rtol(name, value):
    """A relative tolerance for the exact integrators, within ``RTOL_RANGE``."""
    return require_range(name, value, *RTOL_RANGE)
