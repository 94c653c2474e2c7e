"""IDL as independent readers see it: escaped identifiers after the lexical rule, idlc's C, Fast-DDS-Gen."""

from __future__ import annotations

import functools
import json
import os
import re
import shutil
import subprocess
from pathlib import Path

from ..ros_harness import cache

IDLC = shutil.which("idlc")
NO_IDLC = "idlc (Cyclone DDS's IDL compiler, Debian package cyclonedds-tools) is not installed: scripts/test.sh " \
          "installs it where it runs as root"
FASTDDSGEN = shutil.which("fastddsgen")
NO_FASTDDSGEN = "fastddsgen (eProsima Fast-DDS-Gen, Debian package fastddsgen; ArduPilot builds its IDL with its " \
                "fork Micro-XRCE-DDS-Gen) is not installed: scripts/test.sh installs it where it runs as root"
_TEXT = r'"(?:\\.|[^"\\])*"|//[^\n]*'
#: A string, a comment, or a leading underscore that starts an identifier (not one inside a name).
_ESCAPE = re.compile(_TEXT + r"|(?<!\w)_(?=[A-Za-z])")


def code_of(text: str) -> str:
    """``text`` without its strings and comments."""
    return re.sub(_TEXT, " ", text)


def escaped_names(text: str) -> list[str]:
    """The identifiers ``text`` writes escaped (``_struct`` → ``struct``), in order."""
    return re.findall(r"(?<!\w)_([A-Za-z]\w*)", code_of(text))


def unescaped(text: str) -> str:
    """``text`` with IDL's escape applied as OMG IDL 4.2 7.2.3 says: the leading underscore dropped."""
    return _ESCAPE.sub(lambda m: m.group() if len(m.group()) > 1 else "", text)


def idlc_header(root: Path, idl: Path, out: Path) -> tuple[subprocess.CompletedProcess[str], str]:
    """Cyclone DDS's idlc over one file (includes from ``root``): its result and the C header it wrote."""
    out.mkdir(parents=True, exist_ok=True)
    proc = subprocess.run([str(IDLC), "-I", str(root), "-o", str(out), str(idl)], capture_output=True, text=True,
                          timeout=120)
    header = out / idl.with_suffix(".h").name
    return proc, header.read_text() if header.is_file() else ""


def fastddsgen(root: Path, files: list[Path], out: Path) -> subprocess.CompletedProcess[str]:
    """Fast-DDS-Gen with the options ArduPilot's libraries/AP_DDS/wscript gives microxrceddsgen.

    A run that succeeds is kept in the test cache (tests/ros_harness/cache.py) under the key of what it reads:
    every file under ``root``, ``files``, the generator's launcher and jar, and Java. The same input then gives
    what it gave (a JVM over a hundred files is 20 CPU-seconds); what it writes is copied into ``out``, and its
    output names the cache's folders. A run that fails is never kept.
    """
    inputs = [("root", root)] + [(f"file{i}", f) for i, f in enumerate(files)]
    digests = (f"{name}:{cache.digest_tree(path) if path.is_dir() else cache.digest_file(path)}" for name, path in inputs)
    key = cache.key_of("fastddsgen", *_generator_identity(), *digests,
                       *(f.relative_to(root).as_posix() if f.is_relative_to(root) else f.name for f in files))

    def make(folder: Path) -> str | None:
        source = folder / "in" / "root"
        shutil.copytree(root, source)
        copies = []
        for f in files:
            if f.is_relative_to(root):
                copies.append(source / f.relative_to(root))
            else:
                copies.append(folder / "in" / f.name)
                shutil.copyfile(f, copies[-1])
        proc = _run_fastddsgen(source, copies, folder / "gen")
        (folder / "result.json").write_text(json.dumps([proc.returncode, proc.stdout, proc.stderr]))
        return None if proc.returncode == 0 else f"fastddsgen exited {proc.returncode}"

    try:
        folder = cache.entry(key, f"fastddsgen over {root} and {', '.join(map(str, files))}", make).path
    except cache.BuildFailed:
        folder = cache.root() / key
    code, stdout, stderr = json.loads((folder / "result.json").read_text())
    out.mkdir(parents=True, exist_ok=True)
    if (folder / "gen").is_dir():
        shutil.copytree(folder / "gen", out, dirs_exist_ok=True)
    return subprocess.CompletedProcess(["fastddsgen", str(root), *map(str, files)], code, stdout, stderr)


@functools.cache
def _generator_identity() -> tuple[str, ...]:
    """What names the generator that runs: its launcher, the jar the launcher names, and the Java it runs on."""
    assert FASTDDSGEN is not None
    launcher = Path(FASTDDSGEN).resolve()
    parts = [f"{launcher}:{cache.digest_file(launcher)}"]
    jar = re.search(r'^JAR="([^"]+)"', launcher.read_text(errors="replace"), re.MULTILINE)
    if jar and Path(jar.group(1)).is_file():
        parts.append(f"{jar.group(1)}:{cache.digest_file(Path(jar.group(1)))}")
    java = shutil.which("java")
    if java:
        real = Path(java).resolve()
        parts.append(f"{real}:{real.stat().st_size}:{real.stat().st_mtime_ns}:{os.environ.get('JAVA_HOME', '')}")
    return tuple(parts)


def _run_fastddsgen(root: Path, files: list[Path], out: Path) -> subprocess.CompletedProcess[str]:
    """The generator itself. Its preprocessed copies go to a folder of this call's own (``-t``): by default they
    go to /tmp under the input file's name, and two test runs side by side then read each other's half-written
    copy ("mismatched input '<EOF>'")."""
    out.mkdir(parents=True, exist_ok=True)
    temp = out.parent / f"{out.name}-fastddsgen-tmp"
    temp.mkdir(exist_ok=True)
    return subprocess.run([str(FASTDDSGEN), "-cs", "-replace", "-t", str(temp), "-d", str(out), "-I", str(root),
                           *(str(f) for f in files)], capture_output=True, text=True, timeout=600, env=JVM,
                          check=False)


#: A generator run is short: the JVM's optimizing compiler costs more than it saves (half the CPU time of a
#: run over a hundred files), so the quick one only; what it writes is the same.
JVM = {**os.environ, "JAVA_TOOL_OPTIONS": f"{os.environ.get('JAVA_TOOL_OPTIONS', '')} -XX:TieredStopAtLevel=1 "
                                          "-XX:+UseSerialGC".strip()}
