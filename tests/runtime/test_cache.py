"""The test cache (tests/ros_harness/cache.py): built once per key whoever asks, never stale, bounded.

Plain folders stand for built workspaces here (no ROS needed): each build function writes a file and
counts its calls in a file outside the cache, so that builds in other processes are counted too.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from ..ros_harness import cache

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def place(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("IFACE_TEST_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(cache, "_using", {})  # this process uses none of this cache's entries yet
    return tmp_path


def maker(counter: Path, text: str = "built", seconds: float = 0.0,
          fail: str | None = None) -> Callable[[Path], str | None]:
    def make(folder: Path) -> str | None:
        with open(counter, "a") as f:
            f.write(f"{os.getpid()}\n")
        time.sleep(seconds)
        (folder / "ws").mkdir()
        (folder / "ws" / "out.txt").write_text(text)
        return fail

    return make


def test_a_key_is_built_once_then_found(place: Path) -> None:
    counter = place / "calls"
    key = cache.key_of("a", "b")
    first = cache.entry(key, "a b", maker(counter))
    second = cache.entry(key, "a b", maker(counter))
    assert first.built and not second.built and first.path == second.path
    assert counter.read_text().count("\n") == 1
    assert (second.path / "ws" / "out.txt").read_text() == "built"
    assert (second.path / "key.txt").read_text() == "a b\n"
    assert cache.root() == place / "cache" / cache.LAYOUT


def test_other_content_is_another_key(tmp_path: Path) -> None:
    (tmp_path / "p").mkdir()
    (tmp_path / "p" / "a.msg").write_text("int32 x\n")
    before = cache.digest_tree(tmp_path / "p")
    (tmp_path / "p" / "a.msg").write_text("int64 x\n")
    after = cache.digest_tree(tmp_path / "p")
    (tmp_path / "p" / "__pycache__").mkdir()
    (tmp_path / "p" / "__pycache__" / "a.pyc").write_text("bytecode")
    assert before != after and cache.digest_tree(tmp_path / "p") == after  # bytecode is not content
    assert cache.key_of("x", before) != cache.key_of("x", after)
    assert cache.key_of("ab", "c") != cache.key_of("a", "bc")


def test_a_failed_or_half_made_build_is_built_again(place: Path) -> None:
    counter = place / "calls"
    key = cache.key_of("failing")
    with pytest.raises(cache.BuildFailed, match="colcon said no"):
        cache.entry(key, "failing", maker(counter, fail="colcon said no"))
    assert (cache.root() / key / "ws" / "out.txt").is_file()  # its logs stay, without the marker
    assert not (cache.root() / key / cache.COMPLETE).exists()
    assert cache.entry(key, "failing", maker(counter)).built
    assert counter.read_text().count("\n") == 2


def test_an_entry_changed_after_its_build_is_built_again(place: Path, capsys: pytest.CaptureFixture[str]) -> None:
    counter = place / "calls"
    key = cache.key_of("changed")
    entry = cache.entry(key, "changed", maker(counter))
    (entry.path / "ws" / "__pycache__").mkdir()  # what running the entry's code writes is not a change
    (entry.path / "ws" / "__pycache__" / "m.pyc").write_text("bytecode")
    assert not cache.entry(key, "changed", maker(counter)).built
    cache._using.pop(key).close()  # as another process would be, this one no longer uses it
    (entry.path / "ws" / "signature.json").write_text("{}")  # a test wrote into a cached workspace
    again = cache.entry(key, "changed", maker(counter))
    assert again.built and not (again.path / "ws" / "signature.json").exists()
    assert "changed after it was built" in capsys.readouterr().err


#: Asks for one key from another process (the test's interpreter, this checkout), slowly built.
RACE = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    sys.path.insert(0, sys.argv[1])
    from tests.ros_harness import cache

    def make(folder):
        with open(sys.argv[2], "a") as f:
            f.write("build\\n")
        time.sleep(1.5)
        (folder / "ws").mkdir()
        return None

    print(cache.entry(cache.key_of("race"), "race", make).built)
""")


