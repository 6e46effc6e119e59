//! A simulator served by the real binary (`axterm sim KIND --pty`) for
//! tests of the front ends over a real pseudo-terminal: started, its pty
//! path read from its first line, ended (SIGTERM) when dropped.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

pub struct Served {
    child: Child,
    /// The pseudo-terminal to open as a serial port.
    pub pty: String,
}

impl Served {
    /// `axterm sim KIND --pty EXTRA...`.
    pub fn start(kind: &str, extra: &[&str]) -> Served {
        let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
            .args(["sim", kind, "--pty"])
            .args(extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start axterm sim");
        let stdout = child.stdout.take().expect("stdout");
        let mut first = String::new();
        BufReader::new(stdout)
            .read_line(&mut first)
            .expect("read the pty path");
        Served {
            child,
            pty: first.trim().to_string(),
        }
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
