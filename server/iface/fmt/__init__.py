"""The iface formatter; the public functions are in ``iface.format``."""

from .document import Formatted, Region, format_document

__all__ = ["Formatted", "Region", "format_document"]
