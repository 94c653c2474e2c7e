"""Random but valid .iface texts, from a handful of templates and a seeded RNG.

Each text is a list of tokens joined by random whitespace (spaces, tabs, line
breaks, blank lines, CRLF) and random comments of every kind, with random
optional separators, so that the formatter meets layouts nobody wrote by hand.
"""

from __future__ import annotations

import random

BASE = ["bool", "byte", "i8", "i16", "i32", "i64", "double", "string", "binary", "u8", "uint32",
        "int64", "float32", "float64", "char", "octet", "wstring"]
NAMES = ["alpha", "beta", "gamma", "delta", "pose", "speed", "target", "mode", "x", "y"]
TYPES = ["Pose", "Twist", "geometry_msgs.Point", "Header"]


class RandomText:
    """One random text; ``tokens`` are joined by ``text()``."""

    def __init__(self, seed: int) -> None:
        self.rng = random.Random(seed)
        self.tokens: list[str] = []
        self.n = 0

    # ---- pieces ---------------------------------------------------------------------
    def name(self) -> str:
        self.n += 1
        return f"{self.rng.choice(NAMES)}_{self.n}"

    def type_(self, depth: int = 0) -> list[str]:
        r = self.rng.random()
        if depth > 1 or r < 0.45:
            core = [self.rng.choice(BASE)]
        elif r < 0.6:
            core = [self.rng.choice(TYPES)]
        elif r < 0.7:
            core = ["string", "<=", str(self.rng.randint(1, 99))]
        elif r < 0.8:
            core = ["list", "<", *self.type_(depth + 1), ">"]
        elif r < 0.9:
            core = ["map", "<", *self.type_(depth + 1), ",", *self.type_(depth + 1), ">"]
        else:
            core = ["set", "<", *self.type_(depth + 1), ">"]
        if self.rng.random() < 0.2:
            core += self.rng.choice([["[", "]"], ["[", "4", "]"], ["[", "<=", "8", "]"]])
        return core

    def value(self, depth: int = 0) -> list[str]:
        r = self.rng.random()
        if depth > 1 or r < 0.6:
            return [self.rng.choice(["0", "-3", "0x1F", "2.5", "-1e3", '"text"', "'single'", "OTHER"])]
        items: list[str] = []
        count = self.rng.randint(0, 12)
        if r < 0.8:
            for _ in range(count):
                items += [*self.value(depth + 1), *self.sep()]
            return ["[", *items, "]"]
        for i in range(count):
            items += [f'"key_{i}"', ":", *self.value(depth + 1), *self.sep()]
        return ["{", *items, "}"]

    def sep(self) -> list[str]:
        return self.rng.choice([[], [","], [";"], [","]])

    def annotations(self) -> list[str]:
        out = ["("]
        for _ in range(self.rng.randint(1, 4)):
            out += [f"key{self.rng.randint(0, 9)}.part"]
            if self.rng.random() < 0.7:
                out += ["=", self.rng.choice(['"v"', "3", "1.5", "name"])]
            out += self.sep()
        return out + [")"]

    def field(self, fid: int | None, flat: bool = False) -> list[str]:
        out = [str(fid), ":"] if fid is not None else []
        if self.rng.random() < 0.3:
            out.append(self.rng.choice(["required", "optional"]))
        out += [*self.type_(), self.name()]
        if self.rng.random() < 0.3:
            out += ["=", *self.value()]
        if not flat and self.rng.random() < 0.2:
            out += self.annotations()
        return out

    def fields(self, flat: bool = False, ids: bool = True) -> list[str]:
        out: list[str] = []
        for i in range(self.rng.randint(0, 5)):
            fid = i + 1 if ids and self.rng.random() < 0.6 else None
            if self.rng.random() < 0.1:
                out += ["const", self.rng.choice(BASE[:8]), self.name().upper(), "=", "1", *self.sep()]
            else:
                out += [*self.field(fid, flat), *self.sep()]
        return out

    # ---- top-level items -------------------------------------------------------------------
    def item(self) -> list[str]:
        kind = self.rng.choice(["struct", "enum", "senum", "service", "functions", "action", "const",
                                "typedef", "header", "wiring"])
        if kind == "struct":
            kw = self.rng.choice(["struct", "union", "exception", "message", "configuration", "state"])
            out = [kw, self.name().title(), "{", *self.fields(), "}"]
            return out + (self.annotations() if self.rng.random() < 0.2 else [])
        if kind == "enum":
            values: list[str] = []
            for i in range(self.rng.randint(0, 6)):
                values += [self.name().upper()]
                if self.rng.random() < 0.5:
                    values += ["=", str(i * 2)]
                values += self.sep()
            return ["enum", self.name().title(), "{", *values, "}"]
        if kind == "senum":
            return ["senum", self.name().title(), "{", *[t for i in range(3) for t in [f'"s{i}"', *self.sep()]], "}"]
        if kind == "service":
            body = self.rng.choice([
                ["request", "{", *self.fields(), "}", "response", "{", *self.fields(), "}"],
                self.fields(flat=True, ids=False),
            ])
            return ["service", self.name().title(), "{", *body, "}"]
        if kind == "functions":
            out = ["service", self.name().title()] + (["extends", "Base"] if self.rng.random() < 0.3 else []) + ["{"]
            for _ in range(self.rng.randint(0, 4)):
                out += (["oneway"] if self.rng.random() < 0.1 else []) + [self.rng.choice(["void", "i32", "string"])]
                out += [self.name(), "("]
                for i in range(self.rng.randint(0, 5)):
                    out += [*self.field(i + 1), *self.sep()]
                out.append(")")
                if self.rng.random() < 0.3:
                    out += ["throws", "(", "1", ":", "Oops", "e", ")"]
                out += self.sep()
            return out + ["}"]
        if kind == "action":
            body = self.rng.choice([
                ["goal", "{", *self.fields(), "}", "result", "{", *self.fields(), "}",
                 "feedback", "{", *self.fields(), "}"],
                self.fields(flat=True, ids=False),
            ])
            return ["action", self.name().title(), "{", *body, "}"]
        if kind == "const":
            return ["const", *self.type_(), self.name().upper(), "=", *self.value(), *self.sep()]
        if kind == "typedef":
            return ["typedef", *self.type_(), self.name().title()]
        if kind == "header":
            return self.rng.choice([["namespace", "ros2", "pkg"], ["include", '"other.iface"'],
                                    ["component", "arm", "version", '"1.0"'], ["external", "geometry_msgs"]])
        return [self.rng.choice(["publishes", "subscribes", "provides", "calls"]), "Pose", "on", '"/topic"',
                *(self.annotations() if self.rng.random() < 0.3 else [])]

    # ---- joining --------------------------------------------------------------------------
    def gap(self) -> str:
        r = self.rng.random()
        if r < 0.55:
            return " "
        if r < 0.65:
            return self.rng.choice(["", "\t", "   "]) or " "
        if r < 0.8:
            return self.rng.choice(["\n", "\n  ", "\n\n\t", "\r\n    ", "\n\n\n"])
        n = self.rng.randint(0, 999)
        return self.rng.choice([f" // line {n}\n", f"\n# hash {n}\n", f" /* block {n} */ ",
                                f"\n/** doc {n} */\n", f"\n  /* multi {n}\n     line */\n",
                                f"\n\n// own line {n}\n\n"])

    def text(self, items: int) -> str:
        parts: list[str] = []
        for _ in range(items):
            parts.append(self.rng.choice(["", "\n", "\n\n", "\n// before\n", "\n/** doc */\n"]))
            tokens = self.item()
            for i, tok in enumerate(tokens):
                parts.append(tok)
                if i + 1 < len(tokens):
                    gap = self.gap()
                    while tokens[i + 1] in (",", ";") and "/**" in gap:
                        gap = self.gap()  # a doc comment before a separator documents nothing
                    parts.append(gap)
            parts.append(self.rng.choice(["\n", " // end\n", "\n\n", "\r\n"]))
        return "".join(parts)
