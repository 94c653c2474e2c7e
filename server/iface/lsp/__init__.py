"""The iface language server: pygls adapters over the shared model (``iface.compile``, ``iface.query``)."""
