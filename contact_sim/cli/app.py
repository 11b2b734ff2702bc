"""`contact-sim`: a thin command line over the core library (no ROS).

Subcommands: materials, restitution, drop, fit, bounces.  Run `contact-sim <subcommand> --help`.
"""
import argparse
import csv
import io
import math
import os
import sys
from dataclasses import dataclass, field

import numpy as np

from contact_sim.cli import plotting
from contact_sim.model import build_contact, build_mass
from contact_sim.drop import simulate_drop
from contact_sim.impact import compare_laws, fit_damping
from contact_sim.model import equivalent_radius
from contact_sim.model import AZAD_FEATHERSTONE, LAWS, get_law
from contact_sim.model import MATERIALS
from contact_sim.impact import restitution
from contact_sim.validation import InputError, require_int, require_range

MAX_POINTS = 1_000_000   # --points: the table is printed, one line a speed

# The core's field keys as this command line spells them (InputError.render): the same
# refusal reads `--mass = ...` here and `sphere_mass = ...` in the node.
OPTION_NAMES = {key: '--' + key.replace('_', '-') for key in (
    'law', 'sphere', 'plate', 'radius', 'plate_radius', 'stiffness', 'mass', 'damping',
    'damping_factor', 'height', 'gravity', 'duration', 'sample_rate', 'points', 'confidence',
    'speed_range')}
OPTION_NAMES.update(speed='--speeds', material='--sphere/--plate', velocity='--initial-velocity')
for _body in ('sphere', 'plate'):   # custom materials: --sphere-modulus, --plate-poisson, ...
    OPTION_NAMES.update({f'{_body}_{_o}': f'--{_body}-{_o}' for _o in ('modulus', 'poisson', 'density')})

LAW_NAMES = list(LAWS)  # azad_featherstone, hunt_crossley, lee_wang, linear

CONTACT_HELP = """\
the contact (all SI units):
  stiffness k  --stiffness K, else Hertz k = (4/3) E* sqrt(R) from --sphere, --plate and
               --radius (eqs. 5, 6, 10).  The Hertz k is for the n = 1.5 laws only: with
               materials and no --stiffness the linear law is skipped with a note on stderr
               (an error if it is the only law asked for); give --stiffness to include it.
               --stiffness is used for every law chosen, in that law's units N/m^n.
  mass m       --mass M, else (4/3) pi R1^3 rho of the --sphere of --radius R1.  The plate
               (or second sphere, finite --plate-radius) is fixed; for two free spheres give
               the reduced mass m1 m2 / (m1 + m2) as --mass."""

DAMPING_HELP = """
  damping      --damping LAMBDA (N s^q/m^(p+q), N s/m^1.5 for azad_featherstone), or
               --damping-factor LAMBDA_STAR with --radius: lambda = lambda* sqrt(R) (eq. 9).
               The same number is used for every law chosen, in that law's units.
               0 is a purely elastic contact."""

EXIT_HELP = """
exit status: 0 success; 2 bad input (the message names the field and its allowed range);
1 if --plot is given but matplotlib is not installed (pip install 'contact_sim[plot]')."""


# -- argument types -----------------------------------------------------------------------
def _speed_list(text):
    try:
        return [float(item) for item in text.split(',') if item.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f'invalid value {text!r}: allowed comma-separated speeds in m/s, e.g. 0.1,1,10'
        ) from None


def _law_list(args, default):
    """The laws chosen with the repeatable --law, in order, without duplicates."""
    return [get_law(name) for name in dict.fromkeys(args.law or default)]


# -- contact, mass, damping ---------------------------------------------------------------
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
    from contact_sim.model import Material
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


def _has_density(args):
    """True when the sphere's density is known: a library --sphere or --sphere-density."""
    return args.sphere is not None or getattr(args, 'sphere_density', None) is not None


