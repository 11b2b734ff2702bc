"""The README and the docs: short, with the commands CI reads, and nothing typed that a command
prints (transcripts, tables and the API list are made from the code; .ci/run builds the site and
runs its examples)."""
import importlib.util
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / 'docs'
README = (ROOT / 'README.md').read_text()
MAIN_COMMAND = './scripts/setup.sh && source .venv/bin/activate && contact_sim_node'
TEST_COMMAND = 'source .venv/bin/activate && python -m pytest -q -n 2 --dist loadfile'


def load(path, name):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def pages():
    return {path.name: path.read_text() for path in DOCS.glob('*.md')}


def test_readme_is_short():
    words = len(README.split())
    assert words <= 1500, f'README.md has {words} words; at most 1500'


@pytest.mark.parametrize('marker, command', [('<!-- main-command -->', MAIN_COMMAND),
                                             ('<!-- test-command -->', TEST_COMMAND)])
def test_readme_keeps_the_two_commands_under_their_markers(marker, command):
    lines = README.splitlines()
    assert lines.count(marker) == 1
    i = lines.index(marker)
    assert lines[i + 1:i + 4] == ['```bash', command, '```']


def test_ci_reads_the_test_command_from_the_readme():
    found = subprocess.run(['awk', '/<!-- test-command -->/{getline; getline; print; exit}',
                            str(ROOT / 'README.md')], capture_output=True, text=True, check=True)
    assert found.stdout.strip() == TEST_COMMAND


def test_readme_python_example_runs():
    blocks = re.findall(r'```python\n(.*?)```', README, flags=re.S)
    assert len(blocks) == 1
    out = subprocess.run([sys.executable, '-c', blocks[0]], capture_output=True, text=True,
                         check=True, cwd=ROOT).stdout.split('\n')
    e = [float(x) for x in out[0].strip('[] ').split()]
    assert len(e) == 3 and 1 > e[0] > e[1] > e[2] > 0      # e falls with speed
    impacts, rest_time = out[1].split()
    assert int(impacts) > 10 and 0 < float(rest_time) < 5


def test_readme_names_every_docs_page():
    for name in set(pages()) - {'index.md'}:
        assert f'docs/{name}' in README, f'README.md has no row for docs/{name}'


def test_every_page_is_in_the_toctree():
    index = (DOCS / 'index.md').read_text()
    for name in pages():
        if name != 'index.md':
            assert f'\n{name[:-3]}\n' in index, f'{name} is not in docs/index.md'


def test_the_api_reference_lists_exactly_contact_sim_all():
    import contact_sim
    text = (DOCS / 'api' / 'index.rst').read_text()
    block = text.split('.. currentmodule:: contact_sim\n', 1)[1].split(':nosignatures:\n', 1)[1]
    listed = []
    for line in block.splitlines():
        if line.strip() and not line.startswith('   '):
            break                           # the next section
        listed += line.split()
    assert listed == list(contact_sim.__all__)


def test_transcripts_and_figures_the_pages_include_are_made_by_the_scripts():
    transcripts = load(ROOT / 'scripts' / 'transcripts.py', 'transcripts')
    figures = load(ROOT / 'scripts' / 'docs_figures.py', 'docs_figures')
    text = '\n'.join(pages().values())
    fragments = set(re.findall(r'_generated/transcripts/(\w+)\.md', text))
    assert fragments <= set(transcripts.NEEDS)
    direct = set(re.findall(r'_generated/transcripts/(\w+)\.txt', text))
    assert not direct & set(transcripts.NEEDS), 'include these through their NAME.md'
    text += '\n'.join(transcripts.fragment(name, True) for name in fragments)
    included = set(re.findall(r'_generated/transcripts/(\w+)\.txt', text))
    assert included and included <= set(transcripts.TRANSCRIPTS)
    plotted = {m for steps in transcripts.TRANSCRIPTS.values() for shown, _ in steps
               for m in re.findall(r'--plot (\S+\.png)', shown)}
    for name in re.findall(r'_generated/figures/([\w.]+\.png)', text):
        assert name in plotted or name in figures.NAMES, name


