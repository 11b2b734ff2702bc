"""What a bench printed, as a Markdown file the docs include: ``--markdown OUT``.

Each bench ends with ``run(main)``. Given ``--markdown OUT`` (anywhere on its command line; the
bench's own options are unchanged), the bench runs as usual and what it printed is also written
to OUT, with the command, the date and the machine's load, for the docs' benchmarks page
(docs/benchmarks.md includes docs/bench_results/*.md; the docs build never runs a bench).
"""
import io
import os
import shlex
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


class _Tee(io.TextIOBase):
    def __init__(self, stream):
        self.stream, self.text = stream, io.StringIO()

    def write(self, text):
        self.text.write(text)
        return self.stream.write(text)

    def flush(self):
        self.stream.flush()


def _command(script, argv):
    try:
        script = Path(script).resolve().relative_to(ROOT)
    except ValueError:
        pass
    return shlex.join(['python', str(script), *argv])


def markdown(command, output, started, load_before, load_after):
    """The Markdown text: when and how it was run, then the output as printed."""
    stamp = time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime(started))
    return (f'`{command}`, run on {stamp} on a machine with {os.cpu_count()} cores '
            f'(1-minute load average {load_before:.1f} at the start, {load_after:.1f} at the end; '
            f'{time.time() - started:.0f} s):\n\n```text\n{output.rstrip()}\n```\n')


def run(main):
    """Call ``main()``; with ``--markdown OUT`` on the command line, also write OUT."""
    argv = sys.argv[1:]
    if '--markdown' not in argv:
        return main()
    i = argv.index('--markdown')
    if i + 1 >= len(argv):
        sys.exit(f'{sys.argv[0]}: --markdown needs a file name')
    out = Path(argv[i + 1])
    rest = argv[:i] + argv[i + 2:]
    command = _command(sys.argv[0], rest)
    sys.argv = [sys.argv[0], *rest]
    started, load_before = time.time(), os.getloadavg()[0]
    tee = _Tee(sys.stdout)
    sys.stdout = tee
    try:
        result = main()
    finally:
        sys.stdout = tee.stream
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(markdown(command, tee.text.getvalue(), started, load_before,
                            os.getloadavg()[0]))
    print(f'table written to {out}')
    return result
