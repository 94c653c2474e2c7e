"""The manager's own DDS participant announces itself often, so that a process it starts finds it at once.

A new participant learns of the ones already running from their announcements. Fast DDS announces a
participant a few times when it is made, then every 3 s: an instance or a container the manager has just
started again often waited up to 3 s before it knew the manager, and so before its services could answer
it (docs/system.md, "Restart time"). The manager's participant announces every ``ANNOUNCE_SEC`` instead,
through a default Fast DDS profile of the manager's own process, written into its state folder.

Only where nothing else is asked for: the RMW is Fast DDS (``RMW_IMPLEMENTATION`` unset or
``rmw_fastrtps*``), no profile file is named (``FASTDDS_DEFAULT_PROFILES_FILE``,
``FASTRTPS_DEFAULT_PROFILES_FILE``) or found in the working folder (Fast DDS reads
``DEFAULT_FASTDDS_PROFILES.xml`` / ``DEFAULT_FASTRTPS_PROFILES.xml`` there), and no discovery server is
used (``ROS_DISCOVERY_SERVER``). The processes the manager starts get the environment from before it, without
the profile.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

#: Seconds between two announcements of the manager's participant (Fast DDS: 3 s).
ANNOUNCE_SEC = 0.2
#: The variables that name a default profile file (Fast DDS 3; Fast DDS 2, Jazzy's).
PROFILE_VARIABLES = ("FASTDDS_DEFAULT_PROFILES_FILE", "FASTRTPS_DEFAULT_PROFILES_FILE")
#: The files Fast DDS reads from the working folder when no variable names one.
WORKING_FOLDER_PROFILES = ("DEFAULT_FASTDDS_PROFILES.xml", "DEFAULT_FASTRTPS_PROFILES.xml")
#: The profile file's name in the state folder.
PROFILE_FILE = "manager-participant.xml"


def profile_xml(seconds: float = ANNOUNCE_SEC) -> str:
    """A Fast DDS profile whose default participant announces itself every ``seconds``."""
    whole = int(seconds)
    nanos = round((seconds - whole) * 1e9)
    return (
        '<?xml version="1.0" encoding="UTF-8" ?>\n'
        "<!-- Written by iface-lsp manager: its participant announces itself often (iface/operate/announce.py). -->\n"
        '<dds xmlns="http://www.eprosima.com">\n'
        "  <profiles>\n"
        '    <participant profile_name="iface_manager" is_default_profile="true">\n'
        "      <rtps>\n"
        "        <builtin>\n"
        "          <discovery_config>\n"
        f"            <leaseAnnouncement><sec>{whole}</sec><nanosec>{nanos}</nanosec></leaseAnnouncement>\n"
        "          </discovery_config>\n"
        "        </builtin>\n"
        "      </rtps>\n"
        "    </participant>\n"
        "  </profiles>\n"
        "</dds>\n"
    )


def why_not(env: Mapping[str, str], cwd: Path) -> str | None:
    """Why the manager's participant keeps the announcements it is given (None: it may announce often)."""
    rmw = env.get("RMW_IMPLEMENTATION", "")
    if rmw and not rmw.startswith("rmw_fastrtps"):
        return f"the RMW is {rmw}"
    named = [v for v in PROFILE_VARIABLES if env.get(v)]
    if named:
        return f"{named[0]} names a profile file"
    found = [f for f in WORKING_FOLDER_PROFILES if (cwd / f).is_file()]
    if found:
        return f"{found[0]} is in the working folder"
    if env.get("ROS_DISCOVERY_SERVER"):
        return "a discovery server is used (ROS_DISCOVERY_SERVER)"
    return None


def own_profile(env: Mapping[str, str], state_dir: Path, cwd: Path) -> dict[str, str]:
    """The variables to set in the manager's own process before its participant is made (empty: none), the
    profile written into ``state_dir`` first."""
    if why_not(env, cwd) is not None:
        return {}
    path = state_dir / PROFILE_FILE
    text = profile_xml()
    if not path.is_file() or path.read_text(encoding="utf-8") != text:
        partial = path.with_name(path.name + ".partial")
        partial.write_text(text, encoding="utf-8")
        partial.replace(path)
    return {v: str(path) for v in PROFILE_VARIABLES}