def build_setup(args, laws, with_damping=True):
    """Contacts for ``laws`` from the options (damping 0 when ``with_damping`` is false), by the
    core's one rule (``build_contact``, ``build_mass``)."""
    sphere, plate = material(args, 'sphere'), material(args, 'plate')
    radius = None if args.radius is None else equivalent_radius(args.radius, args.plate_radius)
    mass = build_mass(args.mass, sphere if _has_density(args) else None, args.radius)
    mass_source = 'given' if args.mass is not None else f'from the {sphere.name} density'
    source = 'given' if args.stiffness is not None else 'Hertz'
    setup = Setup(mass, mass_source, radius, source)
    damping = dict(damping=args.damping, damping_factor=args.damping_factor) if with_damping \
        else dict(damping=0.0)
    for law in laws:
        if args.stiffness is None and law.n != 1.5 and None not in (sphere, plate, args.radius):
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
    lines = []
    for name, contact in setup.contacts.items():
        line = (f'# {name:<18} k = {contact.stiffness:.6e} {stiffness_unit(contact.law)} '
                f'({setup.stiffness_source})')
        if show_damping:
            line += f', lambda = {contact.damping:.6e} {damping_unit(contact.law)}'
        lines.append(line)
    return lines


def _g(value, spec='.6g'):
    return format(value, spec) if math.isfinite(value) else 'n/a'


# -- materials ----------------------------------------------------------------------------
def _materials(args):
    print(f'{"name":<10} {"E (GPa)":>9} {"nu":>6} {"rho (kg/m3)":>12}  source')
    for m in MATERIALS.values():
        print(f'{m.name:<10} {m.youngs_modulus / 1e9:9.3g} {m.poisson_ratio:6.2f} '
              f'{m.density:12.0f}  {m.source}')
    return 0


# -- restitution --------------------------------------------------------------------------
def _speeds(args):
    if args.speeds is not None:
        if not args.speeds:
            raise ValueError('speeds is empty: allowed one or more speeds, 0 < speed < inf (m/s)')
        return np.asarray(args.speeds, dtype=float)
    low, high = args.speed_range
    if not 0.0 < low < high < math.inf:
        raise ValueError(f'speed_range = ({low:g}, {high:g}) is out of range: allowed '
                         '0 < LOW < HIGH < inf (m/s)')
    points = require_int('points', args.points, 2, MAX_POINTS)
    return np.geomspace(low, high, points)


def _restitution(args):
    speeds = _speeds(args)
    setup = build_setup(args, _law_list(args, LAW_NAMES))
    table = {name: restitution(contact, setup.mass, speeds)
             for name, contact in setup.contacts.items()}
    print('# coefficient of restitution e vs impact speed, no gravity')
    print(f'# {describe_contact(setup, args)} ({setup.mass_source})')
    print('\n'.join(contact_lines(setup)))
    widths = [max(len(name), 12) for name in table]
    print(f'# {"speed (m/s)":>13} ' + ' '.join(f'{n:>{w}}' for n, w in zip(table, widths)))
    for i, v in enumerate(speeds):
        print(f'{v:15.9g} ' + ' '.join(f'{e[i]:{w}.10f}' for e, w in zip(table.values(), widths)))
    if args.plot:
        _plot_restitution(args, setup, speeds, table)
    return 0


def _plot_restitution(args, setup, speeds, table):
    dense = plotting.dense_speeds(speeds, args.log_speed)
    curves, points = {}, {}
    for name, contact in setup.contacts.items():
        label = f'{name}, λ = {contact.damping:.4g} {damping_unit(contact.law)}'
        curves[label] = (dense, restitution(contact, setup.mass, dense))
        if len(speeds) <= 40:
            points[label] = (speeds, table[name])
    stiffness = ', '.join(sorted({f'{c.stiffness:.4g} {stiffness_unit(c.law)}'
                                  for c in setup.contacts.values()}))
    plotting.restitution_figure(
        args.plot, curves, points, 'Coefficient of restitution vs impact speed (no gravity)',
        f'{describe_contact(setup, args)}\nk = {stiffness} ({setup.stiffness_source})',
        args.log_speed)
    print(f'# plot written to {args.plot}')


# -- drop ---------------------------------------------------------------------------------
def _drop(args):
    setup = build_setup(args, [get_law(args.law)])
    contact = next(iter(setup.contacts.values()))
    rate = args.sample_rate if args.plot else None
    result = simulate_drop(contact, setup.mass, args.height, gravity=args.gravity,
                           duration=args.duration, sample_rate=rate, radius=args.radius,
                           velocity=args.initial_velocity)
    thrown = f' at {args.initial_velocity:g} m/s downward' if args.initial_velocity else ''
    print(f'# drop from {args.height:g} m{thrown}, gravity {args.gravity:g} m/s^2, '
          f'{args.duration:g} s simulated')
    print(f'# {describe_contact(setup, args)} ({setup.mass_source})')
    print('\n'.join(contact_lines(setup)))
    print_impacts(result.impacts)
    print_drop_summary(result)
    if args.plot:
        _plot_drop(args, setup, contact, result)
    return 0


