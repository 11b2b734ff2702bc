"""Contact normal-force laws of the family F = k z^n + λ z^p ż^q (Azad & Featherstone 2014,
eq. 1), and the registry of what each law can do.

Units are SI throughout: penetration z in m, penetration rate ż in m/s (z > 0 is penetration,
ż > 0 is approach), stiffness k in N/m^n, damping λ in N·s^q/m^(p+q), force in N.

A ``ContactLaw`` carries its abilities, and this module is the one place that compares its
exponents or its name to decide them: ``hertz``, ``linear_in_rate``, ``damps_at_touch``,
``constant_restitution`` (read from the exponents), and what is registered for the law
itself: ``kernel`` (the compiled kernel's short form), ``closed_form`` (its exact dimensionless
results, ``closed_forms``), ``master_curve`` (its shipped table, ``master_curves``) and
``bounce_table`` (its shipped bounce-model table, ``data/bounce_tables.npz``).  Every other
layer asks the law; the core takes ``ContactLaw`` objects, never names (``get_law`` and
``LAWS`` are for the front ends, and ``build_contact`` takes a name for them).

Why the closed forms and the tables are model-level facts: they are pure functions of
the law and the damping group ζ (the closed forms need numpy and scipy's special functions
and quadrature, the tables numpy and the shipped ``.npz`` files), with no time stepping and
nothing of the impact layer in them.  Kept here, the law can answer for them without an upward
import (model never imports impact) and without a cycle (``closed_forms`` and
``master_curves`` import nothing of the package); the impact layer derives ζ, the tails and the
dimensional results from what the law answers, and the calibration layer its bounce model.

How a law is recognised: by the law object itself, its name and exponents together (the
dataclass's equality).  The closed forms, the compiled kernels and the shipped tables are all
registered per law: a shipped table is found by the law's name and checked against its
exponents, a kernel is listed for the named law.  So a custom law whose exponents equal a named
law's gets none of them: it is integrated by the general power-law kernel (``impact`` warns once
that it integrates), and its bounce table is tabulated once per process.
"""
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

import math

import numpy as np

from contact_sim.model.closed_forms import HUNT_CROSSLEY_FORM, LINEAR_FORM, ClosedForm
from contact_sim.model.master_curves import curve_for
from contact_sim.validation import InputError, require_positive, require_range


