"""What native code writes to descriptor 1 (Fast DDS's log) stays out of iface's output (``live/stdout.py``).

In a process of its own (the real descriptors): inside ``native_output_to_stderr`` a write to descriptor 1
reaches stderr and ``print`` the real stdout; after it, both are as they were. A redirected ``sys.stdout`` is
left alone. The language server (``iface-lsp --stdio``) answers on a stream that a native write to
descriptor 1 does not reach.
"""

from __future__ import annotations

import json
import os
import select
import signal
import subprocess
import sys
import textwrap
import time
from typing import IO, Any

from tests.conftest import ROOT

ENV = {**os.environ, "PYTHONPATH": str(ROOT / "server")}

INSIDE = textwrap.dedent("""
    import os, sys, io, contextlib
    from iface.live.stdout import native_output_to_stderr
    print("before", flush=True)
    with native_output_to_stderr():
        os.write(1, b"native inside\\n")
        print("ours inside")
    os.write(1, b"native after\\n")
    print("ours after", flush=True)
    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer), native_output_to_stderr():
        print("redirected")
    assert buffer.getvalue() == "redirected\\n", buffer.getvalue()
""")


def test_native_writes_go_to_stderr_inside_and_everything_is_restored_after() -> None:
    done = subprocess.run([sys.executable, "-c", INSIDE], capture_output=True, text=True, env=ENV, timeout=60,
                          check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["before", "ours inside", "native after", "ours after"]
    assert done.stderr.splitlines() == ["native inside"]


SERVER = textwrap.dedent("""
    import os, signal, sys, threading
    from iface.cli import main
    # native output from another thread while the server runs, as Fast DDS's log comes while a command reads the
    # ROS graph. SIGUSR1 is blocked in every thread but the one waiting for it: a handler would run only when the
    # main thread runs Python again, which it may not do while it waits for the client's next message (the kernel
    # can hand the signal to any thread; one run in many waited 30 s for it)
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGUSR1})

    def noise():
        signal.sigwait({signal.SIGUSR1})
        os.write(1, b"native noise\\n")

    threading.Thread(target=noise, daemon=True).start()
    sys.exit(main(["--stdio"]))
""")


def _message(payload: dict[str, object]) -> bytes:
    body = json.dumps(payload).encode()
    return b"Content-Length: %d\r\n\r\n%s" % (len(body), body)


def _read(stream: IO[bytes]) -> dict[str, Any]:
    """One message of the server's stream (``Content-Length`` framed), read from ``stream``."""
    length = None
    while (line := stream.readline()) not in (b"\r\n", b""):
        assert line.startswith((b"Content-Length: ", b"Content-Type: ")), line
        if line.startswith(b"Content-Length: "):
            length = int(line.split(b":")[1])
    assert length is not None, "the stream ended"
    return json.loads(stream.read(length))


def test_the_language_servers_stream_carries_only_its_messages() -> None:
    proc = subprocess.Popen([sys.executable, "-c", SERVER], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env=ENV)
    assert proc.stdin is not None and proc.stdout is not None and proc.stderr is not None
    try:
        proc.stdin.write(_message({"jsonrpc": "2.0", "id": 1, "method": "initialize",
                                   "params": {"processId": None, "rootUri": None, "capabilities": {}}}))
        proc.stdin.flush()
        assert _read(proc.stdout)["result"]["serverInfo"]["name"]  # the server runs; the noise comes after
        os.kill(proc.pid, signal.SIGUSR1)
        end, seen = time.monotonic() + 30, b""
        while b"native noise" not in seen:
            assert time.monotonic() < end, f"the noise not on stderr within 30 s: {seen!r}"
            if select.select([proc.stderr], [], [], 0.5)[0]:
                seen += os.read(proc.stderr.fileno(), 4096)
        after: list[dict[str, object]] = [{"jsonrpc": "2.0", "method": "initialized", "params": {}},
                                          {"jsonrpc": "2.0", "id": 2, "method": "shutdown"},
                                          {"jsonrpc": "2.0", "method": "exit"}]
        proc.stdin.write(b"".join(map(_message, after)))
        proc.stdin.close()
        answers = [_read(proc.stdout)]
        while answers[-1].get("id") != 2:
            answers.append(_read(proc.stdout))
        assert proc.stdout.read() == b""
        assert proc.wait(timeout=30) == 0
    finally:
        proc.kill()
        proc.wait(timeout=10)


def test_the_language_server_without_a_standard_output_says_so_in_one_line() -> None:
    done = subprocess.run([sys.executable, "-m", "iface", "--stdio"], stdin=subprocess.DEVNULL, stdout=None,
                          stderr=subprocess.PIPE, text=True, env=ENV, timeout=60, check=False,
                          preexec_fn=lambda: os.close(1))
    assert done.returncode == 2, done.stderr
    assert done.stderr == "iface-lsp: --stdio needs standard input, output and error open\n"
