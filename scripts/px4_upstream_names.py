#!/usr/bin/env python3
"""Write server/iface/emit/px4/upstream.json: the names of PX4's own uORB messages and their topics.

    python scripts/px4_upstream_names.py PX4_MSGS_CHECKOUT TAG > server/iface/emit/px4/upstream.json

PX4_MSGS_CHECKOUT is a clone of https://github.com/PX4/px4_msgs (PX4's own ROS 2 copy of
PX4-Autopilot's msg/ and msg/versioned/, tagged per PX4 release); TAG is the release tag
(v1.17.0). Topics come from the ``# TOPICS`` lines, else the snake_case message name, as PX4's
generator reads them. The data is PX4's (BSD-3-Clause); only names are kept.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys


def snake(name: str) -> str:
    """PX4's CamelCase → snake_case (msg/CMakeLists.txt's two regular expressions)."""
    name = re.sub(r"(.)([A-Z][a-z]+)", r"\1_\2", name)
    return re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", name).lower()


def main(repo: str, tag: str) -> int:
    def git(*args: str) -> str:
        return subprocess.run(["git", "-C", repo, *args], capture_output=True, text=True, check=True).stdout

    commit = git("rev-list", "-n", "1", tag).strip()
    subject = git("log", "-1", "--format=%s", commit).strip()
    upstream = subject.rsplit(" ", 1)[-1] if subject.startswith("Update to PX4 ") else None
    messages: dict[str, list[str]] = {}
    for path in sorted(git("ls-tree", "-r", "--name-only", tag, "msg").split()):
        if not path.endswith(".msg"):
            continue
        name = path.rsplit("/", 1)[-1][:-4]
        topics: list[str] = []
        for line in git("show", f"{tag}:{path}").splitlines():
            if line.startswith("# TOPICS "):
                topics += line.split()[2:]
        messages[name] = topics or [snake(name)]
    data = {
        "px4_version": tag,
        "source": f"https://github.com/PX4/px4_msgs at {tag} ({commit})"
                  + (f", a copy of PX4/PX4-Autopilot {upstream} msg/ and msg/versioned/" if upstream else ""),
        "license": "BSD-3-Clause (PX4 Development Team); names only",
        "messages": messages,
    }
    head = json.dumps({k: v for k, v in data.items() if k != "messages"}, indent=1)[:-2]
    rows = ",\n".join(f"  {json.dumps(k)}: {json.dumps(v)}" for k, v in messages.items())
    sys.stdout.write(f'{head},\n "messages": {{\n{rows}\n }}\n}}\n')  # one message per line
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
