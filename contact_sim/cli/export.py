"""`contact-sim export ENGINE`: the simulator's parameters that best reproduce a contact's e(v)
over a speed range, the e(v) the engine gives with them (measured by running MuJoCo, PyBullet or
Drake, predicted from its own law for Gazebo), the claim checked with gravity, and the snippet
to paste."""
import json
import re

import numpy as np

from contact_sim.cli import plotting
from contact_sim.cli.contact import build_setup, describe_contact
from contact_sim.cli.options import LAW_NAMES, contact_command, plot_option
from contact_sim.cli.params_file import apply_params_file
from contact_sim.cli.restitution import _speeds, add_speed_options
# the parser's choices, from a module without the engines (contact_sim._lazy): the export and
# the impact engine are imported in the functions that run them
from contact_sim.export import ENGINE_NAMES, TIMESTEPS
from contact_sim.model import get_law
from contact_sim.validation import InputError, require_int

# --points and the number of --speeds: each speed is thrown about 100 times by the fit and the
# gravity check; PyBullet took 37 s for 10 speeds at 1e-3 s and 74 s at 1e-4 s (docs/export.md),
# so 40 finish in about 5 minutes at steps down to 1e-4 s; below, the flight to the plate grows
# as 1 / step, and the bound shrinks with it
MAX_POINTS = 40
FULL_POINTS_STEP = 1e-4   # s: the smallest step at which MAX_POINTS speeds are allowed


def max_points(timestep):
    """The most speeds an export at ``timestep`` (s) takes: ``MAX_POINTS``, fewer below
    ``FULL_POINTS_STEP`` in proportion (at least 2)."""
    from contact_sim.export import MIN_TIMESTEP   # a step out of range is refused
    if not timestep or not MIN_TIMESTEP <= timestep < FULL_POINTS_STEP:   # after, by its check
        return MAX_POINTS
    return max(2, int(MAX_POINTS * timestep / FULL_POINTS_STEP))


# argparse takes '-1e-3' for an option (its own pattern knows -1 and -.5 only): this one lets
# `--timestep -1e-3` reach the range check, which names the range
NEGATIVE_NUMBER = re.compile(r'^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf(inity)?|nan)$', re.I)


def accept_negative_numbers(parser):
    """Let ``parser`` take arguments such as -1e-3 as values (it has no options that look like
    negative numbers)."""
    parser._negative_number_matcher = NEGATIVE_NUMBER
    return parser


def bounded_speeds(args):
    """The speeds of --speeds or --speed-range/--points, at most ``max_points`` of them at the
    step, checked before any engine runs."""
    timestep = getattr(args, 'timestep', None)
    most = max_points(timestep if isinstance(timestep, float) else None)
    at = f' at --timestep {timestep:g} s' if most < MAX_POINTS else ''
    if args.speeds is None:
        try:
            require_int('points', args.points, 2, most)
        except InputError as error:
            raise InputError('points', args.points, error.template + at
                             + ' (each speed is thrown about 100 times in the engine)',
                             **error.params) from None
    elif len(args.speeds) > most:
        raise InputError('speeds', len(args.speeds), '{n[speeds]} has {value} speeds: allowed '
                         f'1 to {most}{at} (each is thrown about 100 times in the engine)',
                         value=len(args.speeds))
    return _speeds(args)


def add_parser(sub):
    """Register the subcommand on the subparsers ``sub``."""
    p = contact_command(
        sub, 'export',
        help="a contact's parameters for MuJoCo, PyBullet, Drake or Gazebo, with the e(v) "
             'each gives',
        description='The engine parameters that best reproduce the contact\'s e(v) over the\n'
                    'speeds (minimax), the e(v) the engine gives with them and its snippet.\n'
                    'mujoco, pybullet and drake are run (measured, gravity off), and the claim\n'
                    'is checked with gravity on (the ball dropped and resting on the plate);\n'
                    'gazebo is predicted from its own law (the continuous law\'s e).\n'
                    'A contact that cannot hold the ball up is refused (exit 2).',
        notes='\n\nexample:\n  contact-sim export mujoco --law azad_featherstone --sphere steel '
              '--plate cast_iron\n      --radius 0.0127 --damping-factor 8.87e5 --timestep 1e-3\n')
    p.add_argument('engine', choices=list(ENGINE_NAMES), help='the simulator')
    p.add_argument('--law', choices=LAW_NAMES,
                   help='the target force law (default azad_featherstone)')
    p.add_argument('--params-file', metavar='FILE.yaml',
                   help='the contact from a node parameter file (contact_sim_node, or the '
                        '--save-params file of `contact-sim bounces`); options given here '
                        'take precedence over its keys')
    p.add_argument('--timestep', type=float, default=1e-3,
                   help="the engine's time step in s (default 1e-3), 1e-5 <= DT <= 0.01; drake "
                        'also takes 0, its continuous plant')
    add_speed_options(p, (0.1, 10.0), 10)
    accept_negative_numbers(p)
    p.add_argument('--tolerance', type=float, metavar='TOL',
                   help='also search the time steps ' + ', '.join(f'{x:g}' for x in TIMESTEPS)
                        + ' s for the largest whose export misses the target e by at most TOL '
                        '(text output; a linear law below half the target\'s spread: none)')
    p.add_argument('--format', choices=('text', 'json'), default='text',
                   help='text (a table and the snippet) or json (one record)')
    plot_option(p, 'target and engine e vs speed')
    p.set_defaults(run=run)


