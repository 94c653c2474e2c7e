"""The model: what every stage speaks. Source spans, diagnostics with stable codes, the model nodes.

- ``source``: a source text, ``Span`` (character offsets; lines and columns only at the edges) and
  ``AnchoredSpan`` (offsets relative to another span, so that a parsed chunk's spans move with it);
- ``diagnostics``: ``Diagnostic`` and the table of every code iface reports;
- ``nodes``: the model itself (plain slotted dataclasses, each with its span fields), the seven sets I = M ∪ N ∪ S ∪ A ∪ P ∪ Σ ∪ Δ,
  every node with its span;
- ``walk``, ``normalize``, ``naming``, ``qos``: walking the nodes, reading service and action bodies
  one way, ROS naming rules, QoS annotations.

May import: nothing else of iface (this is the bottom of the pipeline).
"""
