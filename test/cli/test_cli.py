"""The `contact-sim` command line: every subcommand in-process, the installed executable once."""
import io
import os
import warnings
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import contact_sim as cs
from contact_sim.cli import plotting
from contact_sim.cli.app import main

ROOT = Path(__file__).resolve().parents[2]
PNG_MAGIC = b'\x89PNG\r\n\x1a\n'
MATERIALS = ['--sphere', 'steel', '--plate', 'cast_iron', '--radius', '0.0127']
PAPER_DROP = ['--stiffness', '1e10', '--damping', '1e5', '--mass', '0.066', '--gravity', '10']


def run(capsys, argv):
    """main(argv) in-process: (exit code, stdout, stderr); argparse's SystemExit included."""
    try:
        code = main(argv)
    except SystemExit as stop:
        code = stop.code
    out, err = capsys.readouterr()
    return code, out, err


def table(text):
    return np.atleast_2d(np.loadtxt(io.StringIO(text), comments='#'))


def numeric_rows(text, columns):
    """Rows of exactly ``columns`` numbers (the per-point tables of `fit`)."""
    rows = []
    for line in text.splitlines():
        cells = line.split()
        try:
            values = [float(c) for c in cells]
        except ValueError:
            continue
        if len(values) == columns:
            rows.append(values)
    return np.array(rows)


def steel_on_iron(law=cs.AZAD_FEATHERSTONE, damping_factor=8.87e5):
    contact = cs.Contact.from_materials(law, 'steel', 'cast_iron', 0.0127,
                                        damping_factor=damping_factor)
    return contact, cs.sphere_mass(cs.MATERIALS['steel'].density, 0.0127)


def assert_png(path):
    data = Path(path).read_bytes()
    assert data[:8] == PNG_MAGIC
    assert len(data) > 10_000


# -- materials ----------------------------------------------------------------------------
def test_materials_lists_every_material_with_its_source(capsys):
    code, out, _ = run(capsys, ['materials'])
    assert code == 0
    for m in cs.MATERIALS.values():
        assert re.search(rf'^{m.name}\s.*{re.escape(m.source)}$', out, flags=re.M)


# -- restitution --------------------------------------------------------------------------
def test_restitution_table_from_materials_equals_the_library(capsys):
    speeds = [0.1, 1.0, 10.0]
    code, out, err = run(capsys, ['restitution', *MATERIALS, '--damping-factor', '8.87e5',
                                  '--speeds', '0.1,1,10'])
    assert code == 0
    header = [line for line in out.splitlines() if line.startswith('#') and '(m/s)' in line][0]
    assert header.split('(m/s)')[1].split() == ['azad_featherstone', 'hunt_crossley', 'lee_wang']
    assert 'skipped law linear' in err and '--stiffness' in err
    rows = table(out)
    np.testing.assert_allclose(rows[:, 0], speeds, rtol=1e-6)
    for column, law in enumerate((cs.AZAD_FEATHERSTONE, cs.HUNT_CROSSLEY, cs.LEE_WANG), 1):
        contact, mass = steel_on_iron(law)
        np.testing.assert_allclose(rows[:, column], cs.restitution(contact, mass, speeds),
                                   rtol=0, atol=1e-10)
    assert 'k = 1.095172e+10 N/m^1.5 (Hertz)' in out


def test_restitution_direct_contact_includes_the_linear_law_on_a_log_speed_range(capsys):
    code, out, err = run(capsys, ['restitution', '--stiffness', '1e10', '--damping', '1e5',
                                  '--mass', '0.066', '--speed-range', '0.01', '10',
                                  '--points', '7'])
    assert code == 0 and err == ''
    rows = table(out)
    speeds = np.geomspace(0.01, 10.0, 7)
    np.testing.assert_allclose(rows[:, 0], speeds, rtol=1e-6)
    for column, law in enumerate(cs.LAWS.values(), 1):
        expected = cs.restitution(cs.Contact(law, 1e10, 1e5), 0.066, speeds)
        np.testing.assert_allclose(rows[:, column], expected, rtol=0, atol=1e-10)
    assert np.ptp(rows[:, 4]) < 1e-9       # the linear law: the same e at every speed


