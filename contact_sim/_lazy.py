"""Public names imported on first use (PEP 562), the one mechanism of every package ``__init__``.

A package lists where its public names live, ``_EXPORTS = {'damping_fit': ('fit_damping',
...), ...}`` (a submodule, relative to the package or absolute, and the names it gives), and
hands the table to ``lazy_exports``; ``from contact_sim.impact import LOSSES`` then imports the
module that defines ``LOSSES`` and nothing else.  So importing a package costs nothing until
one of its names is used, and the command line parses (and refuses) its arguments without
importing numba, scipy's solvers or the exporters.

A submodule is reached as before (``contact_sim.phase.compiled``, ``from contact_sim import
impact``), imported when first asked for.  No public name is a submodule's name (a test in
``test/test_layout.py``): the import system binds a submodule on its package when it is
imported, and would otherwise replace the public name.
"""
import importlib
import sys


def lazy_exports(package, exports):
    """``(__getattr__, __dir__)`` for the ``__init__`` of ``package``: its public names
    imported when first asked for.

    Parameters
    ----------
    package : str
        The package's ``__name__`` (it is in ``sys.modules``, being initialised).
    exports : dict
        Module -> the names it gives: a submodule relative to ``package`` (``'damping_fit'``)
        or an absolute module name (``'contact_sim.impact'``).

    Returns
    -------
    tuple
        The module's ``__getattr__`` (a public name imported from its module, or a submodule,
        on first use; ``AttributeError`` otherwise) and ``__dir__`` (its globals and
        ``__all__``).

    Raises
    ------
    ValueError
        If a name is given by two modules.

    Examples
    --------
    >>> import contact_sim.impact as impact
    >>> 'LOSSES' in dir(impact) and 'soft_l1' in impact.LOSSES
    True
    """
    module = sys.modules[package]
    sources = {}
    for source, names in exports.items():
        absolute = source if source.startswith('contact_sim') else f'{package}.{source}'
        for name in names:
            if sources.setdefault(name, absolute) != absolute:
                raise ValueError(f'{package}: {name} is given by {sources[name]} and {absolute}')
    module._lazy_sources = sources

    def __getattr__(name):
        source = sources.get(name)
        if source is not None:
            value = getattr(importlib.import_module(source), name)
        elif name.startswith('__'):
            raise AttributeError(f'module {package!r} has no attribute {name!r}')
        else:
            value = _submodule(package, name)
        module.__dict__[name] = value
        return value

    def __dir__():
        return sorted(set(module.__dict__) | set(module.__dict__.get('__all__', ())))

    return __getattr__, __dir__


def _submodule(package, name):
    """Submodule ``name`` of ``package``, imported; ``AttributeError`` if there is none."""
    try:
        return importlib.import_module(f'{package}.{name}')
    except ModuleNotFoundError as error:
        if error.name != f'{package}.{name}':
            raise         # the submodule exists, and something it imports is missing
        raise AttributeError(f'module {package!r} has no attribute {name!r}') from None
