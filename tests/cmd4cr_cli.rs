//! The CMD-4CR through the command-line front ends: `axterm encode cmd4cr`
//! prints the exact bytes in escaped form, and `axterm exec --protocol
//! cmd4cr --tcp …` talks to a controller — here a scripted fake that
//! answers the lines it expects, over a real TCP connection.

mod cli_support;

use cli_support::{axterm, stderr, stdout};
use std::io::{BufRead, BufReader, Write};
use std::net::TcpListener;
use std::thread::JoinHandle;

#[test]
fn encode_prints_the_frame_escaped() {
    let out = axterm(&["encode", "cmd4cr", "PX"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "@01PX\\r\n");
    let out = axterm(&["encode", "cmd4cr", "--address", "7", "hspdx = 5000"]);
    assert_eq!(stdout(&out), "@07HSPDX=5000\\r\n");
    let out = axterm(&["encode", "cmd4cr", "X-20000Y15000"]);
    assert_eq!(stdout(&out), "@01X-20000Y15000\\r\n");
}

#[test]
fn encode_refuses_what_the_controller_would_not_take() {
    let out = axterm(&["encode", "cmd4cr", "EO=16"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "");
    assert!(
        stderr(&out).contains("EO=16: EO 16 is outside 0..15"),
        "{}",
        stderr(&out)
    );
    let out = axterm(&["encode", "cmd4cr", "--address", "100", "PX"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("00..99"), "{}", stderr(&out));
    let out = axterm(&["encode", "cmd4cr", "H-1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("no axis given"), "{}", stderr(&out));
}

/// Controllers on a TCP port (a serial bus behind a bridge) that answer
/// each expected frame with its reply, and hand back every frame received.
struct Fake {
    address: String,
    thread: JoinHandle<Vec<String>>,
}

impl Fake {
    fn start(script: &[(&str, &str)]) -> Fake {
        let listener = TcpListener::bind("127.0.0.1:0").expect("a free port");
        let address = listener.local_addr().expect("bound").to_string();
        let script: Vec<(String, String)> = script
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect();
        let thread = std::thread::spawn(move || {
            let mut received = Vec::new();
            let Ok((stream, _)) = listener.accept() else {
                return received;
            };
            let mut writer = stream.try_clone().expect("clone");
            let mut reader = BufReader::new(stream);
            let mut frame = Vec::new();
            while matches!(reader.read_until(b'\r', &mut frame), Ok(n) if n > 0) {
                let text = String::from_utf8_lossy(&frame)
                    .trim_end_matches('\r')
                    .to_string();
                frame.clear();
                // Frames it has no answer for get none, as on a bus where
                // no controller has that ID.
                let reply = script
                    .iter()
                    .find(|(request, _)| *request == text)
                    .map(|(_, reply)| format!("{reply}\r"));
                received.push(text);
                if let Some(reply) = reply
                    && writer.write_all(reply.as_bytes()).is_err()
                {
                    break;
                }
            }
            received
        });
        Fake { address, thread }
    }

    fn received(self) -> Vec<String> {
        self.thread.join().expect("the fake")
    }
}

#[test]
fn exec_talks_to_a_controller_at_its_id() {
    let fake = Fake::start(&[
        ("@03HSPDX=5000", "OK"),
        ("@03HSPDX", "5000"),
        ("@03PP", "0:10:-20:30"),
        ("@03VER", "V126BL"),
    ]);
    let out = axterm(&[
        "exec",
        "--tcp",
        &fake.address,
        "--protocol",
        "cmd4cr",
        "--address",
        "3",
        "hspdx=5000",
        "HSPDX",
        "PP",
        "VER",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "ok\n5000\n0:10:-20:30\nV126BL\n");
    assert_eq!(
        fake.received(),
        ["@03HSPDX=5000", "@03HSPDX", "@03PP", "@03VER"]
    );
}

#[test]
fn an_error_reply_stops_the_run_with_its_meaning() {
    let fake = Fake::start(&[("@01EO=3", "OK"), ("@01X1000", "?Error Moving")]);
    let out = axterm(&[
        "exec",
        "--tcp",
        &fake.address,
        "--protocol",
        "cmd4cr",
        "EO=3",
        "X1000",
        "Y5",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(stdout(&out), "ok\n");
    assert_eq!(
        stderr(&out),
        "axterm exec: line 2: controller 01 refused X1000: ?Error Moving (the move command \
         could not be processed: one or more of the required axes may be in error state or \
         in motion)\n"
    );
    assert_eq!(fake.received(), ["@01EO=3", "@01X1000"], "Y5 never sent");
}

#[test]
fn a_line_that_does_not_parse_sends_nothing() {
    let fake = Fake::start(&[]);
    let out = axterm(&[
        "exec",
        "--tcp",
        &fake.address,
        "--protocol",
        "cmd4cr",
        "PX",
        "SYNO",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains("line 2 `SYNO`: SYNO: SYNO needs an axis letter"),
        "{err}"
    );
    assert!(err.contains("nothing was sent"), "{err}");
    // Nothing connected: unblock the fake's accept.
    drop(std::net::TcpStream::connect(&fake.address));
    assert!(fake.received().is_empty());
}

#[test]
fn json_shows_the_frames_escaped() {
    let fake = Fake::start(&[("@01MSTX", "2")]);
    let out = axterm(&[
        "exec",
        "--tcp",
        &fake.address,
        "--protocol",
        "cmd4cr",
        "--format",
        "json",
        "mstx",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let object: serde_json::Value = serde_json::from_str(stdout(&out).trim()).expect("JSON");
    assert_eq!(object["command"], "MSTX");
    assert_eq!(object["request"], "@01MSTX\\r");
    assert_eq!(object["reply"], "2");
    assert_eq!(object["value"], 2);
    assert_eq!(object["status"], serde_json::Value::Null);
    drop(fake.received());
}

#[test]
fn scan_asks_every_id_of_the_family_and_only_those() {
    let fake = Fake::start(&[("@02VER", "V126BL")]);
    let out = axterm(&[
        "scan",
        "--tcp",
        &fake.address,
        "--protocol",
        "cmd4cr",
        "--addresses",
        "1-3",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "address 2: V126BL\n");
    assert_eq!(fake.received(), ["@01VER", "@02VER", "@03VER"]);
    // IDs are two digits: `@100VER` would be controller 10's `0VER`.
    let out = axterm(&[
        "scan",
        "--tcp",
        "127.0.0.1:1",
        "--protocol",
        "cmd4cr",
        "--addresses",
        "98-100",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("address 100 is outside 0..99"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn an_id_above_99_is_a_usage_error_before_connecting() {
    let out = axterm(&[
        "exec",
        "--tcp",
        "127.0.0.1:1",
        "--protocol",
        "cmd4cr",
        "--address",
        "100",
        "PX",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("--address 100 is outside 0..99, the addresses of the cmd4cr family"),
        "{}",
        stderr(&out)
    );
}