def test_restitution_linear_alone_with_a_hertz_stiffness_is_an_error(capsys):
    code, out, err = run(capsys, ['restitution', *MATERIALS, '--damping', '1e5',
                                  '--law', 'linear'])
    assert code == 2 and out == ''
    assert err.count('\n') == 1 and 'law linear' in err and '--stiffness' in err


def test_restitution_plot_writes_a_png(capsys, tmp_path):
    png = tmp_path / 'e.png'
    code, out, err = run(capsys, ['restitution', *MATERIALS, '--damping-factor', '8.87e5',
                                '--stiffness', '1e10', '--points', '5', '--log-speed',
                                '--plot', str(png)])
    assert code == 0 and f"plot written to {png}" in out, err
    assert_png(png)


def test_restitution_help_documents_the_linear_law_rule(capsys):
    code, out, _ = run(capsys, ['restitution', '--help'])
    assert code == 0
    assert 'linear law is skipped' in out and '--log-speed' in out


# -- drop ---------------------------------------------------------------------------------
def test_drop_prints_every_impact_and_the_summary(capsys):
    code, out, _ = run(capsys, ['drop', *PAPER_DROP, '--height', '1', '--duration', '5'])
    assert code == 0
    expected = cs.simulate_drop(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5), 0.066, 1.0,
                                gravity=10.0, duration=5.0)
    rows = [line.split() for line in out.splitlines() if re.match(r'\s+\d+\s', line)]
    assert len(rows) == len(expected.impacts) > 10
    assert f'impacts: {len(expected.impacts)} (' in out
    assert f'integrator steps: {expected.steps}\n' in out
    first = expected.impacts[0]
    assert float(rows[0][1]) == pytest.approx(first.time, rel=1e-6)
    assert float(rows[0][2]) == pytest.approx(first.impact_speed, rel=1e-5)
    assert float(rows[0][4]) == pytest.approx(first.restitution, abs=1e-6)
    assert float(rows[0][6]) == pytest.approx(first.peak_force, rel=1e-5)
    assert rows[-1][5] == 'permanent'
    settle = float(re.search(r'settle_time: (\S+) s', out).group(1))
    assert settle == pytest.approx(expected.settle_time, rel=1e-5)


def test_drop_from_materials_with_a_plot(capsys, tmp_path):
    png = tmp_path / 'drop.png'
    code, out, _ = run(capsys, ['drop', *MATERIALS, '--damping-factor', '8.87e5', '--height',
                                '0.05', '--duration', '0.3', '--plot', str(png)])
    assert code == 0
    assert_png(png)
    contact, mass = steel_on_iron()
    expected = cs.simulate_drop(contact, mass, 0.05, duration=0.3)
    assert f'impacts: {len(expected.impacts)} (' in out


# -- fit ----------------------------------------------------------------------------------
def write_model_csv(path, contact, mass, speeds, header=True):
    e = cs.restitution(contact, mass, np.asarray(speeds))
    lines = ['# generated from the model, not measured', 'speed, restitution'] if header \
        else []
    lines += [f'{float(v)!r},{float(x)!r}  # point {i}' for i, (v, x) in enumerate(zip(speeds, e))]
    path.write_text('\n'.join(lines) + '\n')
    return e


def test_fit_recovers_the_damping_the_data_were_made_with(capsys, tmp_path):
    contact, mass = steel_on_iron()
    csv = tmp_path / 'model.csv'
    write_model_csv(csv, contact, mass, np.geomspace(0.05, 5.0, 8))
    code, out, _ = run(capsys, ['fit', str(csv), *MATERIALS, '--law', 'azad_featherstone'])
    assert code == 0
    lam = float(re.search(r'azad_featherstone: lambda = (\S+) N s/m\^1.5', out).group(1))
    assert lam == pytest.approx(contact.damping, rel=1e-6)
    lam_star = float(re.search(r'lambda\* = lambda/sqrt\(R\) = (\S+) N s/m\^2\n', out).group(1))
    assert lam_star == pytest.approx(8.87e5, rel=1e-6)
    low, high = map(float, re.search(r'95% confidence interval: \[(\S+), (\S+)\]', out).groups())
    assert low <= lam * (1 + 1e-6) and high >= lam * (1 - 1e-6)
    points = numeric_rows(out, 5)
    assert points.shape == (8, 5)
    np.testing.assert_allclose(points[:, 0], np.geomspace(0.05, 5.0, 8), rtol=1e-5)
    np.testing.assert_allclose(points[:, 3], 0.0, atol=1e-9)      # residuals
    np.testing.assert_allclose(points[:, 4], contact.damping, rtol=1e-6)  # lambda alone


