"""The tree shows the layers (docs/architecture.md): checked on the source, statically.

* every import inside ``contact_sim`` points down the layers (or stays in its own package);
* across packages a module imports the package, never a module inside another package;
* the static import graph of the modules has no cycle;
* no public name of a package is the name of one of its submodules (``import pkg.name as m``
  would give the module or the name depending on what was imported first);
* no module is over 500 lines (the generated DOP853 coefficients aside).
"""
import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / 'contact_sim'
# bottom up; a module may import its own layer and the layers below
LAYERS = {'validation': 0, '_lazy': 0, 'model': 1, 'phase': 2, 'flight': 2, 'impact': 3, 'drop': 4,
          'calibration': 5, 'export': 5, 'cli': 6, 'ros': 6,
          'coupling': 4}
FRONT_ENDS = {'cli', 'ros'}
MAX_LINES = 500
GENERATED = {'phase/_dop853_coefficients.py'}


def _modules():
    out = {}
    for path in sorted(PACKAGE.rglob('*.py')):
        parts = path.relative_to(PACKAGE.parent).with_suffix('').parts
        name = '.'.join(parts[:-1] if parts[-1] == '__init__' else parts)
        out[name] = path
    return out


MODULES = _modules()


def _exported(package):
    """The names in ``package``'s ``__all__`` (empty for a module or a package without one)."""
    path = MODULES.get(package)
    if path is None or path.name != '__init__.py':
        return set()
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.Assign) and any(getattr(t, 'id', None) == '__all__'
                                                for t in node.targets):
            return set(ast.literal_eval(node.value))
    return set()


def _lazy_exported(package):
    """The names of ``package``'s lazy export table (``_EXPORTS`` of its ``__init__``)."""
    path = MODULES.get(package)
    if path is None or path.name != '__init__.py':
        return set()
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.Assign) and any(getattr(t, 'id', None) == '_EXPORTS'
                                                for t in node.targets):
            return {n for names in ast.literal_eval(node.value).values() for n in names}
    return set()


def _imports(name, path):
    """(imported module or package, line) for every contact_sim import of ``name``, however deep
    in the code (function-level imports count); a package's lazy public names (``_EXPORTS`` of
    its ``__init__``, ``contact_sim._lazy``) count as imports of their modules."""
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if path.name == '__init__.py' and isinstance(node, ast.Assign) \
                and any(getattr(t, 'id', None) == '_EXPORTS' for t in node.targets):
            found += [(m if m.startswith('contact_sim') else f'{name}.{m}', node.lineno)
                      for m in ast.literal_eval(node.value)]
        if isinstance(node, ast.Import):
            found += [(alias.name, node.lineno) for alias in node.names
                      if alias.name.startswith('contact_sim')]
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ''
            if node.level:          # relative: resolved against the importing module's package
                package = name.split('.') if path.name == '__init__.py' else name.split('.')[:-1]
                base = package[:len(package) - node.level + 1]
                module = '.'.join(base + ([module] if module else []))
            if not module.startswith('contact_sim'):
                continue
            exported = _exported(module)          # a name the package exports is its own
            subs = [f'{module}.{a.name}' for a in node.names
                    if f'{module}.{a.name}' in MODULES and a.name not in exported]
            found += [(sub, node.lineno) for sub in subs]
            if len(subs) < len(node.names):
                found.append((module, node.lineno))
    return found


def _layer(name):
    parts = name.split('.')
    return parts[1] if len(parts) > 1 else None


def test_imports_point_down_the_layers_and_name_packages_across_them():
    wrong = []
    for name, path in MODULES.items():
        own = _layer(name)
        if own is None:
            continue        # contact_sim/__init__: the public names of every layer
        for target, line in _imports(name, path):
            layer = _layer(target)
            where = f'{path.relative_to(PACKAGE.parent)}:{line} imports {target}'
            if layer is None:
                if own not in FRONT_ENDS:   # the public names: for the front ends only
                    wrong.append(f'{where}: a core layer imports the top-level package')
            elif layer != own and LAYERS[layer] > LAYERS[own]:
                wrong.append(f'{where}: an upward import ({own} is below {layer})')
            elif layer != own and target.count('.') > 1:
                wrong.append(f'{where}: a module inside another package')
    assert not wrong, '\n'.join(wrong)


def test_the_import_graph_has_no_cycle():
    graph = {name: {t for t, _ in _imports(name, path) if t != name}
             for name, path in MODULES.items()}
    state, cycles = {}, []

    def visit(node, trail):
        state[node] = 'open'
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 'open':
                cycles.append(trail[trail.index(nxt):] + [nxt])
            elif nxt not in state:
                visit(nxt, trail + [nxt])
        state[node] = 'done'

    for name in sorted(graph):
        if name not in state:
            visit(name, [name])
    assert not cycles, '\n'.join(' -> '.join(c) for c in cycles)


PACKAGES = sorted(name for name, path in MODULES.items() if path.name == '__init__.py')


@pytest.mark.parametrize('package', PACKAGES)
def test_no_public_name_of_a_package_is_one_of_its_submodules(package):
    # issue 36: impact/restitution.py gave `restitution`, so the import system's binding of the
    # submodule on its package fought the function (a __setattr__ in _lazy kept the function)
    public = _exported(package) | _lazy_exported(package)
    submodules = {name.rsplit('.', 1)[1] for name in MODULES
                  if name.rsplit('.', 1)[0] == package and name != package}
    assert submodules, package
    assert not public & submodules, f'{package}: submodules named like public names'


@pytest.mark.parametrize('path', [p for p in MODULES.values()
                                  if str(p.relative_to(PACKAGE)) not in GENERATED],
                         ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_module_is_over_500_lines(path):
    assert len(path.read_text().splitlines()) <= MAX_LINES
