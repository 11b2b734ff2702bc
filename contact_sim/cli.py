"""`contact-sim`: a thin command line over the core library (no ROS)."""
import argparse
import sys

from .materials import MATERIALS


def _materials(args):
    print(f'{"name":<10} {"E (GPa)":>9} {"nu":>6} {"rho (kg/m3)":>12}  source')
    for m in MATERIALS.values():
        print(f'{m.name:<10} {m.youngs_modulus / 1e9:9.3g} {m.poisson_ratio:6.2f} '
              f'{m.density:12.0f}  {m.source}')
    return 0


def build_parser():
    parser = argparse.ArgumentParser(prog='contact-sim', description=__doc__)
    sub = parser.add_subparsers(dest='command', required=True)
    sub.add_parser('materials', help='list the material library with sources').set_defaults(
        run=_materials)
    return parser


def main(argv=None):
    args = build_parser().parse_args(argv)
    try:
        return args.run(args)
    except ValueError as error:
        print(f'contact-sim: error: {error}', file=sys.stderr)
        return 2


if __name__ == '__main__':
    sys.exit(main())
