//! A simulator served by the real binary (`axterm sim KIND --pty`) for
//! tests of the front ends over a real pseudo-terminal: started, its pty
//! path read from its first line, ended (SIGTERM) when dropped. Its
//! standard input is empty (it reads input settings there) unless it is
//! started to be driven ([`Served::start_driven`]).
#![allow(dead_code)]

use std::io::{BufRead, BufReader, Write};
use std::process::{Child, ChildStderr, ChildStdin, Command, Stdio};

pub struct Served {
    child: Child,
    /// The pseudo-terminal to open as a serial port.
    pub pty: String,
    /// Its standard input and error, when started to be driven.
    stdin: Option<ChildStdin>,
    stderr: Option<BufReader<ChildStderr>>,
}

impl Served {
    /// `axterm sim KIND --pty EXTRA...`.
    pub fn start(kind: &str, extra: &[&str]) -> Served {
        Served::spawn(kind, extra, false)
    }

    /// The same, with its standard input open for input settings and its
    /// standard error read for the answers ([`Served::drive`]).
    pub fn start_driven(kind: &str, extra: &[&str]) -> Served {
        Served::spawn(kind, extra, true)
    }

    fn spawn(kind: &str, extra: &[&str], driven: bool) -> Served {
        let piped_if = |yes: bool| if yes { Stdio::piped() } else { Stdio::null() };
        let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
            .args(["sim", kind, "--pty"])
            .args(extra)
            .stdin(piped_if(driven))
            .stdout(Stdio::piped())
            .stderr(piped_if(driven))
            .spawn()
            .expect("start axterm sim");
        let stdout = child.stdout.take().expect("stdout");
        let mut first = String::new();
        BufReader::new(stdout)
            .read_line(&mut first)
            .expect("read the pty path");
        Served {
            stdin: child.stdin.take(),
            stderr: child.stderr.take().map(BufReader::new),
            child,
            pty: first.trim().to_string(),
        }
    }

    /// Type `setting` on its standard input and wait for its answer: the
    /// next line on standard error from `axterm sim: `, without that.
    pub fn drive(&mut self, setting: &str) -> String {
        self.type_line(setting);
        self.next_answer()
    }

    /// Type `line` on its standard input, without waiting for an answer.
    pub fn type_line(&mut self, line: &str) {
        let stdin = self.stdin.as_mut().expect("started to be driven");
        writeln!(stdin, "{line}").expect("write a setting");
        stdin.flush().expect("flush the setting");
    }

    /// The next line on standard error from `axterm sim: `, without that
    /// (the answers to `--input` come before any typed setting's).
    pub fn next_answer(&mut self) -> String {
        let stderr = self.stderr.as_mut().expect("started to be driven");
        loop {
            let mut line = String::new();
            let n = stderr.read_line(&mut line).expect("read standard error");
            assert!(n > 0, "axterm sim ended without answering");
            if let Some(answer) = line.trim_end().strip_prefix("axterm sim: ") {
                return answer.to_string();
            }
        }
    }

    /// The next line on standard error, whatever it is (none at its end).
    pub fn next_stderr_line(&mut self) -> Option<String> {
        let stderr = self.stderr.as_mut().expect("started to be driven");
        let mut line = String::new();
        let n = stderr.read_line(&mut line).expect("read standard error");
        (n > 0).then(|| line.trim_end().to_string())
    }

    /// Close its standard input: the end of the settings.
    pub fn end_input(&mut self) {
        self.stdin = None;
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        if let Ok(pid) = libc::pid_t::try_from(self.child.id()) {
            // SAFETY: a signal to our own child process; nothing is shared.
            unsafe {
                libc::kill(pid, libc::SIGTERM);
            }
        }
        let _ = self.child.wait();
    }
}
