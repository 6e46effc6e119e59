//! Frame bytes as text, the way the manual and the traffic monitor show
//! them: upper-case hex bytes separated by single spaces.

/// `[0x01, 0xF4]` → `"01 F4"`.
pub fn to_hex(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len() * 3);
    for (i, b) in bytes.iter().enumerate() {
        if i > 0 {
            out.push(' ');
        }
        out.push_str(&format!("{b:02X}"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_are_upper_case_and_space_separated() {
        assert_eq!(to_hex(&[0x01, 0x01, 0x00, 0xF4, 0xF7]), "01 01 00 F4 F7");
        assert_eq!(to_hex(&[]), "");
        assert_eq!(to_hex(&[0x0a]), "0A");
    }
}