def test_processes_asking_for_one_key_at_once_build_it_once(place: Path) -> None:
    env = {**os.environ, "IFACE_TEST_CACHE": str(place / "cache")}
    procs = [subprocess.Popen([sys.executable, "-c", RACE, str(ROOT), str(place / "calls")], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for _ in range(3)]
    outs = [proc.communicate(timeout=60) for proc in procs]
    assert all(proc.returncode == 0 for proc in procs), outs
    assert sorted(out.strip() for out, _ in outs) == ["False", "False", "True"]
    assert (place / "calls").read_text() == "build\n"


def test_a_busy_key_is_said_so_when_not_waiting(place: Path) -> None:
    env = {**os.environ, "IFACE_TEST_CACHE": str(place / "cache")}
    proc = subprocess.Popen([sys.executable, "-c", RACE, str(ROOT), str(place / "calls")], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 30
        while not (place / "calls").is_file() and time.monotonic() < deadline:
            time.sleep(0.05)
        with pytest.raises(cache.Busy):
            cache.entry(cache.key_of("race"), "race", maker(place / "mine"), wait=False)
        assert not cache.entry(cache.key_of("race"), "race", maker(place / "mine")).built  # waited for it
    finally:
        proc.communicate(timeout=60)
    assert not (place / "mine").exists()


def test_past_the_bound_the_least_recently_used_entries_not_in_use_go(place: Path,
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    counter = place / "calls"
    keys = [cache.key_of(f"entry {i}") for i in range(4)]
    for i, key in enumerate(keys):
        cache.entry(key, f"entry {i}", maker(counter, "x" * 100_000))
        os.utime(cache.root() / key / "last-use", (1000 + i, 1000 + i))  # used in this order
    for key in keys[:2]:
        cache._using.pop(key).close()  # entries 0 and 1: no process uses them; 2 and 3: this one does
    os.utime(cache.root() / keys[1] / "last-use", (2000, 2000))  # 1 was used last
    monkeypatch.setenv("IFACE_TEST_CACHE_MB", str(0.35))  # room for three of them
    removed = cache.evict()
    assert removed == [cache.root() / keys[0]]
    assert not (cache.root() / keys[0]).exists() and (cache.root() / keys[1]).is_dir()
    monkeypatch.setenv("IFACE_TEST_CACHE_MB", "0")
    assert cache.evict() == [cache.root() / keys[1]]  # 2 and 3 are in use: kept past the bound
    assert [path.name for path, _ in cache.entries()] == keys[2:]


def test_clear_and_the_listing(place: Path, capsys: pytest.CaptureFixture[str]) -> None:
    key = cache.key_of("listed")
    cache.entry(key, "what it is", maker(place / "calls"))
    assert cache.main([]) == 0
    listing = capsys.readouterr().out
    assert key in listing and "what it is" in listing and "1 entries" in listing
    info = json.loads((cache.root() / key / cache.COMPLETE).read_text())
    assert info["size"] >= len("built") and info["key"] == key
    assert cache.main(["--clear"]) == 0
    assert "0 entries removed, 1 in use kept" in capsys.readouterr().out
    cache._using.pop(key).close()
    assert cache.main(["--clear"]) == 0
    assert "1 entries removed" in capsys.readouterr().out and not (cache.root() / key).exists()
    assert cache.main(["--bogus"]) == 2


def test_an_own_copy_is_a_view_whose_named_packages_are_copies_the_test_may_change(tmp_path: Path) -> None:
    """workspaces.own_copy: the named packages are copies of the layer the view links for each (the last one),
    sourced and linked instead of the cache's entry; the other packages stay the entries', and a change to a copy
    leaves the entry as it was (a test signs its copy; the cache sees no change)."""
    from ..ros_harness.workspaces import Layer, layers_of, own_copy, write_view

    def layer(key: str, package: str, text: str) -> Layer:
        ws = tmp_path / "cache" / key / "ws"
        (ws / "install" / package).mkdir(parents=True)
        (ws / "install" / package / "lib.so").write_text(text)
        (ws / "install" / "local_setup.bash").write_text(f"# {key}\n")
        return Layer(key, ws, (package,), ())

    layers = [layer("k1", "msgs", "msgs"), layer("k2", "ticker", "1.0"), layer("k3", "ticker", "1.1")]
    view = tmp_path / "view"
    write_view(view, layers)
    own = own_copy(view, ["ticker"], tmp_path / "own")
    copy = tmp_path / "own" / "own" / "ticker"
    assert [layer.path for layer in layers_of(own)] == [layers[0].path, layers[1].path, copy]
    assert (own / "install" / "ticker").resolve() == (copy / "install" / "ticker").resolve()
    assert (own / "install" / "msgs").resolve() == (layers[0].path / "install" / "msgs").resolve()
    setup = (own / "install" / "setup.bash").read_text()
    assert f'. "{copy}/install/local_setup.bash"' in setup and f"{layers[2].path}/install" not in setup
    (own / "install" / "ticker" / "iface-signature.json").write_text("{}")  # signed: the copy changes
    assert (copy / "install" / "ticker" / "lib.so").read_text() == "1.1"
    assert not (layers[2].path / "install" / "ticker" / "iface-signature.json").exists()
