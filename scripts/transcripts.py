#!/usr/bin/env python3
"""Console transcripts for the docs, made by running the real commands.

    python scripts/transcripts.py [OUT_DIR [FIGURES_DIR]]   # default docs/_generated/transcripts
    python scripts/transcripts.py OUT_DIR --names NAME...   # only these, no figures

Each transcript is one ``NAME.txt``: the commands as a user types them (``$ ...``), each followed
by what it printed (stdout and stderr, in order of the steps). The `contact-sim` commands run in
this process through ``contact_sim.cli.main`` (the console script's own entry point: the same
code, without paying Python's and numba's start-up for each), in a temporary working directory,
so the files they write (plots, CSV, YAML) are named as a user would see them. A shell pipeline
is run as its parts: the `contact-sim` part here, the filter (``awk``, ``head``, ``cat``) in the
shell. ``contact_sim_node`` runs installed, in its own process, through the shell. A command
run on a file of the repository (``examples/ball.xml``) finds a copy at the same relative path.
A transcript of ``NEEDS`` (Drake's) needs a package the docs may be built without: its page
includes ``NAME.md``, which holds the transcript and its pictures when the package imports and
a note that it is not installed otherwise. The docs build (docs/_ext/contact_sim_docs.py) runs
this script; it writes only files whose text changed.
"""
import contextlib
import importlib
import io
import os
import re
import runpy
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_OUT = ROOT / 'docs' / '_generated' / 'transcripts'
MODEL_CSV = ('contact-sim restitution --sphere steel --plate cast_iron --radius 0.0127 '
             '--damping-factor 8.87e5 --law azad_featherstone --speed-range 0.05 5 --points 8')
GOLF = '--mass 0.0459 --radius 0.0214 --stiffness 2e8'


def contact_sim(command, stdin=''):
    """Run ``contact-sim ARGS`` (``command`` as typed) here; its printed text."""
    from contact_sim.cli import main
    out = io.StringIO()
    old_stdin = sys.stdin
    sys.stdin = io.StringIO(stdin)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
            try:
                main(command.split()[1:])
            except SystemExit:        # argparse's own errors and --help
                pass
    finally:
        sys.stdin = old_stdin
    return out.getvalue()


def shell(command):
    """A plain shell command (a filter over files the steps before wrote)."""
    done = subprocess.run(command, shell=True, capture_output=True, text=True)
    return done.stdout + done.stderr


def example(script, *args):
    """Run ``python examples/SCRIPT`` here (its ``__main__``); its printed text."""
    out = io.StringIO()
    argv = sys.argv
    sys.argv = [script, *args]
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
            runpy.run_path(str(ROOT / 'examples' / script), run_name='__main__')
    except SystemExit:
        pass
    finally:
        sys.argv = argv
    return out.getvalue()


def model_csv():
    """``MODEL_CSV | awk '!/^#/ {print $1 "," $2}' > model.csv``: prints nothing."""
    rows = [line.split() for line in contact_sim(MODEL_CSV).splitlines()
            if line.strip() and not line.startswith('#') and not line.startswith('contact-sim:')]
    Path('model.csv').write_text(''.join(f'{r[0]},{r[1]}\n' for r in rows))
    return ''


