"""Hostile inputs to the impact layer (issue 17): each refused as an InputError naming the
argument and its range, or computed right; none a traceback, a numpy repr or a RuntimeWarning."""
import math
import warnings

import numpy as np
import pytest

import contact_sim as cs

C = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)
M = 0.066
V = [0.5, 1.0, 2.0, 3.0]
E = [0.8, 0.75, 0.7, 0.66]


@pytest.mark.parametrize('mass, speed, field', [
    (1e308, 1.0, 'mass'), (0.066, 1e308, 'speed'), (0.066, 1e-308, 'speed')])
def test_simulate_impact_refuses_extremes_naming_the_argument(mass, speed, field):
    # reproduced: e = 1 and a 5.1e119 s contact; OverflowError; 'a contact phase needs motion'
    with pytest.raises(cs.InputError, match=rf'^{field} = .*allowed') as info:
        cs.simulate_impact(C, mass, speed)
    assert info.value.field == field


@pytest.mark.parametrize('law, k, lam, mass, speed', [
    ('hunt_crossley', 1.0, 1.0, 1e9, 2e-164), ('azad_featherstone', 4.97e-4, 0.0, 7.83e4, 2.2e-164),
    ('lee_wang', 5.5e-4, 6.7e53, 2.0e4, 3.2e-163)])
def test_a_speed_whose_square_underflows_is_refused_as_for_an_array(law, k, lam, mass, speed):
    # reproduced (a reviewer's random search): the one-speed check's m v v / k stayed > 0 where
    # the array check's m v**2 / k is 0, and the phase refused 'penetration_rate = 0' unnamed
    contact = cs.Contact(cs.LAWS[law], k, lam)
    with pytest.raises(cs.InputError, match=r'^speed = .*allowed') as info:
        cs.simulate_impact(contact, mass, speed)
    assert info.value.field == 'speed'
    with pytest.raises(cs.InputError, match=r'^speeds = .*allowed'):
        cs.restitution(contact, mass, [speed])


@pytest.mark.parametrize('function', [cs.restitution, cs.contact_duration, cs.peak_force,
                                      cs.max_penetration])
@pytest.mark.parametrize('speeds', [
    'abc', None, 1 + 2j, np.array([1.0 + 1j]), np.array(['2020-01-01'], dtype='datetime64[D]'),
    np.ma.masked_array([1.0, -1.0], [False, True]), [1.0, 'x'], True])
def test_restitution_and_its_siblings_take_real_finite_speeds_only(function, speeds):
    # reproduced: ValueError/TypeError tracebacks, complex speeds with the imaginary part
    # dropped, datetime64 days read as m/s, the mask of a masked array ignored
    with pytest.raises(cs.InputError, match=r'^speeds\b') as info:
        function(C, M, speeds)
    assert info.value.field == 'speeds'


@pytest.mark.parametrize('bad', [math.nan, -1.0, 0.0, math.inf])
def test_a_bad_speed_is_named_speeds_as_the_argument_is(bad):
    # reproduced: the message said 'speed', the argument is 'speeds'
    with pytest.raises(cs.InputError, match=r'^speeds = .* allowed 0 < speeds'):
        cs.restitution(C, M, [1.0, bad])


@pytest.mark.parametrize('contact, mass, field', [
    (cs.Contact(cs.AZAD_FEATHERSTONE, 1e300, 1e5), M, 'stiffness'),
    (cs.Contact(cs.AZAD_FEATHERSTONE, 1e-300, 1e5), M, 'stiffness'),
    (cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e300), M, 'damping'),
    (C, 1e300, 'mass')])
def test_restitution_refuses_what_drop_refuses(contact, mass, field):
    # reproduced: e = 1 for k = 1e300 or m = 1e300 where check_drop refuses them
    with pytest.raises(cs.InputError) as fast:
        cs.restitution(contact, mass, 1.0)
    with pytest.raises(cs.InputError) as drop:
        cs.check_drop(contact, mass, 9.81, 1.0, 0.0)
    assert fast.value.field == drop.value.field == field
    assert 'allowed' in str(fast.value) and 'inf' not in str(fast.value).split('allowed')[1]


