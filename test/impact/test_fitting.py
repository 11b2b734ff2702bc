"""Damping from restitution: the exact inverse, least-squares fits, law comparison."""
import math

import numpy as np
import pytest

import contact_sim as cs

K, M = 1.1e10, 0.0675   # steel ball (R = 12.7 mm) on cast iron, roughly


@pytest.mark.parametrize('law', list(cs.LAWS.values()), ids=list(cs.LAWS))
@pytest.mark.parametrize('e', [0.02, 0.5, 0.95, 0.999])
def test_damping_for_restitution_inverts_the_exact_restitution(law, e):
    k = 1e7 if law is cs.LINEAR else K
    lam = cs.damping_for_restitution(law, k, M, e, 0.8)
    assert lam > 0
    assert cs.simulate_impact(cs.Contact(law, k, lam), M, 0.8).restitution == pytest.approx(e, abs=1e-8)


def test_damping_for_restitution_of_one_is_zero_and_bad_values_are_named():
    assert cs.damping_for_restitution(cs.AZAD_FEATHERSTONE, K, M, 1.0, 1.0) == 0.0
    with pytest.raises(ValueError, match=r'restitution = 1\.5 is out of range: allowed 0 < restitution <= 1'):
        cs.damping_for_restitution(cs.AZAD_FEATHERSTONE, K, M, 1.5, 1.0)
    with pytest.raises(ValueError, match=r'speed = -1\.0 is out of range'):
        cs.damping_for_restitution(cs.AZAD_FEATHERSTONE, K, M, 0.5, -1.0)


def test_fit_recovers_the_damping_of_model_data_exactly():
    speeds = np.geomspace(0.05, 5.0, 12)
    truth = cs.Contact(cs.AZAD_FEATHERSTONE, K, 7.5e4)
    fit = cs.fit_damping(cs.AZAD_FEATHERSTONE, K, M, speeds, cs.restitution(truth, M, speeds))
    assert fit.damping == pytest.approx(7.5e4, rel=1e-7)
    assert fit.rms_residual < 1e-9
    np.testing.assert_allclose(fit.pointwise_damping, 7.5e4, rtol=1e-7)
    assert fit.pointwise_spread == pytest.approx(1.0, abs=1e-6)
    lo, hi = fit.confidence_interval
    assert lo <= fit.damping <= hi and hi - lo < 1e-3 * fit.damping


def test_fit_with_noise_has_a_confidence_interval_that_covers_the_truth():
    rng = np.random.default_rng(5)
    speeds = np.geomspace(0.05, 5.0, 30)
    truth = cs.Contact(cs.AZAD_FEATHERSTONE, K, 7.5e4)
    data = cs.restitution(truth, M, speeds) + rng.normal(0.0, 0.005, speeds.size)
    fit = cs.fit_damping(cs.AZAD_FEATHERSTONE, K, M, speeds, data)
    lo, hi = fit.confidence_interval
    assert lo < 7.5e4 < hi
    assert fit.rms_residual == pytest.approx(np.sqrt(np.mean(fit.residuals ** 2)))
    assert fit.residuals.shape == (30,) and fit.pointwise_damping.shape == (30,)
    # the least-squares optimum: moving λ either way makes the squared error worse
    for factor in (0.99, 1.01):
        other = cs.restitution(cs.Contact(cs.AZAD_FEATHERSTONE, K, fit.damping * factor), M, speeds)
        assert np.sum((other - data) ** 2) > np.sum(fit.residuals ** 2)


def test_compare_laws_ranks_the_generating_law_first():
    speeds = np.geomspace(0.05, 5.0, 15)
    data = cs.restitution(cs.Contact(cs.AZAD_FEATHERSTONE, K, 7.5e4), M, speeds)
    fits = cs.compare_laws({cs.AZAD_FEATHERSTONE: K, cs.HUNT_CROSSLEY: K, cs.LEE_WANG: K,
                            cs.LINEAR: 1e7}, M, speeds, data)
    assert [f.law.name for f in fits][0] == 'azad_featherstone'
    assert fits[0].rms_residual < 1e-9 < fits[1].rms_residual
    hc = next(f for f in fits if f.law.name == 'hunt_crossley')
    assert hc.pointwise_spread > 5.0        # Hunt-Crossley needs a very different λ per point
    assert len(fits) == 4


@pytest.mark.parametrize('speeds, restitutions, pattern', [
    ([1.0, 2.0], [0.5], r'speeds and restitutions have 2 and 1 values'),
    ([1.0, -2.0], [0.5, 0.4], r'speeds\[1\] = -2\.0 is out of range: allowed 0 < speed < inf'),
    ([1.0, 2.0], [0.5, 0.0], r'restitutions\[1\] = 0\.0 is out of range: allowed 0 < restitution'),
    ([1.0, float('nan')], [0.5, 0.4], r'speeds\[1\] = nan is not finite'),
    ([], [], r'speeds is empty'),
])
def test_fit_rejects_bad_data_naming_the_point(speeds, restitutions, pattern):
    with pytest.raises(ValueError, match=pattern):
        cs.fit_damping(cs.AZAD_FEATHERSTONE, K, M, speeds, restitutions)


