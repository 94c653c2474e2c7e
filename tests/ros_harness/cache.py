"""The test cache: built workspaces on disk, each under the key of what was built, shared by every process.

An entry is a folder ``ROOT/v1/KEY`` made once by a build function, in its final place (colcon install
trees hold absolute paths: an entry is never moved) and used in place, read-only, by every test, bench
and pytest-xdist worker on this machine. The key is the digest of the content of what is built and of
everything the build reads (sources, the entries it is built on, the ROS release, the compiler, the
command): a changed input is another key, so an entry is never stale. What a key stands for is written
beside the entry (``key.txt``) for whoever wonders.

Where: ``$IFACE_TEST_CACHE``, else ``~/.cache/iface-tests``. Bound: ``$IFACE_TEST_CACHE_MB`` megabytes
(default ``DEFAULT_BOUND_MB``); past it, the least recently used entries that no running process uses
are removed. ``python -m tests.ros_harness.cache`` lists the entries, ``--clear`` removes them all.

Two locks per entry (``locks/KEY.build`` and ``locks/KEY.use``, ``flock``): the build lock is held
exclusively while the entry is checked and, when missing, built (a second process asking for the key
waits, then finds it complete); the use lock is held shared by every process using the entry, until the
process ends, and taken exclusively (without waiting) only by the eviction, which so never removes an
entry in use. A build that stopped half-way leaves no ``complete`` marker: the entry is built again.
An entry whose files changed after it was built (a test wrote into it) is built again too, and said so.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import shutil
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import IO

DEFAULT_BOUND_MB = 2000
#: The layout's version: a change of layout is a new folder, never a misread old one.
LAYOUT = "v1"
COMPLETE = "complete.json"
IN_PROGRESS = "in-progress"
#: Written by the processes that run what an entry holds (Python's bytecode, ctest's records), not part of
#: what was built.
_NOT_BUILT = ("__pycache__", "Testing")

_using: dict[str, IO[str]] = {}  # key → the use lock this process holds (shared) until it ends


def root() -> Path:
    """The cache's folder (made when missing)."""
    given = os.environ.get("IFACE_TEST_CACHE")
    base = Path(given) if given else Path.home() / ".cache" / "iface-tests"
    folder = base / LAYOUT
    (folder / "locks").mkdir(parents=True, exist_ok=True)
    return folder


def bound_bytes() -> int:
    """The size bound of the cache, in bytes."""
    return int(float(os.environ.get("IFACE_TEST_CACHE_MB", DEFAULT_BOUND_MB)) * 1024 * 1024)


def key_of(*parts: str) -> str:
    """The key of an entry made from ``parts`` (each a text that names or digests one input)."""
    h = hashlib.sha256()
    for part in parts:
        h.update(part.encode() + b"\0")
    return h.hexdigest()[:40]


def digest_file(path: Path) -> str:
    """The digest of one file's content."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


def digest_tree(folder: Path) -> str:
    """The digest of every file under ``folder``: relative paths, contents and the executable bit."""
    h = hashlib.sha256()
    for path in sorted(folder.rglob("*")):
        if path.is_file() and not any(part in _NOT_BUILT for part in path.parts):
            mode = b"x" if os.access(path, os.X_OK) else b"-"
            h.update(path.relative_to(folder).as_posix().encode() + b"\0" + mode + path.read_bytes() + b"\0")
    return h.hexdigest()


@dataclass
class Entry:
    """A complete entry: its folder, whether this call built it, and how long the build took when it did."""

    key: str
    path: Path
    built: bool
    seconds: float
    info: dict[str, object]


class Busy(Exception):
    """Another process is building the entry (raised when asked not to wait)."""


class BuildFailed(Exception):
    """The build function said why it failed; the entry's folder stays for its logs, without its marker."""


def _lock(path: Path, mode: int) -> IO[str]:
    """``path`` opened and flock'ed with ``mode``, the file still the one at ``path`` (the eviction removes them)."""
    while True:
        handle = open(path, "a")  # noqa: SIM115 - returned locked
        try:
            fcntl.flock(handle, mode)
        except OSError:
            handle.close()
            raise
        try:
            same = os.fstat(handle.fileno()).st_ino == os.stat(path).st_ino
        except FileNotFoundError:
            same = False
        if same:
            return handle
        handle.close()


def _manifest(folder: Path) -> str:
    """What an entry holds, cheaply: every file's path, size and modification time (bytecode left out)."""
    h = hashlib.sha256()
    for dirpath, dirnames, filenames in os.walk(folder):
        dirnames[:] = sorted(d for d in dirnames if d not in _NOT_BUILT)
        for name in sorted(filenames):
            if name in (COMPLETE, "last-use"):
                continue
            path = os.path.join(dirpath, name)
            st = os.lstat(path)
            h.update(f"{os.path.relpath(path, folder)}\0{st.st_size}\0{st.st_mtime_ns}\0".encode())
    return h.hexdigest()


def _size(folder: Path) -> int:
    total = 0
    for dirpath, _, filenames in os.walk(folder):
        for name in filenames:
            try:
                total += os.lstat(os.path.join(dirpath, name)).st_size
            except FileNotFoundError:
                pass
    return total


