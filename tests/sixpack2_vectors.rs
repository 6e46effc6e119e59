//! The SIXpack 2 manual's worked frames (tests/data/sixpack2-vectors.json):
//! every consistent one is a test of the encoder, both ways (the manual's
//! SQPack line parses to its own bytes, and the mnemonic line with the
//! stated values encodes to them). The two misprints (§5.5.3.3, §5.6.2.1,
//! digest D11 E2 and E4) are never taken as vectors: their corrected frames
//! are, and the printed ones are checked to say something else than the
//! manual states.

use axterm::protocol::sixpack2::{Command, Request, parse_line, to_hex};
use serde_json::Value;

struct Vector {
    section: String,
    frame: String,
    consistent: bool,
    corrected: Option<String>,
}

fn vectors() -> Vec<Vector> {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/sixpack2-vectors.json"
    ))
    .expect("the vectors file");
    let entries: Vec<Value> = serde_json::from_str(&text).expect("JSON");
    entries
        .iter()
        .map(|e| Vector {
            section: e["section"].as_str().expect("section").to_string(),
            frame: e["frame_hex"].as_str().expect("frame").to_string(),
            consistent: e["consistent"].as_bool().expect("consistent"),
            corrected: e["corrected_frame_hex"].as_str().map(str::to_string),
        })
        .collect()
}

/// `00 15 …` as the manual's macro line, `SendToPack($00, $15, …)`.
fn send_to_pack(hex: &str) -> String {
    let values: Vec<String> = hex.split(' ').map(|b| format!("${b}")).collect();
    format!("SendToPack({})", values.join(", "))
}

fn encode(line: &str) -> String {
    let parsed = parse_line(line, None).unwrap_or_else(|e| panic!("{line}: {e}"));
    to_hex(&parsed.request.to_bytes())
}

/// The mnemonic line of each frame, written from the values the manual
/// states for it (not from the bytes).
fn stated_line(section: &str, frame: &str) -> &'static str {
    match (section, frame) {
        ("5.5.3.2", "00 15 00 10 27 00 00 10 04") => "SetMotorParameters 0 10000 NullLeft,MechRef",
        ("5.5.3.2", "00 22 00 00 00 00 00 00 00") => "StartReferenceSearch 0",
        ("5.5.3.3", _) => "SetMotorParameters 0 33333 NullLeft,NullPositive",
        ("5.5.3.4", _) => "SetMotorParameters 0 500000 NullLeft,StopNull,NullPositive",
        ("5.6.2.1", _) => "SetVMinVStart 2 5 100 2",
        ("5.6.2.2", _) => "SetAMaxVMax 3 200 400",
        _ => panic!("no stated values for §{section} {frame}"),
    }
}

#[test]
fn every_consistent_frame_is_what_its_stated_values_encode_to() {
    let vectors = vectors();
    assert_eq!(vectors.len(), 6);
    let mut checked = 0;
    for vector in vectors.iter().filter(|v| v.consistent) {
        let stated = stated_line(&vector.section, &vector.frame);
        assert_eq!(encode(stated), vector.frame, "§{} {stated}", vector.section);
        // The manual's SQPack line gives its own bytes, and reads back as
        // the stated command.
        let macro_line = send_to_pack(&vector.frame);
        assert_eq!(encode(&macro_line), vector.frame, "§{}", vector.section);
        let parsed = parse_line(&macro_line, None).expect("parses");
        assert_eq!(parsed.canonical(), stated, "§{}", vector.section);
        checked += 1;
    }
    assert_eq!(checked, 4);
}

#[test]
fn the_misprints_are_never_vectors_their_corrected_frames_are() {
    let misprints: Vec<Vector> = vectors().into_iter().filter(|v| !v.consistent).collect();
    let sections: Vec<&str> = misprints.iter().map(|v| v.section.as_str()).collect();
    assert_eq!(sections, ["5.5.3.3", "5.6.2.1"]);
    for vector in &misprints {
        let stated = stated_line(&vector.section, &vector.frame);
        let corrected = vector.corrected.as_deref().expect("a corrected frame");
        assert_eq!(encode(stated), corrected, "§{} {stated}", vector.section);
        assert_ne!(
            encode(stated),
            vector.frame,
            "§{}: the misprint",
            vector.section
        );
    }
    // What the printed bytes really say (E2, E4): not the stated values.
    let printed = parse_line(&send_to_pack("00 15 00 20 A1 07 00 10 40"), None).expect("parses");
    assert_eq!(
        printed.canonical(),
        "SetMotorParameters 0 500000 NullLeft,NullPositive",
        "§5.5.3.3 prints §5.5.3.4's poslimit"
    );
    let printed = parse_line(&send_to_pack("00 13 02 0A 00 0A 00 02 00"), None).expect("parses");
    assert_eq!(
        printed.canonical(),
        "SetVMinVStart 2 10 10 2",
        "§5.6.2.1 prints vmin = vstart = 10"
    );
}

#[test]
fn the_vectors_decoded_fields_match_the_command_read_from_the_bytes() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/sixpack2-vectors.json"
    ))
    .expect("the vectors file");
    let entries: Vec<Value> = serde_json::from_str(&text).expect("JSON");
    for entry in &entries {
        let frame = entry["frame_hex"].as_str().expect("frame");
        let bytes: Vec<u8> = frame
            .split(' ')
            .map(|b| u8::from_str_radix(b, 16).expect("hex"))
            .collect();
        let request = Request::from_bytes(&bytes).expect("9 bytes");
        let command = Command::from_request(&request)
            .expect("in range")
            .expect("documented");
        let decoded = &entry["decoded"];
        assert_eq!(
            i64::from(request.address),
            decoded["address"].as_i64().expect("address")
        );
        assert_eq!(
            format!("${:02X}", request.command),
            decoded["cmd"].as_str().expect("cmd")
        );
        for (key, value) in decoded.as_object().expect("fields") {
            let name = match key.as_str() {
                "motno" | "poslimit" | "vmin" | "vstart" | "div" | "amax" | "vmax" => key.as_str(),
                "motor_type_word" => "flags",
                _ => continue,
            };
            let expected = match value {
                Value::String(hex) => {
                    i64::from_str_radix(hex.trim_start_matches('$'), 16).expect("hex")
                }
                other => other.as_i64().expect("a number"),
            };
            assert_eq!(command.value(name), Some(expected), "{frame} {name}");
        }
    }
}