def test_fit_of_a_custom_law_gives_back_its_contact():
    law = cs.ContactLaw('q2', 1.5, 0.5, 2.0)
    speeds = np.array([0.2, 0.5, 1.0])
    data = np.array([cs.simulate_impact(cs.Contact(law, K, 3e4), M, v).restitution for v in speeds])
    fit = cs.fit_damping(law, K, M, speeds, data)
    assert fit.contact() == cs.Contact(law, K, fit.damping)
    assert fit.damping == pytest.approx(3e4, rel=1e-6)


def test_confidence_interval_stays_positive_for_scattered_data():
    speeds = np.geomspace(0.05, 5.0, 6)
    data = np.array([0.9, 0.3, 0.85, 0.2, 0.8, 0.25])
    lo, hi = cs.fit_damping(cs.AZAD_FEATHERSTONE, K, M, speeds, data).confidence_interval
    assert 0 < lo < hi


def test_points_at_or_above_one_are_kept_and_flagged():
    """Noise near e = 1 (issue 8): accepted, flagged, and the fit and spread stay sensible."""
    k, m = 1e10, 0.066
    contact = cs.Contact(cs.AZAD_FEATHERSTONE, k, 2e4)
    v = np.array([0.1, 0.3, 1.0, 3.0])
    e = cs.restitution(contact, m, v)
    noisy = e.copy()
    noisy[0] = 1.003
    fit = cs.fit_damping(cs.AZAD_FEATHERSTONE, k, m, v, noisy)
    assert fit.flagged == (0,)
    assert math.isnan(fit.pointwise_damping[0])
    assert fit.damping == pytest.approx(2e4, rel=0.2)
    assert math.isfinite(fit.pointwise_spread) and fit.pointwise_spread < 1.01
    elastic = cs.fit_damping(cs.AZAD_FEATHERSTONE, k, m, [1.0, 2.0], [1.0, 1.01])
    assert elastic.damping == 0.0 and elastic.flagged == (0, 1)


def test_robust_loss_and_uncertainties():
    k, m = 1e10, 0.066
    contact = cs.Contact(cs.AZAD_FEATHERSTONE, k, 2e4)
    v = np.geomspace(0.1, 5.0, 12)
    e = cs.restitution(contact, m, v) + np.random.default_rng(1).normal(0.0, 1e-3, v.size)
    outlier = e.copy()
    outlier[5] -= 0.08
    plain = cs.fit_damping(cs.AZAD_FEATHERSTONE, k, m, v, outlier)
    robust = cs.fit_damping(cs.AZAD_FEATHERSTONE, k, m, v, outlier, loss='soft_l1')
    assert abs(robust.damping / 2e4 - 1) < 0.3 * abs(plain.damping / 2e4 - 1)
    assert robust.weights[5] < 0.2 and np.all(np.delete(robust.weights, 5) > 0.5)
    # a point with a large stated uncertainty hardly counts
    sigma = np.full(v.size, 1e-3)
    sigma[5] = 1.0
    weighted = cs.fit_damping(cs.AZAD_FEATHERSTONE, k, m, v, outlier, uncertainties=sigma)
    assert weighted.damping == pytest.approx(robust.damping, rel=0.05)
    with pytest.raises(ValueError, match=r'uncertainties\[0\] = 0.0 is out of range'):
        cs.fit_damping(cs.AZAD_FEATHERSTONE, k, m, v, e, uncertainties=np.zeros(v.size))
    with pytest.raises(ValueError, match='loss = .l3. is unknown'):
        cs.fit_damping(cs.AZAD_FEATHERSTONE, k, m, v, e, loss='l3')


def test_fit_cli_accepts_noise_above_one_uncertainties_and_loss(tmp_path, capsys):
    from contact_sim import cli
    contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 2e4)
    v = np.array([0.05, 0.3, 1.0, 2.0, 3.0])
    e = cs.restitution(contact, 0.066, v)
    rows = ['speed,restitution,uncertainty,trial']
    for i, (vi, ei) in enumerate(zip(v, e)):
        ei = 1.001 if i == 0 else (ei - 0.05 if i == 3 else ei)
        rows.append(f'{vi},{ei},{0.5 if i == 3 else 0.001},{i}')
    path = tmp_path / 'points.csv'
    path.write_text('\n'.join(rows) + '\n')
    code = cli.main(['fit', str(path), '--stiffness', '1e10', '--mass', '0.066', '--law',
                     'azad_featherstone', '--loss', 'soft_l1'])
    out = capsys.readouterr().out
    assert code == 0
    assert 'point 1 (speed 0.05 m/s) has e = 1.001 >= 1' in out
    assert 'weighted by 1/uncertainty' in out and 'loss soft_l1' in out
    lam = float(next(ln for ln in out.splitlines() if ln.startswith('azad_featherstone: '))
                .split()[3])
    assert lam == pytest.approx(2e4, rel=0.1)