# name -> steps (what is shown after "$ ", how it is run); later steps see earlier steps' files
TRANSCRIPTS = {
    'errors': [(c, lambda c=c: contact_sim(c)) for c in (
        'contact-sim restitution --radius -1 --sphere steel --plate steel --damping 1',
        'contact-sim drop --stiffness 5e4 --damping 0 --sphere steel --plate cast_iron '
        '--radius 0.0127')] + [
        ("printf '0.1,0.8\\n0.5,high\\n' | contact-sim fit - --stiffness 1e10 --mass 0.066",
         lambda: contact_sim('contact-sim fit - --stiffness 1e10 --mass 0.066',
                             stdin='0.1,0.8\n0.5,high\n'))],
    'materials': [('contact-sim materials', lambda: contact_sim('contact-sim materials'))],
    'restitution_hertz': [(c, lambda c=c: contact_sim(c)) for c in (
        'contact-sim restitution --sphere steel --plate cast_iron --radius 0.0127 '
        '--damping-factor 8.87e5 --speeds 0.01,0.1,1,10',)],
    'restitution_given': [(c, lambda c=c: contact_sim(c)) for c in (
        'contact-sim restitution --stiffness 1e10 --damping 1e5 --mass 0.066 '
        '--speed-range 0.01 10 --points 4',
        'contact-sim restitution --stiffness 1e10 --damping 1e5 --mass 0.066 '
        '--law azad_featherstone --law linear --speed-range 0.001 10 --points 9 --log-speed '
        '--plot e.png')],
    'drop': [(c, lambda c=c: contact_sim(c)) for c in (
        'contact-sim drop --stiffness 1e10 --damping 1e5 --mass 0.066 --gravity 10 '
        '--plot drop.png',)],
    'fit': [
        (MODEL_CSV + " | awk '!/^#/ {print $1 \",\" $2}' > model.csv", model_csv),
        ('cat model.csv', lambda: shell('cat model.csv')),
        ('contact-sim fit model.csv --sphere steel --plate cast_iron --radius 0.0127 '
         '--plot fit.png', lambda: contact_sim(
             'contact-sim fit model.csv --sphere steel --plate cast_iron --radius 0.0127 '
             '--plot fit.png'))],
    'bounces': [
        ('python examples/bounce_recording.py', lambda: example('bounce_recording.py')),
        ('head -3 golf_80cm_50cm.csv', lambda: shell('head -3 golf_80cm_50cm.csv')),
        (f'contact-sim bounces golf_80cm_50cm.csv {GOLF} --fit-drag --plot bounces.png '
         '--save-params golf.yaml', lambda: contact_sim(
             f'contact-sim bounces golf_80cm_50cm.csv {GOLF} --fit-drag --plot bounces.png '
             '--save-params golf.yaml')),
        ('cat golf.yaml', lambda: shell('cat golf.yaml')),
        (f'contact-sim bounces golf_80cm.wav {GOLF} --drag-coefficient 0.25 '
         '--law azad_featherstone --law linear', lambda: contact_sim(
             f'contact-sim bounces golf_80cm.wav {GOLF} --drag-coefficient 0.25 '
             '--law azad_featherstone --law linear'))],
}


def stiffness_loop():
    """The ``for k in ...; do contact-sim bounces ... | grep ...; done`` loop, run here."""
    lines = []
    for k in ('2e7', '2e8', '2e9'):
        text = contact_sim(f'contact-sim bounces golf_80cm_50cm.csv --mass 0.0459 --radius 0.0214 '
                           f'--stiffness {k} --fit-drag --law azad_featherstone')
        lines += [line for line in text.splitlines()
                  if line.startswith('azad') or 'C_d =' in line]
    return '\n'.join(lines) + '\n'


def node_help():
    """``contact_sim_node --help``: the installed executable, in its own process (no ROS starts)."""
    node = Path(sys.executable).parent / 'contact_sim_node'
    done = subprocess.run([str(node), '--help'], capture_output=True, text=True)
    return done.stdout + done.stderr


TRANSCRIPTS['node_help'] = [('contact_sim_node --help', node_help)]
TRANSCRIPTS['paper_drop'] = [('python examples/paper_drop.py', lambda: example('paper_drop.py'))]
TRANSCRIPTS['restitution_curves'] = [
    ('python examples/restitution_curves.py', lambda: example('restitution_curves.py'))]
TRANSCRIPTS['bounces_stiffness'] = [
    ('python examples/bounce_recording.py', lambda: example('bounce_recording.py')),
    ('for k in 2e7 2e8 2e9; do contact-sim bounces golf_80cm_50cm.csv --mass 0.0459 '
     '--radius 0.0214 \\\n      --stiffness $k --fit-drag --law azad_featherstone | '
     'grep -E "^azad|C_d ="; done', stiffness_loop)]


STEEL = ('--law azad_featherstone --sphere steel --plate cast_iron --radius 0.0127 '
         '--damping-factor 8.87e5')


def export_command(engine, timestep, name):
    """The export of the issue's steel-on-cast-iron contact that ``docs/export.md`` shows."""
    return (f'contact-sim export {engine} --timestep {timestep} {STEEL} --speed-range 0.1 10 '
            f'--points 5 --plot {name}.png')


