"""The engines the export knows: each with how it exports, where its version comes from and
whether its e(v) is measured (the engine is run) or predicted (its law evaluated here)."""
from dataclasses import dataclass

import numpy as np

from contact_sim.export import drake, drake_plant, gazebo, mujoco_engine, pybullet_engine
from contact_sim.export.common import Export
from contact_sim.validation import InputError


@dataclass(frozen=True)
class Engine:
    """One simulator: ``export(target, timestep) -> common.EngineFit``, ``version()``,
    ``limit`` (what its contact cannot do) and whether its law is ``linear`` (one e at every
    speed, whatever the time step)."""

    name: str
    export: object
    version: object
    limit: str
    linear: bool


LINEAR_LIMIT = ('a linear spring-damper gives one e at every speed: no choice misses a '
                'speed-dependent target by less than half its spread, at any time step')
ENGINES = {engine.name: engine for engine in (
    Engine('mujoco', mujoco_engine.export_mujoco, mujoco_engine.version, LINEAR_LIMIT, True),
    Engine('pybullet', pybullet_engine.export_pybullet, pybullet_engine.version, LINEAR_LIMIT,
           True),
    Engine('drake', drake.export_drake, drake_plant.version,
           'Hunt-Crossley on a linear spring: e is a function of d v alone, falling from 1, '
           'with a shape of its own; a discrete step adds a loss of its own', False),
    Engine('gazebo', gazebo.export_gazebo, lambda: 'ODE (kp/kd)', LINEAR_LIMIT, True))}


def require_engine(engine):
    """The ``Engine`` named ``engine``, else ``InputError`` keyed ``engine``."""
    if engine not in ENGINES:
        raise InputError('engine', engine, '{n[engine]} = {value} is unknown: allowed '
                         + ', '.join(ENGINES), value=repr(engine))
    return ENGINES[engine]


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
    chosen = require_engine(engine)
    fit = chosen.export(target, timestep)
    return Export(engine, chosen.version(), target, fit.parameters, fit.snippet,
                  np.asarray(fit.restitution), fit.source, fit.note, fit.duration,
                  fit.peak_force, fit.reach, fit.scene, tuple(fit.pitfalls))
