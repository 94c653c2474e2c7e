"""The constants of the component protocol this runtime speaks (iface's ``iface.nodes.protocol``).

They are written here once for the Python runtime; a test of iface ties each one to the protocol's
definition, so a change there that is not made here fails.
"""

from __future__ import annotations

#: The version of the protocol: in the state document, ``ComponentControl`` and ``Describe`` answers.
PROTOCOL_VERSION = "1"
#: The version tag of the state document.
STATE_FORMAT = "iface-state/1"
#: Where every component publishes diagnostic_msgs/DiagnosticArray.
DIAGNOSTICS_TOPIC = "/diagnostics"
#: How long PAUSE, SAVE and RESTORE wait for a work transaction to end when the request says 0.
DEFAULT_TIMEOUT_SEC = 10.0
#: A pause waits for the next tick of a work timer due within this many seconds.
ALIGN_SEC = 0.1
#: ComponentControl commands.
STATUS, PAUSE, RESUME, SAVE = 0, 1, 2, 3
#: Names of a user handler start with one of these (a method so named that handles nothing is reported).
HANDLER_PREFIXES = ("on_", "handle_", "execute_", "accept_", "cancel_")
