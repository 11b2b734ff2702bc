"""Hostile inputs of issue 34: text, bytes and booleans are not numbers anywhere a number is asked
for (``validation.require_real``), as speeds already were; each is refused with an InputError
naming the argument the caller wrote."""
import pytest

import contact_sim as cs

C = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)

# (the call with the bad value as x, the field it must name)
CALLS = [
    (lambda x: cs.Contact(cs.AZAD_FEATHERSTONE, x, 1e5), 'stiffness'),
    (lambda x: cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, x), 'damping'),
    (lambda x: cs.Material('x', x, 0.3, 1000.0), 'youngs_modulus'),
    (lambda x: cs.Material('x', 1e9, x, 1000.0), 'poisson_ratio'),
    (lambda x: cs.build_contact('azad_featherstone', stiffness=x, damping=1.0), 'stiffness'),
    (lambda x: cs.build_mass(sphere='steel', radius=x), 'radius'),
    (lambda x: cs.equivalent_radius(x, 0.01), 'radius'),
    (lambda x: cs.equivalent_radius(0.01, x), 'plate_radius'),
    (lambda x: cs.simulate_impact(C, x, 1.0), 'mass'),
    (lambda x: cs.simulate_impact(C, 0.066, 1.0, gravity=x), 'gravity'),
    (lambda x: cs.restitution(C, x, 1.0), 'mass'),
    (lambda x: cs.restitution(C, 0.066, [1.0, x]), 'speeds'),
    (lambda x: cs.simulate_drop(C, 0.066, x, duration=0.1), 'height'),
    (lambda x: cs.simulate_drop(C, 0.066, 1.0, duration=0.1, gravity=x), 'gravity'),
    (lambda x: cs.simulate_drop(C, 0.066, 1.0, duration=x), 'duration'),
    (lambda x: cs.FlightPath(1.0, 0.0, x), 'gravity'),
    (lambda x: cs.damping_group(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, x), 0.066, 1.0), 'damping'),
    (lambda x: cs.drop.SinusoidalPlate(x, 20.0, 0.0), 'amplitude'),
]
# reproduced: gravity='9.81' ran at 9.81 m/s², gravity=b'1' at 1 m/s², '\u0669' (Arabic-Indic
# nine) at 9 m/s², Contact(law, '1e10', ...) accepted; a boolean among speeds read as 1 m/s
NOT_NUMBERS = ['9.81', b'1', '\u0669', bytearray(b'1'), True]


@pytest.mark.parametrize('bad', NOT_NUMBERS, ids=repr)
@pytest.mark.parametrize('call, field', CALLS, ids=[f for _, f in CALLS])
def test_text_bytes_and_booleans_are_not_numbers(call, field, bad):
    with pytest.raises(cs.InputError) as info:
        call(bad)
    assert info.value.field == field
    assert str(info.value).startswith(f'{field}')
    assert 'not a' in str(info.value) or 'holds' in str(info.value)   # an array's element


@pytest.mark.parametrize('args, field', [
    ((float('nan'), 0.01), 'radius'), ((0.01, float('nan')), 'plate_radius'),
    ((-1.0, 0.01), 'radius'), ((0.01, 0.0), 'plate_radius')])
def test_equivalent_radius_names_the_argument_given(args, field):
    # reproduced: a message naming one radius for the other argument
    with pytest.raises(cs.InputError, match=rf'^{field} = ') as info:
        cs.equivalent_radius(*args)
    assert info.value.field == field
    with pytest.raises(cs.InputError, match=rf'^{field} = '):   # by keyword too
        cs.equivalent_radius(radius=args[0], plate_radius=args[1])


def test_the_default_contact_is_the_nodes_and_the_readmes():
    from contact_sim.model import DEFAULT_CONTACT
    contact = DEFAULT_CONTACT.contact()
    readme = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron', radius=0.0127,
                                       damping_factor=8.87e5)
    assert contact == readme
    assert DEFAULT_CONTACT.mass() == cs.build_mass(sphere='steel', radius=0.0127)


@pytest.mark.parametrize('args, field', [((5e-324, 0.01), 'radius'), ((0.01, 5e-324), 'plate_radius'),
                                         ((0.01, 1e-305), 'plate_radius')])
def test_a_radius_whose_reciprocal_overflows_is_refused_by_name(args, field):
    # reproduced (this branch's probe): --plate-radius 5e-324 refused as '--radius = 0.0'
    with pytest.raises(cs.InputError, match=rf'^{field} = .* allowed 1e-300 <= {field}'):
        cs.equivalent_radius(*args)


@pytest.mark.parametrize('modulus, density, field', [(5e-324, 7850.0, 'youngs_modulus'),
                                                     (0.5, 7850.0, 'youngs_modulus'),
                                                     (2e11, 5e-324, 'density')])
def test_a_material_below_the_floors_is_refused(modulus, density, field):
    # reproduced: E = 5e-324 refused as 'effective_modulus = 0.0', rho = 5e-324 as the radius
    with pytest.raises(cs.InputError, match=rf'^{field} = ') as info:
        cs.Material('x', modulus, 0.3, density)
    assert info.value.field == field


@pytest.mark.parametrize('confidence', [0.9999999999999999, 1.0, 0.0])
def test_a_confidence_whose_interval_is_infinite_is_refused(confidence):
    # reproduced (this branch's probe): 0.9999999999999999 printed the interval [0, inf]
    with pytest.raises(cs.InputError, match=r'^confidence = .* allowed 0 < confidence <= 0.999999'):
        cs.fit_damping(cs.AZAD_FEATHERSTONE, 1e10, 0.066, [0.5, 1, 2], [0.8, 0.75, 0.7],
                       confidence=confidence)