@dataclass(frozen=True)
class ContactLaw:
    """One member of the family F = k z^n + λ z^p ż|ż|^(q-1), clamped as in equation 11.

    ``force`` is zero where z <= 0 and ``max(0, k z^n + λ z^p ż|ż|^(q-1))`` elsewhere: the
    contact can push but never pull.  The named laws are ``AZAD_FEATHERSTONE``,
    ``HUNT_CROSSLEY``, ``LEE_WANG`` and ``LINEAR`` (``LAWS``).

    Attributes
    ----------
    name : str
        A non-empty name.
    n : float
        Stiffness exponent, > 0 (1.5 for the Hertz laws).
    p : float
        Penetration exponent of the damping term, 0 <= p <= n.
    q : float
        Rate exponent of the damping term, > 0.

    Raises
    ------
    InputError
        Keyed ``n``, ``p`` or ``q``: an exponent out of its range.
    ValueError
        An empty or non-string ``name``.

    Examples
    --------
    >>> import contact_sim as cs
    >>> law = cs.AZAD_FEATHERSTONE
    >>> law.n, law.p, law.q, law.hertz
    (1.5, 0.5, 1.0, True)
    >>> cs.ContactLaw('custom', 1.5, 2.0, 1.0)
    Traceback (most recent call last):
        ...
    contact_sim.validation.InputError: p = 2.0 is out of range: allowed 0 <= p <= 1.5
    """

    name: str
    n: float
    p: float
    q: float

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f'name = {self.name!r} is invalid: allowed a non-empty string')
        object.__setattr__(self, 'n', require_positive('n', self.n))
        # p <= n keeps the force divided by z^p finite at touch (it is the lift-off test)
        object.__setattr__(self, 'p', require_range('p', self.p, 0.0, self.n))
        object.__setattr__(self, 'q', require_positive('q', self.q))

    # -- what the law can do: the one place where its exponents are read -------------------
    @property
    def hertz(self):
        """True if the Hertz stiffness k = (4/3) E* √R (equations 5, 6, 10) applies: n = 3/2."""
        return self.n == 1.5

    @property
    def linear_in_rate(self):
        """True if the damping is linear in the rate (q = 1).

        Small motions about rest are then a linear damped oscillator, so the rest closed form
        and the creep proof apply.
        """
        return self.q == 1.0

    @property
    def damps_at_touch(self):
        """True if the damping term acts at z = 0 (p = 0).

        At the first touch with approach the force is then λ ż^q > 0 at once.
        """
        return self.p == 0.0

    @property
    def force_vanishes_inside(self):
        """True if the force can fall to zero while z > 0 (n > p).

        F = zᵖ φ with φ = k z^(n-p) + λ ż|ż|^(q-1).  With n = p (Hunt-Crossley) φ obeys
        φ̇ = λ q abs(ż)^(q-1) (a - zⁿ φ / m), a the other forces per unit mass, so under gravity and
        drag (a >= 0 on the way out) φ only decays towards zero and the sphere leaves at z = 0:
        a force-zero root inside is round-off (``phase`` then tests the surface alone).
        """
        return self.n > self.p

    @property
    def constant_restitution(self):
        """True if the restitution does not depend on the impact speed.

        That is the linear spring-damper, n = q = 1, p = 0: its damping group ζ has no speed
        in it.
        """
        return self.n == 1.0 and self.p == 0.0 and self.q == 1.0

    @property
    def kernel(self):
        """The compiled contact phase's short form of this law (``phase.compiled``), an int.

        1 Azad-Featherstone, 2 Hunt-Crossley, 3 Lee-Wang, 4 linear (right-hand sides without
        pow()), 0 the general power law: registered per named law, so a custom law gets 0 even
        where its exponents equal a named law's.
        """
        return _KERNELS.get(self, 0)

    @property
    def closed_form(self):
        """The law's ``ClosedForm`` (exact e, τc as functions of ζ), or ``None``.

        Registered per law (``register_closed_form``), never found by exponents.
        """
        return CLOSED_FORMS.get(self)

    @property
    def master_curve(self):
        """The law's shipped ``MasterCurve`` (e, τc, F̂, x̂ against ζ), or ``None``.

        A table belongs to a named law, its name and exponents (loaded on first use).
        """
        return curve_for(self.name, (self.n, self.p, self.q))

    @property
    def bounce_table(self):
        """The law's shipped ``BounceTable`` (lift-off depth and gravity coefficients against
        ln ζ, for ``calibration.bounces``), or ``None``.

        Found by the law's name in ``data/bounce_tables.npz`` and checked against its exponents
        (loaded on first use), so a custom law has none and ``calibration`` tabulates it.
        """
        return _shipped_bounce_tables().get((self.name, (self.n, self.p, self.q)))

    def reduced_force(self, z, zdot, k, damping):
        """The reduced force φ = k z^(n-p) + λ ż|ż|^(q-1): the unclamped force is z^p φ (z > 0).

        φ is smooth where the force is not (at z = 0), which makes it the right lift-off test.

        Parameters
        ----------
        z : float or array_like of float
            Penetration, m (negative values count as 0).
        zdot : float or array_like of float
            Penetration rate, m/s (> 0 is approach).
        k : float
            Stiffness, N/m^n.
        damping : float
            Damping λ, N·s^q/m^(p+q).

        Returns
        -------
        numpy.ndarray
            Reduced force φ, N/m^p, of the broadcast shape of ``z`` and ``zdot``.

        Examples
        --------
        >>> import contact_sim as cs
        >>> phi = cs.AZAD_FEATHERSTONE.reduced_force(1e-6, 0.5, 1.095e10, 1e5)
        >>> print(f"{float(phi):.1f}")
        60950.0
        """
        z = np.asarray(z, dtype=float)
        zdot = np.asarray(zdot, dtype=float)
        zp = np.maximum(z, 0.0)
        return k * zp ** (self.n - self.p) + damping * np.sign(zdot) * np.abs(zdot) ** self.q

    def force_at(self, z, zdot, k, damping):
        """``force`` at one state (floats in, a float out), equation 11.

        The same numbers as ``force`` without the array overhead, for the engine's once-a-tick
        state.

        Parameters
        ----------
        z : float
            Penetration, m.
        zdot : float
            Penetration rate, m/s (> 0 is approach).
        k : float
            Stiffness, N/m^n.
        damping : float
            Damping λ, N·s^q/m^(p+q).

        Returns
        -------
        float
            The clamped force in N, >= 0 (NaN for NaN input).

        Examples
        --------
        >>> import contact_sim as cs
        >>> print(f"{cs.AZAD_FEATHERSTONE.force_at(1e-6, 0.5, 1.095e10, 1e5):.3f}")
        60.950
        >>> cs.AZAD_FEATHERSTONE.force_at(-1e-6, 0.5, 1.095e10, 1e5)   # no contact
        0.0
        """
        if not z > 0.0:
            return 0.0
        rate = math.copysign(abs(zdot) ** self.q, zdot) if zdot != 0.0 else 0.0
        unclamped = k * z ** self.n + damping * z ** self.p * rate
        return 0.0 if unclamped < 0.0 else unclamped     # NaN stays NaN, as np.maximum

    def force(self, z, zdot, k, damping):
        """Clamped normal force (equation 11) for arrays of z and ż of any broadcastable shape.

        The same operations as ``force_at``, element by element, so both agree to round-off,
        bit for bit where numpy's pow is the C library's (``np.power`` with an array exponent
        calls it, as Python's ``**`` does, except for numpy's AVX-512 code on CPUs that have it;
        numpy's scalar-exponent fast paths, x**0.5 -> sqrt, round differently).

        Parameters
        ----------
        z : float or array_like of float
            Penetration, m (z <= 0: no contact, force 0).
        zdot : float or array_like of float
            Penetration rate, m/s (> 0 is approach).
        k : float
            Stiffness, N/m^n.
        damping : float
            Damping λ, N·s^q/m^(p+q).

        Returns
        -------
        numpy.ndarray
            The force in N, >= 0, of the broadcast shape of ``z`` and ``zdot``.

        See Also
        --------
        Contact.force : The same with the contact's own k and λ.

        Examples
        --------
        >>> import contact_sim as cs
        >>> f = cs.AZAD_FEATHERSTONE.force([0.0, 1e-6, 2e-6], [0.5, 0.5, -0.1], 1.095e10, 1e5)
        >>> print(*(f"{x:.3f}" for x in f))
        0.000 60.950 16.829
        """
        z, zdot = np.broadcast_arrays(np.asarray(z, dtype=float), np.asarray(zdot, dtype=float))
        inside = z > 0.0
        zz = np.where(inside, z, 1.0)
        speed = np.abs(zdot)
        rate = np.where(zdot != 0.0,
                        np.copysign(np.power(speed, np.full_like(speed, self.q)), zdot), 0.0)
        unclamped = k * np.power(zz, np.full_like(zz, self.n)) + damping * np.power(
            zz, np.full_like(zz, self.p)) * rate
        return np.where(inside, np.where(unclamped < 0.0, 0.0, unclamped), 0.0)