# -- issue 7: edges -------------------------------------------------------------------------
@pytest.mark.parametrize('speed', [1e300, 1e-300])
def test_damping_for_restitution_refuses_speeds_it_cannot_scale(speed):
    # reproduced: speed = 1e300 returned 0.0 and speed = 1e-300 returned inf
    with pytest.raises(ValueError, match=r'speed = .* is out of range') as info:
        cs.damping_for_restitution(cs.AZAD_FEATHERSTONE, 1e10, 0.066, 0.7, speed)
    assert info.value.field == 'speed'


def test_damping_for_restitution_only_returns_a_damping_restitution_accepts():
    # reproduced: e = 1e-9 gave a λ that restitution() then refused (zeta beyond 1e8)
    with pytest.raises(ValueError, match=r'restitution = 1e-09 is out of range for law '
                                         r'hunt_crossley: allowed (\S+) <= restitution') as info:
        cs.damping_for_restitution(cs.HUNT_CROSSLEY, 1e10, 0.066, 1e-9, 1.0)
    e_min = float(info.value.render().split('allowed ')[1].split(' ')[0])
    lam = cs.damping_for_restitution(cs.HUNT_CROSSLEY, 1e10, 0.066, e_min, 1.0)
    assert cs.restitution(cs.Contact(cs.HUNT_CROSSLEY, 1e10, lam), 0.066, 1.0) == \
        pytest.approx(e_min, rel=1e-6)


def test_compare_laws_with_a_partial_stiffness_mapping_names_the_missing_laws():
    # reproduced: KeyError: 'hunt_crossley'
    with pytest.raises(ValueError, match=r'stiffness has no value for hunt_crossley, lee_wang, '
                                         r'linear'):
        cs.compare_laws({cs.AZAD_FEATHERSTONE: K}, M, [1.0, 2.0], [0.7, 0.6])


def test_a_one_point_fit_has_no_confidence_interval():
    # reproduced: a zero-width interval (lambda, lambda) from one point
    fit = cs.fit_damping(cs.LEE_WANG, K, M, [1.0], [0.5])
    assert all(np.isnan(fit.confidence_interval))


@pytest.mark.parametrize('speed', [1e300, 1e-300])
def test_a_fit_to_a_point_out_of_range_names_that_point(speed):
    # reproduced: `math domain error`, `Optimization bounds must be finite scalars.`
    with pytest.raises(ValueError, match=r'speeds\[1\] = .* is out of range') as info:
        cs.fit_damping(cs.AZAD_FEATHERSTONE, K, M, [1.0, speed], [0.6, 0.5])
    assert info.value.field == 'speeds'


def test_points_above_one_still_have_their_speed_checked_and_named():
    # found in review: with e > 1 at that point the bad speed surfaced later as `speed = ...`
    with pytest.raises(ValueError, match=r'^speeds\[0\] = 1e\+300 is out of range'):
        cs.fit_damping(cs.AZAD_FEATHERSTONE, 1e9, 0.05, [1e300, 1.0], [1.05, 0.8])


def test_a_one_point_fit_keeps_its_flags_loss_and_weights():
    fit = cs.fit_damping(cs.AZAD_FEATHERSTONE, K, M, [1.0], [1.2])
    assert fit.flagged == (0,) and fit.damping == 0.0
    fit = cs.fit_damping(cs.AZAD_FEATHERSTONE, K, M, [1.0], [0.8], loss='huber')
    assert fit.loss == 'huber' and list(fit.weights) == [1.0]


def test_points_above_one_may_pull_the_fit_far_below_every_pointwise_damping():
    # found in review: the search stopped at its lower bound, 2e5 e^-3 = 9957, not the optimum
    v = np.linspace(0.5, 5.0, 6)
    e = cs.restitution(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 2e5), 0.066, v)
    e[1:] = 1.02
    fit = cs.fit_damping(cs.AZAD_FEATHERSTONE, 1e10, 0.066, v, e)
    grid = np.geomspace(1.0, 2e5, 3001)
    sse = [np.sum((cs.restitution(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, lam), 0.066, v) - e) ** 2)
           for lam in grid]
    assert fit.damping == pytest.approx(grid[int(np.argmin(sse))], rel=2e-3)
    assert fit.damping < 0.9 * 2e5 * math.exp(-3.0)
