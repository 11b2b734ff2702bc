"""One /clock: which other publisher of /clock a node yields to.

Every instance of the node publishes the global ``/clock`` by default (``publish_clock``), and
two of them together make it go backwards. An instance yields to another publisher of /clock
(says so once and stops publishing it) unless that one is an instance of this node whose fully
qualified name sorts after its own: of several instances one publishes (the first by name),
and none competes with another clock (a simulator, ``ros2 bag play --clock``).
"""
CLOCK_TOPIC = '/clock'
CHECK_PERIOD = 0.5    # s of wall time between looks at the publishers of /clock


def full_name(namespace, name):
    """``/ns`` and ``node`` -> ``/ns/node``."""
    return f'{namespace.rstrip("/")}/{name}'


def is_contact_sim(node, namespace, name):
    """Whether the node ``namespace``/``name`` is an instance of this node: it publishes
    ``~/impact`` and serves ``~/query_restitution``."""
    own = full_name(namespace, name)
    try:
        topics = {topic for topic, _ in node.get_publisher_names_and_types_by_node(name,
                                                                                   namespace)}
        services = {srv for srv, _ in node.get_service_names_and_types_by_node(name, namespace)}
    except Exception:   # the node left the graph meanwhile: not one that matters
        return False
    return f'{own}/impact' in topics and f'{own}/query_restitution' in services


def clock_to_yield_to(node):
    """The fully qualified name of the other /clock publisher ``node`` yields to, or None.

    Parameters
    ----------
    node : rclpy.node.Node
        A node publishing /clock.

    Returns
    -------
    str or None
        The first (by name) other publisher of /clock that is not an instance of this node, or
        an instance whose name sorts before ``node``'s; None if there is none.
    """
    me = full_name(node.get_namespace(), node.get_name())
    others = sorted({(full_name(info.node_namespace, info.node_name), info.node_namespace,
                      info.node_name) for info in node.get_publishers_info_by_topic(CLOCK_TOPIC)})
    for other, namespace, name in others:
        if other != me and (other < me or not is_contact_sim(node, namespace, name)):
            return other
    return None