def test_a_transcript_is_what_the_installed_command_prints():
    """The transcripts run `contact-sim` in-process; the console script prints the same."""
    transcripts = load(ROOT / 'scripts' / 'transcripts.py', 'transcripts')
    text = transcripts.run('errors')
    shown = [line[2:] for line in text.splitlines() if line.startswith('$ ')]
    assert len(shown) == 3
    for command in shown[:2]:          # the third reads stdin from printf
        argv = command.split()
        real = subprocess.run([str(Path(sys.executable).parent / 'contact-sim'), *argv[1:]],
                              capture_output=True, text=True, cwd=ROOT)
        assert real.returncode == 2
        assert f'$ {command}\n{real.stdout}{real.stderr}' in text
    assert "restitution = 'high' is not a number" in text


def test_every_picture_of_the_pages_is_drawn_by_the_docs_build():
    text = '\n'.join(pages().values())
    images = re.findall(r'!\[[^\]]*\]\(([^)]+)\)', text)
    assert images
    assert [i for i in images if not i.startswith('_generated/figures/')] == []
    assert list(DOCS.glob('*.png')) == []


def test_a_transcript_that_needs_a_missing_package_is_a_note_without_picture():
    transcripts = load(ROOT / 'scripts' / 'transcripts.py', 'transcripts')
    assert 'export_drake_1ms' in transcripts.NEEDS
    note = transcripts.fragment('export_drake_1ms', False)
    assert 'drake not installed when these docs were built' in note
    assert 'pip install drake' in note and '_generated/' not in note
    shown = transcripts.fragment('export_drake_1ms', True)
    assert '_generated/transcripts/export_drake_1ms.txt' in shown
    assert '](_generated/figures/export_drake_1ms.png)' in shown
    drake = transcripts.importable('pydrake')
    assert transcripts.files('export_drake_1ms') == (
        ['export_drake_1ms.md', 'export_drake_1ms.txt'] if drake else ['export_drake_1ms.md'])


# PyBullet's export and audit are left out: PyBullet's C code prints a banner on the process's
# own stdout at import, which the installed command shows and an in-process run does not
@pytest.mark.parametrize('name', ['export_gazebo_1ms', 'export_mujoco_1ms', 'audit_mujoco'])
def test_an_export_transcript_is_what_the_installed_command_prints(name, tmp_path):
    transcripts = load(ROOT / 'scripts' / 'transcripts.py', 'transcripts')
    text = transcripts.run(name)
    (shown, _), = transcripts.TRANSCRIPTS[name]
    for model in re.findall(r'examples/\S+', shown):
        (tmp_path / 'examples').mkdir()
        (tmp_path / model).write_text((ROOT / model).read_text())
    argv = shown.split()
    real = subprocess.run([str(Path(sys.executable).parent / 'contact-sim'), *argv[1:]],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          cwd=tmp_path, env={**os.environ, 'PYTHONUNBUFFERED': '1'})
    assert real.returncode == 0, real.stdout
    assert text == f'$ {shown}\n{real.stdout}'
    assert 'measured' in text or 'predicted' in text


def test_bench_markdown_option_writes_the_output_with_its_command(tmp_path, monkeypatch, capsys):
    table = load(ROOT / 'bench' / '_table.py', '_table')
    out = tmp_path / 'b.md'
    monkeypatch.setattr(sys, 'argv', ['bench/bench_x.py', '--rtol', '1e-6', '--markdown', str(out)])
    seen = []

    def main():
        seen.append(list(sys.argv))
        print('law   speeds/s\nlinear  6.3e+06')

    table.run(main)
    assert seen == [['bench/bench_x.py', '--rtol', '1e-6']]     # the bench sees its own options
    text = out.read_text()
    assert text.startswith('`python bench/bench_x.py --rtol 1e-6`, run on ')
    assert '```text\nlaw   speeds/s\nlinear  6.3e+06\n```' in text
    assert 'linear  6.3e+06' in capsys.readouterr().out       # still printed as usual


