"""`contact-sim drop`: a sphere dropped on a plate until it rests, every impact listed."""
import math

from contact_sim.cli import plotting
from contact_sim.cli.contact import build_setup, contact_lines, damping_unit, describe_contact, \
    stiffness_unit
from contact_sim.cli.options import LAW_NAMES, contact_command, plot_option
from contact_sim.model import AZAD_FEATHERSTONE, get_law


def add_parser(sub):
    """Register the subcommand on the subparsers ``sub``."""
    p = contact_command(
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
    plot_option(p, 'height and contact force vs time')
    p.add_argument('--sample-rate', type=float, default=1000.0, metavar='HZ',
                   help='trajectory sampling for --plot in Hz (default 1000); every '
                        "contact's integrator points are added, so no force peak is lost")
    p.set_defaults(run=run)


def run(args):
    """Simulate the drop, print its impacts and summary (and draw it with --plot); returns 0."""
    from contact_sim.drop import simulate_drop   # the engine: after the arguments are parsed
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
        _plot(args, setup, contact, result)
    return 0


def print_impacts(impacts):
    """One row per ``ImpactRecord``: time, speeds, restitution, duration, peak force."""
    print(f'# {"n":>3} {"time (s)":>12} {"impact (m/s)":>13} {"rebound (m/s)":>13} '
          f'{"restitution":>11} {"duration (s)":>12} {"peak force (N)":>14}')
    for i, imp in enumerate(impacts, 1):
        duration = 'permanent' if imp.permanent else f'{imp.contact_duration:.5e}'
        print(f'  {i:3d} {imp.time:12.7f} {imp.impact_speed:13.6g} {imp.rebound_speed:13.6g} '
              f'{imp.restitution:11.6f} {duration:>12} {imp.peak_force:14.6g}')


def _g(value, spec='.6g'):
    return format(value, spec) if math.isfinite(value) else 'n/a'


def print_drop_summary(result):
    """The bounce count, the permanent-contact and settle times and the integrator steps."""
    bounces = sum(1 for imp in result.impacts if not imp.permanent)
    final = ', then permanent contact' if len(result.impacts) > bounces else ''
    print(f'impacts: {len(result.impacts)} ({bounces} bounces{final})')
    print(f'permanent_contact_time: {_g(result.permanent_contact_time)} s')
    print(f'settle_time: {_g(result.settle_time)} s')
    print(f'integrator steps: {result.steps}')


def _plot(args, setup, contact, result):
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
