"""Nothing a client sends can stop the node (issue 33, item 1): malformed requests to every
parameter service, ``~/query_restitution``, ``~/reset`` and ``~/plate_command``, sent from this
(second) process to a ``contact_sim_node`` process, are refused and logged; the node runs on.

Reproduced first: one ``SetParameters`` request with a value of type 99 ended the node with
``[FATAL] Exception in 'services' callback: 99 is not a valid Parameter.Type`` and a traceback
(rclpy's ``Parameter.from_parameter_msg`` raised in its parameter service's callback).
"""


from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue  # noqa: E402
from rcl_interfaces.srv import (DescribeParameters, GetParameters, GetParameterTypes,  # noqa: E402
                                ListParameters, SetParameters, SetParametersAtomically)
from std_srvs.srv import Trigger  # noqa: E402
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint  # noqa: E402

from .harness import Process, assert_clean_exit, rosout_has  # noqa: E402

NAME = 'hostile_target'
NODE = f'/{NAME}'


def raw(name, type_, **fields):
    return Parameter(name=name, value=ParameterValue(type=type_, **fields))


def test_malformed_requests_are_refused_and_the_node_runs_on(client, ros_env, workdir):
    process = Process('contact_sim_node', ['--ros-args', '-r', f'__node:={NAME}', '-p',
                                           'publish_clock:=false', '-p', 'publish_rate:=10.0'],
                      ros_env, workdir)
    try:
        def set_one(*parameters):
            return client.call(SetParameters, f'{NODE}/set_parameters',
                               SetParameters.Request(parameters=list(parameters))).results

        # the request that ended the node: a value of type 99, alone and among good ones
        (result,) = set_one(raw('stiffness', 99))
        assert not result.successful
        assert 'parameters[0].value.type = 99 is not a parameter type' in result.reason
        results = set_one(raw('gravity', ParameterType.PARAMETER_DOUBLE, double_value=9.0),
                          raw('gravity', 200), raw('gravity', 255))
        assert [r.successful for r in results] == [True, False, False], results
        result = client.call(SetParametersAtomically, f'{NODE}/set_parameters_atomically',
                             SetParametersAtomically.Request(parameters=[
                                 raw('initial_height', ParameterType.PARAMETER_DOUBLE,
                                     double_value=0.5), raw('stiffness', 99)])).result
        assert not result.successful and 'type = 99' in result.reason
        # sizes: an array, a string, a name and a request past the limits
        (result,) = set_one(raw('stiffness', ParameterType.PARAMETER_DOUBLE_ARRAY,
                                double_array_value=[1.0] * 100_000))
        assert not result.successful and 'has 100000 elements: allowed at most 1000' \
            in result.reason
        (result,) = set_one(raw('contact_law', ParameterType.PARAMETER_STRING,
                                string_value='x' * 1_000_000))
        assert not result.successful and 'allowed at most 1000' in result.reason
        results = set_one(*[raw('gravity', ParameterType.PARAMETER_DOUBLE, double_value=9.81)]
                          * 5000)
        assert results and not any(r.successful for r in results)
        assert 'parameters has 5000 entries: allowed at most 1000' in results[0].reason
        # odd names and kinds: unknown, empty, undeclaring a declared one, the wrong type
        for parameter, reason in (
                (raw('', ParameterType.PARAMETER_DOUBLE, double_value=1.0), 'name is empty'),
                (raw('/../\u00e9\u00e8', ParameterType.PARAMETER_BOOL, bool_value=True),
                 'not declared'),
                (raw('y' * 5000, ParameterType.PARAMETER_DOUBLE), 'allowed at most 1000'),
                (raw('gravity', ParameterType.PARAMETER_NOT_SET), 'cannot be undeclared'),
                (raw('gravity', ParameterType.PARAMETER_STRING, string_value='9.81'),
                 'Wrong parameter type')):
            (result,) = set_one(parameter)
            assert not result.successful and reason in result.reason, (parameter.name[:20],
                                                                      result.reason)
        # the read-only services: too many or odd names give no answer, never an error
        for srv_type, service, field in ((GetParameters, 'get_parameters', 'values'),
                                         (DescribeParameters, 'describe_parameters',
                                          'descriptors'),
                                         (GetParameterTypes, 'get_parameter_types', 'types')):
            for names in (['gravity'] * 5000, ['', 'gravity'], ['z' * 100_000]):
                response = client.call(srv_type, f'{NODE}/{service}',
                                       srv_type.Request(names=names))
                assert len(getattr(response, field)) == 0, (service, len(names))
            response = client.call(srv_type, f'{NODE}/{service}',
                                   srv_type.Request(names=['gravity']))
            assert len(getattr(response, field)) == 1, service
        response = client.call(ListParameters, f'{NODE}/list_parameters', ListParameters.Request(
            prefixes=['p' * 10] * 5000, depth=2 ** 64 - 1))
        assert list(response.result.names) == []
        response = client.call(ListParameters, f'{NODE}/list_parameters',
                               ListParameters.Request(depth=2 ** 64 - 1))
        assert 'gravity' in response.result.names
        # the node's own services and topic
        values = client.call(GetParameters, f'{NODE}/query_restitution', GetParameters.Request(
            names=['q' * 1_000_000, 'peak_force:' + '9' * 400, 'restitution:nan'])).values
        assert [v.type for v in values] == [ParameterType.PARAMETER_NOT_SET] * 3
        assert client.call(Trigger, f'{NODE}/reset', Trigger.Request()).success
        publisher = client.node.create_publisher(JointTrajectory, f'{NODE}/plate_command', 10)
        client.spin_until(lambda: publisher.get_subscription_count() > 0, 'the subscription')
        publisher.publish(JointTrajectory(joint_names=['j' * 1_000_000], points=[
            JointTrajectoryPoint(positions=[0.0])]))
        publisher.publish(JointTrajectory(joint_names=['plate_z'], points=[
            JointTrajectoryPoint(positions=[float('nan')], velocities=[float('inf')])]))
        client.spin_until(lambda: rosout_has(client, 'refused'), 'a refusal in the log')
        # the node runs on: it answers, its parameters are those accepted, it publishes
        assert client.get_parameters(NODE, ['gravity', 'initial_height', 'stiffness']) == {
            'gravity': 9.0, 'initial_height': 1.0, 'stiffness': 0.0}
        count = client.node.count_publishers(f'{NODE}/pose')
        assert count == 1 and process.popen.poll() is None, process.output()
    finally:
        code, output = process.stop()
    assert code == 0, output
    assert 'Traceback' not in output and '[FATAL]' not in output, output
    assert 'set_parameters refused: parameters[0].value.type = 99' in output, output
    assert max(len(line) for line in output.splitlines()) < 2000    # long text is cut
    assert_clean_exit(process)
