"""Drake: without pydrake no e is claimed (the discrete step loses energy of its own that the law
does not have); the ball's properties against a ground of its own give the pair Drake's series
rule combines to."""
import pytest
from .test_export import steel_on_cast_iron

from contact_sim import cli
from contact_sim.export import drake_plant, export_contact


def _no_pydrake():
    raise ImportError("No module named 'pydrake'")


@pytest.mark.parametrize('timestep', [1e-3, 0.0])
def test_without_pydrake_nothing_is_claimed(monkeypatch, capsys, timestep):
    monkeypatch.setattr(drake_plant, '_pydrake', _no_pydrake)   # as without pydrake
    with pytest.raises(ImportError):
        export_contact('drake', steel_on_cast_iron(), timestep)
    code = cli.main(['export', 'drake', '--sphere', 'steel', '--plate', 'cast_iron', '--radius',
                     '0.0127', '--damping-factor', '8.87e5', '--timestep', repr(timestep)])
    out, err = capsys.readouterr()
    assert code == 2 and out == ''
    assert "pip install 'contact_sim[drake]'" in err and 'no e is claimed' in err


def drake_combined(k1, d1, k2, d2):
    """Drake's combination of two geometries' point-contact properties (contact_properties.cc):
    stiffness in series, dissipation weighted by the other's stiffness."""
    return k1 * k2 / (k1 + k2), (k2 * d1 + k1 * d2) / (k1 + k2)


@pytest.mark.parametrize('ground', [(1e6, 0.0), (3e5, 0.5), (2e5, 0.2)])
def test_ball_properties_give_the_pair(ground):
    k, d = 1e5, 0.3
    k1, d1 = drake_plant.ball_properties(k, d, *ground)
    assert drake_combined(k1, d1, *ground) == pytest.approx((k, d), rel=1e-12)
    assert drake_combined(*drake_plant.pair_properties(k, d), *drake_plant.pair_properties(k, d)
                          ) == pytest.approx((k, d), rel=1e-12)


@pytest.mark.parametrize('ground', [(1e5, 0.0), (5e4, 0.0), (2e5, 5.0)])
def test_a_ground_that_cannot_give_the_pair_is_refused(ground):
    with pytest.raises(ValueError):
        drake_plant.ball_properties(1e5, 0.3, *ground)