def with_repo_file(path, step):
    """``step``, with the repository's file ``path`` at the same relative path in the working
    directory (the command is shown as typed at the repository's root)."""
    def run_step():
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(ROOT / path, path)
        return step()
    return run_step


def node(command, ros=False):
    """A shell command line that runs the installed ``contact_sim_node`` (this venv's first on
    the ``PATH``), in its own process: it refuses before ROS starts a graph. Its output, stdout
    and stderr as one stream in order. ``ros``: the command starts a ROS graph, which gets a
    ROS domain of its own (``ROS_DOMAIN_ID`` from this process's id, so that a build does not
    publish into the domain of whoever runs it) and its logs in the working directory."""
    env = dict(os.environ, PATH=f'{Path(sys.executable).parent}{os.pathsep}{os.environ["PATH"]}')
    if ros:
        env.update(ROS_DOMAIN_ID=str(120 + os.getpid() % 100), ROS_LOG_DIR=os.getcwd())
    done = subprocess.run(command, shell=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, env=env)
    return done.stdout


for engine, timestep, name in (('mujoco', '1e-3', 'export_mujoco_1ms'),
                               ('mujoco', '1e-4', 'export_mujoco_01ms'),
                               ('pybullet', '1e-3', 'export_pybullet_1ms'),
                               ('drake', '0', 'export_drake_continuous'),
                               ('drake', '1e-3', 'export_drake_1ms'),
                               ('gazebo', '1e-3', 'export_gazebo_1ms')):
    command = export_command(engine, timestep, name)
    TRANSCRIPTS[name] = [(command, lambda c=command: contact_sim(c))]
for engine, model, option in (('mujoco', 'examples/ball.xml', '--geom ball'),
                              ('pybullet', 'examples/ball.urdf', '--link ball --timestep 1e-3')):
    command = f'contact-sim audit {engine} {model} {option} {STEEL} --points 4'
    TRANSCRIPTS[f'audit_{engine}'] = [
        (command, with_repo_file(model, lambda c=command: contact_sim(c)))]
TRANSCRIPTS['node_start'] = [(c, lambda c=c: node(c)) for c in (
    'contact_sim_node --help > /dev/null; echo "exit code $?"',
    'contact_sim_node --frobnicate; echo "exit code $?"')]
# a recording whose recorder is killed (SIGKILL: no metadata.yaml), then recovered; in a ROS
# domain of this build's own (``node(..., ros=True)``), the node at real time for 6 s
TRANSCRIPTS['recorder_recover'] = [(c, lambda c=c: node(c, ros=True)) for c in (
    'contact_sim_record -o drop1 > /dev/null 2>&1 & recorder=$!; '
    'contact_sim_node > /dev/null 2>&1 & node=$!; '
    'sleep 6; kill -TERM $node; wait $node; kill -KILL $recorder; wait',
    'ls drop1',
    'contact_sim_record --recover drop1',
    'contact_sim_record --recover drop1; echo "exit code $?"')]
TRANSCRIPTS['node_refusals'] = [
    (c, lambda c=c: shell(c)) for c in (
        "printf 'a: [\\n' > bad.yaml", "printf '\\377\\376' > binary.yaml",
        "printf 'foo: 1\\n' > no_parameters.yaml")] + [
    (c, lambda c=c: node(c)) for c in (
        *(f'contact_sim_node --ros-args --params-file {f}; echo "exit code $?"'
          for f in ('/nonexistent.yaml', 'bad.yaml', 'binary.yaml', 'no_parameters.yaml')),
        'contact_sim_node --ros-args -p contact_law:=; echo "exit code $?"')]

# transcripts that need a package these docs may be built without: name -> (module, install)
NEEDS = {'export_drake_continuous': ('pydrake', 'pip install drake'),
         'export_drake_1ms': ('pydrake', 'pip install drake')}


def importable(module):
    """True when ``module`` imports here."""
    try:
        importlib.import_module(module)
    except ImportError:
        return False
    return True


