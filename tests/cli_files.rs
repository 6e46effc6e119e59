//! The files `axterm` reads and writes, as a script sees them: input files
//! that are not regular files (a device that never ends, a FIFO that would
//! wait for a writer) or that are too big are refused with the file's name
//! and the reason, standard input is capped the same way, a binary
//! `#include` is not quoted back, and `axterm sim --eeprom` refuses a file
//! that is not its own and leaves it as it was.
//!
//! A run that would read without end is given a memory limit (`ulimit -v`),
//! so that without the checks it fails quickly instead of filling memory.

mod cli_support;
mod fifo_support;

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Output, Stdio};

use cli_support::{axterm, stderr, stdout};
use fifo_support::Fifo;

/// More than `axterm` needs, far less than reading `/dev/zero` to its end.
const MEMORY_LIMIT_KIB: u32 = 512 * 1024;

/// `axterm ARGS` with at most [`MEMORY_LIMIT_KIB`] of memory and `stdin`.
fn axterm_limited(args: &[&str], stdin: Stdio) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {MEMORY_LIMIT_KIB} && exec \"$0\" \"$@\""
        ))
        .arg(env!("CARGO_BIN_EXE_axterm"))
        .args(args)
        .stdin(stdin)
        .output()
        .expect("run axterm")
}

fn path_text(path: &Path) -> String {
    path.to_string_lossy().into_owned()
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write");
    path_text(&path)
}

fn assert_refused(out: &Output, expected: &str) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(stdout(out), "");
    assert!(err.contains(expected), "expected `{expected}` in:\n{err}");
}

#[test]
fn a_device_is_refused_as_source_batch_and_include() {
    let out = axterm_limited(&["asm", "/dev/zero"], Stdio::null());
    assert_refused(
        &out,
        "axterm asm: cannot read /dev/zero: it is a character device, not a regular file",
    );
    let out = axterm_limited(&["run", "--dry-run", "/dev/zero"], Stdio::null());
    assert_refused(
        &out,
        "axterm run: cannot read /dev/zero: it is a character device, not a regular file",
    );
    let dir = tempfile::tempdir().expect("temp dir");
    let main = write(dir.path(), "main.tmc", b"#include \"/dev/zero\"\nSTOP\n");
    let out = axterm_limited(&["asm", &main], Stdio::null());
    assert_refused(
        &out,
        &format!(
            "{main}:1:11: cannot include `/dev/zero`: it is a character device, not a regular file"
        ),
    );
}

#[test]
fn endless_standard_input_is_cut_off() {
    let zero = || Stdio::from(std::fs::File::open("/dev/zero").expect("/dev/zero"));
    let out = axterm_limited(&["run", "--dry-run", "-"], zero());
    assert_refused(
        &out,
        "axterm run: cannot read standard input: it is larger than 16 MiB",
    );
    let out = axterm_limited(&["asm", "-"], zero());
    assert_refused(
        &out,
        "axterm asm: cannot read standard input: it is larger than 16 MiB",
    );
}

#[test]
fn a_file_over_16_mib_is_refused_with_its_size() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("huge.txt");
    // Sparse: it takes no room on the disk.
    let file = std::fs::File::create(&path).expect("create");
    file.set_len(16 * 1024 * 1024 + 1).expect("grow");
    let name = path_text(&path);
    for (command, args) in [
        ("asm", vec!["asm", name.as_str()]),
        ("run", vec!["run", "--dry-run", name.as_str()]),
    ] {
        let out = axterm_limited(&args, Stdio::null());
        assert_refused(
            &out,
            &format!(
                "axterm {command}: cannot read {name}: it is larger than 16 MiB (16777217 bytes)"
            ),
        );
    }
}

#[test]
fn a_fifo_is_refused_without_waiting_for_a_writer() {
    // A writer stands ready, so that reading the FIFO would succeed (and
    // exit 0): only the refusal gives exit 2.
    let dir = tempfile::tempdir().expect("temp dir");
    let fifo = Fifo::new(dir.path().join("program.tmc"), "STOP\n");
    let name = path_text(&fifo.path);
    let out = axterm(&["asm", &name]);
    assert_refused(
        &out,
        &format!("axterm asm: cannot read {name}: it is a FIFO (named pipe), not a regular file"),
    );
    drop(fifo);

    let fifo = Fifo::new(dir.path().join("batch.txt"), "GAP 1, 0\n");
    let name = path_text(&fifo.path);
    let out = axterm(&["run", "--dry-run", &name]);
    assert_refused(
        &out,
        &format!("axterm run: cannot read {name}: it is a FIFO (named pipe), not a regular file"),
    );
    drop(fifo);

    let fifo = Fifo::new(dir.path().join("sub.inc"), "STOP\n");
    let main = write(dir.path(), "main.tmc", b"#include sub.inc\n");
    let out = axterm(&["asm", &main]);
    assert_refused(&out, "cannot include `");
    assert!(
        stderr(&out).contains("sub.inc`: it is a FIFO (named pipe), not a regular file"),
        "{}",
        stderr(&out)
    );
    drop(fifo);
}

