"""Writing generated files: checked as a set first, each one atomic, inside the output folder, never over hand edits.

``write_files`` checks every target path before it writes anything (inside the
output folder, each name short enough for the file system, no file where a
folder must go, no two paths that differ only in case) and encodes every file,
so a problem found up front writes no file at all. Each file is then written to
a short temporary name in its own folder and renamed into place, so a reader
never sees half a file; it gets the mode an editor would give it (the mode of
the file it replaces, else 0666 less the umask). A symbolic link where a file
goes is never written through: it is refused, or with ``force`` replaced by the
file. An I/O error in the middle of writing (a full disk) stops the run: the
files already written are complete, the others are left as they were. Ctrl-C
or SIGTERM (turned into an exception by the CLI) leaves no temporary file.
"""

from __future__ import annotations

import os
import re
import signal
import stat
import tempfile
import unicodedata
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from .base import GENERATED_MARK, OLD_TEXT_HASH, TEXT_HASH, GeneratedFile, content_hash

#: The stamp after the generated mark, as written now and as releases before wrote it.
_STAMP = re.compile(rf" \((?:{re.escape(TEXT_HASH)}|{re.escape(OLD_TEXT_HASH)}): ([0-9a-f]{{16}})\)")
#: Used when the file system does not say (the Linux and POSIX limits).
DEFAULT_NAME_MAX = 255
DEFAULT_PATH_MAX = 4096
#: The temporary file of an atomic write: short, so that every name that fits has a temporary that fits.
TEMP_PREFIX = ".iface-"
TEMP_SUFFIX = ".tmp"


@dataclass(slots=True)
class WriteReport:
    """What happened to each file: written, unchanged, kept (the user's), refused (hand-edited, or not
    iface's: ``foreign``), or differing (check).

    ``errors`` are path problems found before writing (nothing was written then) or
    the I/O error that stopped the run.
    """

    written: list[str] = field(default_factory=list)
    unchanged: list[str] = field(default_factory=list)
    #: Files written once that exist: the user's, left as they are.
    kept: list[str] = field(default_factory=list)
    refused: list[str] = field(default_factory=list)
    differing: list[str] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)
    #: of ``refused``, the files iface did not write at all (no stamp): not edited, someone else's
    foreign: list[str] = field(default_factory=list)
    #: Of ``refused``: the paths where a symbolic link stands (not followed; ``force`` replaces the link).
    links: list[str] = field(default_factory=list)
    #: Of ``written``: the paths where ``force`` replaced a symbolic link, with where it pointed.
    replaced_links: dict[str, str] = field(default_factory=dict)


def _parts(rel: str) -> tuple[str, ...] | None:
    """The parts of the generated path ``rel``; None for a path that names no file inside the output folder
    (empty, ``.``, absolute, with ``..``, a backslash or a NUL)."""
    p = PurePosixPath(rel)
    if not p.parts or p.is_absolute() or any(part in ("..", "") for part in p.parts) or "\\" in rel or "\0" in rel:
        return None
    return p.parts


def _exists(path: Path) -> bool:
    """``path.exists()``, False where the system cannot even look (a name too long…)."""
    try:
        os.stat(path)
    except (OSError, ValueError):
        return False
    return True


def _existing_ancestor(path: Path) -> Path:
    """The nearest folder of ``path`` (or ``path`` itself) that exists."""
    for p in (path, *path.parents):
        if _exists(p):
            return p
    return Path(path.anchor or ".")


def _limit(folder: Path, name: str, default: int) -> int:
    """``os.pathconf(folder, name)``, or ``default`` where the system does not tell."""
    try:
        value = os.pathconf(folder, name)
    except (OSError, ValueError, AttributeError):
        return default
    return value if value and value > 0 else default


@dataclass(frozen=True, slots=True)
class FolderFacts:
    """What a folder's files need checked against: the file system's limits there, and why nothing can be
    written in it (an existing file where a folder must be), if so."""

    name_max: int
    path_max: int
    problem: str | None


def folder_facts(folder: Path) -> FolderFacts:
    """The limits that hold in ``folder`` (or its nearest existing folder), and whether it can hold files."""
    ancestor = _existing_ancestor(folder)
    problem = None
    for f in (*reversed(folder.parents), folder):
        if _exists(f) and not f.is_dir():
            problem = f"{f} exists and is not a folder"
            break
    return FolderFacts(_limit(ancestor, "PC_NAME_MAX", DEFAULT_NAME_MAX),
                       _limit(ancestor, "PC_PATH_MAX", DEFAULT_PATH_MAX), problem)


