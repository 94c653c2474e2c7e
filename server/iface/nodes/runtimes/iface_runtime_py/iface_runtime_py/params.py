"""Configuration parameters (P): the values each one accepts, and why another is refused."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class ParamSpec:
    """A configuration parameter of the interface and the values it accepts."""

    name: str
    kind: str
    default: Any = None
    description: str = ""
    constraints: str = ""
    unit: str | None = None
    low: float | int | None = None
    high: float | int | None = None
    read_only: bool = False
    choices: tuple[tuple[str, int], ...] = ()
    max_length: int | None = None
    size: int | None = None
    size_kind: str | None = None

    def problem(self, value: Any) -> str | None:
        """Why ``value`` is refused, or None."""
        if self.kind.endswith("_array"):
            items = list(value) if value is not None else []
            if self.size_kind == "fixed" and len(items) != self.size:
                return f"{self.name} must have exactly {self.size} elements, not {len(items)}"
            if self.size_kind == "bounded" and self.size is not None and len(items) > self.size:
                return f"{self.name} may have at most {self.size} elements, not {len(items)}"
            for i, item in enumerate(items):
                found = self._scalar(item, f"{self.name}[{i}]")
                if found:
                    return found
            return None
        return self._scalar(value, self.name)

    def _scalar(self, value: Any, what: str) -> str | None:
        unit = f" {self.unit}" if self.unit else ""
        if self.choices and value not in [v for _, v in self.choices]:
            names = ", ".join(f"{n} ({v})" for n, v in self.choices)
            return f"{what}={value} is not one of {names}"
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            if self.low is not None and value < self.low:
                return f"{what}={value}{unit} is below the minimum {self.low}{unit}"
            if self.high is not None and value > self.high:
                return f"{what}={value}{unit} is above the maximum {self.high}{unit}"
        if isinstance(value, str) and self.max_length is not None and len(value) > self.max_length:
            return f"{what} is {len(value)} characters long; at most {self.max_length} are allowed"
        return None
