"""``iface-lsp generate`` and ``iface-lsp targets`` through the real command line."""

from __future__ import annotations

from pathlib import Path

from iface.emit import generate
from tests.conftest import run_cli

from .helpers import CASES, compile_file

LISTING1 = str(CASES["listing1"])


def tree(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def test_targets_lists_ros2_and_idl_with_a_description() -> None:
    proc = run_cli("targets")
    assert proc.returncode == 0
    lines = {line.split()[0]: line for line in proc.stdout.splitlines()}
    assert "ros2" in lines and "idl" in lines
    assert "ament package" in lines["ros2"] and "IDL" in lines["idl"]


def test_generate_writes_the_package_and_is_idempotent(tmp_path: Path) -> None:
    out = tmp_path / "out"
    proc = run_cli("generate", LISTING1, "--target", "ros2", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    files = tree(out)
    assert "listing1/package.xml" in files and "listing1/msg/Message1.msg" in files
    assert all(b"iface-text-hash: " in data for data in files.values())
    assert proc.stderr.count("wrote ") == len(files)
    again = run_cli("generate", LISTING1, "--target", "ros2", "--out", str(out))
    assert again.returncode == 0 and tree(out) == files
    assert "0 written" in again.stderr


def test_quiet_prints_nothing(tmp_path: Path) -> None:
    proc = run_cli("generate", LISTING1, "-t", "ros2", "-o", str(tmp_path), "-q")
    assert proc.returncode == 0 and proc.stdout == "" and proc.stderr == ""


def test_dry_run_lists_and_writes_nothing(tmp_path: Path) -> None:
    out = tmp_path / "out"
    proc = run_cli("generate", LISTING1, "-t", "idl", "-o", str(out), "--dry-run")
    assert proc.returncode == 0
    assert "would write: " in proc.stdout and "Message1.idl" in proc.stdout
    assert not out.exists()


def test_check_is_0_when_up_to_date_and_1_otherwise(tmp_path: Path) -> None:
    assert run_cli("generate", LISTING1, "-t", "ros2", "-o", str(tmp_path), "--check").returncode == 1
    assert run_cli("generate", LISTING1, "-t", "ros2", "-o", str(tmp_path), "-q").returncode == 0
    current = run_cli("generate", LISTING1, "-t", "ros2", "-o", str(tmp_path), "--check")
    written = sorted(p for p in tmp_path.rglob("*") if p.is_file())
    assert current.returncode == 0 and current.stdout == f"ok: {len(written)} files up to date\n", current.stdout
    quiet = run_cli("generate", LISTING1, "-t", "ros2", "-o", str(tmp_path), "--check", "-q")
    assert quiet.returncode == 0 and quiet.stdout == "" and quiet.stderr == ""
    (tmp_path / "listing1/msg/Message1.msg").write_text("changed\n")
    proc = run_cli("generate", LISTING1, "-t", "ros2", "-o", str(tmp_path), "--check")
    assert proc.returncode == 1 and "Message1.msg" in proc.stdout


def test_hand_edited_file_is_kept_without_force(tmp_path: Path) -> None:
    assert run_cli("generate", LISTING1, "-t", "ros2", "-o", str(tmp_path), "-q").returncode == 0
    target = tmp_path / "listing1/msg/Message1.msg"
    edited = target.read_text() + "int32 added_by_hand\n"
    target.write_text(edited)
    proc = run_cli("generate", LISTING1, "-t", "ros2", "-o", str(tmp_path))
    assert proc.returncode == 1 and "edited by hand" in proc.stderr
    assert target.read_text() == edited
    proc = run_cli("generate", LISTING1, "-t", "ros2", "-o", str(tmp_path), "--force", "-q")
    assert proc.returncode == 0 and "added_by_hand" not in target.read_text()


def test_input_errors_exit_1_and_write_nothing(tmp_path: Path) -> None:
    bad = tmp_path / "bad.iface"
    bad.write_text("message M { unknown_t x }\n")
    out = tmp_path / "out"
    proc = run_cli("generate", str(bad), "-t", "ros2", "-o", str(out))
    assert proc.returncode == 1 and "error[unknown-type]" in proc.stdout
    assert not out.exists()


def test_target_errors_exit_1_and_write_nothing(tmp_path: Path) -> None:
    bad = tmp_path / "hash.iface"
    bad.write_text('message M { string s = "a#b" }\n')
    out = tmp_path / "out"
    proc = run_cli("generate", str(bad), "-t", "ros2", "-o", str(out))
    assert proc.returncode == 1 and "hash.iface:1:" in proc.stdout and "error[ros2-hash-in-string]" in proc.stdout
    assert not out.exists()


def test_usage_errors_exit_2(tmp_path: Path) -> None:
    assert run_cli("generate", LISTING1, "-t", "no-such-target", "-o", str(tmp_path)).returncode == 2
    assert run_cli("generate", str(tmp_path / "missing.iface"), "-t", "ros2").returncode == 2
    assert run_cli("generate", LISTING1, "-t", "ros2", "--check", "--dry-run").returncode == 2
    afile = tmp_path / "file"
    afile.write_text("x")
    assert run_cli("generate", LISTING1, "-t", "ros2", "-o", str(afile)).returncode == 2


def test_names_never_write_outside_the_output_folder(tmp_path: Path) -> None:
    src = tmp_path / "in"
    src.mkdir()
    evil = src / "evil.iface"
    evil.write_text('namespace ros2 "../../escaped"\ncomponent x\nmessage M { i32 a }\n'
                    'configuration p { string s = "../../x" }\n')
    out = tmp_path / "deep" / "out"
    proc = run_cli("generate", str(evil), "-t", "ros2", "-o", str(out))
    assert proc.returncode == 1 and "ros-name-invalid" in proc.stdout
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["evil.iface", "in"]


def test_template_override_option(tmp_path: Path) -> None:
    templates = tmp_path / "templates"
    templates.mkdir()
    (templates / "package.xml.j2").write_text("<!-- {{ header }} -->\n<package format=\"3\"/>\n")
    out = tmp_path / "out"
    proc = run_cli("generate", LISTING1, "-t", "ros2", "-o", str(out), "--templates", str(templates), "-q")
    assert proc.returncode == 0, proc.stderr
    assert (out / "listing1/package.xml").read_text().endswith('<package format="3"/>\n')


def test_every_target_generates_the_robot_arm(tmp_path: Path) -> None:
    proc = run_cli("targets")
    names = [line.split()[0] for line in proc.stdout.splitlines() if line.strip()]
    assert {"ros2", "idl"} <= set(names)
    for name in names:
        # the launch target writes a system's launch file: it takes the living room, a system of components
        source = CASES["robot_arm"].parent / "living_room.iface" if name == "launch" else CASES["robot_arm"]
        result = generate(compile_file(source), name)
        assert not result.has_errors, (name, [d.format() for d in result.diagnostics])
        assert result.files


def test_a_package_split_over_two_files_generates_in_one_command(tmp_path: Path) -> None:
    """The ROS 2 importer puts a message and an action of one name into two files of one package."""
    pkg = tmp_path / "dock_msgs"
    (pkg / "msg").mkdir(parents=True)
    (pkg / "action").mkdir()
    (pkg / "msg" / "Dock.msg").write_text("int32 id\n")
    (pkg / "action" / "Dock.action").write_text("int32 goal\n---\nbool ok\n---\nfloat32 progress\n")
    assert run_cli("import", "--from", "ros2", str(pkg), "--out", str(tmp_path / "ifc")).returncode == 0
    inputs = sorted(str(p) for p in (tmp_path / "ifc").glob("*.iface"))
    assert len(inputs) == 2
    r = run_cli("generate", *inputs, "--target", "ros2", "--out", str(tmp_path / "gen"))
    assert r.returncode == 0, r.stderr
    cmake = (tmp_path / "gen" / "dock_msgs" / "CMakeLists.txt").read_text()
    assert '"msg/Dock.msg"' in cmake and '"action/Dock.action"' in cmake


def _as_the_previous_release_wrote(path: Path) -> None:
    """Stamp ``path`` as iface did before the edit guard was named ``iface-text-hash``: ``(iface-hash: …)``."""
    from iface.emit.base import GENERATED_MARK, content_hash
    from iface.emit.write import unstamp

    body, digest = unstamp(path.read_text(encoding="utf-8"))
    assert digest is not None
    path.write_text(body.replace(GENERATED_MARK, f"{GENERATED_MARK} (iface-hash: {content_hash(body)})", 1),
                    encoding="utf-8")


def test_a_file_the_previous_release_generated_is_still_iface_s_own(tmp_path: Path) -> None:
    """Its header says ``iface-hash``: it is regenerated (with the new name), not refused as the user's; an old
    file edited by hand is still refused as edited."""
    assert run_cli("generate", LISTING1, "-t", "ros2", "-o", str(tmp_path), "-q").returncode == 0
    files = sorted(p for p in tmp_path.rglob("*") if p.is_file())
    for path in files:
        _as_the_previous_release_wrote(path)
    assert all(b"(iface-hash: " in p.read_bytes() for p in files)
    again = run_cli("generate", LISTING1, "-t", "ros2", "-o", str(tmp_path))
    assert again.returncode == 0, again.stderr
    assert "not written by iface" not in again.stderr and "edited by hand" not in again.stderr
    assert f"{len(files)} written, 0 unchanged" in again.stderr
    assert all(b"(iface-text-hash: " in p.read_bytes() for p in files)
    target = tmp_path / "listing1/msg/Message1.msg"
    _as_the_previous_release_wrote(target)
    target.write_text(target.read_text() + "int32 added_by_hand\n")
    refused = run_cli("generate", LISTING1, "-t", "ros2", "-o", str(tmp_path))
    assert refused.returncode == 1 and "Message1.msg was edited by hand" in refused.stderr