def print_impacts(impacts):
    print(f'# {"n":>3} {"time (s)":>12} {"impact (m/s)":>13} {"rebound (m/s)":>13} '
          f'{"restitution":>11} {"duration (s)":>12} {"peak force (N)":>14}')
    for i, imp in enumerate(impacts, 1):
        duration = 'permanent' if imp.permanent else f'{imp.contact_duration:.5e}'
        print(f'  {i:3d} {imp.time:12.7f} {imp.impact_speed:13.6g} {imp.rebound_speed:13.6g} '
              f'{imp.restitution:11.6f} {duration:>12} {imp.peak_force:14.6g}')


def print_drop_summary(result):
    bounces = sum(1 for imp in result.impacts if not imp.permanent)
    final = ', then permanent contact' if len(result.impacts) > bounces else ''
    print(f'impacts: {len(result.impacts)} ({bounces} bounces{final})')
    print(f'permanent_contact_time: {_g(result.permanent_contact_time)} s')
    print(f'settle_time: {_g(result.settle_time)} s')
    print(f'integrator steps: {result.steps}')


def _plot_drop(args, setup, contact, result):
    traj = result.trajectory
    plotting.drop_figure(
        args.plot, traj.time, -traj.penetration, traj.force,
        [(imp.time, imp.peak_force) for imp in result.impacts],
        f'Drop from {args.height:g} m: {len(result.impacts)} impacts, '
        f'{contact.law.name} law',
        f'{describe_contact(setup, args)}, k = {contact.stiffness:.4g} '
        f'{stiffness_unit(contact.law)}, \u03bb = {contact.damping:.4g} '
        f'{damping_unit(contact.law)}, g = {args.gravity:g} m/s\u00b2')
    print(f'# plot written to {args.plot}')


# -- fit ----------------------------------------------------------------------------------
def _is_number(text):
    try:
        float(text)
    except ValueError:
        return False
    return True


def read_restitution_csv(path, with_uncertainties=False):
    """(speeds, restitutions) from ``speed,restitution`` rows: optional header, # comments.

    A third column is the uncertainty of e (> 0; returned as a third array, NaN where empty,
    with ``with_uncertainties``); further columns are ignored.  e >= 1 is accepted (noise)."""
    name = 'stdin' if path == '-' else path
    try:
        if path == '-':
            text = sys.stdin.read()
        else:
            with open(path, encoding='utf-8') as f:
                text = f.read()
    except (OSError, UnicodeDecodeError) as error:
        reason = getattr(error, 'strerror', None) or str(error)
        raise ValueError(f'data = {name!r} cannot be read: {reason}') from None
    rows = []
    for number, line in enumerate(text.splitlines(), 1):
        content = line.split('#', 1)[0].strip()
        if content:
            rows.append((number, next(csv.reader(io.StringIO(content)))))
    speeds, values, sigmas = [], [], []
    for index, (number, cells) in enumerate(rows):
        where = f'{name} line {number}'
        cells = [c.strip() for c in cells]
        if len(cells) < 2:
            raise ValueError(f'{where}: {len(cells)} columns in {",".join(cells)!r}: '
                             'allowed speed,restitution[,uncertainty,...]')
        if index == 0 and not any(_is_number(c) for c in cells):
            continue  # a header
        try:
            speeds.append(require_range('speed', cells[0], 0.0, low_open=True))
            values.append(require_range('restitution', cells[1], 0.0, low_open=True))
            sigmas.append(require_range('uncertainty', cells[2], 0.0, low_open=True)
                          if len(cells) > 2 and cells[2] else math.nan)
        except ValueError as error:
            raise ValueError(f'{where}: {error}') from None
    if not speeds:
        raise ValueError(f'data = {name!r} has no speed,restitution rows: allowed at least one')
    if with_uncertainties:
        return np.asarray(speeds), np.asarray(values), np.asarray(sigmas)
    return np.asarray(speeds), np.asarray(values)


