//! Tab completion and inline help for SIXpack 2 lines, read from the
//! instruction tables ([`super::catalog`]): mnemonics and aliases, then
//! per operand what its field takes (motors with their "Motor n" names,
//! flags, masks, current steps); help gives a command's syntax, fields,
//! ranges, reply and cautions, or a topic (`flags`, `actions`, `currents`,
//! `confirm`).

use super::catalog::{
    ACTIONS, COMMANDS, CURRENT_STEPS, CommandSpec, Confirm, Field, FieldKind, MOTOR_FLAGS,
    UNDOCUMENTED, by_code, by_name, flag_by_name,
};
use super::command::allowed;
use super::line::{Form, operand_words, parse_line};
use crate::protocol::console::{Candidate, Completions};

/// The frame forms a line may start with besides a mnemonic.
const FRAME_FORMS: &[(&str, &str)] = &[
    (
        "SendToPack",
        "SendToPack(adr, cmd, p0..p6): a frame as SQPack's macro files write it, always hex",
    ),
    ("raw", "raw adr cmd p0..p6: nine hex bytes sent as written"),
];

/// What a channel of `$30`/`$31` is (§7.3).
fn channel_note(channel: u8) -> String {
    match channel {
        0..=5 => format!("A_In of motor {channel} (Motor {})", channel + 1),
        6 => "external analog input (pin 7 of the multifunction connector)".into(),
        _ => "supply voltage, 22 counts per volt".into(),
    }
}

fn candidate(text: impl Into<String>, note: impl Into<String>) -> Candidate {
    Candidate {
        text: text.into(),
        note: note.into(),
    }
}

/// The values a field offers.
fn field_candidates(field: &Field) -> Vec<Candidate> {
    match field.kind {
        FieldKind::Motor => (0..6)
            .map(|m| candidate(m.to_string(), format!("Motor {}", m + 1)))
            .collect(),
        FieldKind::Channel => (0..8)
            .map(|c| candidate(c.to_string(), channel_note(c)))
            .collect(),
        FieldKind::MotorMask => {
            let mut list: Vec<Candidate> = (0..6)
                .map(|m| candidate(m.to_string(), format!("motor {m} (Motor {})", m + 1)))
                .collect();
            list.push(candidate("all", "motors 0..5"));
            list.push(candidate("none", "no motor"));
            list
        }
        FieldKind::Flags(flags) => {
            let mut list: Vec<Candidate> = flags
                .iter()
                .map(|f| candidate(f.name, format!("{} {}", f.place(), f.meaning)))
                .collect();
            list.push(candidate("none", "no flag set"));
            list
        }
        FieldKind::CurrentIndex => CURRENT_STEPS
            .iter()
            .map(|s| candidate(format!("{}%", s.percent), format!("index {}", s.index)))
            .collect(),
        FieldKind::Bit => vec![candidate("0", field.meaning), candidate("1", field.meaning)],
        FieldKind::OneOf(values) => values
            .iter()
            .map(|v| candidate(v.to_string(), field.meaning))
            .collect(),
        FieldKind::ResponseAddress => vec![candidate("0", "the console's response address")],
        FieldKind::Number { .. } | FieldKind::Action | FieldKind::InputsAndJumpers => Vec::new(),
    }
}

/// Candidates for the word being typed up to `cursor`: mnemonics first,
/// then, operand by operand, what each field takes.
pub fn complete(line: &str, cursor: usize) -> Completions {
    let Some(before) = line.get(..cursor) else {
        return Completions::default();
    };
    // The word being typed starts after the last blank, comma or `=`.
    let start = after_last(before, |c| c.is_whitespace() || c == ',' || c == '=');
    let partial = &before[start..];
    let head = &before[..start];
    let Some(first) = head.split_whitespace().next() else {
        // The first word: a command.
        let mut candidates: Vec<Candidate> = COMMANDS
            .iter()
            .flat_map(|c| {
                std::iter::once(c.mnemonic)
                    .chain(c.aliases.iter().copied())
                    .map(move |name| {
                        candidate(
                            name,
                            format!("${:02X} {} (§{})", c.code, c.heading, c.section),
                        )
                    })
            })
            .chain(
                FRAME_FORMS
                    .iter()
                    .map(|(name, note)| candidate(*name, *note)),
            )
            .collect();
        candidates.retain(|c| starts_with_ignoring_case(&c.text, partial));
        return Completions {
            start,
            end: cursor,
            candidates,
            separator: " ",
        };
    };
    let Some(spec) = by_name(first) else {
        return Completions::default();
    };
    let operands = head.get(first.len()..).unwrap_or_default();
    let Some((index, field)) = operand_at(spec, operands) else {
        return Completions::default();
    };
    let mut candidates = field_candidates(field);
    // An item after a comma is one more motor or flag, not `all`/`none`.
    let in_list = head.ends_with(',');
    candidates.retain(|c| {
        starts_with_ignoring_case(&c.text, partial)
            && !(in_list && matches!(c.text.as_str(), "all" | "none"))
    });
    let lists = matches!(field.kind, FieldKind::Flags(_) | FieldKind::MotorMask);
    let last = index + 1 == spec.fields.len();
    Completions {
        start,
        end: cursor,
        candidates,
        separator: if lists || last { "" } else { " " },
    }
}

