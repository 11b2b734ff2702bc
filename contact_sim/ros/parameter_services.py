"""The node's six parameter services (``~/describe_parameters``, ``~/get_parameters``,
``~/get_parameter_types``, ``~/list_parameters``, ``~/set_parameters``,
``~/set_parameters_atomically``), served by the node itself: nothing a client sends through them
can stop it.

rclpy's own ``ParameterService`` turns each request's values into ``Parameter`` objects with
``Parameter.from_parameter_msg``, which raises ``ValueError`` for a type outside
``rcl_interfaces/msg/ParameterType`` (one ``SetParameters`` request with type 99 ended the node
with a traceback, issue 33): an exception in a service callback leaves the executor and ends the
spin. The node is therefore made with ``start_parameter_services=False`` (a public argument of
``rclpy.node.Node``) and serves the same services here, with the same answers, through the
node's public parameter API (``describe_parameter``, ``get_parameter``, ``get_parameter_type``,
``list_parameters``, ``set_parameters_atomically``). A request that cannot be read (an unknown
type, more than ``MAX_ITEMS`` names or parameters, a name or string value longer than
``MAX_TEXT`` characters, an array of more than ``MAX_ARRAY`` elements) is refused: an
unsuccessful result naming the field and the limit (set), or an empty answer (describe, get,
types, list), and one warning (``refusals.RefusalLog``); the node runs on.
"""
from rcl_interfaces.msg import SetParametersResult
from rcl_interfaces.srv import (DescribeParameters, GetParameters, GetParameterTypes,
                                ListParameters, SetParameters, SetParametersAtomically)
from rclpy.exceptions import ParameterNotDeclaredException, ParameterUninitializedException
from rclpy.parameter import Parameter
from rclpy.qos import qos_profile_parameters

from .refusals import ClientError, guarded, shorten

MAX_ITEMS = 1000    # names or parameters a request (the node has about 30 parameters)
MAX_TEXT = 1000     # characters of a parameter name, a prefix or a string value
MAX_ARRAY = 1000    # elements of an array value (the node declares no array parameter)
TYPES = frozenset(t.value for t in Parameter.Type)
_ARRAYS = {Parameter.Type.BYTE_ARRAY: 'byte_array_value', Parameter.Type.BOOL_ARRAY:
           'bool_array_value', Parameter.Type.INTEGER_ARRAY: 'integer_array_value',
           Parameter.Type.DOUBLE_ARRAY: 'double_array_value',
           Parameter.Type.STRING_ARRAY: 'string_array_value'}


class RequestError(ClientError):
    """A request the node cannot read: the message names the field and the limit."""


def _check_count(field, items):
    if len(items) > MAX_ITEMS:
        raise RequestError(f'{field} has {len(items)} entries: allowed at most {MAX_ITEMS} a '
                           'request')


def _check_text(field, text):
    if len(text) > MAX_TEXT:
        raise RequestError(f'{field} has {len(text)} characters: allowed at most {MAX_TEXT}')


def read_parameter(msg, index=0):
    """An ``rcl_interfaces/msg/Parameter`` as an ``rclpy.parameter.Parameter``, checked first.

    Parameters
    ----------
    msg : rcl_interfaces.msg.Parameter
        As a client sent it.
    index : int
        Its place in the request, for the message.

    Returns
    -------
    rclpy.parameter.Parameter

    Raises
    ------
    RequestError
        For a type outside ``rcl_interfaces/msg/ParameterType`` (0-9), an empty name, a name or
        string value longer than ``MAX_TEXT`` characters, or an array longer than
        ``MAX_ARRAY``.

    Examples
    --------
    >>> from rcl_interfaces.msg import Parameter as Msg, ParameterValue
    >>> read_parameter(Msg(name='gravity', value=ParameterValue(type=3, double_value=9.8))).value
    9.8
    >>> read_parameter(Msg(name='gravity', value=ParameterValue(type=99)))
    Traceback (most recent call last):
    ...
    contact_sim.ros.parameter_services.RequestError: parameters[0].value.type = 99 is not a \
parameter type: allowed 0 (not set) to 9 (rcl_interfaces/msg/ParameterType)
    """
    where = f'parameters[{index}]'
    _check_text(f'{where}.name', msg.name)
    if not msg.name:   # rclpy would store it as a new parameter '' (any(['']) is False)
        raise RequestError(f'{where}.name is empty: allowed the name of a declared parameter')
    kind = msg.value.type
    if kind not in TYPES:
        raise RequestError(f'{where}.value.type = {kind} is not a parameter type: allowed 0 (not '
                           'set) to 9 (rcl_interfaces/msg/ParameterType)')
    kind = Parameter.Type(kind)
    if kind == Parameter.Type.STRING:
        _check_text(f'{where}.value.string_value', msg.value.string_value)
    elif kind in _ARRAYS:
        values = getattr(msg.value, _ARRAYS[kind])
        if len(values) > MAX_ARRAY:
            raise RequestError(f'{where}.value.{_ARRAYS[kind]} has {len(values)} elements: '
                               f'allowed at most {MAX_ARRAY}')
        if kind == Parameter.Type.STRING_ARRAY:
            for i, text in enumerate(values):
                _check_text(f'{where}.value.string_array_value[{i}]', text)
    return Parameter.from_parameter_msg(msg)


