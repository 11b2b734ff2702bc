"""`contact-sim fit` reads no further than the fit's limit on points (issue 17: a 100,000-row CSV
gave no answer in 120 s; 10 million rows a MemoryError traceback)."""
from contact_sim import cli
from contact_sim.impact import MAX_POINTS


def test_a_100000_row_csv_is_refused_with_the_limit(tmp_path, capsys):
    path = tmp_path / 'big.csv'
    path.write_text('speed,restitution\n' + '1.0,0.8\n' * 100_000)
    code = cli.main(['fit', str(path), '--stiffness', '2e8', '--mass', '0.046'])
    err = capsys.readouterr().err
    assert code == 2
    assert f'has more than {MAX_POINTS} rows: allowed at most {MAX_POINTS}' in err
    assert 'Traceback' not in err
