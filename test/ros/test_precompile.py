"""``python -m contact_sim.ros.precompile`` (issue 33: the workspace's pre-compile step,
``python3 -c "import contact_sim"``, compiled nothing, and the node's first start compiled for
34.8 s). The engine's kernels compile, with their signatures, when their modules are imported
(and are cached): the step must import every one the node's engine uses, which importing the
package does not.
"""
import subprocess
import sys

from .harness import TIMEOUT

KERNEL_MODULES = ('contact_sim.phase.compiled', 'contact_sim.drop.plate.compiled_flight',
                  'contact_sim.drop.plate.compiled_ballistic')
PROBE = ('import sys; {step}; print(sorted(m for m in {modules!r} if m in sys.modules))')


def loaded_after(step):
    code = PROBE.format(step=step, modules=KERNEL_MODULES)
    done = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                          timeout=10 * TIMEOUT)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout.strip().splitlines()[-1]


def test_importing_the_package_compiles_nothing_and_the_step_everything_the_node_runs():
    assert loaded_after('import contact_sim') == '[]'
    step = 'from contact_sim.ros.precompile import main; main()'
    assert loaded_after(step) == repr(sorted(KERNEL_MODULES))


def test_the_step_says_what_it_ran(capsys):
    from contact_sim.ros.precompile import RUNS, main
    assert main() == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split(':')[0] for line in lines[:-1]] == [name for name, _ in RUNS]
    assert lines[-1].startswith("the node's kernels are compiled and cached (")