def _fit(args):
    speeds, measured, sigmas = read_restitution_csv(args.data, with_uncertainties=True)
    if np.all(np.isnan(sigmas)):
        sigmas = None
    elif np.any(np.isnan(sigmas)):
        raise ValueError(f'uncertainty is missing on line(s) of {args.data}: allowed an '
                         'uncertainty on every row or on none')
    laws = _law_list(args, LAW_NAMES)
    setup = build_setup(args, laws, with_damping=False)
    if len(laws) == 1:
        fits = [fit_damping(laws[0], setup.contacts[laws[0].name].stiffness, setup.mass,
                            speeds, measured, args.confidence, args.loss, sigmas)]
    else:
        stiffness = {name: c.stiffness for name, c in setup.contacts.items()}
        fits = compare_laws(stiffness, setup.mass, speeds, measured, laws=list(stiffness),
                            confidence=args.confidence, loss=args.loss, uncertainties=sigmas)
    source = 'stdin' if args.data == '-' else args.data
    print(f'# fit of lambda to {len(speeds)} point(s) of {source}, speeds '
          f'{speeds.min():g} to {speeds.max():g} m/s, least squares in e')
    print(f'# {describe_contact(setup, args)} ({setup.mass_source})')
    print('\n'.join(contact_lines(setup, show_damping=False)))
    print_fit_summary(fits, setup.radius, args.confidence)
    _print_fit_flags(fits[0], speeds, measured, sigmas)
    for fit in fits:
        print_fit_points(fit, speeds, measured)
    if args.plot:
        _plot_fit(args, setup, fits, speeds, measured)
    return 0


def _print_fit_flags(fit, speeds, measured, sigmas):
    """e >= 1 points, the weighting and the robust loss's down-weighted points."""
    if sigmas is not None:
        print('# residuals weighted by 1/uncertainty (third column)')
    for i in fit.flagged:
        print(f'# note: point {i + 1} (speed {speeds[i]:g} m/s) has e = {measured[i]:g} >= 1: '
              'kept as measurement noise, no lambda matches it alone')
    if fit.loss != 'linear':
        down = [i for i, w in enumerate(fit.weights) if w < 0.5]
        print(f'# loss {fit.loss}: down-weighted points (weight < 0.5, {fit.law.name}): '
              + (', '.join(f'{i + 1} (speed {speeds[i]:g}, weight {fit.weights[i]:.2f})'
                           for i in down) or 'none'))


def print_fit_summary(fits, radius, confidence):
    level = f'{100 * confidence:g}%'
    if len(fits) > 1:
        print('# laws ranked by rms residual, best first')
    for fit in fits:
        law = fit.law
        low, high = fit.confidence_interval
        print(f'{law.name}: lambda = {fit.damping:.9e} {damping_unit(law)}')
        if math.isnan(low):
            print(f'  {level} confidence interval: n/a (one point: no residual variance)')
        else:
            print(f'  {level} confidence interval: [{low:.6e}, {high:.6e}]')
        print(f'  rms residual in e: {fit.rms_residual:.3e}')
        print(f'  pointwise lambda spread (max/min): {fit.pointwise_spread:.6f}')
        if radius is not None:
            print(f'  lambda* = lambda/sqrt(R) = {fit.damping / math.sqrt(radius):.9e} '
                  f'{damping_unit(law, extra=0.5)}')


def print_fit_points(fit, speeds, measured):
    law = fit.law
    print(f'# {law.name}: per point (lambda alone = the lambda that matches that point exactly)')
    print(f'# {"speed (m/s)":>12} {"e data":>10} {"e fitted":>10} {"residual":>11} '
          f'{"lambda alone (" + damping_unit(law) + ")":>26}')
    for v, e, r, lam in zip(speeds, measured, fit.residuals, fit.pointwise_damping):
        print(f'  {v:12.6g} {e:10.6f} {e + r:10.6f} {r:11.3e} {lam:26.6e}')


def _plot_fit(args, setup, fits, speeds, measured):
    dense = plotting.dense_speeds(speeds, log_speed=True)
    curves = {f'{fit.law.name}: \u03bb = {fit.damping:.4g} {damping_unit(fit.law)}, '
              f'rms {fit.rms_residual:.2g}':
              (dense, restitution(fit.contact(), setup.mass, dense)) for fit in fits}
    plotting.fit_figure(args.plot, (speeds, measured), curves,
                        f'Damping fit to {args.data}',
                        f'{describe_contact(setup, args)}, k {setup.stiffness_source}')
    print(f'# plot written to {args.plot}')


