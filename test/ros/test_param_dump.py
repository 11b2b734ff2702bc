"""`ros2 param dump` -> `ros2 param load` and `--params-file` with real processes: a node's
parameters reproduced in a fresh node, through the functions the ``ros2 param`` verbs use (the
``ListParameters`` and ``GetParameters`` services and PyYAML for the dump; rclpy's
``parameter_dict_from_yaml_file`` and one ``SetParameters`` a parameter, in file order, for the
load).

Issue 22: a dump of a node with ``initial_height 0.3`` and ``stiffness 5e4`` did not load one by
one into a fresh node (the stiffness was checked against the running 1 m drop and refused).
"""
import yaml

import rclpy  # noqa: E402,F401  (pinned: a missing install fails here)

from rcl_interfaces.msg import Parameter  # noqa: E402
from rcl_interfaces.srv import ListParameters, SetParameters  # noqa: E402
from rclpy.parameter import parameter_dict_from_yaml_file  # noqa: E402

from std_srvs.srv import Trigger  # noqa: E402

from .harness import Process, assert_clean_exit  # noqa: E402

NAME = 'contact_sim_dumped'
CHANGED = {'initial_height': 0.3, 'stiffness': 5.0e4, 'damping': 10.0, 'sphere_mass': 0.05,
           'publish_clock': False}


def dump(client, node, path):
    """``ros2 param dump node``: every parameter the node lists, its values, as YAML."""
    names = client.call(ListParameters, f'{node}/list_parameters',
                        ListParameters.Request()).result.names
    values = client.get_parameters(node, list(names))
    path.write_text(yaml.dump({node: {'ros__parameters': values}}, default_flow_style=False))
    return values


def load(client, node, path):
    """``ros2 param load node path``: one SetParameters a parameter, in the file's order."""
    loaded = parameter_dict_from_yaml_file(str(path), target_nodes=[node])
    results = {}
    for name, parameter in loaded.items():
        request = SetParameters.Request(parameters=[Parameter(name=name, value=parameter.value)])
        (results[name],) = client.call(SetParameters, f'{node}/set_parameters', request).results
    return results


def start(ros_env, workdir, client, args):
    process = Process('contact_sim_node', ['--ros-args', '-r', f'__node:={NAME}', *args],
                      ros_env, workdir)
    client.spin_until(lambda: client.node.count_publishers(f'/{NAME}/pose') > 0
                      or process.popen.poll() is not None, f'/{NAME} to start')
    assert process.popen.poll() is None, process.output()
    return process


def test_a_dump_loads_into_a_fresh_node_one_by_one_and_with_params_file(client, ros_env,
                                                                       workdir):
    node, path = f'/{NAME}', workdir / 'dumped.yaml'
    overrides = [arg for name, value in CHANGED.items()
                 for arg in ('-p', f'{name}:={yaml.safe_dump(value).splitlines()[0]}')]
    process = start(ros_env, workdir, client, overrides)
    try:
        values = dump(client, node, path)
        assert {name: values[name] for name in CHANGED} == CHANGED
    finally:
        assert_clean_exit(process)
    # a fresh node on its defaults (from 1 m), the file loaded parameter by parameter
    process = start(ros_env, workdir, client, ['-p', 'publish_clock:=false'])
    try:
        results = load(client, node, path)
        refused = {name: r.reason for name, r in results.items() if not r.successful}
        # the read-only parameters cannot be set, but they hold the dump's values already
        assert set(refused) <= {'publish_rate', 'frame_id', 'publish_clock',
                                'start_type_description_service'}, refused
        assert client.get_parameters(node, list(values)) == values
        # the drop restarts from the loaded parameters
        response = client.call(Trigger, f'{node}/reset', Trigger.Request())
        assert response.success and 'k = 5e+04 N/m^1.5' in response.message, response.message
        assert 'drop from 0.3 m' in response.message, response.message
    finally:
        assert_clean_exit(process)
    # the dump as the start-up parameters of a fresh node
    process = start(ros_env, workdir, client, ['--params-file', str(path)])
    try:
        assert client.get_parameters(node, list(values)) == values
    finally:
        assert_clean_exit(process)
