"""The engines the export knows: each with how it exports, where its version comes from and
whether its e(v) is measured (the engine is run) or predicted (its law evaluated here)."""
from dataclasses import dataclass
from importlib import metadata

from contact_sim.export import drake, gazebo, mujoco_engine, pybullet_engine
from contact_sim.export.common import Export
from contact_sim.validation import InputError


@dataclass(frozen=True)
class Engine:
    """One simulator: ``export(target, timestep) -> (parameters, snippet, e, note)``, ``version()``,
    ``source`` ('measured' or 'predicted') and ``limit``: what its contact cannot do."""

    name: str
    export: object
    version: object
    source: str
    limit: str


def _distribution_version(name):
    def version():
        try:
            return metadata.version(name)
        except metadata.PackageNotFoundError:
            return 'not installed'
    return version


LINEAR_LIMIT = ('a linear spring-damper gives one e at every speed: the best choice misses a '
                'speed-dependent target by half its spread, at any time step')
ENGINES = {engine.name: engine for engine in (
    Engine('mujoco', mujoco_engine.export_mujoco, mujoco_engine.version, 'measured',
           LINEAR_LIMIT),
    Engine('pybullet', pybullet_engine.export_pybullet, pybullet_engine.version, 'measured',
           LINEAR_LIMIT),
    Engine('drake', drake.export_drake, _distribution_version('drake'), 'predicted',
           'Hunt-Crossley on a linear spring: e is a function of d v alone, falling from 1, '
           'with a shape of its own'),
    Engine('gazebo', gazebo.export_gazebo, lambda: 'ODE (kp/kd)', 'predicted', LINEAR_LIMIT))}


def export_contact(engine, target, timestep):
    """Export ``target`` (``common.Target``) to ``engine`` (a name in ``ENGINES``) at
    ``timestep`` (s).

    Returns
    -------
    Export

    Raises
    ------
    InputError
        If the engine is unknown or the timestep out of range.
    ImportError
        If a measured engine's Python package is not installed.

    Examples
    --------
    >>> export_contact('gazebo', make_target(contact, mass, 0.0127, [0.1, 1.0]), 1e-3)
    ... # doctest: +SKIP
    """
    if engine not in ENGINES:
        raise InputError('engine', engine, '{n[engine]} = {value} is unknown: allowed '
                         + ', '.join(ENGINES), value=repr(engine))
    chosen = ENGINES[engine]
    parameters, snippet, e, note = chosen.export(target, timestep)
    return Export(engine, chosen.version(), target, parameters, snippet, e, chosen.source, note)
