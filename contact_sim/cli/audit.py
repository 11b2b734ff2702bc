"""`contact-sim audit mujoco MODEL.xml --geom NAME` and `contact-sim audit pybullet MODEL.urdf
--link NAME`: the e(v) a sphere geom of a user's MuJoCo model, or a sphere link of a URDF in
PyBullet, gives (the engine run: the sphere thrown at a plane, gravity off), beside a target
contact's, with the export's suggestion for the same time step."""
import numpy as np

from contact_sim.cli.export import accept_negative_numbers, export_of, print_scene, print_snippet
from contact_sim.cli.restitution import add_speed_options
from contact_sim.cli.options import LAW_NAMES, contact_command
from contact_sim.validation import InputError


def _mujoco():
    from contact_sim.export import audit, geom_contact   # the engine: after parsing
    return lambda args: geom_contact(args.model, args.geom), audit


def _pybullet():
    from contact_sim.export import audit_link, link_contact   # the engine: after parsing
    return lambda args: link_contact(args.model, args.link, args.timestep), audit_link


def _coupled(engine, target, model):
    """The e(v) the coupling (``contact_sim.coupling``) gives the model's sphere (its radius,
    mass and step; MuJoCo's integrator) with the target's contact, at the target's speeds."""
    from contact_sim.coupling import engine_restitution     # the engine: when run
    return engine_restitution(engine, target.contact, model.radius, model.mass, target.speeds,
                              model.timestep, getattr(model, 'integrator', None))


# engine -> (read the model's contact and measure its e(v), imported when run; the option
# naming the sphere)
AUDITS = {'mujoco': (_mujoco, '--geom'), 'pybullet': (_pybullet, '--link')}


def add_parser(sub):
    """Register the subcommand on the subparsers ``sub``."""
    p = contact_command(
        sub, 'audit',
        help="the e(v) a geom of a MuJoCo model or a link of a URDF gives, beside a target's",
        description="The e(v) of a sphere geom in the user's MuJoCo model (its solref, solimp,\n"
                    "the model's time step and integrator; the sphere thrown, gravity off, at a\n"
                    "plane with the contact attributes of the model's floor, the first plane on\n"
                    "the world body, so that MuJoCo combines the two as in the model), beside\n"
                    "the target contact's e(v), and the parameters `contact-sim export mujoco`\n"
                    'suggests for that time step.\n'
                    'pybullet: the sphere link of a URDF (its <contact> restitution, stiffness,\n'
                    'damping as PyBullet reads them) thrown at a plane of restitution 1 at\n'
                    '--timestep, beside the target, with `contact-sim export pybullet`\'s.',
        notes='\n\nexample:\n  contact-sim audit mujoco ball.xml --geom ball --law azad_featherstone '
              '--sphere steel\n      --plate cast_iron --radius 0.0127 --damping-factor 8.87e5\n'
              '  contact-sim audit pybullet ball.urdf --link ball --sphere steel --plate '
              'cast_iron\n      --radius 0.0127 --damping-factor 8.87e5\n')
    p.add_argument('engine', choices=list(AUDITS), help='the simulator of the model')
    p.add_argument('model', metavar='MODEL', help='the MJCF file (mujoco) or URDF (pybullet)')
    p.add_argument('--geom', metavar='NAME', help='mujoco: the sphere geom to audit')
    p.add_argument('--link', metavar='NAME', help='pybullet: the sphere link to audit')
    p.add_argument('--timestep', type=float, default=1.0 / 240.0,
                   help="pybullet: the step in s (default 1/240, PyBullet's); mujoco uses "
                        "the model's")
    p.add_argument('--law', choices=LAW_NAMES,
                   help='the target force law (default azad_featherstone)')
    p.add_argument('--coupled', action='store_true',
                   help='also the e(v) with the target contact coupled into the engine '
                        '(contact_sim.coupling, docs/coupling.md), at the model\'s step')
    add_speed_options(p, (0.1, 10.0), 10)
    accept_negative_numbers(p)
    p.set_defaults(run=run, params_file=None, plot=None)


def run(args):
    """Print the model's e(v) beside the target's, then the export's suggestion; exit 0."""
    functions, option = AUDITS[args.engine]
    if getattr(args, option[2:]) is None:
        raise ValueError(f'{option} is missing: audit {args.engine} needs {option} NAME, the '
                         'sphere to audit')
    names = {'model': 'MODEL', 'geom': '--geom', 'link': '--link', 'timestep': '--timestep'}
    read, measure = functions()
    try:
        contact = read(args)
    except ValueError as error:   # InputError: spelled as this command's arguments
        raise ValueError(error.render(names)) from None
    args.timestep = contact.timestep
    try:
        _, suggestion = export_of(args)
        target, refusal = suggestion.target, None
    except InputError as error:   # the suggestion at the model's step cannot hold the ball up
        if error.field != '--timestep':
            raise
        suggestion, refusal = None, error.render({'--timestep': "the model's timestep"})
        target = _target(args)
    model_e = measure(contact, target.speeds)
    coupled = None
    if getattr(args, 'coupled', False):
        try:
            coupled = _coupled(args.engine, target, contact)
        except ValueError as error:   # InputError (RK4): spelled as this command's arguments
            raise ValueError(error.render(names) if hasattr(error, 'render') else str(error)) \
                from None
    described = contact.describe()
    lines = described if isinstance(described, list) else [described]
    print(f'# {args.model}, {option[2:]} {getattr(args, option[2:])}: {lines[0]}')
    for line in lines[1:]:
        print(f'# {line}')
    error = float(np.max(np.abs(model_e - target.restitution)))
    coupled_error = '' if coupled is None else \
        f'; coupled: {float(np.max(np.abs(coupled - target.restitution))):.4f}'
    if refusal is not None:
        print(f'# model e measured (gravity off); max |error| = {error:.4f}; no suggestion: '
              f'{refusal}{coupled_error}')
    else:
        print(f'# model e measured (gravity off); max |error| = {error:.4f}; the export\'s '
              f'suggestion: {suggestion.max_abs_error:.4f}{coupled_error}')
    print(f'# {"speed (m/s)":>13} {"target e":>10} {"model e":>10} {"error":>10}'
          + ('' if suggestion is None else f' {"suggested":>10}')
          + ('' if coupled is None else f' {"coupled":>10}'))
    suggested = (np.full(len(target.speeds), np.nan) if suggestion is None
                 else suggestion.engine_restitution)
    extra = coupled if coupled is not None else [None] * len(target.speeds)
    for v, t, m, s, c in zip(target.speeds, target.restitution, model_e, suggested, extra):
        print(f'{v:15.6g} {t:10.5f} {m:10.5f} {m - t:+10.5f}'
              + ('' if suggestion is None else f' {s:10.5f}')
              + ('' if c is None else f' {c:10.5f}'))
    if suggestion is not None:
        print('# the suggestion:')
        print_scene(suggestion)
        print_snippet(suggestion)
    return 0


def _target(args):
    """The target the options describe, without an export."""
    from contact_sim.cli.contact import build_setup
    from contact_sim.cli.export import bounded_speeds
    from contact_sim.export import make_target
    from contact_sim.model import get_law
    law = get_law(args.law or 'azad_featherstone')
    setup = build_setup(args, [law])
    return make_target(setup.contacts[law.name], setup.mass, args.radius, bounded_speeds(args))