def path_problem(full: Path, facts: FolderFacts | None = None) -> str | None:
    """Why the file ``full`` cannot be written, as far as can be told without writing; None when it can.

    Checked: each name at most NAME_MAX bytes (UTF-8), the whole path at most PATH_MAX,
    no existing file where a folder must be, no folder where the file must be. ``facts``
    are those of ``full``'s folder, when already looked up.
    """
    facts = facts or folder_facts(full.parent)
    for part in full.parts[1:]:
        size = len(part.encode("utf-8", "surrogateescape"))
        if size > facts.name_max:
            return f"the name '{part[:40]}…' is {size} bytes long; the file system allows {facts.name_max}"
    size = len(str(full).encode("utf-8", "surrogateescape"))
    if size >= facts.path_max:
        return f"the path is {size} bytes long; the file system allows {facts.path_max - 1}"
    if facts.problem is not None:
        return facts.problem
    if full.is_symlink():
        return None  # refused or replaced when written, never followed
    if _exists(full) and not full.is_file():
        return "a folder (or other non-file) is in its place"
    return None


def _folder_conflicts(paths: Iterable[tuple[str, Path]]) -> list[str]:
    """Files of the set that another file of the set needs as a folder (``a`` and ``a/b``)."""
    files = {str(full): rel for rel, full in paths}
    out = []
    for full, rel in files.items():
        folder, parent = full, os.path.dirname(full)
        while parent != folder:
            folder, parent = parent, os.path.dirname(parent)
            if folder in files:
                out.append(f"{rel}: refused: {files[folder]} is generated as a file, so it cannot be a folder")
                break
    return out


def stamp(text: str) -> str:
    """Put the edit guard, the hash of the text, right after the generated mark of the header.

    The hash covers the text without the stamp, so an edit anywhere is detected.
    """
    if GENERATED_MARK not in text:
        return text
    return text.replace(GENERATED_MARK, f"{GENERATED_MARK} ({TEXT_HASH}: {content_hash(text)})", 1)


def unstamp(text: str) -> tuple[str, str | None]:
    """The text without its stamp, and the stamped hash (None if there is none).

    A file of an older release, stamped ``iface-hash``, reads the same: it is iface's own, not the user's.
    """
    m = _STAMP.search(text)
    if m is None:
        return text, None
    return text[:m.start()] + text[m.end():], m.group(1)


def hand_edited(existing: str) -> bool:
    """True when a file on disk was not written by iface as it is now."""
    body, digest = unstamp(existing)
    return digest is None or content_hash(body) != digest


def umask() -> int:
    """The process's umask (read without changing it where the system allows)."""
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _mode(path: Path) -> int:
    """The mode a file written at ``path`` gets: that of the regular file it replaces, else 0666 less the umask."""
    try:
        st = os.lstat(path)
    except OSError:
        st = None
    if st is not None and stat.S_ISREG(st.st_mode):
        return stat.S_IMODE(st.st_mode)
    return 0o666 & ~umask()


@contextmanager
def signals_deferred() -> Iterator[None]:
    """Hold back SIGINT and SIGTERM while the block runs (where the system can)."""
    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def atomic_write(path: Path, text: str | bytes) -> None:
    """Write via a short-named temporary file in the same folder and rename it into place.

    A symbolic link at ``path`` is replaced, never followed. Whatever stops the
    write (an error, Ctrl-C, SIGTERM raised as an exception) removes the temporary file.
    """
    data = text.encode("utf-8") if isinstance(text, str) else text
    path.parent.mkdir(parents=True, exist_ok=True)
    mode = _mode(path)
    with signals_deferred():  # the temporary file exists only inside the try below
        fd, tmp = tempfile.mkstemp(prefix=TEMP_PREFIX, suffix=TEMP_SUFFIX, dir=path.parent)
        try:
            os.fchmod(fd, mode)
            with os.fdopen(fd, "wb") as f:
                fd = -1
                f.write(data)
            os.replace(tmp, path)
        except BaseException:
            if fd >= 0:
                os.close(fd)
            try:
                os.unlink(tmp)
            except OSError:
                pass
            raise


def _looked_at(root: Path | None, out: Path, folder: tuple[str, ...]) -> tuple[Path, FolderFacts] | None:
    """The folder ``out/folder`` resolved, with its facts; None when it resolves outside the output folder ``root``
    or cannot be resolved (a loop of links; ``root`` None: the output folder itself cannot)."""
    if root is None:
        return None
    try:
        resolved = out.joinpath(*folder).resolve()
    except (OSError, RuntimeError):
        return None
    if root != resolved and root not in resolved.parents:
        return None
    return resolved, folder_facts(resolved)


