"""The contact the options describe, read once for every subcommand: the materials, the mass, the
per-law contacts (with the one rule that skips a law the Hertz stiffness does not fit), and the
lines that print them."""
import math
import sys
from dataclasses import dataclass, field

from contact_sim.model import (DEFAULT_CONTACT, MATERIALS, Material, build_contact, build_mass,
                               equivalent_radius)
from contact_sim.validation import InputError


@dataclass
class Setup:
    """What the options describe: per-law contacts, the mass and the equivalent radius R."""

    mass: float
    mass_source: str
    radius: float  # equivalent radius R (m), or None without --radius
    stiffness_source: str
    contacts: dict = field(default_factory=dict)   # law name -> Contact
    skipped: dict = field(default_factory=dict)    # law name -> reason


def material(args, body):
    """The ``body`` ('sphere' or 'plate') material: the library one named by --sphere/--plate,
    with any of --BODY-modulus, --BODY-poisson, --BODY-density replacing its values; without a
    library name, a custom material from those three (``None`` if nothing is given)."""
    name = getattr(args, body)
    options = (('youngs_modulus', 'modulus'), ('poisson_ratio', 'poisson'), ('density', 'density'))
    given = {field_: getattr(args, f'{body}_{option}', None) for field_, option in options}
    given = {k: v for k, v in given.items() if v is not None}
    if not given:
        return None if name is None else MATERIALS[name]
    if name is None:
        missing = [f'--{body}-{o}' for k, o in options[:2] if k not in given]
        if missing:
            raise ValueError(f'{body}_material is incomplete: give {" and ".join(missing)} '
                             f'(or --{body} MATERIAL to start from)')
    base = MATERIALS[name] if name is not None else None
    # a custom sphere without --sphere-density has no mass from density (see _has_density);
    # the placeholder 1 kg/m^3 never reaches a result
    values = {k: given.get(k, getattr(base, k, 1.0)) for k, _ in options}
    try:
        return Material(f'{name} (modified)' if name else 'custom', values['youngs_modulus'],
                        values['poisson_ratio'], values['density'])
    except InputError as error:   # keyed by the material's field: say which option it was
        option = dict(options).get(error.field)
        raise error.rekeyed(f'{body}_{option}') if option else error from None


# the options that describe a contact: none of them given -> the default contact
CONTACT_OPTIONS = ('sphere', 'plate', 'radius', 'stiffness', 'mass', 'damping', 'damping_factor',
                   'params_file') + tuple(f'{body}_{option}' for body in ('sphere', 'plate')
                                          for option in ('modulus', 'poisson', 'density'))
# the subcommands that fall back to it (bounces fits its own contact from the recordings)
DEFAULT_CONTACT_COMMANDS = ('restitution', 'drop', 'fit', 'export')


def use_default_contact(args):
    """With no contact option at all, take the core's default contact (``DEFAULT_CONTACT``, the
    node's defaults: the README's steel ball on cast iron, its law unless --law is given) and say
    so in the first line of the output; returns True if it did.

    Refused as before (a missing option named): a contact given in part, e.g. --mass alone."""
    if getattr(args, 'command', None) not in DEFAULT_CONTACT_COMMANDS \
            or any(getattr(args, name, None) is not None for name in CONTACT_OPTIONS) \
            or not math.isinf(getattr(args, 'plate_radius', math.inf)):
        return False
    args.sphere, args.plate, args.radius = \
        DEFAULT_CONTACT.sphere, DEFAULT_CONTACT.plate, DEFAULT_CONTACT.radius
    if hasattr(args, 'damping_factor'):
        args.damping_factor = DEFAULT_CONTACT.damping_factor
    if args.command in ('restitution', 'fit') and args.law is None:   # --law: repeatable
        args.law = [DEFAULT_CONTACT.law]
    json = getattr(args, 'format', None) == 'json'   # keep a JSON output parseable
    print(f'# no contact given: the default contact, {DEFAULT_CONTACT.describe()} (the '
          'node\'s defaults; give --sphere/--plate/--radius or --stiffness/--mass/--damping for '
          'another)', file=sys.stderr if json else sys.stdout)
    return True


