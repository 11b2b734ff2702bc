"""`contact-sim restitution`: the coefficient of restitution of single impacts (no gravity) per
law at the given impact speeds, as a table and optionally a plot."""
import argparse
import math

import numpy as np

from contact_sim.cli import plotting
from contact_sim.cli.contact import build_setup, contact_lines, damping_unit, describe_contact, \
    stiffness_unit
from contact_sim.cli.options import LAW_NAMES, contact_command, law_list, plot_option, \
    refuse_beside
from contact_sim.validation import InputError, require_int

MAX_POINTS = 1_000_000   # --points: the table is printed, one line a speed


def _speed_list(text):
    """The speeds of ``--speeds V1,V2,...``: every item a number (an empty one is refused)."""
    try:
        return [float(item) for item in text.split(',')]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f'invalid value {text!r}: allowed comma-separated speeds in m/s, e.g. 0.1,1,10 '
            '(no empty items)') from None


def add_speed_options(p, speed_range, points):
    """--speeds, or --speed-range (default ``speed_range``, m/s) with --points (default
    ``points``): the speeds of `restitution`, and of every subcommand that takes them so."""
    speeds = p.add_mutually_exclusive_group()
    speeds.add_argument('--speeds', type=_speed_list, metavar='V1,V2,...',
                        help='impact speeds in m/s, comma-separated')
    speeds.add_argument('--speed-range', type=float, nargs=2, metavar=('LOW', 'HIGH'),
                        default=speed_range, help='log-spaced speeds from LOW to HIGH m/s '
                        f'(default {speed_range[0]:g} {speed_range[1]:g})')
    p.add_argument('--points', type=int, default=points,
                   help=f'number of speeds in --speed-range (default {points}), >= 2')


def add_parser(sub):
    """Register the subcommand on the subparsers ``sub``."""
    p = contact_command(
        sub, 'restitution',
        help='coefficient of restitution vs impact speed, as a table or a plot',
        description='Coefficient of restitution e of single impacts without gravity, per law,\n'
                    'at the given impact speeds (cs.restitution).',
        notes='\n\nexample:\n  contact-sim restitution --sphere steel --plate cast_iron '
              '--radius 0.0127 --damping-factor 8.87e5\n')
    p.add_argument('--law', action='append', choices=LAW_NAMES,
                   help='force law, repeatable (default: all four)')
    add_speed_options(p, (0.01, 10.0), 20)
    plot_option(p, 'e vs speed')
    p.add_argument('--log-speed', action='store_true',
                   help='logarithmic speed axis in the plot (the new law is near-linear there)')
    p.set_defaults(run=run)


def _speeds(args):
    if args.speeds is not None:
        refuse_beside(args, 'points', '--points', '--speeds', 'lists the speeds itself '
                      '(--points counts those of --speed-range)')
        from contact_sim.impact import require_speeds   # the engine: after parsing
        return require_speeds(args.speeds)
    low, high = args.speed_range
    if not 0.0 < low < high < math.inf:
        raise InputError('speed_range', (low, high), '{n[speed_range]} %g %g is out of range: '
                         'allowed 0 < LOW < HIGH < inf (m/s)' % (low, high))
    points = require_int('points', args.points, 2, MAX_POINTS)
    return np.geomspace(low, high, points)


def run(args):
    """Print e per law at each speed (and draw it with --plot); returns the exit status 0."""
    from contact_sim.impact import restitution   # the engine: after the arguments are parsed
    speeds = _speeds(args)
    setup = build_setup(args, law_list(args, LAW_NAMES))
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
        _plot(args, setup, speeds, table)
    return 0


def _plot(args, setup, speeds, table):
    from contact_sim.impact import restitution
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