# -- parser -------------------------------------------------------------------------------
def _contact_options(damping=True):
    parent = argparse.ArgumentParser(add_help=False)
    mats = parent.add_argument_group('contact from materials')
    mats.add_argument('--sphere', choices=sorted(MATERIALS), metavar='MATERIAL',
                      help='sphere material (see `contact-sim materials`)')
    mats.add_argument('--plate', choices=sorted(MATERIALS), metavar='MATERIAL',
                      help='plate (or second sphere) material')
    mats.add_argument('--radius', type=float, metavar='R1',
                      help='sphere radius in m, 0 < R1')
    mats.add_argument('--plate-radius', type=float, default=math.inf, metavar='R2',
                      help='plate radius in m: inf (default) is a flat plate, finite a second '
                           'sphere; 1/R = 1/R1 + 1/R2')
    for body in ('sphere', 'plate'):   # custom materials, or changes to a library one
        mats.add_argument(f'--{body}-modulus', type=float, metavar='E',
                          help=f"{body} Young's modulus in Pa, 0 < E")
        mats.add_argument(f'--{body}-poisson', type=float, metavar='NU',
                          help=f'{body} Poisson ratio, -1 < NU < 0.5')
        mats.add_argument(f'--{body}-density', type=float, metavar='RHO',
                          help=f'{body} density in kg/m^3, 0 < RHO' + (
                              ' (for the mass)' if body == 'sphere' else ' (not used)'))
    direct = parent.add_argument_group('contact given directly')
    direct.add_argument('--stiffness', type=float, metavar='K',
                        help='k in N/m^n (overrides the Hertz value), 0 < K')
    direct.add_argument('--mass', type=float, metavar='M',
                        help='(reduced) mass in kg, 0 < M; default from the sphere density')
    if damping:
        direct.add_argument('--damping', type=float, metavar='LAMBDA',
                            help='lambda in N s^q/m^(p+q), 0 <= LAMBDA')
        direct.add_argument('--damping-factor', type=float, metavar='LAMBDA_STAR',
                            help='or lambda* in N s^q/m^(p+q+1/2), 0 <= LAMBDA_STAR; needs '
                                 '--radius')
    return parent


def _plot_option(parser, what):
    parser.add_argument('--plot', metavar='OUT.png',
                        help=f'also write a figure of {what} (needs matplotlib)')


def _contact_command(sub, name, help, description, notes, damping=True):
    """A subcommand that takes the contact options; its epilog explains them, then ``notes``."""
    return sub.add_parser(
        name, parents=[_contact_options(damping=damping)],
        formatter_class=argparse.RawDescriptionHelpFormatter, help=help, description=description,
        epilog=CONTACT_HELP + (DAMPING_HELP if damping else '') + notes + EXIT_HELP)


def _add_restitution(sub):
    p = _contact_command(
        sub, 'restitution',
        help='coefficient of restitution vs impact speed, as a table or a plot',
        description='Coefficient of restitution e of single impacts without gravity, per law,\n'
                    'at the given impact speeds (cs.restitution).',
        notes='\n\nexample:\n  contact-sim restitution --sphere steel --plate cast_iron '
              '--radius 0.0127 --damping-factor 8.87e5\n')
    p.add_argument('--law', action='append', choices=LAW_NAMES,
                   help='force law, repeatable (default: all four)')
    speeds = p.add_mutually_exclusive_group()
    speeds.add_argument('--speeds', type=_speed_list, metavar='V1,V2,...',
                        help='impact speeds in m/s, comma-separated')
    speeds.add_argument('--speed-range', type=float, nargs=2, metavar=('LOW', 'HIGH'),
                        default=(0.01, 10.0),
                        help='log-spaced speeds from LOW to HIGH m/s (default 0.01 10)')
    p.add_argument('--points', type=int, default=20,
                   help='number of speeds in --speed-range (default 20), >= 2')
    _plot_option(p, 'e vs speed')
    p.add_argument('--log-speed', action='store_true',
                   help='logarithmic speed axis in the plot (the new law is near-linear there)')
    p.set_defaults(run=_restitution)


