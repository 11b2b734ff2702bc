"""A node parameter file (``contact_sim_node --params-file``, or the ``--save-params`` file of
`contact-sim bounces`) read as the contact options: its contact keys fill the options not given
on the command line, with the node's meaning of 0 (Hertz stiffness, lambda* sqrt(R), flat plate,
mass from density).  Keys missing from the file are not assumed: the options then apply."""
import math
import os

import yaml

from contact_sim.model import MATERIALS

# node key -> (option attribute, the core field a refusal of it is keyed by)
KEYS = {'contact_law': ('law', 'law'), 'sphere_radius': ('radius', 'radius'),
        'sphere_mass': ('mass', 'mass'), 'stiffness': ('stiffness', 'stiffness'),
        'damping': ('damping', 'damping'), 'damping_factor': ('damping_factor', 'damping_factor'),
        'plate_radius': ('plate_radius', 'plate_radius')}
CUSTOM = {f'{body}_{key}': (f'{body}_{option}', f'{body}_{option}') for body in ('sphere', 'plate')
          for key, option in (('youngs_modulus', 'modulus'), ('poisson_ratio', 'poisson'),
                              ('density', 'density'))}
ZERO_MEANS_DEFAULT = {'sphere_mass', 'stiffness', 'damping'}
MAX_BYTES = 1_000_000   # a parameter file: a few kB; read only below this size


def node_parameters(path):
    """The ``ros__parameters`` mapping of the parameter file ``path`` (the first node's).

    Raises
    ------
    ValueError
        Naming --params-file, if the file cannot be read or holds no ``ros__parameters``.
    """
    try:
        size = os.path.getsize(path)
        if size > MAX_BYTES:
            raise ValueError(f'--params-file = {path!r} has {size} bytes: allowed at most '
                             f'{MAX_BYTES} (a node parameter file)')
        with open(path, encoding='utf-8') as f:
            document = yaml.safe_load(f)
    except OSError as error:
        raise ValueError(f'--params-file = {path!r} cannot be read: {error.strerror}') from None
    except UnicodeDecodeError as error:
        raise ValueError(f'--params-file = {path!r} cannot be read: byte {error.start} is not '
                         'UTF-8 text; allowed a UTF-8 YAML file') from None
    except yaml.YAMLError as error:
        raise ValueError(f'--params-file = {path!r} is not YAML: {error}') from None
    nodes = document.values() if isinstance(document, dict) else ()
    for node in nodes:
        if isinstance(node, dict) and isinstance(node.get('ros__parameters'), dict):
            return node['ros__parameters']
    raise ValueError(f'--params-file = {path!r} is not a node parameter file: allowed a YAML '
                     'mapping NODE: {ros__parameters: {...}}')


def apply_params_file(args, path):
    """Fill ``args``' contact options from the parameter file ``path``; return the map
    core field -> the file's key for the values taken from it (to name them in a refusal, which
    ``errors.report`` prefixes with ``--params-file FILE:``; ``args.params_file_keys`` lists
    those keys)."""
    values = node_parameters(path)
    taken = {}
    args.params_file_keys = set()

    def record(field, key):
        taken[field] = key
        args.params_file_keys.add(key)

    def take(key, attribute, field, value):
        if getattr(args, attribute, None) is None:
            setattr(args, attribute, value)
            record(field, key)
    for body, option in (('sphere', 'sphere'), ('plate', 'plate')):
        name = values.get(f'{body}_material')
        if name == 'custom':
            for key, (attribute, field) in CUSTOM.items():
                if key.startswith(body) and key in values:
                    take(key, attribute, field, values[key])
        elif name is not None and getattr(args, option) is None:
            if name not in MATERIALS:
                raise ValueError(f'--params-file {path}: {body}_material = {name!r} is unknown: allowed '
                                 f'{", ".join(sorted(MATERIALS))}, custom')
            setattr(args, option, name)
            record('material', f'{body}_material')
    for key, (attribute, field) in KEYS.items():
        value = values.get(key)
        if value is None or key in ZERO_MEANS_DEFAULT and value == 0:
            continue
        if key == 'plate_radius':
            if math.isinf(args.plate_radius) and value != 0:
                args.plate_radius = value
                record(field, key)
            continue
        if key == 'damping_factor' and (args.damping is not None or values.get('damping')):
            continue   # the node uses damping_factor only when damping is 0
        take(key, attribute, field, value)
    return taken