class ParameterServices:
    """The parameter services of ``node`` (made with ``start_parameter_services=False``).

    Parameters
    ----------
    node : rclpy.node.Node
        The node whose parameters are served.
    refusals : refusals.RefusalLog
        Where a refused request is logged (at most one warning a second, the rest counted).
    """

    def __init__(self, node, refusals):
        self._node, self._refusals = node, refusals
        for srv_type, name, serve in (
                (DescribeParameters, 'describe_parameters', self._describe),
                (GetParameters, 'get_parameters', self._get),
                (GetParameterTypes, 'get_parameter_types', self._types),
                (ListParameters, 'list_parameters', self._list),
                (SetParameters, 'set_parameters', self._set),
                (SetParametersAtomically, 'set_parameters_atomically', self._set_atomically)):
            node.create_service(srv_type, f'~/{name}', self._guard(name, serve),
                                qos_profile=qos_profile_parameters)

    def _guard(self, name, serve):
        """``serve`` answering every request: what it raises is refused and logged, and the
        answer is the empty response (no values; for a set, one unsuccessful result)."""
        def refused(request, response, reason):
            response = type(response)()
            if hasattr(response, 'results'):
                response.results = [SetParametersResult(successful=False, reason=reason)
                                    for _ in range(min(len(request.parameters), MAX_ITEMS))]
            elif hasattr(response, 'result') and isinstance(response.result, SetParametersResult):
                response.result = SetParametersResult(successful=False, reason=reason)
            return response
        return guarded(serve, self._refusals, f'~/{name}', refused)

    def _names(self, request):
        names = list(request.names)
        _check_count('names', names)
        for i, name in enumerate(names):
            _check_text(f'names[{i}]', name)
        return names

    def _describe(self, request, response):
        node = self._node
        for name in self._names(request):
            if not node.has_parameter(name):   # as rclpy: one unknown name, no descriptors
                response.descriptors = []
                return response
            response.descriptors.append(node.describe_parameter(name))
        return response

    def _get(self, request, response):
        node = self._node
        for name in self._names(request):
            try:
                value = node.get_parameter(name).get_parameter_value()
            except (ParameterNotDeclaredException, ParameterUninitializedException):
                response.values = []    # as rclpy: one unknown name, no values
                return response
            response.values.append(value)
        return response

    def _types(self, request, response):
        node = self._node
        for name in self._names(request):
            if not node.has_parameter(name):
                response.types = []
                return response
            response.types.append(int(node.get_parameter_type(name)))
        return response

    def _list(self, request, response):
        prefixes = list(request.prefixes)
        _check_count('prefixes', prefixes)
        for i, prefix in enumerate(prefixes):
            _check_text(f'prefixes[{i}]', prefix)
        response.result = self._node.list_parameters(prefixes, int(request.depth))
        return response

    def _set(self, request, response):
        _check_count('parameters', request.parameters)
        for i, msg in enumerate(request.parameters):
            response.results.append(self._set_one(i, msg))
        return response

    def _declared(self, parameters):
        """ParameterNotDeclaredException naming the first parameter the node has not declared
        (rclpy's own says ``undeclared parameter(s): []``)."""
        for parameter in parameters:
            if not self._node.has_parameter(parameter.name):
                raise ParameterNotDeclaredException(
                    f'{shorten(repr(parameter.name))} is not declared: allowed the names '
                    '`ros2 param list` shows')
        return parameters

    def _set_one(self, index, msg):
        try:
            parameters = self._declared([read_parameter(msg, index)])
            return self._node.set_parameters_atomically(parameters)
        except ParameterNotDeclaredException as error:
            return SetParametersResult(successful=False, reason=shorten(str(error)))
        except RequestError as error:
            self._refusals.refused(f'~/set_parameters refused: {error}')
            return SetParametersResult(successful=False, reason=str(error))

    def _set_atomically(self, request, response):
        _check_count('parameters', request.parameters)
        try:
            parameters = self._declared([read_parameter(msg, i)
                                         for i, msg in enumerate(request.parameters)])
            response.result = self._node.set_parameters_atomically(parameters)
        except ParameterNotDeclaredException as error:
            response.result = SetParametersResult(successful=False, reason=shorten(str(error)))
        return response