def _complete(path: Path) -> dict[str, object] | None:
    """The entry's marker when it is complete and unchanged since it was built."""
    try:
        info = json.loads((path / COMPLETE).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if info.get("manifest") != _manifest(path):
        print(f"iface test cache: {path} changed after it was built (a cached workspace is read-only: copy what "
              "you change); it is built again", file=sys.stderr)
        return None
    return info


def _number(info: dict[str, object], name: str) -> float:
    value = info.get(name, 0)
    return float(value) if isinstance(value, (int, float, str)) else 0.0


def _touch(path: Path) -> None:
    (path / "last-use").write_text(f"{time.time():.0f}\n")


def entry(key: str, what: str, make: Callable[[Path], str | None], *, wait: bool = True) -> Entry:
    """The complete entry ``key``, built now by ``make(folder)`` when missing.

    ``make`` builds into the empty ``folder`` (the entry's final place) and returns None, or why it
    failed (then ``BuildFailed``). ``what`` says what the key stands for (written to ``key.txt``).
    With ``wait=False``, raises ``Busy`` instead of waiting for another process that builds it.
    The entry stays in use (not evicted) until this process ends.
    """
    base = root()
    path = base / key
    while True:
        try:
            build = _lock(base / "locks" / f"{key}.build", fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
        except BlockingIOError:
            raise Busy(key) from None
        try:
            info = _complete(path)
            built, seconds = info is None, 0.0
            if info is None:
                try:  # nobody uses an entry that is not complete; a changed one may be in use
                    use = _lock(base / "locks" / f"{key}.use", fcntl.LOCK_EX | fcntl.LOCK_NB)
                except BlockingIOError:
                    raise RuntimeError(f"the cached {path} changed while a process uses it: stop that process, "
                                       "then run the tests again") from None
                try:
                    start = time.monotonic()
                    shutil.rmtree(path, ignore_errors=True)
                    path.mkdir()
                    (path / IN_PROGRESS).write_text(f"{os.getpid()}\n")
                    (path / "key.txt").write_text(what + "\n", encoding="utf-8")
                    why = make(path)
                    if why is not None:
                        raise BuildFailed(why)
                    (path / IN_PROGRESS).unlink()
                    seconds = time.monotonic() - start
                    info = {"key": key, "seconds": round(seconds, 1), "built": time.strftime("%Y-%m-%d %H:%M:%S"),
                            "size": _size(path), "manifest": _manifest(path)}
                    temp = path / f"{COMPLETE}.tmp"
                    temp.write_text(json.dumps(info), encoding="utf-8")
                    temp.rename(path / COMPLETE)
                finally:
                    use.close()
            if key not in _using:
                _using[key] = _lock(base / "locks" / f"{key}.use", fcntl.LOCK_SH)
            _touch(path)
        finally:
            build.close()
        if built:
            evict(keep=key)
        return Entry(key, path, built, seconds, info)


def entries() -> list[tuple[Path, dict[str, object]]]:
    """Every complete entry and its marker, least recently used first."""
    found = []
    for path in root().iterdir():
        marker = path / COMPLETE
        if marker.is_file():
            try:
                info = json.loads(marker.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                continue
            last = path / "last-use"
            info["last_use"] = last.stat().st_mtime if last.is_file() else marker.stat().st_mtime
            found.append((path, info))
    return sorted(found, key=lambda item: _number(item[1], "last_use"))


def _remove(path: Path) -> bool:
    """Remove the entry at ``path`` unless a process uses or builds it; True when removed."""
    locks = root() / "locks"
    try:
        use = _lock(locks / f"{path.name}.use", fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    try:
        try:
            build = _lock(locks / f"{path.name}.build", fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            return False
        try:
            trash = path.with_name(f"{path.name}.removing-{os.getpid()}")
            path.rename(trash)
            shutil.rmtree(trash, ignore_errors=True)
            for lock in (f"{path.name}.use", f"{path.name}.build"):
                (locks / lock).unlink(missing_ok=True)
            return True
        finally:
            build.close()
    finally:
        use.close()


def evict(keep: str = "") -> list[Path]:
    """Remove the least recently used entries not in use until the cache is within its bound; what was removed."""
    found = entries()
    total = sum(_number(info, "size") for _, info in found)
    removed = []
    for path, info in found:
        if total <= bound_bytes():
            break
        if path.name != keep and path.name not in _using and _remove(path):
            total -= _number(info, "size")
            removed.append(path)
    return removed


def clear() -> tuple[int, int]:
    """Remove every entry no process uses (and what half-made builds left); (removed, kept because in use)."""
    removed = kept = 0
    for path in sorted(root().iterdir()):
        if path.name == "locks" or not path.is_dir():
            continue
        if ".removing-" in path.name:
            shutil.rmtree(path, ignore_errors=True)
        elif _remove(path):
            removed += 1
        else:
            kept += 1
    return removed, kept


def main(argv: list[str]) -> int:
    """``python -m tests.ros_harness.cache [--clear]``: list the entries (or remove them)."""
    if argv == ["--clear"]:
        removed, kept = clear()
        print(f"{root()}: {removed} entries removed" + (f", {kept} in use kept" if kept else ""))
        return 0
    if argv:
        print("usage: python -m tests.ros_harness.cache [--clear]", file=sys.stderr)
        return 2
    found = entries()
    for path, info in found:
        what = (path / "key.txt").read_text(encoding="utf-8").splitlines()[0] if (path / "key.txt").is_file() else ""
        print(f"{_number(info, 'size') / 2**20:8.1f} MB  {_number(info, 'seconds'):6.0f} s  {path.name}  {what}")
    total = sum(_number(info, "size") for _, info in found)
    print(f"{root()}: {len(found)} entries, {total / 2**20:.0f} MB of {bound_bytes() / 2**20:.0f} MB")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