def test_every_bench_table_the_benchmarks_page_includes_is_there_and_written_by_a_bench():
    page = (DOCS / 'benchmarks.md').read_text()
    for name in re.findall(r'bench_results/(\w+)\.md', page):
        path = DOCS / 'bench_results' / f'{name}.md'
        assert path.exists(), path
        command = re.match(r'`python (bench/\w+\.py)', path.read_text())
        assert command, f'{path} was not written by a bench (bench/_table.py)'
        bench = ROOT / command.group(1)
        assert 'run(main)' in bench.read_text(), f'{bench.name} has no --markdown (bench/_table.py)'


@pytest.mark.ros
def test_node_tables_list_every_parameter_and_topic():
    sys.path.insert(0, str(DOCS / '_ext'))
    try:
        ext = load(DOCS / '_ext' / 'contact_sim_docs.py', 'contact_sim_docs')
    finally:
        sys.path.pop(0)
    from contact_sim.ros.messages import TOPICS
    from contact_sim.ros.params import PARAMETERS
    parameters = ext.parameters_table()
    assert len(parameters.splitlines()) == len(PARAMETERS) + 2
    for spec in PARAMETERS:
        assert f'| `{spec.name}` |' in parameters
    topics = ext.topics_table()
    for topic in TOPICS:
        assert f'| `{topic.name}` | `{topic.type_name}` |' in topics


@pytest.mark.ros
def test_range_refusals_quoted_in_the_docs_are_the_nodes():
    """Issue 33: docs/node.md quoted `Max: inf` for gravity where the node says 1e6. The node's
    page includes rclpy's refusals generated from the node; any other quote matches the range
    the node declares (as rclpy prints it: min and max of the descriptor, str() of floats)."""
    from contact_sim.ros.params import PARAMETERS
    ranges = {spec.name: spec.range for spec in PARAMETERS if spec.range is not None}
    assert '_generated/ros_range_refusals.md' in (DOCS / 'node.md').read_text()
    quotes = [(page.name, *m) for page in [*DOCS.glob('*.md'), ROOT / 'README.md']
              for m in re.findall(r'Parameter (\w+) out of range\s+Min: ([^,]+), Max: ([^,`]+)',
                                  page.read_text())]
    for page, name, low, high in quotes:
        lo, hi = sorted(float(v) for v in ranges[name])
        assert (low.strip(), high.strip()) == (str(lo), str(hi)), (page, name, low, high)


@pytest.mark.ros
def test_the_nodes_help_points_to_the_page_with_the_parameter_table():
    # issue 33: --help named docs/ros.md, which has no parameter table
    from contact_sim.ros.startup import USAGE
    pages_named = re.findall(r'docs/(\w+)\.md', USAGE)
    assert pages_named == ['node']
    node = (DOCS / 'node.md').read_text()
    section = node[node.index('\n## Parameters\n'):]
    assert '_generated/ros_parameters.md' in section.split('\n## ')[1]


def test_docstring_notation_is_escaped_outside_literals_and_examples():
    ext = load(DOCS / '_ext' / 'contact_sim_docs.py', 'contact_sim_docs')
    lines = textwrap.dedent('''\
        a call (ns, *values) with |v0| <= 1 and ``|x|`` kept
        >>> abs(-1) | 0
        1

        *emphasis* stays''').splitlines()
    ext.escape_math_notation(None, 'function', 'f', None, {}, lines)
    assert lines[0] == r'a call (ns, \*values) with \|v0\| <= 1 and ``|x|`` kept'
    assert lines[1:4] == ['>>> abs(-1) | 0', '1', '']
    assert lines[4] == '*emphasis* stays'