def _add_drop(sub):
    p = _contact_command(
        sub, 'drop',
        help='drop a sphere on a plate and list every impact',
        description='Simulate a sphere dropped on a plate until it rests (cs.simulate_drop)\n'
                    'and print each impact and a summary.',
        notes='\n\nexample (the paper\'s drop, section II-C):\n'
              '  contact-sim drop --stiffness 1e10 --damping 1e5 --mass 0.066 --gravity 10\n')
    p.add_argument('--law', choices=LAW_NAMES, default=AZAD_FEATHERSTONE.name,
                   help='force law (default azad_featherstone)')
    p.add_argument('--height', type=float, default=1.0,
                   help='release height of the lowest point above the plate in m (default 1)')
    p.add_argument('--gravity', type=float, default=9.81,
                   help='gravity in m/s^2, >= 0 (default 9.81)')
    p.add_argument('--duration', type=float, default=5.0,
                   help='simulated time in s, > 0 (default 5)')
    p.add_argument('--initial-velocity', type=float, default=0.0, metavar='V',
                   help='initial velocity in m/s, > 0 towards the plate (default 0: released '
                        'at rest)')
    _plot_option(p, 'height and contact force vs time')
    p.add_argument('--sample-rate', type=float, default=1000.0, metavar='HZ',
                   help='trajectory sampling for --plot in Hz (default 1000); every '
                        "contact's integrator points are added, so no force peak is lost")
    p.set_defaults(run=_drop)


def _add_fit(sub):
    p = _contact_command(
        sub, 'fit', damping=False,
        help='fit the damping lambda to measured (speed, restitution) points',
        description='Least-squares fit of lambda to measured restitution (cs.fit_damping for\n'
                    'one law, cs.compare_laws for several), with k fixed from the materials\n'
                    'or --stiffness, as in the paper\'s Fig. 5.',
        notes='\n\ndata file: rows "speed,restitution" (m/s, 0 < e; e >= 1 is kept and flagged)\n'
              'and optionally a third column, the uncertainty of e (used as weights 1/u^2);\n'
              'further columns are ignored; an optional header row; text after # is a\n'
              'comment; - reads stdin.\n\nexample:\n'
              '  contact-sim fit data.csv --sphere steel --plate cast_iron --radius 0.0127\n')
    p.add_argument('data', help='CSV file of speed,restitution rows, or - for stdin')
    p.add_argument('--law', action='append', choices=LAW_NAMES,
                   help='force law, repeatable (default: all four, ranked by rms residual)')
    p.add_argument('--confidence', type=float, default=0.95,
                   help='confidence level of the interval on lambda, 0 < C < 1 (default 0.95)')
    p.add_argument('--loss', choices=['linear', 'soft_l1', 'huber', 'cauchy', 'arctan'],
                   default='linear', help='least-squares loss (default linear; soft_l1 etc. '
                                          'down-weight outliers)')
    _plot_option(p, 'the data and the fitted curves on a log speed axis')
    p.set_defaults(run=_fit)


def build_parser():
    parser = argparse.ArgumentParser(prog='contact-sim', description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=EXIT_HELP)
    sub = parser.add_subparsers(dest='command', required=True)
    sub.add_parser('materials', help='list the material library with sources').set_defaults(
        run=_materials)
    _add_restitution(sub)
    _add_drop(sub)
    _add_fit(sub)
    from contact_sim.cli import bounces as cli_bounces   # calibration from recorded bounces (its own module)
    cli_bounces.add_parser(sub)
    return parser


def _names(args):
    names = dict(OPTION_NAMES)
    if getattr(args, 'data', None) is not None:
        source = 'stdin' if args.data == '-' else args.data
        names.update(speeds=f'{source} speed', restitutions=f'{source} restitution')
    return names


def main(argv=None):
    args = build_parser().parse_args(argv)
    try:
        if getattr(args, 'plot', None):
            plotting.load_pyplot()
            plotting.check_output(args.plot)
        return args.run(args)
    except InputError as error:
        print(f'contact-sim: error: {error.render(_names(args))}', file=sys.stderr)
        return 2
    except ValueError as error:
        print(f'contact-sim: error: {error}', file=sys.stderr)
        return 2
    except ArithmeticError as error:   # extreme values that overflow the model
        print(f'contact-sim: error: the values given overflow the model ({error}): allowed '
              'physically sensible magnitudes', file=sys.stderr)
        return 2
    except plotting.MissingMatplotlib as error:
        print(f'contact-sim: error: {error}', file=sys.stderr)
        return 1
    except BrokenPipeError:  # e.g. `contact-sim drop ... | head`: stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1


if __name__ == '__main__':
    sys.exit(main())