def test_fit_compares_all_laws_and_plots(capsys, tmp_path):
    contact = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)
    csv = tmp_path / 'data.csv'
    write_model_csv(csv, contact, 0.066, [0.1, 0.3, 1.0, 3.0], header=False)
    png = tmp_path / 'fit.png'
    code, out, err = run(capsys, ['fit', str(csv), '--stiffness', '1e10', '--mass', '0.066',
                                  '--plot', str(png)])
    assert code == 0 and err == ''
    ranked = re.findall(r'^(\w+): lambda = ', out, flags=re.M)
    assert ranked[0] == 'azad_featherstone' and sorted(ranked) == sorted(cs.LAWS)
    assert 'lambda*' not in out                     # no radius given: R unknown
    assert numeric_rows(out, 5).shape == (4 * 4, 5)
    assert_png(png)


# -- bad input ----------------------------------------------------------------------------
@pytest.mark.parametrize('argv, field', [
    (['restitution', '--sphere', 'wood', '--plate', 'steel', '--radius', '0.01',
      '--damping', '1'], '--sphere'),
    (['restitution', '--sphere', 'steel', '--plate', 'steel', '--radius', '-0.01',
      '--damping', '1'], '--radius = -0.01 is out of range: allowed 0 < --radius'),
    (['restitution', '--stiffness', '1e10', '--mass', 'nan', '--damping', '1'], '--mass = nan'),
    (['restitution', '--stiffness', '1e10', '--mass', '1', '--damping', '1',
      '--speeds', '1,-2'], '--speeds = -2.0 is out of range: allowed 0 < --speeds'),
    (['restitution', '--stiffness', '1e10', '--mass', '1', '--damping', '1',
      '--speed-range', '1', '0.1'], '--speed-range 1 0.1'),
    (['restitution', '--stiffness', '1e10', '--mass', '1', '--damping', '1',
      '--points', '1'], '--points = 1 is out of range: allowed 2 <= --points <= 1e+06'),
    (['restitution', '--stiffness', '1e10', '--mass', '1'], '--damping is missing'),
    (['restitution', '--stiffness', '1e10', '--damping', '1'], '--mass is missing'),
    (['restitution', '--stiffness', '1e10', '--mass', '1', '--damping', '1', '--radius', '0.01',
      '--damping-factor', '1'], '--damping and --damping-factor are both given'),
    (['drop', '--stiffness', '1e10', '--mass', '1', '--damping', '1', '--height', 'nan'],
     '--height = nan'),
    (['drop', '--stiffness', '1e10', '--mass', '1', '--damping', '1', '--gravity', '-1'],
     '--gravity = -1.0 is out of range: allowed 0 <= --gravity'),
    (['drop', '--stiffness', '1e10', '--mass', '1', '--damping', '1', '--plot',
      '/nonexistent-dir/x.png'], 'plot ='),
])
def test_bad_input_exits_2_with_one_line_naming_the_field(capsys, argv, field):
    code, out, err = run(capsys, argv)
    assert code == 2 and out == ''
    last = err.strip().splitlines()[-1]
    assert last.startswith('contact-sim') and 'error' in last and field in last
    assert 'Traceback' not in err


@pytest.mark.parametrize('rows, message', [
    ('speed,restitution\n1,0.5\n2,abc\n', 'line 3: restitution = '),
    ('1,0.5\n2,0\n', 'line 2: restitution = 0.0 is out of range: allowed 0 < restitution'),
    ('1,0.5\n2\n', 'line 2: 1 columns'),
    ('1,0.5\nspeed,restitution\n', "line 2: speed = 'speed'"),
    ('# nothing\n', 'no speed,restitution rows'),
])
def test_malformed_csv_exits_2_naming_the_line_and_field(capsys, tmp_path, rows, message):
    csv = tmp_path / 'bad.csv'
    csv.write_text(rows)
    code, out, err = run(capsys, ['fit', str(csv), '--stiffness', '1e10', '--mass', '1'])
    assert code == 2 and out == ''
    assert err.count('\n') == 1 and message in err


