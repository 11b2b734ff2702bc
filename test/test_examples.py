"""The paper's numbers, reproduced by the examples/ scripts."""
import importlib.util
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


def load(name):
    spec = importlib.util.spec_from_file_location(name, ROOT / 'examples' / f'{name}.py')
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_section_ii_c_drop_numbers():
    r = load('paper_drop').replicate()
    assert 2.3 < r['time_apex_below_1mm'] < 2.5            # paper: 2.4 s
    assert r['microscopic_bounces'] == 26                  # paper: 26
    assert r['settle_time'] - r['time_apex_below_1mm'] < 0.3   # paper: a further ~0.2 s
    # linearised rest frequency: f = sqrt(1.5 k sqrt(z0) / m) / 2 pi, z0 = (m g / k)^(2/3)
    assert r['rest_frequency_undamped'] == pytest.approx(1525.0, abs=1.0)
    assert r['rest_frequency_measured_late'] == pytest.approx(r['rest_frequency_damped'], rel=1e-3)
    assert r['steps'] < 2100                               # paper: 2100 (ode23t, rtol 1e-5)


def test_fig3_linear_law_is_flat_and_nonlinear_laws_decrease():
    ex = load('restitution_curves')
    curves = ex.fig3()
    assert np.ptp(curves['linear']) < 1e-9
    for name in ('hunt_crossley', 'azad_featherstone'):
        assert np.all(np.diff(curves[name]) < 0)
    speeds = ex.SPEEDS
    i = int(np.argmin(np.abs(speeds - 1.0)))
    for e in curves.values():
        assert e[i] == pytest.approx(0.7, abs=1e-8)


def test_fig4_new_law_is_nearly_linear_in_log_speed_and_hunt_crossley_is_not():
    ex = load('restitution_curves')
    curves = ex.fig4()
    for (_, e_new), (_, e_hc) in zip(curves['azad_featherstone'],
                                     curves['hunt_crossley']):
        dev_new, _ = ex.log_linearity(e_new)
        dev_hc, _ = ex.log_linearity(e_hc)
        assert dev_new < 0.01 and dev_hc > 0.05


def test_examples_run_as_scripts(tmp_path):
    out = subprocess.run([sys.executable, str(ROOT / 'examples' / 'restitution_curves.py'),
                          '--plot', str(tmp_path / 'a.png'), str(tmp_path / 'b.png')],
                         capture_output=True, text=True, check=True)
    assert 'worst deviation' in out.stdout
    assert (tmp_path / 'a.png').read_bytes()[:4] == b'\x89PNG'


def test_the_bounces_help_example_reads_the_file_the_example_script_writes(tmp_path):
    """``contact-sim bounces --help`` names a recording a new user can make: the one that
    examples/bounce_recording.py writes (it used to name golf_80cm.csv, which nothing wrote)."""
    import re

    from contact_sim.cli import bounces
    named = re.findall(r'contact-sim bounces (\S+\.csv)', bounces.NOTES)
    assert named, 'the help shows no example'
    subprocess.run([sys.executable, str(ROOT / 'examples' / 'bounce_recording.py'), str(tmp_path)],
                   capture_output=True, text=True, check=True, timeout=600)
    for name in named:
        assert (tmp_path / name).is_file(), name

