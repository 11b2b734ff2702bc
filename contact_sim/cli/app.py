"""`contact-sim`: a thin command line over the core library (no ROS).

Subcommands: materials, restitution, drop, fit, bounces.  Run `contact-sim <subcommand> --help`.
"""
import argparse
import sys

from contact_sim.cli import (audit, bounces, drop, errors, export, fit, materials, outputs,
                             plotting, restitution)
from contact_sim.cli.options import EXIT_HELP

SUBCOMMANDS = (materials, restitution, drop, fit, bounces, export, audit)   # in the order of --help


def build_parser():
    """The `contact-sim` parser: each subcommand module registers itself (``add_parser``)."""
    parser = argparse.ArgumentParser(prog='contact-sim', description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=EXIT_HELP)
    sub = parser.add_subparsers(dest='command', required=True)
    for command in SUBCOMMANDS:
        command.add_parser(sub)
    return parser


def main(argv=None):
    """Run `contact-sim` on ``argv`` (default ``sys.argv[1:]``); returns the exit status."""
    args = build_parser().parse_args(argv)
    try:
        outputs.check_outputs(args)   # every output file, before any work
        if getattr(args, 'plot', None) is not None:
            plotting.load_pyplot()
        return args.run(args)
    except errors.REPORTED as error:
        return errors.report(error, args)


if __name__ == '__main__':
    sys.exit(main())
