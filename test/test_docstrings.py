"""Every public name has a numpydoc docstring, and every ``>>>`` example in them runs as printed.

The rule of issue 18 (item 3, 4): each name in ``contact_sim.__all__`` documents its
Parameters (callables that take arguments; a dataclass its fields, as Attributes), Returns
(functions), Raises where it refuses input, and Examples; the public methods of those classes do
the same.  The examples run here with the standard ``doctest`` module, so a plain pytest run
checks them (the docs build runs them again with ``sphinx.ext.doctest``).  Sections are found by
their numpydoc underline, so the test needs nothing beyond the standard library.  The same holds
for the subpackages' names the API reference lists (``REFERENCED``) and, without running their
examples (they need a ROS graph), for the node's Python API (``ROS_API``, marker ``ros``).
"""
import ast
import dataclasses
import doctest
import inspect
import re
import textwrap

import pytest

import contact_sim as cs

SECTION = re.compile(r'^(\w[\w ]*)\n-{3,}$', re.MULTILINE)


def _sections(obj):
    return set(SECTION.findall(inspect.getdoc(obj) or ''))


def _takes_arguments(func):
    try:
        signature = inspect.signature(func)
    except (TypeError, ValueError):
        return False
    return any(name not in ('self', 'cls') for name in signature.parameters)


CALLABLES = [name for name in cs.__all__ if inspect.isclass(getattr(cs, name))
             or inspect.isfunction(getattr(cs, name))]
CONSTANTS = [name for name in cs.__all__ if name not in CALLABLES]


def _returns_something(func):
    """True if ``func`` has a ``return <value>`` of its own (numpydoc's rule for RT01)."""
    tree = ast.parse(textwrap.dedent(inspect.getsource(func)))
    body = tree.body[0]
    nested = {id(node) for node in ast.walk(body) if node is not body
              and isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))}
    inner = set()
    for node in ast.walk(body):
        if id(node) in nested:
            inner.update(id(child) for child in ast.walk(node))
    return any(isinstance(node, ast.Return) and node.value is not None and id(node) not in inner
               for node in ast.walk(body))


def _public_methods(cls):
    """(name, function) of the methods a user calls: defined in contact_sim, not ``_``-named."""
    out = []
    for name, member in vars(cls).items():
        if name.startswith('_'):
            continue
        if isinstance(member, (classmethod, staticmethod)):
            member = member.__func__
        if inspect.isfunction(member) and member.__module__.startswith('contact_sim'):
            out.append((name, member))
    return out


def test_the_public_names_are_split_into_callables_and_constants():
    assert len(CALLABLES) + len(CONSTANTS) == len(cs.__all__)
    assert 'simulate_drop' in CALLABLES and 'LAWS' in CONSTANTS


@pytest.mark.parametrize('name', CALLABLES)
def test_every_public_callable_has_numpydoc_sections(name):
    obj = getattr(cs, name)
    found = _sections(obj)
    doc = inspect.getdoc(obj) or ''
    assert doc.split('\n', 1)[0].strip(), f'{name}: no one-line summary'
    assert 'Examples' in found, f'{name}: no Examples section (has {sorted(found)})'
    assert '>>>' in doc.split('Examples\n--------', 1)[1], f'{name}: Examples without >>>'
    if inspect.isclass(obj):
        fields = dataclasses.is_dataclass(obj)
        need = 'Attributes' if fields else 'Parameters'
        if fields or _takes_arguments(obj):
            assert need in found, f'{name}: no {need} section (has {sorted(found)})'
        if fields:     # Attributes documents the fields; a Parameters copy would warn twice
            assert 'Parameters' not in found, f'{name}: fields in Parameters and Attributes'
    else:
        if _takes_arguments(obj):
            assert 'Parameters' in found, f'{name}: no Parameters section (has {sorted(found)})'
        assert 'Returns' in found, f'{name}: no Returns section (has {sorted(found)})'
        # every public function checks its input: it says what it refuses
        assert 'Raises' in found, f'{name}: no Raises section (has {sorted(found)})'


@pytest.mark.parametrize('name', [n for n in CALLABLES if inspect.isclass(getattr(cs, n))])
def test_public_methods_and_properties_are_documented(name):
    cls = getattr(cs, name)
    missing = []
    for method_name, method in _public_methods(cls):
        found = _sections(method)
        if not (inspect.getdoc(method) or '').strip():
            missing.append(f'{method_name}: no docstring')
            continue
        if _takes_arguments(method) and 'Parameters' not in found:
            missing.append(f'{method_name}: no Parameters')
        if _returns_something(method) and 'Returns' not in found:
            missing.append(f'{method_name}: no Returns')
    for prop_name, prop in vars(cls).items():
        if isinstance(prop, property) and not prop_name.startswith('_') \
                and not (prop.__doc__ or '').strip():
            missing.append(f'{prop_name}: property without a docstring')
    assert not missing, f'{name}: ' + '; '.join(missing)


