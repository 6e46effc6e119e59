//! Lists of module addresses as a technician writes them: `7`, `1-4`,
//! `1,3,7`, `1,5,10-20` (`--address` of every connection, `--addresses`
//! of `scan` and of the fleet commands). Pure text to numbers; whether an
//! address suits a family is the caller's question
//! ([`crate::protocol::console::FamilyConsole::addresses`]).

use std::fmt;
use std::str::FromStr;

/// A part of an address list that is not one.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum AddressError {
    #[error("`{0}` is not an address 0..255")]
    NotAnAddress(String),
    #[error("range {0} runs backwards")]
    Backwards(String),
}

impl From<AddressError> for String {
    fn from(error: AddressError) -> String {
        error.to_string()
    }
}

/// `1-255`, `7`, `1,3,10-20` → the addresses in the order written, each
/// once (a repeat is dropped, not an error: `1-4,2` is the bus 1-4). The
/// error names the part that is wrong, not the option it came from: the
/// caller says which.
pub fn parse_addresses(text: &str) -> Result<Vec<u8>, AddressError> {
    let mut addresses = Vec::new();
    for part in text.split(',').map(str::trim) {
        let number = |s: &str| {
            s.trim()
                .parse::<u8>()
                .map_err(|_| AddressError::NotAnAddress(s.trim().to_string()))
        };
        let (first, last) = match part.split_once('-') {
            Some((a, b)) => (number(a)?, number(b)?),
            None => {
                let n = number(part)?;
                (n, n)
            }
        };
        if first > last {
            return Err(AddressError::Backwards(part.to_string()));
        }
        for address in first..=last {
            if !addresses.contains(&address) {
                addresses.push(address);
            }
        }
    }
    Ok(addresses)
}

/// A non-empty list of module addresses, kept with the text it was
/// written as (for messages: `--address 1-4`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AddressList {
    addresses: Vec<u8>,
    text: String,
}

impl AddressList {
    /// One address.
    pub fn one(address: u8) -> AddressList {
        AddressList {
            addresses: vec![address],
            text: address.to_string(),
        }
    }

    /// The addresses, in the order written, each once; never empty.
    pub fn as_slice(&self) -> &[u8] {
        &self.addresses
    }

    /// The first address written: the module that single-module work goes to.
    pub fn first(&self) -> u8 {
        // Never empty: parse_addresses refuses empty text.
        self.addresses.first().copied().unwrap_or_default()
    }

    /// More than one module.
    pub fn is_several(&self) -> bool {
        self.addresses.len() > 1
    }

    /// The text as written.
    pub fn text(&self) -> &str {
        &self.text
    }
}

impl From<u8> for AddressList {
    fn from(address: u8) -> AddressList {
        AddressList::one(address)
    }
}

impl FromStr for AddressList {
    type Err = AddressError;
    fn from_str(text: &str) -> Result<AddressList, AddressError> {
        let addresses = parse_addresses(text)?;
        Ok(AddressList {
            addresses,
            text: text.trim().to_string(),
        })
    }
}

impl fmt::Display for AddressList {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn address_lists_and_ranges() {
        assert_eq!(parse_addresses("1-255").unwrap().len(), 255);
        assert_eq!(parse_addresses("7").unwrap(), [7]);
        assert_eq!(parse_addresses("1, 3,2-4").unwrap(), [1, 3, 2, 4]);
        assert_eq!(parse_addresses("1,5,10-12").unwrap(), [1, 5, 10, 11, 12]);
        assert_eq!(
            parse_addresses("5-1").unwrap_err().to_string(),
            "range 5-1 runs backwards"
        );
        assert_eq!(
            parse_addresses("1-256").unwrap_err().to_string(),
            "`256` is not an address 0..255"
        );
        assert!(parse_addresses("").is_err());
        assert!(parse_addresses("1,,2").is_err());
        assert!(parse_addresses("a").is_err());
        assert!(parse_addresses("-3").is_err());
    }

    #[test]
    fn a_list_keeps_its_text_and_names_its_first_module() {
        let list: AddressList = " 3,1-2 ".parse().unwrap();
        assert_eq!(list.as_slice(), [3, 1, 2]);
        assert_eq!(list.first(), 3);
        assert!(list.is_several());
        assert_eq!(list.to_string(), "3,1-2");
        let one = AddressList::from(7);
        assert_eq!((one.first(), one.is_several(), one.text()), (7, false, "7"));
        assert_eq!("7".parse::<AddressList>().unwrap(), one);
        assert!(!"1-1".parse::<AddressList>().unwrap().is_several());
    }

    proptest! {
        #[test]
        fn any_text_parses_or_is_refused_without_a_panic(text in ".{0,40}") {
            if let Ok(list) = text.parse::<AddressList>() {
                prop_assert!(!list.as_slice().is_empty());
            }
        }

        #[test]
        fn written_lists_parse_back_to_their_addresses(
            parts in proptest::collection::vec((any::<u8>(), 0u8..8), 1..6)
        ) {
            let text = parts
                .iter()
                .map(|&(start, len)| {
                    let end = start.saturating_add(len);
                    if start == end { start.to_string() } else { format!("{start}-{end}") }
                })
                .collect::<Vec<_>>()
                .join(",");
            let parsed = parse_addresses(&text).expect("a written list parses");
            let mut expected = Vec::new();
            for &(start, len) in &parts {
                for a in start..=start.saturating_add(len) {
                    if !expected.contains(&a) {
                        expected.push(a);
                    }
                }
            }
            prop_assert_eq!(parsed, expected);
        }
    }
}
