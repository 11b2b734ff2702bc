"""The packages' public names, imported on first use (``contact_sim._lazy``, issue 17 item 7).

Importing a package imports none of its modules; every name of its ``__all__`` is reached as
before (``from contact_sim.impact import LOSSES``), whatever was imported first: no public name
is a submodule's name (``test_layout``; issue 36 renamed ``impact/restitution.py`` to
``impact/outcomes.py``).  The import-order cases run in a fresh interpreter: this one has
imported everything already.
"""
import importlib
import subprocess
import sys
import types

import pytest

PACKAGES = ('contact_sim', 'contact_sim.calibration', 'contact_sim.drop', 'contact_sim.export',
            'contact_sim.flight', 'contact_sim.impact', 'contact_sim.phase')


def _fresh(code):
    """The stdout lines of ``code`` run by a new interpreter."""
    done = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip().splitlines()


@pytest.mark.parametrize('name', PACKAGES)
def test_every_public_name_of_a_package_is_reached_from_its_module(name):
    package = importlib.import_module(name)
    sources = package._lazy_sources
    eager = set(package.__all__) - set(sources)    # imported by the __init__ itself
    assert eager <= {'InputError'} and eager <= set(vars(package))
    for public in set(package.__all__) - eager:
        value = getattr(package, public)
        assert value is getattr(importlib.import_module(sources[public]), public), public
    assert set(package.__all__) <= set(dir(package))


def test_importing_the_packages_imports_none_of_their_modules():
    lines = _fresh('import sys\n'
                   f'import {", ".join(PACKAGES)}\n'
                   'print(sorted(m for m in sys.modules if m.startswith("contact_sim.")))\n'
                   'print(sorted(m for m in sys.modules if m.split(".")[0] in ("numpy", "scipy",'
                   ' "numba")))\n')
    assert lines[-2] == str(sorted(PACKAGES[1:] + ('contact_sim._lazy', 'contact_sim.validation')))
    assert lines[-1] == '[]'


def test_a_public_name_stays_itself_when_its_module_was_imported_first():
    # importing contact_sim/impact/outcomes.py binds the module `outcomes` on its package; the
    # function restitution it defines is what `contact_sim.impact.restitution` gives (issue 36:
    # once the module had the function's name, and _lazy overrode the import system's binding)
    lines = _fresh('import importlib\n'
                   'for m in ("contact_sim.impact.outcomes", "contact_sim.impact.dimensionless_outcomes",'
                   ' "contact_sim.drop.sweeps"):\n'
                   '    importlib.import_module(m)\n'
                   'import contact_sim.impact as impact, contact_sim.drop as drop\n'
                   'import contact_sim.impact.outcomes as outcomes\n'
                   'print([type(f).__name__ for f in (impact.restitution, impact.dimensionless, '
                   'drop.sweep, outcomes, drop.sweeps)])\n'
                   'print(impact.restitution is outcomes.restitution)\n')
    assert lines[-2:] == [str(['function'] * 3 + ['module'] * 2), 'True']


def test_a_submodule_is_reached_as_an_attribute_and_a_missing_name_is_refused():
    import contact_sim.phase as phase
    assert isinstance(phase.compiled, types.ModuleType)
    assert phase.compiled is sys.modules['contact_sim.phase.compiled']
    with pytest.raises(AttributeError, match="'contact_sim.phase' has no attribute 'nothing'"):
        phase.nothing  # noqa: B018
    assert not hasattr(phase, '__wrapped__')


def test_a_name_given_by_two_modules_is_refused():
    from contact_sim._lazy import lazy_exports
    module = types.ModuleType('contact_sim.lazy_probe')
    sys.modules[module.__name__] = module
    try:
        with pytest.raises(ValueError, match='LOSSES is given by contact_sim.lazy_probe.a and '
                                             'contact_sim.lazy_probe.b'):
            lazy_exports(module.__name__, {'a': ('LOSSES',), 'b': ('LOSSES',)})
    finally:
        del sys.modules[module.__name__]