/// The field of the operand that follows `operands` (the text after the
/// mnemonic, up to the word being typed).
fn operand_at(spec: &'static CommandSpec, operands: &str) -> Option<(usize, &'static Field)> {
    let words = operand_words(operands);
    // A list or a `name=` being continued is the last word.
    let continuing = operands.trim_end().ends_with([',', '=']) && !words.is_empty();
    let (done, current) = if continuing {
        (&words[..words.len() - 1], words.last())
    } else {
        (&words[..], None)
    };
    if let Some((key, _)) = current.and_then(|w| w.split_once('=')) {
        return spec.field(key);
    }
    // Positional operands fill the fields no `name=` operand took.
    let keyed: Vec<usize> = done
        .iter()
        .filter_map(|w| w.split_once('='))
        .filter_map(|(key, _)| spec.field(key))
        .map(|(index, _)| index)
        .collect();
    let positional = done.iter().filter(|w| !w.contains('=')).count();
    let index = (0..spec.fields.len())
        .filter(|i| !keyed.contains(i))
        .nth(positional)?;
    spec.fields.get(index).map(|f| (index, f))
}

/// The byte offset just after the last character of `text` that
/// `breaks`, or 0.
fn after_last(text: &str, breaks: impl Fn(char) -> bool) -> usize {
    text.char_indices()
        .rev()
        .find(|(_, c)| breaks(*c))
        .map_or(0, |(i, c)| i + c.len_utf8())
}

fn starts_with_ignoring_case(text: &str, prefix: &str) -> bool {
    text.get(..prefix.len())
        .is_some_and(|head| head.eq_ignore_ascii_case(prefix))
}

/// One line on a field: `target (P1-4, signed): -2147483648..2147483647
/// µsteps — target position`.
fn field_line(field: &Field) -> String {
    let signed = if field.signed() { ", signed" } else { "" };
    let unit = if field.unit.is_empty() {
        String::new()
    } else {
        format!(" {}", field.unit)
    };
    let default = field
        .default
        .map(|d| format!("; {d} when left out"))
        .unwrap_or_default();
    format!(
        "  {} ({}{signed}): {}{unit} — {}{default}",
        field.name,
        field.bytes_label(),
        allowed(field),
        field.meaning
    )
}

/// Help on a command: its syntax, every field, its answer, the cautions.
fn command_help(spec: &CommandSpec) -> Vec<String> {
    let mut lines = vec![format!(
        "{} — ${:02X} {} (§{})",
        spec.syntax(),
        spec.code,
        spec.heading,
        spec.section
    )];
    if !spec.aliases.is_empty() {
        lines.push(format!("  also written {}", spec.aliases.join(", ")));
    }
    lines.extend(spec.fields.iter().map(field_line));
    match spec.reply {
        Some(reply) => {
            let names: Vec<&str> = reply.iter().map(|f| f.name).collect();
            lines.push(format!("  answers {}", names.join(" ")));
        }
        None => lines.push(
            "  never acknowledged (§7): the console shows `sent`, and no command reads it back"
                .into(),
        ),
    }
    match spec.confirm {
        Confirm::Never => {}
        Confirm::Always(why) => lines.push(format!("  asks first: {why}")),
        Confirm::WhenFlag { flag, why } => {
            lines.push(format!("  asks first when {flag} is set: {why}"));
        }
    }
    lines.push(format!("  {}", spec.note));
    for field in spec.fields.iter().chain(spec.reply.unwrap_or_default()) {
        match field.kind {
            FieldKind::Flags(_) => lines.extend(flag_lines()),
            FieldKind::Action => {
                lines.extend(action_lines());
                break;
            }
            _ => {}
        }
    }
    lines
}

