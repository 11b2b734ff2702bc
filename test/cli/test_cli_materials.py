"""Command line: custom materials (--sphere-modulus ...) and drop --initial-velocity."""
import math

import pytest

import contact_sim as cs
from contact_sim import cli


def run(capsys, argv):
    code = cli.main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_custom_sphere_material_gives_the_hertz_stiffness_and_mass(capsys):
    code, out, _ = run(capsys, ['restitution', '--sphere-modulus', '2e9', '--sphere-poisson',
                                '0.4', '--sphere-density', '1100', '--plate', 'steel',
                                '--radius', '0.02', '--damping-factor', '1e5', '--law',
                                'azad_featherstone', '--speeds', '1'])
    assert code == 0
    nylon_like = cs.Material('custom', 2e9, 0.4, 1100.0)
    k = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, nylon_like, 'steel', 0.02).stiffness
    assert f'k = {k:.6e}' in out
    assert f'm = {cs.sphere_mass(1100.0, 0.02):.4g} kg (from the custom density)' in out


def test_library_material_with_one_value_changed(capsys):
    code, out, _ = run(capsys, ['restitution', '--sphere', 'steel', '--sphere-modulus', '190e9',
                                '--plate', 'cast_iron', '--plate-poisson', '0.3', '--radius',
                                '0.0127', '--damping-factor', '8.87e5', '--law',
                                'azad_featherstone', '--speeds', '1'])
    assert code == 0
    sphere = cs.Material('s', 190e9, 0.30, 7850.0)
    plate = cs.Material('p', 100e9, 0.3, 7300.0)
    k = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, sphere, plate, 0.0127).stiffness
    assert f'k = {k:.6e}' in out and 'steel (modified) sphere' in out


@pytest.mark.parametrize('argv, message', [
    (['--sphere-modulus', '2e9', '--plate', 'steel'], 'sphere_material is incomplete: give '
                                                      '--sphere-poisson'),
    (['--sphere-modulus=-2e9', '--sphere-poisson', '0.3', '--plate', 'steel'],
     '--sphere-modulus = -2000000000.0 is out of range'),
    (['--sphere', 'steel', '--plate', 'steel', '--plate-poisson', '0.7'],
     '--plate-poisson = 0.7 is out of range'),
])
def test_bad_custom_material_exits_2_naming_the_field(capsys, argv, message):
    code, out, err = run(capsys, ['restitution', '--radius', '0.02', '--mass', '0.03',
                                  '--damping', '1e4', '--law', 'azad_featherstone',
                                  '--speeds', '1'] + argv)
    assert code == 2 and out == '' and message in err and err.count('\n') == 1


def test_drop_initial_velocity(capsys):
    base = ['drop', '--stiffness', '1e10', '--damping', '1e5', '--mass', '0.066', '--gravity',
            '10', '--duration', '0.5']
    code, out, _ = run(capsys, base + ['--initial-velocity', '2'])
    assert code == 0 and 'at 2 m/s downward' in out
    first = next(line for line in out.splitlines() if line.strip().startswith('1 '))
    assert float(first.split()[2]) == pytest.approx(math.sqrt(4.0 + 2 * 10 * 1.0), rel=1e-5)
    code, out, err = run(capsys, base + ['--initial-velocity', 'nan'])
    assert code == 2 and '--initial-velocity = nan is not finite' in err
