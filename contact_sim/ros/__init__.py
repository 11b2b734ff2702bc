"""The ROS 2 face of contact_sim: the only subpackage that imports rclpy or a ROS message package.

- ``params``: the node's parameters (specs, descriptors) and ``build_model``, the one function
  from parameter values to the simulation's model;
- ``messages``: the table of every topic (name, type, QoS, encoder, decoder) and the message
  functions;
- ``query``: ``~/query_restitution`` names -> answers;
- ``node``: ``contact_sim_node`` (``ContactSimNode``, ``main``);
- ``recorder``: ``contact_sim_record`` (``Recorder``, ``record_main``, ``--recover``);
- ``bag``: rosbag2 files with the ``rosbags`` library (no ROS import), crash-safe, recoverable.
"""