#: The Azad-Featherstone law F = k z^1.5 + λ z^0.5 ż (eq. 8): n = 1.5, p = 0.5, q = 1.
AZAD_FEATHERSTONE = ContactLaw('azad_featherstone', 1.5, 0.5, 1.0)  # eq. 8
#: The Hunt-Crossley law F = k z^1.5 + λ z^1.5 ż (eq. 2): n = p = 1.5, q = 1.
HUNT_CROSSLEY = ContactLaw('hunt_crossley', 1.5, 1.5, 1.0)  # eq. 2
#: The Lee-Wang law F = k z^1.5 + λ z ż: n = 1.5, p = 1, q = 1.
LEE_WANG = ContactLaw('lee_wang', 1.5, 1.0, 1.0)
#: The linear spring-damper F = k z + λ ż: n = q = 1, p = 0 (k in N/m, λ in N·s/m).
LINEAR = ContactLaw('linear', 1.0, 0.0, 1.0)  # spring-damper: n = q = 1, p = 0

#: The named laws, name -> ``ContactLaw``: azad_featherstone, hunt_crossley, lee_wang, linear.
LAWS = {law.name: law for law in (AZAD_FEATHERSTONE, HUNT_CROSSLEY, LEE_WANG, LINEAR)}

CLOSED_FORMS = {HUNT_CROSSLEY: HUNT_CROSSLEY_FORM, LINEAR: LINEAR_FORM}   # ContactLaw -> ClosedForm

# ContactLaw -> the compiled kernel's short form (``ContactLaw.kernel``; ``phase.compiled``)
_KERNELS = {AZAD_FEATHERSTONE: 1, HUNT_CROSSLEY: 2, LEE_WANG: 3, LINEAR: 4}

BOUNCE_TABLE_FILE = 'bounce_tables.npz'   # in contact_sim/data: scripts/build_bounce_tables.py


