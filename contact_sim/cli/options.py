"""The options every `contact-sim` subcommand shares, declared once: the contact options (materials
or k, mass, damping), the repeatable --law, --plot, and the help texts that explain them."""
import argparse
import math

from contact_sim.model import LAWS, MATERIALS, get_law
from contact_sim.validation import InputError

LAW_NAMES = list(LAWS)  # azad_featherstone, hunt_crossley, lee_wang, linear

LINEAR_SKIPPED = """\
with
               materials and no --stiffness the linear law is skipped with a note on stderr
               (an error if it is the only law asked for); give --stiffness to include it."""

CONTACT_HELP = """\
the contact (all SI units):
  stiffness k  --stiffness K, else Hertz k = (4/3) E* sqrt(R) from --sphere, --plate and
               --radius (eqs. 5, 6, 10).  The Hertz k is for the n = 1.5 laws only: {linear}
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


def law_list(args, default):
    """The laws chosen with the repeatable --law (``ContactLaw`` objects), in order, without
    duplicates; ``default`` (law names) when none is given."""
    return [get_law(name) for name in dict.fromkeys(args.law or default)]


def contact_options(damping=True):
    """A parent parser of the contact options; --damping and --damping-factor with ``damping``."""
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
                          help=f"{body} Young's modulus in Pa, 1 <= E")
        mats.add_argument(f'--{body}-poisson', type=float, metavar='NU',
                          help=f'{body} Poisson ratio, -1 < NU < 0.5')
        mats.add_argument(f'--{body}-density', type=float, metavar='RHO',
                          help=f'{body} density in kg/m^3, 0.001 <= RHO' + (
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


def plot_option(parser, what):
    """--plot OUT.png, whose help says the figure shows ``what``."""
    parser.add_argument('--plot', metavar='OUT.png',
                        help=f'also write a figure of {what} (needs matplotlib)')


def contact_command(sub, name, help, description, notes, damping=True,
                    linear=LINEAR_SKIPPED):
    """A subcommand that takes the contact options; its epilog explains them, then ``notes``;
    ``linear`` says what becomes of the linear law with materials and no --stiffness."""
    return sub.add_parser(
        name, parents=[contact_options(damping=damping)],
        formatter_class=argparse.RawDescriptionHelpFormatter, help=help, description=description,
        epilog=CONTACT_HELP.format(linear=linear) + (DAMPING_HELP if damping else '') + notes
        + EXIT_HELP)


# -- options given once: a repeated option is refused, not silently overridden ----------------
GIVEN = 'given_options'   # the namespace attribute: the dests given on the command line


class _Once:
    """Mixed into an option's action: records its dest in ``args.given_options`` and refuses a
    second occurrence unless the action is repeatable (append, count); a repeatable option
    given twice with the same value is refused too."""

    def __call__(self, parser, namespace, values, option_string=None):
        given = getattr(namespace, GIVEN, None)
        if given is None:
            given = set()
            setattr(namespace, GIVEN, given)
        repeatable = isinstance(self, (argparse._AppendAction, argparse._CountAction))
        if self.dest in given and not repeatable:
            raise argparse.ArgumentError(self, 'given twice: allowed once (the last would '
                                               'silently win)')
        if isinstance(self, argparse._AppendAction) and self.dest in given \
                and values in (getattr(namespace, self.dest, None) or ()):
            raise argparse.ArgumentError(self, f'{values!r} is given twice: allowed each once')
        given.add(self.dest)
        super().__call__(parser, namespace, values, option_string)


def refuse_repeats(parser):
    """Make every option of ``parser`` (and of its subcommands) record itself in
    ``args.given_options`` and refuse being given twice (``--law a --law b`` where --law takes
    one law); repeatable options (``action='append'``) stay repeatable."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                refuse_repeats(sub)
        elif action.option_strings and not isinstance(
                action, (argparse._HelpAction, argparse._VersionAction, _Once)):
            action.__class__ = type('Once' + type(action).__name__, (_Once, type(action)), {})
    return parser


def given(args, dest):
    """True when the option stored in ``dest`` was given on the command line."""
    return dest in (getattr(args, GIVEN, None) or ())


def refuse_beside(args, dest, option, other, why):
    """Refuse ``option`` (stored in ``dest``) given together with ``other``, ``why`` it would be
    ignored."""
    if given(args, dest):
        raise InputError(dest, getattr(args, dest), '%s = {value} is given with %s, which %s: '
                         'allowed one of them' % (option, other, why))