def test_the_core_refuses_a_law_name_with_one_error_naming_the_law_field():
    # names are resolved by the front ends (cs.get_law, cs.LAWS) and by build_contact only
    calls = [lambda law: cs.Contact(law, 1e10, 1e5),
             lambda law: cs.Contact.from_materials(law, 'steel', 'cast_iron', 0.0127),
             lambda law: cs.damping_for_restitution(law, 1e10, M, 0.7, 1.0),
             lambda law: cs.fit_damping(law, 1e10, M, [1.0, 2.0], [0.8, 0.75])]
    for call in calls:
        for name in ('azad_featherstone', 'no_such_law'):
            with pytest.raises(cs.InputError, match=r"law = '%s' is a name: allowed a ContactLaw "
                               r"\(resolve a name with cs\.get_law" % name) as refused:
                call(name)
            assert refused.value.field == 'law'
        with pytest.raises(cs.InputError, match='law = 3 is not a ContactLaw') as refused:
            call(3)
        assert refused.value.field == 'law'
    with pytest.raises(cs.InputError, match="laws = 'linear' is a name") as refused:
        cs.compare_laws(1e10, M, [1.0, 2.0], [0.8, 0.75], laws=['linear'])
    assert refused.value.field == 'laws'
    assert cs.build_contact('linear', stiffness=1e5, damping=2.0).law is cs.LINEAR


@pytest.mark.parametrize('speeds, restitutions, field', [
    ([1.0, 2.0], [0.8], 'restitutions'), ([1.0, 2j], [0.8, 0.7], 'speeds'),
    ([1.0, 2.0], ['a', 0.7], 'restitutions')])
def test_fit_damping_refuses_bad_data_as_input_errors(speeds, restitutions, field):
    # reproduced: a plain ValueError for the length mismatch, TypeError for complex
    with pytest.raises(cs.InputError) as info:
        cs.fit_damping(cs.AZAD_FEATHERSTONE, 1e10, M, speeds, restitutions)
    assert info.value.field == field


@pytest.mark.parametrize('sigma', [1e-300, 1e300])
def test_equal_uncertainties_of_any_size_give_the_equal_weights_fit(sigma):
    # reproduced: lambda = 107475 instead of 101246 and the interval (nan, nan)
    plain = cs.fit_damping(cs.AZAD_FEATHERSTONE, 1e10, M, V, E)
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        weighted = cs.fit_damping(cs.AZAD_FEATHERSTONE, 1e10, M, V, E,
                                  uncertainties=np.full(4, sigma))
    assert weighted.damping == pytest.approx(plain.damping, rel=1e-9)
    assert np.all(np.isfinite(weighted.confidence_interval))
    assert weighted.confidence_interval == pytest.approx(plain.confidence_interval, rel=1e-6)


def test_a_fit_of_points_all_at_or_above_one_has_no_zero_width_interval():
    # reproduced: lambda = 0 with the interval [0, 0]
    fit = cs.fit_damping(cs.AZAD_FEATHERSTONE, 1e10, M, [1.0, 2.0, 3.0], [1.01, 1.02, 1.0])
    assert fit.damping == 0.0
    assert all(math.isnan(x) for x in fit.confidence_interval)


@pytest.mark.parametrize('laws', [0.0, 'azad_featherstone', cs.AZAD_FEATHERSTONE])
def test_compare_laws_refuses_laws_that_are_not_a_list(laws):
    # reproduced: "'float' object is not iterable"
    with pytest.raises(cs.InputError, match='^laws = '):
        cs.compare_laws(1e10, M, V, E, laws=laws)


def test_no_message_shows_a_numpy_repr():
    # reproduced: "count = np.float64(2.5) is not an integer" (and "times[2] = np.float64(...)")
    with pytest.raises(cs.InputError) as info:
        cs.predict_bounces(C, M, height=1.0, count=np.float64(2.5))
    assert 'np.' not in str(info.value) and 'count = 2.5 is not an integer' in str(info.value)
    with pytest.raises(cs.InputError) as info:
        cs.simulate_impact(C, np.float64(-1.0), 1.0)
    assert 'np.' not in str(info.value) and 'mass = -1.0' in str(info.value)


@pytest.mark.parametrize('stiffness, mass, field', [(1e308, M, 'stiffness'),
                                                   (1e-308, M, 'stiffness'),
                                                   (1e10, 1e308, 'mass'), (1e10, 1e-308, 'mass')])
def test_fit_damping_names_an_extreme_contact(stiffness, mass, field):
    # found by scripts/hostile_inputs.py: KeyError 'stiffness'
    with pytest.raises(cs.InputError) as info:
        cs.fit_damping(cs.AZAD_FEATHERSTONE, stiffness, mass, V, E)
    assert info.value.field == field
