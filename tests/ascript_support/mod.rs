//! The CMD-4CR manual's A-Script example programs (§5.4), as the vectors
//! file holds them.
#![allow(dead_code)]

/// The example program of manual section `section` from the vectors.
pub fn example(section: &str) -> String {
    let vectors: serde_json::Value =
        serde_json::from_str(include_str!("../data/cmd4cr-vectors.json")).expect("vectors");
    vectors
        .as_array()
        .expect("array")
        .iter()
        .find(|e| e["section"] == section && e["program"].is_string())
        .and_then(|e| e["program"].as_str())
        .unwrap_or_else(|| panic!("no program for {section}"))
        .to_string()
}
