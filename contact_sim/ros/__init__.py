"""The ROS 2 face of contact_sim: the only subpackage that imports rclpy or a ROS message package.

- ``params``: the node's parameters (specs, descriptors), ``build``, the one function from
  parameter values to the simulation's model and its drop, and ``loop_settings``;
- ``parameter_services``: the node's parameter services (no request stops the node);
- ``refusals``: refusals logged once a second, and callbacks guarded against a client's input;
- ``rclpy_private``: the one module that uses rclpy's private API, each use commented;
- ``messages``: the table of every topic (name, type, QoS, encoder, decoder) and the message
  functions;
- ``query``: ``~/query_restitution`` names -> answers;
- ``start``: the console entry point of ``contact_sim_node``, which takes SIGINT and SIGTERM before
  the node's import;
- ``node``: ``contact_sim_node`` (``ContactSimNode``: parameters, the plate, services; ``main``);
- ``loop``: the node's tick loop (``TickLoop``: ticks due, wall budgets, a recorder's pace),
  given the drop, its settings, the model and the stamp offset it runs;
- ``outbox``: the node's publishers and its wait for reliable readers (``Outbox``);
- ``plate_command``: ``~/plate_command`` messages as the core's commands (``read_plate_command``);
- ``recorder``: ``contact_sim_record`` (``Recorder``, ``record_main``, ``--recover``), its
  command line checked by ``record_options``;
- ``bag``: rosbag2 files with the ``rosbags`` library (no ROS import), crash-safe, recoverable.
"""
