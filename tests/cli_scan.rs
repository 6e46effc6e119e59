//! `axterm scan` finds the modules on a bus by their firmware version.

mod cli_support;

use cli_support::{axterm, stderr, stdout};
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

/// `axterm sim … --pty` running, with the path it announced.
struct Served {
    child: Child,
    path: String,
}

impl Served {
    fn start(args: &[&str]) -> Served {
        let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start axterm sim");
        let mut first_line = String::new();
        BufReader::new(child.stdout.take().expect("stdout"))
            .read_line(&mut first_line)
            .expect("read the pty path");
        Served {
            child,
            path: first_line.trim().to_string(),
        }
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn scan_finds_a_served_simulator_at_its_address() {
    let served = Served::start(&["sim", "tmcm1110", "--pty", "--address", "7"]);
    let out = axterm(&["scan", "--port", &served.path, "--addresses", "6-8"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "address 7: 1110V112\n");
    assert!(
        stderr(&out).contains("1 module found at 3 addresses"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn scan_finds_an_in_process_simulator() {
    let out = axterm(&[
        "scan",
        "--sim",
        "tmcm1110",
        "--address",
        "4",
        "--addresses",
        "3,4",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "address 4: 1110V112\n");
}

#[test]
fn an_empty_range_exits_1() {
    let out = axterm(&["scan", "--sim", "tmcm1110", "--addresses", "2-3"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert_eq!(stdout(&out), "");
    assert!(stderr(&out).contains("0 modules found"), "{}", stderr(&out));
}

#[test]
fn a_bad_address_list_is_a_usage_error() {
    let out = axterm(&["scan", "--sim", "tmcm1110", "--addresses", "9-2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("backwards"), "{}", stderr(&out));
}
