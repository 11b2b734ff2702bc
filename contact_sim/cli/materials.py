"""`contact-sim materials`: the material library with its sources."""
from contact_sim.model import MATERIALS


def add_parser(sub):
    """Register the subcommand on the subparsers ``sub``."""
    sub.add_parser('materials', help='list the material library with sources').set_defaults(
        run=run)


def run(args):
    """Print one line per library material: E (GPa), Poisson ratio, density (kg/m^3), source."""
    print(f'{"name":<10} {"E (GPa)":>9} {"nu":>6} {"rho (kg/m3)":>12}  source')
    for m in MATERIALS.values():
        print(f'{m.name:<10} {m.youngs_modulus / 1e9:9.3g} {m.poisson_ratio:6.2f} '
              f'{m.density:12.0f}  {m.source}')
    return 0