def plan(files: list[GeneratedFile], out: Path) -> tuple[list[tuple[GeneratedFile, Path]], list[str]]:
    """Each file with its full path, and every path problem (when there is one, nothing may be written).

    Each folder is resolved and looked at once, however many files it gets. The folders are resolved; a file's
    own name is not: a symbolic link there is the writer's to refuse or replace, never to follow.
    """
    planned: list[tuple[GeneratedFile, Path]] = []
    errors: list[str] = []
    try:
        root: Path | None = out.resolve()
    except (OSError, RuntimeError):  # a loop of links
        root = None
    folders: dict[tuple[str, ...], tuple[Path, FolderFacts] | None] = {}
    for f in files:
        parts = _parts(f.path)
        if parts is not None and parts[:-1] not in folders:
            folders[parts[:-1]] = _looked_at(root, out, parts[:-1])
        known = folders[parts[:-1]] if parts is not None else None
        if parts is None or known is None:
            errors.append(f"{f.path}: refused: the path leaves the output folder")
            continue
        folder, facts = known
        full = folder / parts[-1]
        problem = path_problem(full, facts)
        if problem is not None:
            errors.append(f"{f.path}: cannot be written: {problem}")
            continue
        planned.append((f, full))
    errors.extend(_folder_conflicts((f.path, full) for f, full in planned))
    errors.extend(_case_conflicts(f.path for f, _ in planned))
    return planned, errors


def _case_conflicts(paths: Iterable[str]) -> list[str]:
    """Paths of the set that differ from another only in case: one file on macOS and Windows."""
    first: dict[str, str] = {}
    out = []
    for rel in paths:
        key = unicodedata.normalize("NFC", rel).casefold()
        seen = first.setdefault(key, rel)
        if seen != rel:
            out.append(f"{rel}: refused: it differs from {seen} only in case, and case-insensitive file systems "
                       "(macOS, Windows) hold them as one file")
    return out


def _encoded(planned: list[tuple[GeneratedFile, Path]], stamped: bool) -> tuple[list[tuple[str, Path, bytes, bool]],
                                                                                list[str]]:
    """Every file's bytes as written (stamped, UTF-8), and the files that cannot be encoded."""
    out: list[tuple[str, Path, bytes, bool]] = []
    errors: list[str] = []
    for f, full in planned:
        try:
            text = stamp(f.text) if stamped and not f.once else f.text
            out.append((f.path, full, text.encode("utf-8"), f.once))
        except UnicodeEncodeError as e:
            errors.append(f"{f.path}: cannot be written as UTF-8: character {e.start} is "
                          f"U+{ord(e.object[e.start]):04X} ({e.reason})")
    return out, errors


def write_files(files: list[GeneratedFile], out_dir: str | Path, *, force: bool = False,
                dry_run: bool = False, check: bool = False, stamped: bool = True) -> WriteReport:
    """Write (or, with ``check``, compare) files under ``out_dir``: all of them or, on a path problem, none.

    Every path is checked and every file encoded before anything is written. An
    I/O error while writing stops the run and is reported in ``errors``; the files
    written before it are complete (each write is atomic), the rest are untouched.
    Generated files are ``stamped`` and an existing one is refused only when edited
    by hand; unstamped files (imported ``.iface`` files, the user's to edit) refuse
    any different file. A symbolic link where a file goes is refused (``links``),
    or with ``force`` replaced by the file (``replaced_links``); it is never followed.
    A file marked ``once`` is written only where none exists (``kept`` otherwise, even
    with ``force``).
    """
    out = Path(out_dir)
    report = WriteReport()
    planned, report.errors = plan(files, out)
    if report.errors:
        return report
    encoded, report.errors = _encoded(planned, stamped)
    if report.errors:
        return report
    for rel, full, data, once in encoded:
        if once and _exists(full):
            report.kept.append(rel)
            continue
        link = _link_target(full)
        existing = None
        if link is None and full.is_file():
            try:
                existing = full.read_bytes()
            except OSError:
                existing = b""
        if existing == data:
            report.unchanged.append(rel)
            continue
        if check:
            report.differing.append(rel)
            continue
        if link is not None and not force:
            report.refused.append(rel)
            report.links.append(rel)
            continue
        if existing is not None and not force:
            existing_text = existing.decode("utf-8", errors="replace")
            if not stamped or hand_edited(existing_text):
                report.refused.append(rel)
                if stamped and unstamp(existing_text)[1] is None:
                    report.foreign.append(rel)
                continue
        if not dry_run:
            try:
                atomic_write(full, data)
            except OSError as e:
                report.errors.append(f"{rel}: cannot write: {e.strerror or e}; stopped after "
                                     f"{len(report.written)} file(s), the others are unchanged")
                return report
        report.written.append(rel)
        if link is not None:
            report.replaced_links[rel] = link
    return report


def _link_target(path: Path) -> str | None:
    """Where the symbolic link at ``path`` points; None when ``path`` is not a link."""
    try:
        return os.readlink(path)
    except (OSError, ValueError):
        return None
