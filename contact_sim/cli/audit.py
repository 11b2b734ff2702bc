"""`contact-sim audit mujoco MODEL.xml --geom NAME`: the e(v) a sphere geom of a user's MuJoCo
model gives (MuJoCo run: the sphere thrown at a plane, gravity off), beside a target contact's,
with the export's suggestion for the model's time step."""
import numpy as np

from contact_sim.cli.export import export_of, print_snippet
from contact_sim.cli.restitution import add_speed_options
from contact_sim.cli.options import LAW_NAMES, contact_command
from contact_sim.export import audit, geom_contact


def add_parser(sub):
    """Register the subcommand on the subparsers ``sub``."""
    p = contact_command(
        sub, 'audit',
        help="the e(v) a geom of a MuJoCo model gives, beside a target contact's",
        description="The e(v) of a sphere geom in the user's MuJoCo model (its solref, solimp,\n"
                    "the model's time step and integrator; the sphere thrown at a plane at\n"
                    "MuJoCo's defaults, gravity off), beside the target contact's e(v), and the\n"
                    'parameters `contact-sim export mujoco` suggests for that time step.',
        notes='\n\nexample:\n  contact-sim audit mujoco ball.xml --geom ball --law azad_featherstone '
              '--sphere steel\n      --plate cast_iron --radius 0.0127 --damping-factor 8.87e5\n')
    p.add_argument('engine', choices=['mujoco'], help='the simulator of the model')
    p.add_argument('model', metavar='MODEL.xml', help='the MJCF file')
    p.add_argument('--geom', required=True, metavar='NAME', help='the sphere geom to audit')
    p.add_argument('--law', choices=LAW_NAMES,
                   help='the target force law (default azad_featherstone)')
    add_speed_options(p, (0.1, 10.0), 10)
    p.set_defaults(run=run, params_file=None, plot=None)


def run(args):
    """Print the model's e(v) beside the target's, then the export's suggestion; exit 0."""
    names = {'model': 'MODEL.xml', 'geom': '--geom'}
    try:
        contact = geom_contact(args.model, args.geom)
    except ValueError as error:   # InputError: spelled as this command's arguments
        raise ValueError(error.render(names)) from None
    args.timestep = contact.timestep
    _, suggestion = export_of(args)
    target = suggestion.target
    model_e = audit(contact, target.speeds)
    print(f'# {args.model}, geom {args.geom}: solref = {list(contact.solref)}, solimp = '
          f'{list(contact.solimp)}, timestep = {contact.timestep:g} s, integrator '
          f'{contact.integrator}, R = {contact.radius:g} m, m = {contact.mass:.6g} kg')
    print(f'# model e measured; max |error| = '
          f'{float(np.max(np.abs(model_e - target.restitution))):.4f}; the export\'s '
          f'suggestion: {suggestion.max_abs_error:.4f}')
    print(f'# {"speed (m/s)":>13} {"target e":>10} {"model e":>10} {"error":>10} '
          f'{"suggested":>10}')
    for v, t, m, s in zip(target.speeds, target.restitution, model_e,
                          suggestion.engine_restitution):
        print(f'{v:15.6g} {t:10.5f} {m:10.5f} {m - t:+10.5f} {s:10.5f}')
    print_snippet(suggestion)
    return 0
