"""The model: what every stage speaks. Source spans, diagnostics with stable codes, the model nodes.

- ``source``: a source text and ``Span`` (character offsets; lines and columns only at the edges);
- ``diagnostics``: ``Diagnostic`` and the table of every code iface reports;
- ``nodes``: the model itself (frozen-shape dataclasses), the seven sets I = M ∪ N ∪ S ∪ A ∪ P ∪ Σ ∪ Δ,
  every node with its span;
- ``walk``, ``normalize``, ``naming``, ``qos``: walking the nodes, reading service and action bodies
  one way, ROS naming rules, QoS annotations.

May import: nothing else of iface (this is the bottom of the pipeline).
"""