def _has_density(args):
    """True when the sphere's density is known: a library --sphere or --sphere-density."""
    return args.sphere is not None or getattr(args, 'sphere_density', None) is not None


def mass_of(args):
    """The (reduced) mass in kg: --mass, else from the sphere material's density and --radius,
    by the core's one rule (``build_mass``)."""
    return build_mass(args.mass, material(args, 'sphere') if _has_density(args) else None,
                      args.radius)


def lacks_hertz_stiffness(args, law, sphere, plate):
    """True when ``law``'s k would be the Hertz k of the materials, which it cannot use (it is
    not a Hertz law): such a law is left out unless --stiffness is given."""
    return args.stiffness is None and not law.hertz and None not in (sphere, plate, args.radius)


def build_setup(args, laws, with_damping=True):
    """Contacts for ``laws`` (``ContactLaw`` objects) from the options (damping 0 when
    ``with_damping`` is false), by the core's one rule (``build_contact``, ``build_mass``)."""
    sphere, plate = material(args, 'sphere'), material(args, 'plate')
    radius = None if args.radius is None else equivalent_radius(args.radius, args.plate_radius)
    mass = mass_of(args)
    mass_source = 'given' if args.mass is not None else f'from the {sphere.name} density'
    source = 'given' if args.stiffness is not None else 'Hertz'
    setup = Setup(mass, mass_source, radius, source)
    damping = dict(damping=args.damping, damping_factor=args.damping_factor) if with_damping \
        else dict(damping=0.0)
    for law in laws:
        if lacks_hertz_stiffness(args, law, sphere, plate):
            setup.skipped[law.name] = (
                f'law {law.name} (n = {law.n:g}) cannot use the Hertz stiffness, which needs '
                'n = 1.5: give --stiffness K (N/m) to include it')
            continue
        setup.contacts[law.name] = build_contact(
            law, stiffness=args.stiffness, sphere=sphere, plate=plate,
            radius=args.radius, plate_radius=args.plate_radius, **damping)
    if not setup.contacts:
        raise ValueError(next(iter(setup.skipped.values())))
    for reason in setup.skipped.values():
        print(f'contact-sim: note: skipped {reason}', file=sys.stderr)
    return setup


# -- formatting ---------------------------------------------------------------------------
def _power(unit, exponent):
    return unit if exponent == 1.0 else f'{unit}^{exponent:g}'


def stiffness_unit(law):
    """Units of k: N/m^n."""
    return 'N/' + _power('m', law.n)


def damping_unit(law, extra=0.0):
    """Units of lambda (``extra`` = 0.5: of lambda* = lambda / sqrt(R))."""
    return f'N {_power("s", law.q)}/{_power("m", law.p + law.q + extra)}'


def describe_contact(setup, args):
    """One line saying which bodies and mass the numbers are for."""
    parts = []
    sphere, plate_material = material(args, 'sphere'), material(args, 'plate')
    if sphere is not None and args.radius is not None:
        plate = 'flat' if math.isinf(args.plate_radius) else f'R2 = {args.plate_radius:g} m'
        parts.append(f'{sphere.name} sphere R1 = {args.radius:g} m on '
                     f'{plate_material.name if plate_material else "?"} ({plate})')
    if setup.radius is not None:
        parts.append(f'R = {setup.radius:.4g} m')
    parts.append(f'm = {setup.mass:.4g} kg')
    return ', '.join(parts)


def contact_lines(setup, show_damping=True):
    """One comment line per law: its k (and lambda) with units."""
    lines = []
    for name, contact in setup.contacts.items():
        line = (f'# {name:<18} k = {contact.stiffness:.6e} {stiffness_unit(contact.law)} '
                f'({setup.stiffness_source})')
        if show_damping:
            line += f', lambda = {contact.damping:.6e} {damping_unit(contact.law)}'
        lines.append(line)
    return lines
