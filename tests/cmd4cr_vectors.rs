//! Every command exchange printed in the CMD-4CR manual
//! (tests/data/cmd4cr-vectors.json): the text parses and frames to exactly
//! the bytes the manual sends, and the three replies it prints read as it
//! says. Where the manual misprints a command (the entry's
//! `likely_intended`, digest §10), the intended command is the vector; the
//! misprint itself is only checked to be refused with a reason when it is
//! not a valid command at all (`H-1` has no axis).

use axterm::protocol::cmd4cr::{
    Answer, CommandError, encode, parse_answer, parse_command, parse_request,
};
use serde_json::Value;

struct Vector {
    section: String,
    send: String,
    reply: Option<String>,
    likely_intended: Option<String>,
}

fn vectors() -> Vec<Vector> {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/cmd4cr-vectors.json"
    ))
    .expect("the vectors file");
    let entries: Vec<Value> = serde_json::from_str(&text).expect("JSON");
    entries
        .iter()
        .filter_map(|e| {
            let text = |key: &str| e.get(key).and_then(Value::as_str).map(str::to_string);
            Some(Vector {
                section: text("section")?,
                send: text("send")?,
                reply: text("reply"),
                likely_intended: text("likely_intended"),
            })
        })
        .collect()
}

/// The command text of a frame as the manual prints it (`@01PX` → `PX`).
fn command_of(frame: &str) -> String {
    let request = parse_request(frame.as_bytes()).expect("an @ID frame");
    assert_eq!(request.id, 1, "{frame}: every example talks to ID 01");
    request.text
}

#[test]
fn every_command_of_the_manual_parses_and_frames_as_printed() {
    let vectors = vectors();
    assert!(vectors.len() >= 70, "{} command vectors", vectors.len());
    for vector in &vectors {
        let sent = vector.likely_intended.as_deref().unwrap_or(&vector.send);
        let text = command_of(sent);
        let (command, bytes) =
            encode(1, &text).unwrap_or_else(|e| panic!("§{} {sent}: {e}", vector.section));
        assert_eq!(
            bytes,
            format!("{sent}\r").into_bytes(),
            "§{} {sent}",
            vector.section
        );
        assert_eq!(command.to_string(), text, "already canonical");
        // What the simulator reads from the wire is the same command.
        assert_eq!(parse_command(&command_of(sent)), Ok(command));
    }
}

#[test]
fn misprints_without_an_axis_are_refused_naming_it() {
    let mut refused = 0;
    for vector in vectors() {
        if vector.likely_intended.is_none() {
            continue;
        }
        let text = command_of(&vector.send);
        match parse_command(&text) {
            Ok(_) => {
                // §4.3.3's second `PX=0` is a valid command, just not the
                // one meant (`EX=0`): nothing to check on it.
            }
            Err(error) => {
                refused += 1;
                let message = error.to_string();
                assert!(
                    matches!(
                        error,
                        CommandError::MissingAxis { .. } | CommandError::Syntax { .. }
                    ),
                    "{text}: {message}"
                );
                assert!(
                    message.contains("axis") && message.contains(&text),
                    "{text}: {message}"
                );
            }
        }
    }
    // H-1, SSPDM=2, SSPD=70000, SYNO.
    assert_eq!(refused, 4);
}

#[test]
fn the_three_printed_replies_read_as_the_manual_says() {
    let replies: Vec<(String, String)> = vectors()
        .into_iter()
        .filter_map(|v| Some((command_of(&v.send), v.reply?)))
        .collect();
    assert_eq!(replies.len(), 3);
    for (text, reply) in replies {
        let command = parse_command(&text).expect("valid");
        let answer = parse_answer(&reply, command.reply_format()).expect("a success");
        let expected = match text.as_str() {
            // §3.2.2: the X polarity word 7.
            "POLX" => Answer::Integer(7),
            // §3.2.2: DI4 on, bit 3.
            "DI" => Answer::Integer(8),
            // §3.2.2: stored.
            "STORE" => Answer::Done("OK".into()),
            other => panic!("unexpected reply vector {other}"),
        };
        assert_eq!(answer, expected, "{text} → {reply}");
    }
}