@dataclass(frozen=True, eq=False)
class BounceTable:
    """A law's bounce-model table (``calibration.contact_tables``) on a grid uniform in ln ζ.

    Attributes
    ----------
    log_zeta : numpy.ndarray
        The grid, ln ζ (dimensionless).
    x_lift : numpy.ndarray
        The lift-off depth z_lift / Z of the unit impact (dimensionless).
    a, b : numpy.ndarray
        The first-order gravity coefficients of its crossing speed and time (dimensionless).
    """

    log_zeta: np.ndarray
    x_lift: np.ndarray
    a: np.ndarray
    b: np.ndarray


@lru_cache(maxsize=1)
def _shipped_bounce_tables():
    """(name, (n, p, q)) -> ``BounceTable`` from the shipped file ({} if it is not there)."""
    path = resources.files('contact_sim') / 'data' / BOUNCE_TABLE_FILE
    tables = {}
    try:
        with resources.as_file(path) as real_path, np.load(real_path) as data:
            for name in data['laws']:
                name = str(name)
                key = tuple(float(v) for v in data[f'{name}/key'])
                tables[name, key] = BounceTable(*(data[f'{name}/{field}'] for field in
                                                  ('log_zeta', 'x_lift', 'a', 'b')))
    except FileNotFoundError:
        pass
    return tables


def register_closed_form(law, vector, scalar=None, table_duration=None):
    """Give ``law`` exact dimensionless results: keyed by the law itself (its name and
    exponents), not by its exponents, so ``law.closed_form`` answers them from now on.

    Parameters
    ----------
    law : ContactLaw
        The law.
    vector : mapping
        Quantity ('restitution', 'duration', 'peak_force', 'max_penetration') -> function of
        an array of damping groups ζ > 0 (dimensionless) giving e, τc (units of T), F̂ or x̂.
    scalar : callable, optional
        e(ζ) for one float ζ > 0, in plain Python.
    table_duration : tuple, optional
        (ζ0, τc): the exact duration τc(ζ) for one float ζ >= ζ0, used to build a master curve.
    """
    CLOSED_FORMS[law] = ClosedForm(dict(vector), scalar, table_duration)


def get_law(name):
    """The named law (a ``ContactLaw`` is returned as is): how a front end resolves a name.

    The core takes ``ContactLaw`` objects and refuses names (``require_law``); the command line,
    the node's parameters and ``build_contact`` resolve them here.

    Parameters
    ----------
    name : str or ContactLaw
        A key of ``LAWS``, or a ``ContactLaw``.

    Returns
    -------
    ContactLaw
        The law.

    Raises
    ------
    InputError
        Keyed ``law`` (a ``ValueError``): an unknown name; the message lists the known ones.

    Examples
    --------
    >>> import contact_sim as cs
    >>> cs.get_law('hunt_crossley') is cs.HUNT_CROSSLEY
    True
    >>> cs.get_law('kelvin_voigt')
    Traceback (most recent call last):
        ...
    contact_sim.validation.InputError: law = 'kelvin_voigt' is unknown: allowed one of azad_featherstone, hunt_crossley, lee_wang, linear
    """
    if isinstance(name, ContactLaw):
        return name
    try:
        return LAWS[name]
    except (KeyError, TypeError):
        raise InputError('law', name, '{n[law]} = {value} is unknown: allowed one of %s'
                         % ', '.join(sorted(LAWS)), value=repr(name)) from None


def require_law(law, name='law'):
    """Check that ``law`` is a ``ContactLaw``: the core takes law objects, never names.

    Parameters
    ----------
    law : object
        The value to check.
    name : str, optional
        The field the error names (default ``'law'``).

    Returns
    -------
    ContactLaw
        ``law`` itself.

    Raises
    ------
    InputError
        Keyed ``name``: ``law`` is a name (resolve it with ``get_law`` or ``LAWS[...]``), or
        something else that is not a ``ContactLaw``.

    Examples
    --------
    >>> import contact_sim as cs
    >>> from contact_sim.model import require_law
    >>> require_law(cs.LINEAR) is cs.LINEAR
    True
    >>> require_law('linear')
    Traceback (most recent call last):
        ...
    contact_sim.validation.InputError: law = 'linear' is a name: allowed a ContactLaw (resolve a name with cs.get_law('linear') or cs.LAWS['linear'])
    """
    if isinstance(law, ContactLaw):
        return law
    if isinstance(law, str):
        raise InputError(name, law, '{n[%s]} = {value} is a name: allowed a ContactLaw (resolve '
                         'a name with cs.get_law({value}) or cs.LAWS[{value}])' % name,
                         value=repr(law))
    raise InputError(name, law, '{n[%s]} = {value} is not a ContactLaw: allowed a ContactLaw '
                     '(the named ones are cs.LAWS: %s)' % (name, ', '.join(sorted(LAWS))))