@pytest.mark.parametrize('name', CONSTANTS)
def test_every_public_constant_is_documented_where_it_is_defined(name):
    """A constant's doc is a ``#:`` comment above its assignment (what autodoc reads)."""
    obj = getattr(cs, name)
    module = next(m for m in ('contact_sim.model.laws', 'contact_sim.model.materials')
                  if name in vars(__import__(m, fromlist=['_'])))
    source = inspect.getsource(__import__(module, fromlist=['_']))
    match = re.search(r'((?:^#:.*\n)+)^%s = ' % re.escape(name), source, re.MULTILINE)
    assert obj is not None and match, f'{name}: no #: doc comment above its assignment'


def _doctests(obj, name):
    finder = doctest.DocTestFinder(recurse=True, exclude_empty=True)
    module = inspect.getmodule(obj)
    return [test for test in finder.find(obj, name, module=module, globs={'cs': cs})
            if test.examples]


@pytest.mark.parametrize('name', CALLABLES)
def test_the_docstring_examples_run_as_printed(name):
    obj = getattr(cs, name)
    tests = _doctests(obj, name)
    assert tests, f'{name}: no doctest found'
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in tests:
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f'{name}: {result.failed} of {result.attempted} examples failed'


def test_there_are_at_least_thirty_examples():
    count = sum(len(test.examples) for name in CALLABLES
                for test in _doctests(getattr(cs, name), name))
    assert count >= 30, count


ROS_API = ('contact_sim.ros.node:ContactSimNode', 'contact_sim.ros.node:StartupError',
           'contact_sim.ros.node:main', 'contact_sim.ros.start:node_main',
           'contact_sim.ros.recorder:Recorder',
           'contact_sim.ros.recorder:record_main', 'contact_sim.ros.recorder:recover_main',
           'contact_sim.ros.record_options:record_parser')


@pytest.mark.ros
@pytest.mark.parametrize('target', ROS_API)
def test_the_nodes_python_api_has_numpydoc_sections(target):
    """The node, the recorder and their entry points (imported only: no ROS process starts).

    Their examples need a ROS graph, so they are ``.. code-block::`` text, not doctests."""
    module, name = target.split(':')
    obj = getattr(__import__(module, fromlist=[name]), name)
    found = _sections(obj)
    if inspect.isfunction(obj):
        assert 'Returns' in found, f'{target}: no Returns (has {sorted(found)})'
        if _takes_arguments(obj):
            assert 'Parameters' in found, f'{target}: no Parameters (has {sorted(found)})'
        assert 'Examples' in found, f'{target}: no Examples (has {sorted(found)})'
    elif _takes_arguments(obj) and obj.__init__ is not Exception.__init__:
        assert {'Parameters', 'Examples'} <= found, f'{target}: has {sorted(found)}'
    for method_name, method in (_public_methods(obj) if inspect.isclass(obj) else ()):
        assert (inspect.getdoc(method) or '').strip(), f'{target}.{method_name}: no docstring'
        if _returns_something(method):
            assert 'Returns' in _sections(method), f'{target}.{method_name}: no Returns'


# the subpackages' names the API reference lists beside contact_sim.__all__ (docs/api)
REFERENCED = ('contact_sim.drop:SinusoidalPlate', 'contact_sim.drop:CommandedPlate',
              'contact_sim.drop:SwitchedPlate', 'contact_sim.drop:table_transition',
              'contact_sim.drop:command_motion', 'contact_sim.drop:VibratingTable',
              'contact_sim.drop:bifurcation_diagram', 'contact_sim.drop:period_one_threshold',
              'contact_sim.drop:period_doubling_threshold', 'contact_sim.calibration:BounceFit',
              'contact_sim.calibration:bounce_times_from_audio',
              'contact_sim.calibration:corrected_restitution_table',
              'contact_sim.coupling:NormalCoupling', 'contact_sim.coupling:friction_impulse',
              'contact_sim.coupling:touch_time', 'contact_sim.coupling.mujoco:CoupledContacts',
              'contact_sim.coupling.pybullet:CoupledContacts',
              'contact_sim.coupling.drake:CoupledContacts',
              'contact_sim.coupling.mujoco:coupled_restitution',
              'contact_sim.coupling.pybullet:coupled_restitution',
              'contact_sim.coupling:engine_restitution')


@pytest.mark.parametrize('target', REFERENCED)
def test_the_referenced_subpackage_names_have_sections_and_running_examples(target):
    module, name = target.split(':')
    obj = getattr(__import__(module, fromlist=[name]), name)
    found = _sections(obj)
    assert 'Examples' in found, f'{target}: no Examples (has {sorted(found)})'
    assert found & {'Parameters', 'Attributes'}, f'{target}: no Parameters or Attributes'
    if inspect.isfunction(obj):
        assert 'Returns' in found, f'{target}: no Returns (has {sorted(found)})'
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    finder = doctest.DocTestFinder(recurse=False, exclude_empty=True)
    for test in finder.find(obj, name, module=inspect.getmodule(obj), globs={}):
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.attempted and result.failed == 0, f'{target}: {result}'
