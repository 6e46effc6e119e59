//! The SIXpack 2 through the command-line front ends: `axterm encode
//! sixpack2` prints the 9 bytes of a line, and `axterm exec`/`axterm run
//! --protocol sixpack2 --tcp …` talk to a unit — here a scripted fake that
//! reads 9-byte frames and answers the ones it expects with the bytes
//! written out by hand from §7, over a real TCP connection.

mod cli_support;

use cli_support::{axterm, stderr, stdout};
use std::io::{Read, Write};
use std::net::TcpListener;
use std::thread::JoinHandle;

#[test]
fn encode_prints_the_nine_bytes() {
    let out = axterm(&["encode", "sixpack2", "StartRamp 0 10000"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "00 23 00 10 27 00 00 00 00\n");
    let out = axterm(&[
        "encode",
        "sixpack2",
        "--address",
        "3",
        "SetAMaxVMax 3 200 400",
    ]);
    assert_eq!(stdout(&out), "03 14 03 C8 00 90 01 00 00\n");
}

#[test]
fn encode_prints_a_pasted_sqpack_line_as_its_own_bytes() {
    // §5.5.3.2, as printed, with its full stop.
    let out = axterm(&[
        "encode",
        "sixpack2",
        "SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04).",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "00 15 00 10 27 00 00 10 04\n");
    let out = axterm(&[
        "encode",
        "sixpack2",
        "SendToPack($00, $22, $00, $00, $00, $00, $00, $00, $00).",
    ]);
    assert_eq!(stdout(&out), "00 22 00 00 00 00 00 00 00\n");
}

#[test]
fn encode_refuses_a_bad_operand_naming_it() {
    let out = axterm(&["encode", "sixpack2", "StartRamp 6 100"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "");
    assert_eq!(
        stderr(&out),
        "axterm encode: StartRamp: motno 6 is outside 0..5 (Motor 1..6)\n"
    );
    let out = axterm(&["encode", "sixpack2", "SetAMaxVMax 0 500 2000"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("vmax 2000 is outside 1..511"),
        "{}",
        stderr(&out)
    );
    let out = axterm(&[
        "encode",
        "sixpack2",
        "--address",
        "1",
        "SendToPack($00, $22, $00, $00, $00, $00, $00, $00, $00)",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("for unit 0"), "{}", stderr(&out));
}

/// A unit on a TCP port that reads 9-byte frames and answers each one it
/// expects with its reply bytes, and hands back every frame received.
struct Fake {
    address: String,
    thread: JoinHandle<Vec<String>>,
}

fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

impl Fake {
    fn start(script: &[(&str, &[u8])]) -> Fake {
        let listener = TcpListener::bind("127.0.0.1:0").expect("a free port");
        let address = listener.local_addr().expect("bound").to_string();
        let script: Vec<(String, Vec<u8>)> = script
            .iter()
            .map(|(request, reply)| (request.to_string(), reply.to_vec()))
            .collect();
        let thread = std::thread::spawn(move || {
            let mut received = Vec::new();
            let Ok((mut stream, _)) = listener.accept() else {
                return received;
            };
            let mut frame = [0u8; 9];
            while stream.read_exact(&mut frame).is_ok() {
                let text = hex(&frame);
                // Setting commands get no answer (§7), nor do frames it
                // has no reply for.
                let reply = script
                    .iter()
                    .find(|(request, _)| *request == text)
                    .map(|(_, reply)| reply.clone());
                received.push(text);
                if let Some(reply) = reply
                    && stream.write_all(&reply).is_err()
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

    /// Unblock a fake nothing connected to.
    fn never_contacted(self) -> Vec<String> {
        drop(std::net::TcpStream::connect(&self.address));
        self.received()
    }
}

fn exec(fake: &Fake, lines: &[&str]) -> std::process::Output {
    let mut args = vec!["exec", "--tcp", &fake.address, "--protocol", "sixpack2"];
    args.extend_from_slice(lines);
    axterm(&args)
}

#[test]
fn exec_sends_settings_unanswered_and_reads_queries() {
    let fake = Fake::start(&[(
        "00 20 00 00 00 00 00 00 00",
        // §7.2 / §6.2.2.3: $20, motno 0, posact 10000, action 0, stop 0.
        &[0x20, 0x00, 0x10, 0x27, 0x00, 0x00, 0x00, 0x00],
    )]);
    let out = exec(&fake, &["StartRamp 0 10000", "GetPositionAndActivity 0"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "sent\nposact=10000 action=inactive stop=0\n");
    assert_eq!(
        fake.received(),
        ["00 23 00 10 27 00 00 00 00", "00 20 00 00 00 00 00 00 00"],
        "the factory address 0 by default"
    );
}

#[test]
fn a_late_28_between_the_bytes_is_not_taken_for_the_answer() {
    // The delayed $28 of an earlier GetAllActivities lands just before
    // the $21 answer.
    let mut burst = vec![0x28, 0, 0, 0, 0, 0, 0, 0];
    burst.extend_from_slice(&[0x21, 0x02, 0x01, 0xFE, 0x0F, 0, 0, 0]);
    let fake = Fake::start(&[("00 21 02 00 00 00 00 00 00", &burst)]);
    let out = exec(&fake, &["GetVelocityAndActivity 2"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "vact=-511 action=rotation\n");
    drop(fake.received());
}

#[test]
fn an_answer_for_another_motor_is_no_answer() {
    let fake = Fake::start(&[(
        "00 20 01 00 00 00 00 00 00",
        &[0x20, 0x02, 0, 0, 0, 0, 0, 0],
    )]);
    let out = axterm(&[
        "exec",
        "--tcp",
        &fake.address,
        "--protocol",
        "sixpack2",
        "--timeout",
        "300",
        "GetPositionAndActivity 1",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(stdout(&out), "");
    assert!(
        stderr(&out).contains("GetPositionAndActivity 1"),
        "{}",
        stderr(&out)
    );
    drop(fake.received());
}

#[test]
fn exec_refuses_a_line_to_confirm_without_yes_and_sends_nothing() {
    let fake = Fake::start(&[]);
    let out = exec(&fake, &["StartRamp 0 100", "HardwareReset"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "");
    let err = stderr(&out);
    assert!(
        err.starts_with(
            "axterm exec: line 2 `HardwareReset`: not sent without --yes: every setting is \
             replaced by the factory defaults"
        ),
        "{err}"
    );
    assert!(err.ends_with("axterm exec: nothing was sent\n"), "{err}");
    assert!(fake.never_contacted().is_empty());
}

#[test]
fn exec_sends_a_confirmed_line_with_yes() {
    let fake = Fake::start(&[]);
    let out = axterm(&[
        "exec",
        "--tcp",
        &fake.address,
        "--protocol",
        "sixpack2",
        "--yes",
        "StartReferenceSearch 0",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "sent\n");
    assert_eq!(fake.received(), ["00 22 00 00 00 00 00 00 00"]);
}

#[test]
fn warnings_go_to_stderr_and_stop_nothing() {
    let fake = Fake::start(&[]);
    let out = exec(&fake, &["SetPeakCurrent 1 100"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "sent\n");
    assert_eq!(
        stderr(&out),
        "axterm exec: line 1 `SetPeakCurrent 1 100`: warning: the peak current of motors 0 and \
         1 is set on motor 0 only: this frame for motor 1 is ignored (§7.1)\n"
    );
    assert_eq!(fake.received(), ["00 10 01 64 00 00 00 00 00"]);
}

#[test]
fn run_refuses_a_file_with_a_line_to_confirm_unless_told_yes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("homing.txt");
    // §5.5.3.2: mechanical reference of motor 0.
    std::fs::write(
        &file,
        "SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04)\n\
         SendToPack($00, $22, $00, $00, $00, $00, $00, $00, $00)\n",
    )
    .expect("write");
    let file = file.to_string_lossy().into_owned();
    let fake = Fake::start(&[]);
    let args = ["run", "--tcp", &fake.address, "--protocol", "sixpack2"];
    let mut refused = args.to_vec();
    refused.push(&file);
    let out = axterm(&refused);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.starts_with(&format!(
            "{file}:2: `StartReferenceSearch 0`: not sent without --yes: it stops the motor"
        )),
        "{err}"
    );
    assert!(err.ends_with("nothing was sent\n"), "{err}");
    let mut dry = refused.clone();
    dry.insert(1, "--dry-run");
    assert_eq!(
        axterm(&dry).status.code(),
        Some(2),
        "a dry run checks it too"
    );
    assert!(fake.never_contacted().is_empty());

    let fake = Fake::start(&[]);
    let args = [
        "run",
        "--tcp",
        &fake.address,
        "--protocol",
        "sixpack2",
        "--yes",
        &file,
    ];
    let out = axterm(&args);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "sent\nsent\n");
    let received = fake.received();
    assert_eq!(
        received.get(..2).unwrap_or_default(),
        ["00 15 00 10 27 00 00 10 04", "00 22 00 00 00 00 00 00 00"]
    );
    // Then the run reads the axes' status ($20) to stop one it would
    // leave moving; this fake never answers, which the run says.
    assert!(
        received.iter().skip(2).all(|f| f.starts_with("00 20 ")),
        "{received:?}"
    );
    assert!(
        stderr(&out).contains("cannot tell whether an axis still moves at the end of the run"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn the_reply_framing_is_a_link_option() {
    // The fake answers in the 8-byte form of §6.2.2.3 (digest D1.4, Cmd8).
    let reply: &[u8] = &[0x20, 0x00, 0x10, 0x27, 0x00, 0x00, 0x00, 0x00];
    let query = "GetPositionAndActivity 0";
    let run = |fake: &Fake, option: &str| {
        axterm(&[
            "exec",
            "--tcp",
            &fake.address,
            "--protocol",
            "sixpack2",
            "--timeout",
            "300",
            "--link-option",
            option,
            query,
        ])
    };
    let fake = Fake::start(&[("00 20 00 00 00 00 00 00 00", reply)]);
    let out = run(&fake, "framing=cmd8");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "posact=10000 action=inactive stop=0\n");
    drop(fake.received());
    let fake = Fake::start(&[("00 20 00 00 00 00 00 00 00", reply)]);
    let out = run(&fake, "framing=addr9");
    assert_eq!(
        out.status.code(),
        Some(1),
        "9-byte replies only: the 8-byte form is no answer"
    );
    drop(fake.received());
    let out = axterm(&[
        "exec",
        "--sim",
        "sixpack2",
        "--link-option",
        "framing=cmd9",
        query,
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("framing=auto|cmd8|addr9"),
        "{}",
        stderr(&out)
    );
}
