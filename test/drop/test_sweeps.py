"""The sweep API: order, executors (processes, threads, a local Dask cluster), named errors."""
import importlib
from concurrent.futures import Executor, Future, ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pytest

import contact_sim as cs

from contact_sim.model.contact import Contact
from contact_sim.drop.sweeps import bifurcation_diagram, sweep
from contact_sim.drop.table import VibratingTable, period_one_threshold, period_doubling_threshold

TABLE = VibratingTable(Contact(cs.LINEAR, 1e9, 715.0), 0.01, 20.0, bounces=30, transient=150,
                       restitution_guess=0.7177)


def _square(x):
    return x * x


def test_sweep_keeps_order_on_processes_and_threads():
    assert sweep(_square, range(7), max_workers=2) == [x * x for x in range(7)]
    with ThreadPoolExecutor(2) as pool:
        assert sweep(_square, [3, 1, 2], executor=pool) == [9, 1, 4]


def test_sweep_errors_are_named():
    with pytest.raises(ValueError, match='executor'):
        sweep(_square, [1], executor='local')
    with pytest.raises(ValueError, match='max_workers'):
        sweep(_square, [1], max_workers=0)
    for values in (1.0, None, 1 + 2j):      # issue 17 (scripts/hostile_inputs.py): a TypeError
        with pytest.raises(cs.InputError, match=r'values = .* is not a sequence'):
            sweep(_square, values)


def test_sweep_refuses_a_pool_beyond_its_stated_limit_and_starts_no_more_than_the_values(
        monkeypatch):
    # issue 17: max_workers=10**6 started every worker at once under fork (~5000 processes)
    sweep_module = importlib.import_module('contact_sim.drop.sweeps')   # (the package's sweep is the function)
    limit = sweep_module.max_workers_limit()
    for bad in (10 ** 6, limit + 1, 2.5, 'abc', True):
        with pytest.raises(cs.InputError, match=r'max_workers = .* allowed 1 <= max_workers <= %d'
                           % limit):
            sweep(_square, [1], max_workers=bad)
    started = []

    class Recording(sweep_module.ProcessPoolExecutor):
        def __init__(self, max_workers):
            started.append(max_workers)
            super().__init__(max_workers=max_workers)

    monkeypatch.setattr(sweep_module, 'ProcessPoolExecutor', Recording)
    assert sweep(_square, [2, 3], max_workers=limit) == [4, 9]
    assert started == [2]       # two values: two processes, not the limit


def test_bifurcation_diagram_period_one_then_two():
    g1, g2 = period_one_threshold(0.7177), period_doubling_threshold(0.7177)
    gammas = [0.5 * (g1 + g2), 1.1 * g2]
    x, phases = bifurcation_diagram(TABLE, gammas, max_workers=2)
    one, two = phases[x == gammas[0]], phases[x == gammas[1]]
    assert len(one) == len(two) == 30
    assert np.ptp(one) < 1e-6                       # one phase: period 1
    assert np.ptp(two[::2]) < 1e-6 and np.ptp(two[1::2]) < 1e-6 and np.ptp(two) > 1e-2


def test_a_callers_executor_gives_the_default_paths_diagram_and_is_left_running():
    # issue 21: the hook bench/bench_cluster.py measures (concurrent.futures here, no Dask)
    gammas = [0.9, 1.3, 2.0]
    default = bifurcation_diagram(TABLE, gammas, max_workers=2)
    assert len(default[1]) == 3 * 30
    for pool in (ProcessPoolExecutor(2), ThreadPoolExecutor(2)):
        with pool:
            given = bifurcation_diagram(TABLE, gammas, executor=pool)
            for a, b in zip(default, given):    # the same code on the same machine
                np.testing.assert_array_equal(a, b)
            assert pool.submit(_square, 4).result() == 16   # still the caller's, not shut down


def test_an_executor_that_takes_no_work_or_a_pool_size_beside_it_is_refused_by_name():
    # issue 21: a shut-down executor raised the pool's own RuntimeError ("cannot schedule new
    # futures after shutdown"), and max_workers beside an executor was silently ignored
    pool = ThreadPoolExecutor(1)
    pool.shutdown()
    with pytest.raises(cs.InputError, match=r"executor = .*ThreadPoolExecutor.* takes no work "
                                            r"\(cannot schedule new futures after shutdown\)"):
        sweep(_square, [1, 2], executor=pool)
    with ThreadPoolExecutor(1) as pool:
        with pytest.raises(cs.InputError, match=r'max_workers = 2 with an executor: allowed '
                                                r'None') as refused:
            sweep(_square, [1, 2], executor=pool, max_workers=2)
    assert refused.value.field == 'max_workers'
    with pytest.raises(cs.InputError, match=r"executor = 'local' is invalid: allowed None or a "
                                            r"concurrent.futures.Executor"):
        sweep(_square, [1], executor='local')


def test_an_executor_refusing_work_midway_leaves_nothing_submitted_to_run():
    # review of issue 21's change: the futures submitted before the refusal went on running
    class FailsThird(Executor):
        def __init__(self):
            self.futures = []

        def submit(self, function, *args):
            if len(self.futures) == 2:
                raise RuntimeError('broken')
            self.futures.append(Future())     # accepted, not started
            return self.futures[-1]
    executor = FailsThird()
    with pytest.raises(cs.InputError, match=r'takes no work \(broken\)'):
        sweep(_square, [1, 2, 3], executor=executor)
    assert [f.cancelled() for f in executor.futures] == [True, True]


def test_sweep_on_a_local_dask_cluster():
    import distributed
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        executor = client.get_executor()
        local = sweep(TABLE, [1.2], max_workers=1)
        remote = sweep(TABLE, [1.2], executor=executor)
        np.testing.assert_array_equal(local[0], remote[0])
        assert sweep(_square, [2, 5], executor=executor) == [4, 25]


def test_bifurcation_example_runs_as_a_script(tmp_path):
    import subprocess
    import sys
    from pathlib import Path
    root = Path(__file__).resolve().parents[2]
    out = subprocess.run([sys.executable, str(root / 'examples' / 'bifurcation.py'),
                          '--points', '3', '--bounces', '10', '--transient', '10',
                          '--workers', '1', '--gamma', '0.8', '1.5',
                          '--out', str(tmp_path / 'b.png')],
                         capture_output=True, text=True, check=True)
    assert 'azad_featherstone' in out.stdout and 'linear' in out.stdout
    assert (tmp_path / 'b.png').read_bytes()[:4] == b'\x89PNG'
