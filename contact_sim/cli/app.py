"""`contact-sim`: a thin command line over the core library (no ROS).

Subcommands: materials, restitution, drop, fit, bounces, export, audit.  Run
`contact-sim <subcommand> --help`.  Without contact options, restitution, drop, fit and export
use the default contact (the node's: a steel ball, R1 = 12.7 mm, on cast iron, the
azad_featherstone law, lambda* = 8.87e5) and say so in their first output line.
"""
import argparse
import importlib
import sys

from contact_sim.cli import errors, outputs, plotting
from contact_sim.cli.contact import use_default_contact
from contact_sim.cli.options import EXIT_HELP, refuse_repeats

# the subcommand modules, in the order of --help
SUBCOMMANDS = ('materials', 'restitution', 'drop', 'fit', 'bounces', 'export', 'audit')


def build_parser(only=None):
    """The `contact-sim` parser: each subcommand module registers itself (``add_parser``).

    With ``only`` (a subcommand name), only that module is imported and registered in full;
    the others are names only, so that parsing its arguments (and refusing them) does not
    import what the other subcommands need (the drop engine, calibration, the exporters)."""
    parser = argparse.ArgumentParser(prog='contact-sim', description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=EXIT_HELP)
    sub = parser.add_subparsers(dest='command', required=True)
    for name in SUBCOMMANDS:
        if only is None or name == only:
            importlib.import_module(f'contact_sim.cli.{name}').add_parser(sub)
        else:
            sub.add_parser(name)
    return refuse_repeats(parser)   # a repeated option is refused, not silently overridden


def requested(argv):
    """The subcommand ``argv`` asks for (its first word), or None (e.g. only --help)."""
    word = next((a for a in argv if not a.startswith('-')), None)
    return word if word in SUBCOMMANDS else None


def main(argv=None):
    """Run `contact-sim` on ``argv`` (default ``sys.argv[1:]``); returns the exit status."""
    argv = sys.argv[1:] if argv is None else list(argv)
    args = build_parser(requested(argv)).parse_args(argv)
    try:
        outputs.check_outputs(args)   # every output file, before any work
        if getattr(args, 'plot', None) is not None:
            plotting.load_pyplot()
        use_default_contact(args)   # no contact given: the node's default one, said so
        return args.run(args)
    except errors.REPORTED as error:
        return errors.report(error, args)


if __name__ == '__main__':
    sys.exit(main())
