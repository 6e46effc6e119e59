//! Properties of the CMD-4CR parser and encoder: every command the table
//! allows writes to text that parses back to the same command (in any
//! case, with blanks), frames as `@ID…CR`, and is read back the same from
//! the frame; values outside a row's range are refused and say the range;
//! replies and requests of any bytes never panic.

use axterm::protocol::cmd4cr::catalog::{Access, COMMANDS, Form, Format, Kind};
use axterm::protocol::cmd4cr::command::ANGLE_MAX;
use axterm::protocol::cmd4cr::{
    Axis, Cmd4crCommand, CommandError, Direction, Rotation, Selector, encode, parse_command,
    parse_request,
};
use proptest::prelude::*;

const POSITION: std::ops::RangeInclusive<i64> = -134_217_728..=134_217_727;

fn axis() -> impl Strategy<Value = Axis> {
    prop::sample::select(Axis::ALL.to_vec())
}

fn direction() -> impl Strategy<Value = Direction> {
    prop_oneof![Just(Direction::Plus), Just(Direction::Minus)]
}

fn rotation() -> impl Strategy<Value = Rotation> {
    prop_oneof![Just(Rotation::Clockwise), Just(Rotation::CounterClockwise)]
}

fn two_axes() -> impl Strategy<Value = [Axis; 2]> {
    (axis(), axis())
        .prop_filter("two different axes", |(a, b)| a != b)
        .prop_map(|(a, b)| [a, b])
}

/// A register read or write, or an action, of any row of the table.
fn table_command() -> impl Strategy<Value = Cmd4crCommand> {
    (
        0..COMMANDS.len(),
        any::<prop::sample::Index>(),
        any::<bool>(),
        axis(),
    )
        .prop_filter_map(
            "rows of registers and actions",
            |(row, pick, write, axis)| {
                let spec = &COMMANDS[row];
                let selector = match spec.form {
                    Form::Bare => Selector::All,
                    Form::Axis => Selector::Axis(axis),
                    Form::Index { first, last } => {
                        Selector::Index(first + pick.index(usize::from(last - first) + 1) as u8)
                    }
                    Form::Motion => return None,
                };
                match spec.kind {
                    Kind::Action(action) => Some(Cmd4crCommand::Action { action, selector }),
                    Kind::Register(register) => {
                        let values = spec.values?;
                        let writes =
                            spec.access.writes() && (write || spec.access == Access::Write);
                        if writes && !matches!(values.format, Format::Fields(_) | Format::Text) {
                            let span = (values.max - values.min) as u128 + 1;
                            let offset = (pick.index(usize::MAX) as u128 % span) as i64;
                            Some(Cmd4crCommand::Write {
                                register,
                                selector,
                                value: values.min + offset,
                            })
                        } else if spec.access.reads() {
                            Some(Cmd4crCommand::Read { register, selector })
                        } else {
                            None
                        }
                    }
                    _ => None,
                }
            },
        )
}

