"""One /clock: which other publisher of /clock a node yields to.

Every instance of the node publishes the global ``/clock`` by default (``publish_clock``), and
two of them together make it go backwards. An instance yields to another publisher of /clock
(says so once and stops publishing it) unless that one is an instance of this node whose fully
qualified name sorts after its own: of several instances one publishes (the first by name),
and none competes with another clock (a simulator, ``ros2 bag play --clock``).
"""
CLOCK_TOPIC = '/clock'
CHECK_PERIOD = 0.5    # s of wall time between looks at the publishers of /clock
# s of wall time a later-named publisher of /clock must have been seen, still not looking like an
# instance of this node, before it counts as a foreign clock: discovery of a new instance's
# ~/impact and ~/query_restitution trails that of its /clock publisher (taking it for a foreign
# clock at once made the first instance yield to the second, and then none published)
FOREIGN_GRACE = 5.0


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


def clock_to_yield_to(node, first_seen, now):
    """The fully qualified name of the other /clock publisher ``node`` yields to, or None.

    Parameters
    ----------
    node : rclpy.node.Node
        A node publishing /clock.
    first_seen : dict
        Fully qualified name -> the wall time (s) it was first seen publishing /clock; updated.
    now : float
        The wall time (s, any steady clock).

    Returns
    -------
    str or None
        The first (by name) other publisher of /clock that sorts before ``node``, or one seen
        for at least ``FOREIGN_GRACE`` s that is not an instance of this node; None if none.
    """
    me = full_name(node.get_namespace(), node.get_name())
    others = sorted({(full_name(info.node_namespace, info.node_name), info.node_namespace,
                      info.node_name) for info in node.get_publishers_info_by_topic(CLOCK_TOPIC)})
    for other, namespace, name in others:
        if other == me:
            continue
        if other < me:
            return other
        seen = first_seen.setdefault(other, now)
        if now - seen >= FOREIGN_GRACE and not is_contact_sim(node, namespace, name):
            return other
    return None
