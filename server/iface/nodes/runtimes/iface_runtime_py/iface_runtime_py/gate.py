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
    get there in time leaves the gate as it was. ``quiet`` (a snapshot's moment) holds the gate:
    new work waits until the hold ends instead of being refused, so that a snapshot loses no message.
    ``close`` (the members are about to be destroyed: cleanup, shutdown, error) lets no new transaction in and
    waits for the ones in progress, so that none runs on a destroyed member; ``open`` (configure) undoes it.
    """

    def __init__(self) -> None:
        self._cond = threading.Condition()
        self.in_flight = 0
        self.paused = False
        self.transactions = 0
        self.refused = 0
        self.holds = 0
        self.closed = False

    def enter(self) -> bool:
        """Start a transaction, after a hold if one is on; False while closed, and (counted as refused) while
        paused."""
        with self._cond:
            self._cond.wait_for(lambda: self.holds == 0 or self.paused or self.closed)
            if self.closed:
                return False
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
            self._cond.notify_all()  # work waiting on a hold is refused now
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

    def close(self, timeout: float) -> tuple[bool, str]:
        """Let no new transaction in and wait for the ones in progress to end (at most ``timeout`` s); the gate
        stays closed either way."""
        with self._cond:
            self.closed = True
            self._cond.notify_all()  # work waiting on a hold is turned away now
            if not self._cond.wait_for(lambda: self.in_flight == 0, timeout):
                return False, f"{self.in_flight} work transaction(s) still running after {timeout:g} s"
            return True, "closed"

    def open(self) -> None:
        """Let transactions in again (a closed gate's members were made anew)."""
        with self._cond:
            self.closed = False

    @contextmanager
    def quiet(self, timeout: float) -> Iterator[None]:
        """No transaction runs inside: new work waits (a paused gate refuses it anyway), none is refused;
        TimeoutError when the work in progress does not end within ``timeout`` s."""
        with self._cond:
            held = not self.paused
            if held:
                self.holds += 1
                busy = self.in_flight
                if not self._cond.wait_for(lambda: self.in_flight == 0, timeout):
                    self.holds -= 1
                    self._cond.notify_all()
                    raise TimeoutError(f"{busy} work transaction(s) still running after {timeout:g} s")
        try:
            yield
        finally:
            if held:
                with self._cond:
                    self.holds -= 1
                    self._cond.notify_all()

    @contextmanager
    def transaction(self) -> Iterator[None]:
        """A work transaction for user code (a thread of its own, a longer operation); Paused when refused."""
        if not self.enter():
            raise Paused("the component is paused")
        try:
            yield
        finally:
            self.leave()
