"""The package is where ROS tools look for it, and the README's commands are the ones CI runs."""
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXECUTABLES = ['contact-sim', 'contact_sim_node', 'contact_sim_record']


def test_ament_index_resolves_the_package_and_its_executables():
    # Exactly the lookup `ros2 run contact_sim <exe>` performs.
    from ament_index_python.packages import get_package_prefix, get_package_share_directory
    prefix = Path(get_package_prefix('contact_sim'))
    for exe in EXECUTABLES:
        path = prefix / 'lib' / 'contact_sim' / exe
        assert path.is_file(), f'{path} missing: run scripts/setup.sh'
        assert os.access(path, os.X_OK)
    share = Path(get_package_share_directory('contact_sim'))
    assert (share / 'package.xml').is_file()


def test_installed_executable_runs_the_checkout_code():
    from ament_index_python.packages import get_package_prefix
    exe = Path(get_package_prefix('contact_sim')) / 'lib' / 'contact_sim' / 'contact-sim'
    out = subprocess.run([str(exe), 'materials'], capture_output=True, text=True, check=True)
    assert 'steel' in out.stdout


def test_readme_starts_with_the_two_commands_and_ci_runs_the_second():
    readme = (ROOT / 'README.md').read_text()
    blocks = re.findall(r'```bash\n(.*?)\n```', readme, flags=re.S)
    assert blocks[0].startswith('./scripts/setup.sh')
    ci = (ROOT / '.ci' / 'run').read_text()
    assert 'test-command' in ci and 'scripts/setup.sh' in ci
    marker = readme.index('<!-- test-command -->')
    assert readme.index(blocks[1]) > marker


def test_package_xml_declares_the_runtime_dependencies():
    xml = (ROOT / 'package.xml').read_text()
    assert '<package format="3">' in xml
    for dep in ('rclpy', 'std_msgs', 'geometry_msgs', 'python3-numpy', 'python3-scipy'):
        assert f'<exec_depend>{dep}</exec_depend>' in xml
    assert '<build_type>ament_python</build_type>' in xml


def test_activating_the_venv_puts_the_executables_on_path():
    # The README's first command ends with a bare `contact_sim_node`.
    venv = ROOT / '.venv'
    script = f'source "{venv}/bin/activate" && command -v ' + ' && command -v '.join(EXECUTABLES)
    out = subprocess.run(['bash', '-c', script], capture_output=True, text=True, check=True,
                         env={k: v for k, v in os.environ.items() if k != 'VIRTUAL_ENV'})
    found = out.stdout.split()
    assert found == [str(venv / 'lib' / 'contact_sim' / exe) for exe in EXECUTABLES]


def test_the_checkout_builds_with_plain_colcon_in_a_ros_workspace(tmp_path):
    # What a user with ROS installed does: the package in src/ of a workspace, `colcon build`.
    src = tmp_path / 'src' / 'contact_sim'
    files = subprocess.run(['git', 'ls-files'], cwd=ROOT, capture_output=True, text=True,
                           check=True).stdout.split()
    for name in files:
        (src / name).parent.mkdir(parents=True, exist_ok=True)
        (src / name).write_bytes((ROOT / name).read_bytes())
    env = {k: v for k, v in os.environ.items()
           if k not in ('AMENT_PREFIX_PATH', 'COLCON_PREFIX_PATH')}
    colcon = Path(sys.executable).parent / 'colcon'
    subprocess.run([str(colcon), 'build', '--event-handlers', 'console_direct-'], cwd=tmp_path,
                   env=env, check=True, capture_output=True)
    prefix = tmp_path / 'install' / 'contact_sim'
    for exe in EXECUTABLES:
        assert (prefix / 'lib' / 'contact_sim' / exe).is_file()
    assert (prefix / 'share' / 'ament_index' / 'resource_index' / 'packages' / 'contact_sim').is_file()
    assert (prefix / 'share' / 'contact_sim' / 'config' / 'default.yaml').is_file()
    assert list(prefix.glob('lib/python*/site-packages/contact_sim/data/master_curves.npz'))
