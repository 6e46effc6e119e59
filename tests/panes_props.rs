//! Property tests of what the parameter, traffic and connect panes read
//! from files, users and devices: nothing panics on any input, parameter
//! files read back what was written, typed values read back as numbers.

use axterm::families::find_family;
use axterm::protocol::parameter_file::{Exported, parse, render};
use axterm::protocol::parameters::{
    ParamAccess, ParamRange, ParamRole, ParamRow, ParameterSet, Scope, parse_integer,
};
use axterm::protocol::tmcl::parameter_set::TmclParameters;
use axterm::ui::field::Field;
use proptest::prelude::*;
use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

fn row(scope: Scope, number: u16) -> ParamRow {
    ParamRow {
        scope,
        number,
        name: format!("parameter {number}"),
        unit: "",
        range: ParamRange::Span {
            min: i64::MIN,
            max: i64::MAX,
        },
        access: ParamAccess::default(),
        role: ParamRole::Setting,
        default: None,
        description: "",
    }
}

fn scope() -> impl Strategy<Value = Scope> {
    prop_oneof![
        any::<u8>().prop_map(Scope::Axis),
        any::<u8>().prop_map(Scope::Bank)
    ]
}

proptest! {
    #[test]
    fn any_text_as_a_parameter_file_is_read_or_refused(text in ".{0,300}") {
        let _ = parse(&text);
    }

    #[test]
    fn any_toml_like_text_is_read_or_refused(
        lines in prop::collection::vec("(\\[(axis|bank)\\.[0-9a-z]{1,3}\\]|[0-9a-z]{1,3} = -?[0-9\"a-z.]{1,12}|family = \"[a-z]{0,5}\")", 0..12)
    ) {
        let _ = parse(&lines.join("\n"));
    }

    #[test]
    fn a_written_parameter_file_reads_back_its_values(
        values in prop::collection::btree_map((scope(), any::<u16>()), any::<i64>(), 0..40)
    ) {
        let rows: Vec<(ParamRow, i64)> = values
            .iter()
            .map(|(&(scope, number), &value)| (row(scope, number), value))
            .collect();
        let exported: Vec<Exported> = rows
            .iter()
            .map(|(row, value)| Exported { row, value: Ok(*value) })
            .collect();
        let text = render("tmcl", &["header\nwith a newline".into()], &exported);
        let file = parse(&text).map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        prop_assert!(file.problems.is_empty(), "{:?}", file.problems);
        let read: Vec<((Scope, u16), i64)> = file
            .entries
            .iter()
            .map(|e| ((e.scope, e.number), e.value))
            .collect();
        let written: Vec<((Scope, u16), i64)> = values.into_iter().collect();
        prop_assert_eq!(read, written);
    }

    #[test]
    fn integers_read_back(value in any::<i64>()) {
        prop_assert_eq!(parse_integer(&value.to_string()), Ok(value));
    }

    #[test]
    fn any_typed_value_is_read_or_refused(text in ".{0,40}", number in 0u16..300) {
        let tables = TmclParameters.tables(0);
        for table in &tables {
            if let Some(row) = table.rows.iter().find(|r| r.number == number) {
                let _ = TmclParameters.parse_value(row, &text, &|n| Some(i64::from(n % 14)));
                let _ = TmclParameters.parse_value(row, &text, &|_| None);
            }
        }
    }

    #[test]
    fn any_bytes_from_a_device_are_described(
        bytes in prop::collection::vec(any::<u8>(), 0..20),
        request in prop::option::of(prop::collection::vec(any::<u8>(), 0..12)),
    ) {
        let console = find_family("tmcl").expect("tmcl").console;
        let _ = console.describe_request(&bytes);
        let _ = console.describe_reply(&bytes, request.as_deref());
    }

    #[test]
    fn any_keys_leave_the_field_whole(
        start in ".{0,10}",
        keys in prop::collection::vec(
            prop_oneof![
                any::<char>().prop_map(KeyCode::Char),
                Just(KeyCode::Backspace),
                Just(KeyCode::Delete),
                Just(KeyCode::Left),
                Just(KeyCode::Right),
                Just(KeyCode::Home),
                Just(KeyCode::End),
            ],
            0..30,
        ),
        ctrl in prop::collection::vec(any::<bool>(), 30),
    ) {
        let mut field = Field::new(start);
        for (code, ctrl) in keys.into_iter().zip(ctrl) {
            let modifiers = if ctrl { KeyModifiers::CONTROL } else { KeyModifiers::NONE };
            field.edit(&KeyEvent::new(code, modifiers));
            prop_assert!(field.cursor_column() <= field.text().chars().count());
        }
    }
}