#[test]
fn an_included_binary_file_is_refused_without_quoting_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Valid UTF-8, but a binary file: its first "line" must not be shown.
    write(
        dir.path(),
        "blob.bin",
        b"PRIVATE_FIRST_LINE\n\x00\x00\x01\x02\x03 binary\n",
    );
    let main = write(dir.path(), "main.tmc", b"STOP\n#include blob.bin\n");
    let out = axterm(&["asm", &main]);
    assert_refused(
        &out,
        "blob.bin`: not a text file: byte 19 is the control byte 0x00 (a binary file?)",
    );
    assert!(
        !stderr(&out).contains("PRIVATE_FIRST_LINE"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_regular_file_and_standard_input_still_work() {
    let dir = tempfile::tempdir().expect("temp dir");
    let main = write(dir.path(), "main.tmc", b"#include sub.inc\n");
    write(dir.path(), "sub.inc", b"STOP\n");
    let out = axterm(&["asm", &main]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stdout(&out).ends_with("1C 00 00 00 00 00 00  // 0\n"),
        "{}",
        stdout(&out)
    );
    let out = cli_support::axterm_stdin(&["run", "--dry-run", "-"], "GAP 1, 0\n");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

// ---- axterm sim --eeprom ----------------------------------------------------

/// `axterm sim KIND --pty --eeprom FILE`: its first line on standard
/// output (the pty, if it serves), then it is stopped; its exit code.
fn sim_with_memory_file(kind: &str, file: &str) -> (String, Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["sim", kind, "--pty", "--eeprom", file])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start axterm sim");
    let mut first = String::new();
    BufReader::new(child.stdout.take().expect("stdout"))
        .read_line(&mut first)
        .expect("read standard output");
    if !first.is_empty()
        && let Ok(pid) = libc::pid_t::try_from(child.id())
    {
        // It serves: stop it as a user would.
        // SAFETY: a signal to our own child process.
        unsafe {
            libc::kill(pid, libc::SIGTERM);
        }
    }
    let out = child.wait_with_output().expect("wait for axterm sim");
    (first, out.status.code(), stderr(&out))
}

/// 300 KB that are no simulator's memory file.
fn unrelated_binary() -> Vec<u8> {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    (0..300_000)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state.to_le_bytes()[0]
        })
        .collect()
}

#[test]
fn sim_refuses_a_file_that_is_not_its_memory_and_leaves_it_alone() {
    let dir = tempfile::tempdir().expect("temp dir");
    let binary = unrelated_binary();
    let foreign_json = br#"{"format": "axterm TMCM-1110 simulated EEPROM", "version": 1, "axis_parameters": {}, "global_parameters": {}, "user_variables": [], "coordinates": [], "program": []}"#;
    let notes = b"Commissioning notes\nline 2: axis X\n";
    for (kind, name, bytes, reason) in [
        ("tmcm1110", "firmware.bin", &binary[..], "not a text file"),
        ("cmd4cr", "firmware.bin", &binary[..], "not a text file"),
        ("mccl-eth", "firmware.bin", &binary[..], "not a text file"),
        ("mccl-eth", "stepRocker.json", &foreign_json[..], "macro"),
        (
            "cmd4cr",
            "stepRocker.json",
            &foreign_json[..],
            "is not a simulated flash file of this simulator",
        ),
        (
            "tmcm1110",
            "notes.txt",
            &notes[..],
            "is not a simulated EEPROM file of this simulator",
        ),
    ] {
        let file = write(dir.path(), name, bytes);
        let (first, code, err) = sim_with_memory_file(kind, &file);
        assert_eq!(first, "", "{kind} served on {file}: {err}");
        assert_eq!(code, Some(2), "{kind}: {err}");
        assert!(err.contains(&file), "{kind}: {err}");
        assert!(err.contains(reason), "{kind}: {err}");
        assert!(err.contains("nothing is served"), "{kind}: {err}");
        assert_eq!(
            std::fs::read(&file).expect("read"),
            bytes,
            "{kind} changed {file}"
        );
    }
}

#[test]
fn sim_takes_a_new_name_or_an_empty_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    for kind in ["tmcm1110", "cmd4cr", "mccl-eth"] {
        let empty = write(dir.path(), &format!("{kind}-empty.json"), b"");
        let new = path_text(&dir.path().join(format!("{kind}-new.json")));
        for file in [empty, new] {
            let (first, _, err) = sim_with_memory_file(kind, &file);
            assert!(first.starts_with("/dev/"), "{kind} on {file}: {err}");
        }
    }
}