def fragment(name, installed):
    """``NAME.md``, the Markdown a page includes for a transcript of ``NEEDS``: the transcript
    and the pictures it draws when its package imports (``installed``), else a note."""
    module, install = NEEDS[name]
    if not installed:
        package = install.split()[-1]
        return (f'**Not shown: {package} not installed when these docs were built** (`{module}` '
                f'did not import): `{install}` and build the docs again for this example\'s '
                'output and picture.\n')
    lines = [f'```{{literalinclude}} _generated/transcripts/{name}.txt', ':language: text',
             '```', '']
    for shown, _ in TRANSCRIPTS[name]:
        for png in re.findall(r'--plot (\S+\.png)', shown):
            lines += [f'![The plot of the command above: --plot {png}](_generated/figures/{png})',
                      '']
    return '\n'.join(lines)


def files(name):
    """The files ``write_all`` writes for transcript ``name`` (here, as installed now)."""
    if name not in NEEDS:
        return [f'{name}.txt']
    return [f'{name}.md', f'{name}.txt'] if importable(NEEDS[name][0]) else [f'{name}.md']


def missing(out_dir):
    """True when a transcript file is absent from ``out_dir``."""
    return any(not (Path(out_dir) / file).exists() for name in TRANSCRIPTS for file in files(name))


def run(name, figures=None):
    """The text of transcript ``name``, its steps run in a fresh temporary directory; the PNG
    files they drew are copied into ``figures`` (a directory) when it is given."""
    here = os.getcwd()
    with tempfile.TemporaryDirectory(prefix='contact_sim_transcript_') as work:
        os.chdir(work)
        try:
            parts = []
            for shown, step in TRANSCRIPTS[name]:
                parts.append(f'$ {shown}\n{step()}')
        finally:
            os.chdir(here)
        if figures is not None:
            Path(figures).mkdir(parents=True, exist_ok=True)
            for png in Path(work).glob('*.png'):
                shutil.copyfile(png, Path(figures) / png.name)
    return ''.join(parts)


# each of these starts the installed node (about 2 s apiece, in a process of its own): they run
# in a second process of this script while this one runs the rest, on the machine's other core
BESIDE = ('node_help', 'node_start', 'node_refusals', 'recorder_recover')


def write(out_dir, name, figures=None):
    """Write transcript ``name``'s files into ``out_dir`` (``files``); their paths."""
    texts = {}
    if name in NEEDS:
        installed = importable(NEEDS[name][0])
        texts[f'{name}.md'] = fragment(name, installed)
        (out_dir / f'{name}.txt').unlink(missing_ok=True)   # from a build that had it
    if name not in NEEDS or installed:
        texts[f'{name}.txt'] = run(name, figures)
    for file, text in texts.items():
        path = out_dir / file
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
    return [out_dir / file for file in texts]


def write_all(out_dir=DEFAULT_OUT, names=None, figures=None):
    """Write the files of each transcript (all by default) into ``out_dir``; their paths. The
    plots the commands draw (``--plot``) go to ``figures`` when it is given.

    Raises
    ------
    RuntimeError
        When the second process, which runs the ``BESIDE`` transcripts, fails."""
    import matplotlib
    matplotlib.use('Agg')
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    names = list(names or TRANSCRIPTS)
    beside = [name for name in names if name in BESIDE]
    child = subprocess.Popen([sys.executable, __file__, str(out_dir), '--names', *beside],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             text=True) if beside else None
    paths = []
    try:
        for name in names:
            if name not in beside:
                paths += write(out_dir, name, figures)
    finally:
        output = child.communicate()[0] if child else ''
    if child and child.returncode != 0:
        raise RuntimeError(f'scripts/transcripts.py --names {" ".join(beside)} failed:\n{output}')
    return paths + [out_dir / file for name in beside for file in files(name)]


if __name__ == '__main__':
    started = time.perf_counter()
    args = sys.argv[1:]
    only = args[args.index('--names') + 1:] if '--names' in args else None
    places = args[:args.index('--names')] if only is not None else args
    out = Path(places[0]) if places else DEFAULT_OUT
    if only is not None:      # the BESIDE part of write_all, or any names asked for, here
        out.mkdir(parents=True, exist_ok=True)
        written = [path for name in only for path in write(out, name)]
    else:
        written = write_all(out, figures=places[1] if len(places) > 1 else None)
    print(f'{len(written)} transcripts in {time.perf_counter() - started:.1f} s')
