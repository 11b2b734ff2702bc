#!/usr/bin/env python3
"""Console transcripts for the docs, made by running the real commands.

    python scripts/transcripts.py [OUT_DIR [FIGURES_DIR]]   # default docs/_generated/transcripts

Each transcript is one ``NAME.txt``: the commands as a user types them (``$ ...``), each followed
by what it printed (stdout and stderr, in order of the steps). The `contact-sim` commands run in
this process through ``contact_sim.cli.main`` (the console script's own entry point: the same
code, without paying Python's and numba's start-up for each), in a temporary working directory,
so the files they write (plots, CSV, YAML) are named as a user would see them. A shell pipeline
is run as its parts: the `contact-sim` part here, the filter (``awk``, ``head``, ``cat``) in the
shell. The docs build (docs/_ext/contact_sim_docs.py) runs this script; it writes only files
whose text changed.
"""
import contextlib
import io
import os
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


def missing(out_dir):
    """True when a transcript file is absent from ``out_dir``."""
    return any(not (Path(out_dir) / f'{name}.txt').exists() for name in TRANSCRIPTS)


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


def write_all(out_dir=DEFAULT_OUT, names=None, figures=None):
    """Write ``NAME.txt`` for each transcript (all by default) into ``out_dir``; their paths.
    The plots the commands draw (``--plot``) go to ``figures`` when it is given."""
    import matplotlib
    matplotlib.use('Agg')
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    for name in names or TRANSCRIPTS:
        path = out_dir / f'{name}.txt'
        text = run(name, figures)
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
        paths.append(path)
    return paths


if __name__ == '__main__':
    started = time.perf_counter()
    written = write_all(sys.argv[1] if len(sys.argv) > 1 else DEFAULT_OUT,
                        figures=sys.argv[2] if len(sys.argv) > 2 else None)
    print(f'{len(written)} transcripts in {time.perf_counter() - started:.1f} s')