fn flag_lines() -> Vec<String> {
    MOTOR_FLAGS
        .iter()
        .map(|f| {
            let sqpack = f.sqpack.map(|s| format!(" ({s})")).unwrap_or_default();
            format!("  {} {}{sqpack}: {}", f.place(), f.name, f.meaning)
        })
        .collect()
}

fn action_lines() -> Vec<String> {
    ACTIONS
        .iter()
        .map(|a| {
            let codes = if a.first == a.last {
                a.first.to_string()
            } else {
                format!("{}-{}", a.first, a.last)
            };
            format!("  action {codes} {}: {}", a.name, a.meaning)
        })
        .collect()
}

fn current_lines() -> Vec<String> {
    CURRENT_STEPS
        .iter()
        .map(|s| format!("  index {} = {}% of the peak current", s.index, s.percent))
        .collect()
}

/// Help on a topic, or every command whose names or meaning hold the
/// words.
fn topic(text: &str) -> Vec<String> {
    match text.to_ascii_lowercase().as_str() {
        "flags" | "motortype" | "motor type" => flag_lines(),
        "actions" | "action" => action_lines(),
        "currents" | "current" => current_lines(),
        "confirm" | "confirmation" => super::caution::confirmed_commands()
            .map(|c| format!("{} (${:02X})", c.mnemonic, c.code))
            .collect(),
        words => COMMANDS
            .iter()
            .filter(|c| {
                c.mnemonic.to_ascii_lowercase().contains(words)
                    || c.heading.to_ascii_lowercase().contains(words)
                    || c.note.to_ascii_lowercase().contains(words)
            })
            .map(|c| format!("{} — ${:02X} {}", c.syntax(), c.code, c.heading))
            .collect(),
    }
}

/// The word of `line` around byte offset `cursor` (a flag name in a list
/// counts alone).
fn word_at(line: &str, cursor: usize) -> &str {
    let is_break = |c: char| c.is_whitespace() || matches!(c, ',' | '=' | '(' | ')');
    let cursor = cursor.min(line.len());
    let Some(before) = line.get(..cursor) else {
        return "";
    };
    let start = after_last(before, is_break);
    let end = line
        .get(cursor..)
        .and_then(|after| after.find(is_break))
        .map_or(line.len(), |i| cursor + i);
    line.get(start..end).unwrap_or_default()
}

