"""The hostile-input campaign's named cases (``scripts/hostile_inputs.py``), run in this process
so CI replays them in seconds: every library expression is refused with an ``InputError`` naming
the field it lists (or, with no field, answered with finite numbers and no RuntimeWarning), and
every issue-34 command line is refused naming its option (exit 2) or, for a valid one, runs
(exit 0).  The full campaign (about 750 cases, a few minutes) stays a script."""
import contextlib
import importlib.util
import io
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

import contact_sim as cs
from contact_sim.calibration import parse_impact_times  # noqa: F401 (used by the expressions)
from contact_sim.cli.app import main
from contact_sim.drop import CommandedPlate, command_motion, sphere_motion  # noqa: F401

SCRIPT = Path(__file__).resolve().parent.parent / 'scripts' / 'hostile_inputs.py'
_spec = importlib.util.spec_from_file_location('hostile_inputs', SCRIPT)
hostile = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(hostile)

C = cs.Contact(cs.AZAD_FEATHERSTONE, 1e10, 1e5)
T = np.cumsum([0.0, 0.45, 0.40, 0.36, 0.32, 0.29])


def _finite(x, depth=0):
    """Every number in ``x`` (results, arrays, dataclasses) is finite (the campaign's rule)."""
    if depth > 4:
        return True
    if isinstance(x, (float, int, np.floating, np.integer)) and not isinstance(x, bool):
        return math.isfinite(float(x))
    if isinstance(x, np.ndarray) and x.dtype.kind in 'fc':
        return bool(np.all(np.isfinite(x)))
    if isinstance(x, (list, tuple)):
        return all(_finite(v, depth + 1) for v in list(x)[:1000])
    if hasattr(x, '__dataclass_fields__'):
        return all(_finite(getattr(x, f), depth + 1) for f in x.__dataclass_fields__
                   if f not in hostile_documented())
    return True


def hostile_documented():
    # the fields documented as possibly non-finite (a time not reached, a permanent contact)
    return {'permanent_contact_time', 'settle_time', 'contact_duration', 'drag_interval',
            'delta_aic'}


@pytest.mark.parametrize('expression, field', hostile.EXPRESSIONS,
                         ids=[e[:60] for e, _ in hostile.EXPRESSIONS])
def test_a_named_library_case_is_refused_naming_its_field_or_answered_finite(expression, field):
    with warnings.catch_warnings():
        warnings.simplefilter('error', RuntimeWarning)   # a warning is a failure
        if field:
            with pytest.raises(cs.InputError) as info:
                eval(expression)
            assert field in str(info.value), str(info.value)
            assert 'np.' not in str(info.value)          # plain numbers, no numpy repr
        else:
            assert _finite(eval(expression))


CLI_CASES = hostile.issue34_cli_cases('/files', write_files=False)   # for the ids only


@pytest.mark.parametrize('index', range(len(CLI_CASES)),
                         ids=[' '.join(argv)[:70] for argv, _ in CLI_CASES])
def test_an_issue_34_command_line_is_refused_naming_its_option_or_runs(index, tmp_path,
                                                                       monkeypatch):
    argv, option = hostile.issue34_cli_cases(tmp_path)[index]   # its input files written here
    monkeypatch.chdir(tmp_path)   # --plot x.png and the like land here
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as stop:   # argparse's own refusals
            code = stop.code
    out, err = out.getvalue(), err.getvalue()
    assert 'Traceback' not in out + err
    if option is None:
        assert code == 0, err
        assert out.startswith('# no contact given: the default contact')   # said first
        assert 'nan' not in out and ' inf' not in out
    else:
        assert code == 2, out[-300:]
        assert option in err.strip().splitlines()[-1], err