def test_missing_csv_exits_2(capsys, tmp_path):
    code, _, err = run(capsys, ['fit', str(tmp_path / 'none.csv'), '--stiffness', '1e10',
                                '--mass', '1'])
    assert code == 2 and 'cannot be read' in err


def test_plot_without_matplotlib_fails_clearly_before_computing(capsys, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, 'matplotlib', None)   # makes `import matplotlib` fail
    png = tmp_path / 'x.png'
    code, out, err = run(capsys, ['restitution', '--stiffness', '1e10', '--mass', '1',
                                  '--damping', '1', '--plot', str(png)])
    assert code == 1 and out == '' and not png.exists()
    assert 'needs matplotlib' in err and "pip install 'contact_sim[plot]'" in err


# -- the installed executable -------------------------------------------------------------
def installed_executable():
    venv = Path(sys.executable).parent / 'contact-sim'
    if venv.is_file():
        return venv
    from ament_index_python.packages import get_package_prefix
    return Path(get_package_prefix('contact_sim')) / 'lib' / 'contact_sim' / 'contact-sim'


def test_installed_executable_prints_the_restitution_table_and_rejects_bad_input():
    exe = str(installed_executable())
    env = dict(os.environ, PYTHONWARNINGS='ignore')
    ok = subprocess.run([exe, 'restitution', '--stiffness', '1e10', '--damping', '1e5',
                         '--mass', '0.066', '--speeds', '1', '--law', 'azad_featherstone'],
                        capture_output=True, text=True, env=env, timeout=60)
    assert ok.returncode == 0, ok.stderr
    e = cs.restitution(cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5), 0.066, 1.0)
    assert table(ok.stdout)[0, 1] == pytest.approx(e, abs=1e-10)
    bad = subprocess.run([exe, 'drop', '--sphere', 'steel', '--plate', 'steel', '--radius',
                          'nan', '--damping', '1'], capture_output=True, text=True, env=env,
                         timeout=60)
    assert bad.returncode == 2 and bad.stdout == ''
    assert bad.stderr.strip() == ('contact-sim: error: --radius = nan is not finite; '
                                  'it must be a finite real number')


# -- issue 7: the command line's promises at the edges ---------------------------------------
DIRECT = ['--stiffness', '1e10', '--damping', '1e5', '--mass', '0.066']


def strict_run(capsys, argv):
    """``run`` with every warning an error: a RuntimeWarning wall would show as a failure."""
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        return run(capsys, argv)


@pytest.mark.parametrize('argv, field', [
    (['drop', '--stiffness', '1e10', '--damping', '1e5', '--mass', '1e-300'], '--mass = 1e-300'),
    (['drop', '--stiffness', '1e10', '--damping', '1e5', '--mass', '1e300'], '--mass = 1e+300'),
    (['drop', *DIRECT, '--gravity', '1e300'], '--gravity = 1e+300'),
    (['drop', '--stiffness', '1e300', '--damping', '1e5', '--mass', '0.066'],
     '--stiffness = 1e+300'),
    (['drop', '--stiffness', '1e10', '--damping', '1e30', '--mass', '0.066'],
     '--damping = 1e+30 is too large for this drop'),
    (['drop', *DIRECT, '--sample-rate', '1e9', '--plot', 'PNG'], '--sample-rate = 1000000000.0'),
    (['drop', *DIRECT, '--duration', '1e6', '--plot', 'PNG'],
     'allowed at most 200000 (--sample-rate x --duration <= 200000)'),
    (['drop', *DIRECT, '--height', '-1'], '--height = -1.0 is out of range'),
    (['restitution', *DIRECT, '--points', '100000000'], '--points = 100000000 is out of range'),
    (['drop', '--stiffness', '1e-300', '--damping', '0', '--mass', '0.066'],
     '--stiffness = 1e-300 N/m^1.5 is too small'),
    (['restitution', '--sphere', 'steel', '--plate', 'cork', '--radius', '1e300', '--damping',
      '1'], '--radius = 1e+300 m gives a sphere mass'),
    (['restitution', '--sphere', 'steel', '--plate', 'cork', '--radius', '1e-300',
      '--damping-factor', '1', '--law', 'azad_featherstone'], '--radius = 1e-300 m gives'),
    (['drop', '--stiffness', '5e4', '--damping', '0', *MATERIALS],
     '--stiffness = 5e+04 N/m^1.5 is too small for this drop'),
])
def test_extreme_input_exits_2_with_one_line_and_no_warning(capsys, tmp_path, argv, field):
    # reproduced: tracebacks, RuntimeWarning walls, a nan column with exit 0, a hang, 15.7 GB
    argv = [str(tmp_path / 'd.png') if a == 'PNG' else a for a in argv]
    code, out, err = strict_run(capsys, argv)
    assert code == 2 and out == '' and err.count('\n') == 1, err
    assert err.startswith('contact-sim: error: ') and field in err


