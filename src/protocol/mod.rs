//! Protocol knowledge of every controller family: frames, typed commands,
//! console line syntax, parameter tables. No I/O here.

pub mod addresses;
pub mod ascii;
pub mod cmd4cr;
pub mod console;
pub mod io;
pub mod jog;
pub mod line_error;
pub mod mccl;
pub mod parameter_file;
pub mod parameters;
pub mod plausible;
pub mod program;
pub mod settings;
pub mod sixpack2;
pub mod step_response;
pub mod tmcl;
pub mod tuning;
pub mod units;
pub mod wire;

use console::FamilyConsole;
pub use console::{LinkChoice, LinkOption};

/// One controller family as the command line knows it. The families are
/// registered, each with its simulators, in [`crate::families`]: this layer
/// names none of the layers above it.
pub struct Family {
    /// Name on the command line (`axterm encode tmcl …`).
    pub name: &'static str,
    pub description: &'static str,
    /// Parse and validate a console line and return the bytes it becomes on
    /// the wire for a module at `address` (the family's default when `None`).
    pub encode_line: fn(line: &str, address: Option<u8>) -> Result<Vec<u8>, line_error::LineError>,
    /// Show bytes of this family the way a technician reads them.
    pub show_bytes: fn(bytes: &[u8]) -> String,
    /// What the session layer needs of the family: its wire format, how a
    /// line is sent and its answer read, emergency stop, status polling.
    pub console: &'static dyn FamilyConsole,
}

/// A link option that is not one of the family's: what was given, and the
/// options the family has (`the sixpack2 family has framing=auto|cmd8|addr9`).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LinkOptionError {
    #[error("link option `{given}`: give NAME=VALUE; {known}")]
    NotNameValue { given: String, known: String },
    #[error("link option `{name}`: unknown; {known}")]
    UnknownName { name: String, known: String },
    #[error("link option {name}={value}: unknown value; {known}")]
    UnknownValue {
        name: String,
        value: String,
        known: String,
    },
}

impl From<LinkOptionError> for String {
    fn from(error: LinkOptionError) -> String {
        error.to_string()
    }
}

/// `family` with the link options `NAME=VALUE` given ([`LinkOption`]):
/// the family as the last choice of each option makes it. An option or a
/// value the family does not have is refused, naming what it has.
pub fn with_link_options(
    family: &'static Family,
    options: &[String],
) -> Result<&'static Family, LinkOptionError> {
    let mut chosen = family;
    for option in options {
        let known = || {
            let names: Vec<String> = chosen
                .console
                .link_options()
                .iter()
                .map(|o| {
                    let values: Vec<&str> = o.choices.iter().map(|c| c.value).collect();
                    format!("{}={}", o.name, values.join("|"))
                })
                .collect();
            if names.is_empty() {
                format!("the {} family has no link options", family.name)
            } else {
                format!("the {} family has {}", family.name, names.join(", "))
            }
        };
        let Some((name, value)) = option.split_once('=') else {
            return Err(LinkOptionError::NotNameValue {
                given: option.clone(),
                known: known(),
            });
        };
        let (name, value) = (name.trim(), value.trim());
        let Some(link_option) = chosen
            .console
            .link_options()
            .iter()
            .find(|o| o.name.eq_ignore_ascii_case(name))
        else {
            return Err(LinkOptionError::UnknownName {
                name: name.to_string(),
                known: known(),
            });
        };
        let Some(choice) = link_option
            .choices
            .iter()
            .find(|c| c.value.eq_ignore_ascii_case(value))
        else {
            return Err(LinkOptionError::UnknownValue {
                name: name.to_string(),
                value: value.to_string(),
                known: known(),
            });
        };
        chosen = choice.family;
    }
    Ok(chosen)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sixpack2() -> &'static Family {
        &sixpack2::FAMILY_AUTO
    }

    #[test]
    fn a_link_option_picks_the_family_as_its_choice_makes_it() {
        let strict = with_link_options(sixpack2(), &["framing=cmd8".into()]).expect("known");
        assert_eq!(strict.name, "sixpack2");
        let line = strict
            .console
            .prepare("GetPositionAndActivity 2", 0)
            .expect("valid");
        // Cmd8 does not read the address form.
        assert!(
            strict
                .console
                .interpret(&line, &[vec![0, 0x20, 2, 0, 0, 0, 0, 0, 0]])
                .is_err()
        );
        let addressed = with_link_options(sixpack2(), &["FRAMING = Addr9".into()])
            .expect("any case, blanks around");
        assert!(
            addressed
                .console
                .interpret(&line, &[vec![0, 0x20, 2, 0, 0, 0, 0, 0, 0]])
                .is_ok()
        );
        assert!(
            addressed
                .console
                .interpret(&line, &[vec![0x20, 2, 0, 0, 0, 0, 0, 0]])
                .is_err()
        );
        let last_wins =
            with_link_options(sixpack2(), &["framing=cmd8".into(), "framing=auto".into()])
                .expect("known");
        assert!(
            last_wins
                .console
                .interpret(&line, &[vec![0, 0x20, 2, 0, 0, 0, 0, 0, 0]])
                .is_ok()
        );
        assert!(std::ptr::eq(
            with_link_options(sixpack2(), &[]).expect("none"),
            sixpack2()
        ));
    }

    #[test]
    fn an_unknown_link_option_is_refused_naming_what_there_is() {
        let error = with_link_options(sixpack2(), &["framing=cmd9".into()])
            .err()
            .expect("refused")
            .to_string();
        assert_eq!(
            error,
            "link option framing=cmd9: unknown value; the sixpack2 family has \
             framing=auto|cmd8|addr9"
        );
        let error = with_link_options(sixpack2(), &["framing".into()])
            .err()
            .expect("refused")
            .to_string();
        assert!(error.contains("give NAME=VALUE"), "{error}");
        let tmcl = &tmcl::FAMILY;
        let error = with_link_options(tmcl, &["framing=cmd8".into()])
            .err()
            .expect("refused")
            .to_string();
        assert_eq!(
            error,
            "link option `framing`: unknown; the tmcl family has no link options"
        );
    }
}