fn motion_command() -> impl Strategy<Value = Cmd4crCommand> {
    let position = || POSITION;
    prop_oneof![
        prop::array::uniform4(prop::option::of(position()))
            .prop_filter("at least one axis", |t| t.iter().any(Option::is_some))
            .prop_map(|targets| Cmd4crCommand::Move { targets }),
        (axis(), direction()).prop_map(|(axis, direction)| Cmd4crCommand::Jog { axis, direction }),
        (axis(), direction(), 0u8..=12).prop_map(|(axis, direction, mode)| Cmd4crCommand::Home {
            axis,
            direction,
            mode
        }),
        (axis(), direction())
            .prop_map(|(axis, direction)| Cmd4crCommand::ZMove { axis, direction }),
        (axis(), position()).prop_map(|(axis, target)| Cmd4crCommand::NewTarget { axis, target }),
        (two_axes(), rotation(), position(), position()).prop_map(|(axes, rotation, a, b)| {
            Cmd4crCommand::Circle {
                axes,
                rotation,
                centre: [a, b],
            }
        }),
        (
            two_axes(),
            rotation(),
            position(),
            position(),
            0..=ANGLE_MAX
        )
            .prop_map(|(axes, rotation, a, b, angle)| Cmd4crCommand::Arc {
                axes,
                rotation,
                centre: [a, b],
                angle
            }),
        (rotation(), position(), position(), position()).prop_map(|(rotation, a, b, z)| {
            Cmd4crCommand::HelicalCircle {
                rotation,
                centre: [a, b],
                z,
            }
        }),
        (
            rotation(),
            position(),
            position(),
            0..=ANGLE_MAX,
            position()
        )
            .prop_map(|(rotation, a, b, angle, z)| Cmd4crCommand::HelicalArc {
                rotation,
                centre: [a, b],
                angle,
                z
            }),
        (position(), position(), position(), 1i64..=6_553_500).prop_map(|(x, y, z, speed)| {
            Cmd4crCommand::BufferMove {
                target: [x, y, z],
                speed,
            }
        }),
    ]
}

fn command() -> impl Strategy<Value = Cmd4crCommand> {
    prop_oneof![table_command(), motion_command()]
}

/// The text as someone might type it: lower case here and there, blanks
/// between some characters.
fn sloppy(text: &str, case: &[bool], blanks: &[bool]) -> String {
    let mut out = String::new();
    for (i, c) in text.chars().enumerate() {
        if blanks.get(i).copied().unwrap_or(false) {
            out.push(' ');
        }
        if case.get(i).copied().unwrap_or(false) {
            out.push(c.to_ascii_lowercase());
        } else {
            out.push(c);
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn every_command_round_trips_through_text_and_frame(
        command in command(),
        id in 0u8..=99,
        case in prop::collection::vec(any::<bool>(), 64),
        blanks in prop::collection::vec(prop::bool::weighted(0.1), 64),
    ) {
        let text = command.to_string();
        prop_assert!(text.len() <= 62, "{text} fits a line");
        prop_assert_eq!(parse_command(&text), Ok(command.clone()));
        prop_assert_eq!(parse_command(&sloppy(&text, &case, &blanks)), Ok(command.clone()));
        let (parsed, bytes) = encode(id, &text).expect("valid");
        prop_assert_eq!(&parsed, &command);
        prop_assert_eq!(bytes.first(), Some(&b'@'));
        prop_assert_eq!(bytes.last(), Some(&b'\r'));
        let request = parse_request(&bytes).expect("a frame");
        prop_assert_eq!(request.id, id);
        prop_assert_eq!(parse_command(&request.text), Ok(command));
    }

    #[test]
    fn a_value_outside_a_rows_range_is_refused_naming_it(
        row in 0..COMMANDS.len(),
        beyond in 1i64..1_000_000,
        above in any::<bool>(),
    ) {
        let spec = &COMMANDS[row];
        let Some(values) = spec.values else { return Ok(()) };
        if !spec.access.writes() || values.format != Format::Integer {
            return Ok(());
        }
        let value = if above { values.max.saturating_add(beyond) } else { values.min.saturating_sub(beyond) };
        let selector = match spec.form {
            Form::Bare => String::new(),
            Form::Axis => "X".into(),
            Form::Index { first, .. } => first.to_string(),
            Form::Motion => return Ok(()),
        };
        let text = format!("{}{selector}={value}", spec.keyword);
        match parse_command(&text) {
            Err(CommandError::OutOfRange { allowed, .. }) => {
                prop_assert!(allowed.starts_with(&format!("{}..{}", values.min, values.max)), "{allowed}");
            }
            Err(CommandError::NotANumber { .. }) => {
                // Beyond i64: not a number the manual writes.
            }
            other => prop_assert!(false, "{text}: {other:?}"),
        }
    }

    #[test]
    fn requests_of_any_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..80)) {
        if let Ok(request) = parse_request(&bytes) {
            let _ = parse_command(&request.text);
        }
    }
}
