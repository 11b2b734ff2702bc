"""The coupling's e(v) in an engine by the engine's name, for the command line's ``audit
--coupled``: the adapter (and its engine) imported when called."""
from contact_sim.validation import InputError

ENGINES = ('mujoco', 'pybullet')


def engine_restitution(engine, contact, radius, mass, speeds, timestep, integrator=None):
    """The e(v) the coupling gives in ``engine``: a free sphere thrown at a plane, gravity off.

    Parameters
    ----------
    engine : str
        'mujoco' or 'pybullet'.
    contact : Contact
        The contact coupled in.
    radius, mass : float
        The sphere's radius (m) and mass (kg), > 0.
    speeds : array_like of float
        Impact speeds, m/s, > 0.
    timestep : float
        The engine's step, s, > 0.
    integrator : str, optional
        MuJoCo's integrator ('Euler', 'implicit', 'implicitfast'; default implicitfast).

    Returns
    -------
    numpy.ndarray
        e at each speed (``contact_sim.coupling.mujoco.coupled_restitution``,
        ``contact_sim.coupling.pybullet.coupled_restitution``).

    Raises
    ------
    InputError
        Keyed ``engine`` (not one of ``ENGINES``), or the adapter's fields.

    Examples
    --------
    >>> import contact_sim as cs
    >>> from contact_sim.coupling import engine_restitution
    >>> contact = cs.Contact.from_materials(cs.AZAD_FEATHERSTONE, 'steel', 'cast_iron',
    ...                                     radius=0.0127, damping_factor=8.87e5)
    >>> print(f"{engine_restitution('mujoco', contact, 0.0127, 0.0674, [1.0], 1e-3)[0]:.4f}")
    0.7381
    """
    if engine == 'mujoco':
        from contact_sim.coupling.mujoco import coupled_restitution
        return coupled_restitution(contact, radius, mass, speeds, timestep,
                                   integrator or 'implicitfast')
    if engine == 'pybullet':
        from contact_sim.coupling.pybullet import coupled_restitution
        return coupled_restitution(contact, radius, mass, speeds, timestep)
    raise InputError('engine', engine, '{n[engine]} = {value} is not coupled: allowed one of '
                     + ', '.join(ENGINES))