/// Help from the tables for the line's command (the flag under the cursor
/// first, where there is one), a frame, or a topic.
pub fn help(line: &str, cursor: usize) -> Vec<String> {
    let text = line.trim();
    let Some(first) = text.split(|c: char| c.is_whitespace() || c == '(').next() else {
        return Vec::new();
    };
    if first.is_empty() {
        return Vec::new();
    }
    let is_frame = FRAME_FORMS
        .iter()
        .any(|(name, _)| name.eq_ignore_ascii_case(first));
    if is_frame {
        let mut lines: Vec<String> = FRAME_FORMS.iter().map(|(_, n)| (*n).to_string()).collect();
        match parse_line(text, None) {
            Ok(parsed) if parsed.form == Form::Frame => {
                lines.insert(0, format!("this frame is {}", parsed.canonical()));
                if let Some(command) = parsed.command {
                    lines.extend(command_help(command.spec));
                }
            }
            Ok(_) => {}
            Err(e) => lines.insert(0, e.to_string()),
        }
        return lines;
    }
    if let Some(undocumented) = UNDOCUMENTED
        .iter()
        .find(|u| u.name.eq_ignore_ascii_case(first))
    {
        return vec![format!(
            "{} (${:02X}): {}; send it as a frame, SendToPack(…)",
            undocumented.name, undocumented.code, undocumented.why
        )];
    }
    let spec = by_name(first).or_else(|| {
        first
            .strip_prefix('$')
            .and_then(|d| u8::from_str_radix(d, 16).ok())
            .and_then(by_code)
    });
    match spec {
        Some(spec) => {
            let mut lines = command_help(spec);
            if let Some(flag) = flag_by_name(word_at(line, cursor)) {
                lines.insert(
                    0,
                    format!("{} {}: {}", flag.place(), flag.name, flag.meaning),
                );
            }
            lines
        }
        None => topic(text),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(line: &str) -> Vec<String> {
        complete(line, line.len())
            .candidates
            .into_iter()
            .map(|c| c.text)
            .collect()
    }

    #[test]
    fn mnemonics_and_aliases_complete() {
        assert_eq!(
            texts("StartR"),
            ["StartReferenceSearch", "StartRamp", "StartRampParallel"]
        );
        assert_eq!(texts("startref"), ["StartReferenceSearch"]);
        assert_eq!(texts("Peak"), ["PeakCurrent"]);
        assert!(texts("Send").contains(&"SendToPack".to_string()));
        assert!(texts("").len() > 40);
        let c = complete("  getp", 6);
        assert_eq!((c.start, c.end, c.separator), (2, 6, " "));
        assert!(c.candidates[0].note.contains("$20"));
    }

    #[test]
    fn operands_complete_from_their_fields() {
        let motors = complete("StartRamp ", 10);
        assert_eq!(motors.candidates.len(), 6);
        assert_eq!(motors.candidates[2].note, "Motor 3");
        assert_eq!(motors.separator, " ");
        assert!(texts("StartRamp 0 ").is_empty(), "a target is any number");
        assert_eq!(
            texts("SetMotorParameters 0 10000 Null"),
            ["NullLeft", "NullCenter", "NullPositive"]
        );
        assert_eq!(texts("SetMotorParameters 0 10000 NullLeft,Me"), ["MechRef"]);
        assert_eq!(texts("SetMotorParameters 0 flags=Fast"), ["FastRef"]);
        assert_eq!(texts("StopMotors 0,"), ["0", "1", "2", "3", "4", "5"]);
        assert_eq!(texts("StopMotors a"), ["all"]);
        assert_eq!(texts("SetCurrentControl 0 1"), ["100%", "19%", "13%"]);
        assert_eq!(texts("GetInputValues 7"), ["7"]);
        assert!(
            complete("GetInputValues ", 15).candidates[7]
                .note
                .contains("22 counts")
        );
        assert_eq!(complete("StopMotors 0", 12).separator, "");
        assert!(texts("Bogus 1").is_empty());
        assert!(texts("StartRamp 0 1 2 ").is_empty(), "no operand left");
    }

    #[test]
    fn help_gives_syntax_fields_answer_and_cautions() {
        let h = help("StartRamp 0 10000", 0);
        assert_eq!(
            h[0],
            "StartRamp motno target — $23 Start trapezoidal Ramp (§7.2)"
        );
        assert!(h[1].starts_with("  also written Ramp"), "{h:?}");
        assert!(h[2].contains("motno (P0): 0..5 (Motor 1..6)"), "{h:?}");
        assert!(
            h[3].contains("target (P1-4, signed): -2147483648..2147483647 µsteps"),
            "{h:?}"
        );
        assert!(h.iter().any(|l| l.contains("never acknowledged")), "{h:?}");
        let h = help("GetPositionAndActivity 0", 0);
        assert!(
            h.iter().any(|l| l == "  answers motno posact action stop"),
            "{h:?}"
        );
        assert!(
            h.iter().any(|l| l.contains("action 20-29 ref search")),
            "{h:?}"
        );
        assert!(h.iter().any(|l| l.contains("0 when left out")), "{h:?}");
        let h = help("HardwareReset", 0);
        assert!(
            h.iter()
                .any(|l| l.starts_with("  asks first: every setting")),
            "{h:?}"
        );
        let line = "SetMotorParameters 0 1 NullLeft,MechRef";
        let h = help(line, line.len() - 2);
        assert!(
            h[0].starts_with("P6.2 MechRef: mechanical reference"),
            "{h:?}"
        );
        assert!(
            h.iter()
                .any(|l| l.contains("asks first when AutonullCmd is set"))
        );
        assert!(h.iter().any(|l| l.contains("P5.4 NullLeft (MT_NULLLEFT)")));
        assert_eq!(
            help("$14", 0)[0],
            "SetAMaxVMax motno amax vmax — $14 Velocity, Acceleration (§7.1)"
        );
    }

    #[test]
    fn frames_and_topics() {
        let h = help("SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04)", 0);
        assert_eq!(
            h[0],
            "this frame is SetMotorParameters 0 10000 NullLeft,MechRef"
        );
        let h = help("SendToPack($00, $15)", 0);
        assert!(h[0].contains("9 values"), "{h:?}");
        assert!(help("SetMargin", 0)[0].contains("§6.5.3"));
        assert_eq!(help("flags", 0).len(), 16);
        assert_eq!(help("actions", 0).len(), 6);
        assert_eq!(help("currents", 0).len(), 9);
        assert!(help("confirm", 0).contains(&"HardwareReset ($CC)".to_string()));
        assert!(
            help("reference", 0)
                .iter()
                .any(|l| l.starts_with("StartReferenceSearch"))
        );
        assert!(help("", 0).is_empty());
        assert!(help("nothing like it", 0).is_empty());
    }
}
