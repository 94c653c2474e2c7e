"""Work transactions and pausing: the gate every main callback of a component passes."""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager


class Paused(RuntimeError):
    """Work was refused: the component is paused."""


class Gate:
    """Work transactions and pausing.

    Every main callback is a work transaction: it enters the gate and leaves it. ``pause`` lets
    no new transaction in and waits until the ones in progress have ended; a pause that does not
    get there in time leaves the gate as it was.
    """

    def __init__(self) -> None:
        self._cond = threading.Condition()
        self.in_flight = 0
        self.paused = False
        self.transactions = 0
        self.refused = 0

    def enter(self) -> bool:
        """Start a transaction; False (counted as refused) while paused."""
        with self._cond:
            if self.paused:
                self.refused += 1
                return False
            self.in_flight += 1
            return True

    def leave(self) -> None:
        """End a transaction."""
        with self._cond:
            self.in_flight -= 1
            self.transactions += 1
            self._cond.notify_all()

    def pause(self, timeout: float) -> tuple[bool, str]:
        """Refuse new work and wait for the work in progress to end (at most ``timeout`` s)."""
        with self._cond:
            if self.paused:
                return True, "already paused"
            self.paused = True
            busy = self.in_flight
            if not self._cond.wait_for(lambda: self.in_flight == 0, timeout):
                self.paused = False
                return False, (f"{self.in_flight} work transaction(s) still running after {timeout:g} s: "
                               "not paused")
            return True, f"paused after {busy} work transaction(s) in progress ended" if busy else "paused"

    def resume(self) -> tuple[bool, str]:
        """Accept work again."""
        with self._cond:
            if not self.paused:
                return True, "not paused"
            self.paused = False
            return True, "resumed"

    @contextmanager
    def quiet(self, timeout: float) -> Iterator[None]:
        """No transaction runs inside (pausing for the time if needed); TimeoutError when it cannot be had."""
        was_paused = self.paused
        ok, message = self.pause(timeout)
        if not ok:
            raise TimeoutError(message)
        try:
            yield
        finally:
            if not was_paused:
                self.resume()

    @contextmanager
    def transaction(self) -> Iterator[None]:
        """A work transaction for user code (a thread of its own, a longer operation); Paused when refused."""
        if not self.enter():
            raise Paused("the component is paused")
        try:
            yield
        finally:
            self.leave()
