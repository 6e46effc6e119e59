//! The family seam keeps its errors typed: a caller tells an empty line,
//! a syntax error, an operand out of range and a wrong address apart
//! without reading text, and reaches the family's own error; a parameter
//! line refused says whether the parameter is read-only or the value out
//! of range.

use axterm::families::FAMILIES;
use axterm::families::find_family;
use axterm::protocol::line_error::Mistake;
use axterm::protocol::parameters::{ParamOp, ParamRange, ParamRefusal};

/// For each family: a line and the mistake its refusal must carry.
const CASES: &[(&str, u8, &str, Mistake)] = &[
    ("tmcl", 1, "", Mistake::Empty),
    ("tmcl", 1, "FROB 1", Mistake::Syntax),
    ("tmcl", 1, "SAP 6, 0, 100000", Mistake::Range),
    ("cmd4cr", 1, "", Mistake::Empty),
    ("cmd4cr", 1, "FROB", Mistake::Syntax),
    ("cmd4cr", 1, "EO=16", Mistake::Range),
    ("cmd4cr", 100, "PX", Mistake::Address),
    ("sixpack2", 0, "", Mistake::Empty),
    ("sixpack2", 0, "Frob 1", Mistake::Syntax),
    ("sixpack2", 0, "StartRamp 6 100", Mistake::Range),
    (
        "sixpack2",
        0,
        "SendToPack($03, $22, $00, $00, $00, $00, $00, $00, $00)",
        Mistake::Address,
    ),
    ("mccl", 0, "1XX", Mistake::Syntax),
    ("mccl", 0, "1DS0", Mistake::Range),
    ("mccl", 1, "1TP", Mistake::Address),
    ("mccl", 0, "BK\"wait\"", Mistake::NotSent),
];

#[test]
fn each_family_s_refusal_says_what_kind_of_mistake_it_is() {
    for &(name, address, line, mistake) in CASES {
        let family = find_family(name).expect("registered");
        let error = family
            .console
            .prepare(line, address)
            .err()
            .unwrap_or_else(|| panic!("{name}: `{line}` was accepted"));
        assert_eq!(error.mistake(), mistake, "{name}: `{line}`: {error}");
    }
}

#[test]
fn the_family_s_own_error_is_reached_through_the_seam() {
    let tmcl = find_family("tmcl").expect("registered");
    let error = (tmcl.encode_line)("SAP 6, 0, 100000", None).expect_err("out of range");
    let own = error
        .downcast_ref::<axterm::protocol::tmcl::LineError>()
        .expect("the TMCL parser's error");
    assert!(
        matches!(own, axterm::protocol::tmcl::LineError::OutOfRange { .. }),
        "{own:?}"
    );
    let cmd4cr = find_family("cmd4cr").expect("registered");
    let error = (cmd4cr.encode_line)("HSPDX=-5", None).expect_err("refused");
    assert!(
        error
            .downcast_ref::<axterm::protocol::cmd4cr::FrameError>()
            .is_some(),
        "{error}"
    );
}

#[test]
fn a_refused_parameter_line_says_why_by_kind() {
    for family in FAMILIES {
        let Some(parameters) = family.console.parameters() else {
            continue;
        };
        let first_axis = family.console.axes()[0].number;
        let rows: Vec<_> = parameters
            .tables(first_axis)
            .into_iter()
            .flat_map(|t| t.rows)
            .collect();
        if let Some(read_only) = rows.iter().find(|r| r.access.read && !r.access.write) {
            let error = parameters
                .line(read_only, ParamOp::Write(0))
                .expect_err("a read-only row");
            assert_eq!(
                error.kind,
                ParamRefusal::ReadOnly,
                "{}: {}: {error}",
                family.name,
                read_only.name
            );
        }
        let span = rows.iter().find_map(|r| match r.range {
            ParamRange::Span { max, .. } if r.access.write && max < i64::MAX => Some((r, max)),
            _ => None,
        });
        let (row, max) =
            span.unwrap_or_else(|| panic!("{}: a writable row with a range", family.name));
        let error = parameters
            .line(row, ParamOp::Write(max + 1))
            .expect_err("past the range");
        assert_eq!(
            error.kind,
            ParamRefusal::OutOfRange,
            "{}: {}: {error}",
            family.name,
            row.name
        );
        let error = parameters
            .parse_value(row, "twelve", &|_| None)
            .expect_err("not a number");
        assert_eq!(
            error.kind,
            ParamRefusal::NotANumber,
            "{}: {error}",
            family.name
        );
    }
}

#[test]
fn a_refused_jog_says_whether_the_speed_or_the_target_was_wrong() {
    use axterm::protocol::jog::{Direction, JogError};
    for family in FAMILIES {
        let Some(plan) = family.console.jog() else {
            continue;
        };
        let axis = &family.console.axes()[0];
        let fastest = *plan.speeds().last().expect("speeds");
        let error = plan
            .run(axis, Direction::Positive, i64::MAX)
            .expect_err("no speed is that fast");
        assert!(
            matches!(
                error,
                JogError::Speed {
                    speed: i64::MAX,
                    ..
                }
            ),
            "{}: {error}",
            family.name
        );
        let error = plan
            .step(axis, 0, i64::MAX, fastest)
            .expect_err("no target is that far");
        assert!(
            matches!(
                error,
                JogError::Target {
                    distance: i64::MAX,
                    ..
                }
            ),
            "{}: {error}",
            family.name
        );
    }
}

#[test]
fn a_value_in_units_says_what_kept_it_from_converting() {
    use axterm::protocol::units::{MechanicsTable, UnitRefusal, check_line, convert_line};
    let tmcl = find_family("tmcl").expect("registered");
    let law = tmcl.console.units();
    let (mechanics, _) = MechanicsTable::parse_file(
        "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\nmicrosteps = 256\ntravel_per_rev = 5\n",
    )
    .expect("mechanics");
    let error = check_line(law, "MVP ABS, 1, 10mm", &mechanics).expect_err("axis 1 has none");
    assert_eq!(error.kind, UnitRefusal::NoMechanics, "{error}");
    let error = check_line(law, "MVP ABS, 0, 10deg", &mechanics).expect_err("another unit");
    assert_eq!(error.kind, UnitRefusal::WrongUnit, "{error}");
    let error = convert_line(law, "ROR 0, 20mm/s", &mechanics, &|_, _| None)
        .expect_err("the pulse divisor is not known");
    assert_eq!(error.kind, UnitRefusal::NeedsReading, "{error}");
    let error = MechanicsTable::parse_file("family = \"tmcl\"\n").expect_err("no mechanics");
    assert_eq!(error.kind, UnitRefusal::NoMechanics, "{error}");
}

#[test]
fn program_tools_name_their_refusals_by_type() {
    use axterm::protocol::program::{LoadError, NoIncludes, SourceLoader, StoreError};
    assert!(matches!(
        NoIncludes.load("a.inc"),
        Err(LoadError::NoIncludes)
    ));
    let files = std::collections::BTreeMap::<String, String>::new();
    assert!(matches!(files.load("a.inc"), Err(LoadError::NotFound)));
    for family in FAMILIES {
        let Some(tool) = family.console.program() else {
            continue;
        };
        if let Some(variables) = tool.variables() {
            let error = (variables.parse)("x").expect_err("no variable x");
            assert_eq!(error.typed, "x", "{}", family.name);
        }
        if let Some(store) = tool.store() {
            let error = store.delete(&[], 7).expect_err("nothing stored");
            assert!(
                matches!(error, StoreError::NoSuch { number: 7, .. }),
                "{}: {error}",
                family.name
            );
        }
    }
}