def export_of(args):
    """The ``Export`` the options describe."""
    from contact_sim.export import export_contact, make_target   # the engines: after parsing
    speeds = bounded_speeds(args)
    names = {'timestep': '--timestep'}   # core field -> how this call spells it
    if args.params_file is not None:
        names.update(apply_params_file(args, args.params_file))
    try:
        law = get_law(args.law or 'azad_featherstone')
        setup = build_setup(args, [law])
        if args.radius is None:
            raise ValueError('--radius is missing: the engines need the sphere radius R1 in m, '
                             '0 < R1')
        target = make_target(setup.contacts[law.name], setup.mass, args.radius, speeds)
        return setup, export_contact(args.engine, target, args.timestep)
    except InputError as error:   # a field from the file, or the export's own: spelled so
        raise error.rekeyed(names[error.field]) if error.field in names else error from None
    except ImportError as error:   # a measured engine whose package is absent
        extra = 'drake' if args.engine == 'drake' else 'engines'
        raise ValueError(f'engine {args.engine} is not installed ({error}): pip install '
                         f"'contact_sim[{extra}]'; no e is claimed without running it") from None


def run(args):
    """Print the export (a table and the snippet, or one JSON record); exit status 0."""
    from contact_sim.export import ENGINES, require_tolerance, timestep_for_tolerance
    if args.tolerance is not None:
        if args.format == 'json':
            raise ValueError('--tolerance is reported in the text output: allowed with '
                             '--format text only')
        try:
            require_tolerance(args.tolerance)
        except InputError as error:
            raise error.rekeyed('--tolerance') from None
    setup, result = export_of(args)
    law = result.target.contact.law.name
    if args.plot:
        _plot(args, setup, result)
    if args.format == 'json':
        print(json.dumps(result.as_dict(), indent=2))
        return 0
    print(f'# {result.engine} {result.engine_version}: parameters for {law}, '
          f'{describe_contact(setup, args)}')
    for key, value in result.parameters.items():
        print(f'# {key} = {value}')
    print(f'# engine e {result.engine_restitution_source} (gravity off); max |error| = '
          f'{result.max_abs_error:.4f}: {result.miss()}')
    print(f'# {ENGINES[result.engine].limit}')
    print(f'# {result.note}')
    print_scene(result)
    print_table(result)
    print_snippet(result)
    if args.tolerance is not None:
        print_search(timestep_for_tolerance(result.engine, result.target, args.tolerance))
    return 0


def print_search(search):
    """The time step search's outcome, as comment lines."""
    for timestep, error in search.tried:
        print(f'# time step {timestep:g} s: ' + ('unusable, its contact cannot hold the ball up'
                                                 if error is None else
                                                 f'max |error| = {error:.4f}'))
    if search.timestep is not None:
        print(f'# tolerance {search.tolerance:g}: the largest time step that meets it is '
              f'{search.timestep:g} s')
    elif search.floor is not None and not search.tried:
        print(f'# tolerance {search.tolerance:g}: none does for a linear law: the best '
              f'achievable max |error| is half the target\'s spread, {search.floor:.4f}, at '
              'any time step')
    else:
        print(f'# tolerance {search.tolerance:g}: none of the time steps meets it; the best '
              f'max |error| found is {search.best_error:.4f}')


def print_scene(result):
    """The claim with gravity, and what in a user's model changes it, as comment lines."""
    if result.scene is not None:
        for line in result.scene.lines(result.target.speeds):
            print(f'# {line}')
    if result.pitfalls:
        print('# what in your model changes this claim:')
        for line in result.pitfalls:
            print(f'#   - {line}')


def print_table(result):
    """speed, target e, engine e, error; then the contact duration (s) and peak force (N) of
    the target and of the engine, where the engine's are known."""
    from contact_sim.impact import contact_duration, peak_force
    target = result.target
    columns = [target.restitution, result.engine_restitution,
               result.engine_restitution - target.restitution]
    header = f'# {"speed (m/s)":>13} {"target e":>10} {"engine e":>10} {"error":>10}'
    if result.scene is not None:
        columns.append(result.scene.restitution)
        header += f' {"e, gravity":>10}'
    if result.engine_duration is not None:
        columns += [contact_duration(target.contact, target.mass, target.speeds),
                    result.engine_duration, peak_force(target.contact, target.mass,
                                                       target.speeds), result.engine_peak_force]
        header += (f' {"target T (s)":>12} {"engine T (s)":>12} {"target F (N)":>12} '
                   f'{"engine F (N)":>12}')
    print(header)
    first = 4 if result.scene is not None else 3
    for v, *row in zip(target.speeds, *columns):
        e_row = f'{v:15.6g} {row[0]:10.5f} {row[1]:10.5f} {row[2]:+10.5f}'
        e_row += ''.join(f' {x:10.5f}' for x in row[3:first])
        print(e_row + ''.join(f' {x:12.4g}' for x in row[first:]))


def print_snippet(result):
    """The engine's snippet, after a comment line."""
    print(f'# snippet ({result.engine}):')
    print(result.snippet)


def _plot(args, setup, result):
    from contact_sim.export import make_target
    speeds = result.target.speeds
    dense = plotting.dense_speeds(speeds, True)
    target = f'target {result.target.contact.law.name}'
    engine = f'{result.engine} ({result.engine_restitution_source})'
    curves = {target: (dense, np.asarray(make_target(result.target.contact, result.target.mass,
                                                     result.target.radius, dense).restitution)),
              engine: (speeds, result.engine_restitution)}
    plotting.restitution_figure(
        args.plot, curves, {target: (speeds, result.target.restitution)},
        f'{result.engine} e vs impact speed (no gravity), max |error| '
        f'{result.max_abs_error:.3f}', describe_contact(setup, args), True)
    print(f'# plot written to {args.plot}')
