"""iface: one explicit, machine-checkable interface file per robotic component."""

__version__ = "0.1.0"