def test_the_depth_check_names_both_bounds_in_option_names(capsys):
    code, _, err = run(capsys, ['drop', '--stiffness', '5e4', '--damping', '0', *MATERIALS])
    assert code == 2
    assert re.search(r'allowed --stiffness >= \S+ N/m\^1\.5 or --height <= \S+ m', err)


def test_plot_writes_the_file_it_names(capsys, tmp_path):
    # reproduced: `--plot name` wrote name.png and reported name
    target = tmp_path / 'name'
    code, out, _ = run(capsys, ['restitution', *DIRECT, '--points', '3', '--plot', str(target)])
    assert code == 0 and f'plot written to {target}' in out
    assert target.read_bytes().startswith(PNG_MAGIC) and not (tmp_path / 'name.png').exists()


@pytest.mark.parametrize('rows, field', [('1e-300,0.5\n1,0.6\n', 'speed[0] = 1e-300'),
                                         ('1,0.6\n1e300,0.5\n', 'speed[1] = 1e+300')])
def test_fit_to_an_unscalable_speed_names_the_data_point(capsys, tmp_path, rows, field):
    # reproduced: `math domain error`, `Optimization bounds must be finite scalars.`
    data = tmp_path / 'd.csv'
    data.write_text(rows)
    code, out, err = strict_run(capsys, ['fit', str(data), '--stiffness', '1e10', '--mass',
                                         '0.066'])
    assert code == 2 and out == '' and err.count('\n') == 1
    assert f'error: {data}: {field}' in err   # the file named before the field


def test_a_one_point_fit_prints_no_zero_width_interval(capsys, tmp_path):
    data = tmp_path / 'one.csv'
    data.write_text('1,0.5\n')
    code, out, _ = run(capsys, ['fit', str(data), '--stiffness', '1e10', '--mass', '0.066',
                                '--law', 'lee_wang'])
    assert code == 0
    assert 'confidence interval: n/a (one point: no residual variance)' in out


def test_the_heavily_damped_drop_reports_its_landing(capsys):
    # reproduced: `impacts: 0` for a sphere resting on the plate with force m g
    code, out, _ = run(capsys, ['drop', '--stiffness', '1e10', '--damping', '1e10', '--mass',
                                '0.066'])
    assert code == 0 and 'impacts: 1 (0 bounces, then permanent contact)' in out


@pytest.mark.parametrize('values', [[np.array([1.0 - 1e-9, 1.0 - 3e-9])],   # near-elastic
                                    [np.array([1.0, 1.0])],                 # elastic
                                    [np.array([0.2, 0.9]), np.array([0.5])]])
def test_restitution_plot_limits_keep_every_curve_inside_the_frame(values):
    # reproduced: a near-elastic `restitution --plot` put every curve on the frame (top = 1.02
    # with the data at 1 - 1e-9 drawn on the upper edge of a 0..1 axis)
    low, high = plotting.restitution_limits(values)
    data = np.concatenate(values)
    assert low < data.min() and data.max() < high
    if data.max() > data.min():
        assert high - low < 2 * (data.max() - data.min())        # zoomed to the data
