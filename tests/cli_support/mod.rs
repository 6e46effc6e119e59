//! The real `axterm` binary run once by a test: its exit code, standard
//! output and standard error.
#![allow(dead_code)]

use std::io::Write;
use std::process::{Command, Output, Stdio};

/// Run `axterm ARGS` to its end, with no standard input.
pub fn axterm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(args)
        .output()
        .expect("run axterm")
}

/// Run `axterm ARGS` to its end with `input` on its standard input.
pub fn axterm_stdin(args: &[&str], input: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run axterm");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(input.as_bytes())
        .expect("write stdin");
    child.wait_with_output().expect("wait for axterm")
}

pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Send `signal` to `child` (an `axterm` this test started with a piped
/// standard error), wait for it to end, and return its exit status and
/// what it said on standard error.
pub fn signal_and_wait(
    child: &mut std::process::Child,
    signal: i32,
) -> (std::process::ExitStatus, String) {
    use std::io::Read;
    let pid = libc::pid_t::try_from(child.id()).expect("pid");
    // SAFETY: a signal to our own child process; nothing is shared.
    unsafe {
        libc::kill(pid, signal);
    }
    let status = child.wait().expect("wait");
    let mut err = String::new();
    child
        .stderr
        .take()
        .expect("stderr")
        .read_to_string(&mut err)
        .expect("stderr text");
    (status, err)
}
