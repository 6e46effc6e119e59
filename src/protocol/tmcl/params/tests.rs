use super::*;

fn all_tables() -> [(&'static str, &'static [ParamInfo]); 4] {
    [
        ("axis", AXIS_PARAMS),
        ("bank 0", BANK0_PARAMS),
        ("bank 2", BANK2_PARAMS),
        ("bank 3", BANK3_PARAMS),
    ]
}

#[test]
fn numbers_are_sorted_and_unique_in_every_table() {
    for (label, table) in all_tables() {
        assert!(!table.is_empty(), "{label} table is empty");
        for pair in table.windows(2) {
            let (a, b) = (&pair[0], &pair[1]);
            assert!(
                a.numbers.start() <= a.numbers.end(),
                "{label}: empty number range in {}",
                a.name
            );
            assert!(
                a.numbers.end() < b.numbers.start(),
                "{label}: {} and {} overlap or are out of order",
                a.name,
                b.name
            );
        }
    }
}

#[test]
fn names_are_unique_per_table() {
    for (label, table) in all_tables() {
        for (i, a) in table.iter().enumerate() {
            for b in &table[i + 1..] {
                assert!(
                    !a.name.eq_ignore_ascii_case(b.name),
                    "{label}: duplicate name {}",
                    a.name
                );
            }
        }
    }
}

#[test]
fn defaults_lie_in_their_ranges() {
    for (label, table) in all_tables() {
        for row in table {
            if let Some(default) = row.default {
                assert!(
                    row.range.contains(default),
                    "{label} {}: default {default} outside {}",
                    row.name,
                    row.range
                );
            }
        }
    }
}

#[test]
fn every_row_is_readable_and_documented() {
    for (label, table) in all_tables() {
        for row in table {
            assert!(row.access.read, "{label} {} not readable", row.name);
            assert!(!row.description.is_empty(), "{label} {}", row.name);
            assert!(row.section.starts_with('§'), "{label} {}", row.name);
        }
    }
}

#[test]
fn ap6_is_a_byte_shown_as_0_to_255() {
    let p = axis_param(6).expect("AP6 exists");
    assert_eq!(p.name, "Maximum current");
    assert_eq!(p.range, ValueRange::span(0, 255));
    assert_eq!(p.range.to_string(), "0..255");
    assert!(!p.range.contains(256));
    // Storable as the STAP/RSAP examples of §3.6.7/§3.6.8 store it,
    // though Table 16 prints RW: the row names both.
    assert_eq!(p.access, Access::RWE);
    assert!(
        p.section.contains("Table 16 prints RW") && p.section.contains("§3.6.7/§3.6.8"),
        "{}",
        p.section
    );
    // The standby current stays as Table 16 has it.
    assert_eq!(axis_param(7).map(|p| p.access), Some(Access::RW));
}

#[test]
fn ap4_follows_table_16_not_table_1() {
    let p = axis_param(4).expect("AP4 exists");
    assert_eq!(p.range.to_string(), "1..2047");
    assert_eq!(p.access, Access::RWE);
    assert_eq!(p.unit, Unit::VelocityInternal);
    assert_eq!(axis_param(5).map(|p| p.access), Some(Access::RWE));
    assert_eq!(
        axis_param(5).map(|p| p.unit),
        Some(Unit::AccelerationInternal)
    );
}

#[test]
fn velocity_parameters_use_internal_velocity_units() {
    for number in [2, 3, 4, 130, 181, 182, 194, 195] {
        let p = axis_param(number).expect("velocity parameter exists");
        assert_eq!(p.unit, Unit::VelocityInternal, "AP{number}");
    }
}

#[test]
fn ap8_is_read_only() {
    let p = axis_param(8).expect("AP8 exists");
    assert_eq!(p.access, Access::R);
    assert_eq!(p.access.to_string(), "R");
}

#[test]
fn ap193_accepts_only_documented_modes() {
    let p = axis_param(193).expect("AP193 exists");
    for ok in [1, 8, 65, 68, 133, 136] {
        assert!(p.range.contains(ok), "{ok}");
    }
    for bad in [0, 9, 64, 69, 72, 129, 132, 137, 193] {
        assert!(!p.range.contains(bad), "{bad}");
    }
}

#[test]
fn known_defaults() {
    assert_eq!(axis_param(214).and_then(|p| p.default), Some(200));
    assert_eq!(axis_param(140).and_then(|p| p.default), Some(8));
    assert_eq!(axis_param(172).and_then(|p| p.default), Some(0));
    assert_eq!(axis_param(6).and_then(|p| p.default), None);
    assert_eq!(global_param(0, 69).and_then(|p| p.default), Some(8));
    assert_eq!(global_param(0, 78).and_then(|p| p.default), Some(7));
}

#[test]
fn thirty_two_bit_parameters_span_i32() {
    let p = axis_param(0).expect("AP0 exists");
    assert!(p.range.contains(i64::from(i32::MIN)));
    assert!(p.range.contains(i64::from(i32::MAX)));
    assert!(!p.range.contains(i64::from(i32::MAX) + 1));
}

#[test]
fn gp66_serial_address_is_auto_stored() {
    let p = global_param(0, 66).expect("GP66 exists");
    assert_eq!(p.range.to_string(), "1..255");
    assert_eq!(p.access, Access::RWA);
    assert_eq!(p.access.to_string(), "RWA");
}

#[test]
fn bank0_access_classes() {
    for row in BANK0_PARAMS {
        let first = *row.numbers.start();
        if (64..128).contains(&first) {
            assert_eq!(row.access, Access::RWA, "GP{first}");
        }
    }
    for number in [128, 129, 130] {
        assert_eq!(global_param(0, number).map(|p| p.access), Some(Access::R));
    }
    for number in [132, 133, 255] {
        assert_eq!(global_param(0, number).map(|p| p.access), Some(Access::RW));
    }
}

#[test]
fn user_variables_cover_bank_2() {
    let low = global_param(2, 42).expect("variable 42 exists");
    assert_eq!(low.access, Access::RWE);
    let high = global_param(2, 255).expect("variable 255 exists");
    assert_eq!(high.access, Access::RW);
    assert_eq!(global_param(2, 55).map(|p| p.access), Some(Access::RWE));
    assert_eq!(global_param(2, 56).map(|p| p.access), Some(Access::RW));
    assert!(low.range.contains(i64::from(i32::MIN)));
}

#[test]
fn bank_3_rows() {
    for number in [0, 1, 2, 27, 28, 39, 40, 41, 42, 43, 44] {
        assert!(global_param(3, number).is_some(), "GP3.{number}");
    }
    for number in [3, 26, 29, 38, 45] {
        assert!(global_param(3, number).is_none(), "GP3.{number}");
    }
    let input = global_param(3, 44).expect("input 5 transition");
    assert_eq!(input.name, "Input 5 trigger transition");
    assert!(input.range.contains(3));
    assert!(!input.range.contains(4));
}

#[test]
fn timer_period_accepts_unsigned_32_bit_values() {
    let timer = global_param(3, 0).expect("timer 0 exists");
    assert!(timer.range.contains(4_294_967_295));
    assert!(!timer.range.contains(4_294_967_296));
    assert_eq!(timer.wire_value(4_294_967_295), Some(-1));
    assert_eq!(timer.wire_value(2_147_483_648), Some(i32::MIN));
    assert_eq!(timer.wire_value(1000), Some(1000));
    assert_eq!(timer.wire_value(4_294_967_296), None);
    assert_eq!(timer.value_from_wire(-1), 4_294_967_295);
    assert_eq!(timer.value_from_wire(1000), 1000);
    assert!(timer.accepts_wire(-1), "the bits of 4294967295");
    assert!(!timer.range.contains(-1), "users type periods as unsigned");
    assert_eq!(timer.range.to_string(), "0..4294967295");
}

#[test]
fn wire_value_checks_the_range() {
    let ap6 = axis_param(6).expect("AP6 exists");
    assert_eq!(ap6.wire_value(255), Some(255));
    assert_eq!(ap6.wire_value(256), None);
    assert_eq!(ap6.wire_value(-1), None);
    let ap0 = axis_param(0).expect("AP0 exists");
    assert_eq!(ap0.wire_value(-5), Some(-5));
    assert_eq!(ap0.value_from_wire(-5), -5);
    assert!(ap0.accepts_wire(-5));
    assert!(!ap6.accepts_wire(256));
}

#[test]
fn missing_numbers_and_banks() {
    assert!(axis_param(14).is_none());
    assert!(axis_param(255).is_none());
    assert!(global_param(0, 67).is_none());
    assert!(global_param(0, 0).is_none());
    assert!(global_param(1, 0).is_none());
    assert!(global_param(4, 0).is_none());
    assert!(Bank::from_number(1).is_none());
}

#[test]
fn lookup_by_name_ignores_case() {
    assert_eq!(
        axis_param_by_name("maximum CURRENT").map(|p| p.numbers.clone()),
        Some(6..=6)
    );
    assert!(axis_param_by_name("no such parameter").is_none());
    assert_eq!(
        global_param_by_name(0, "serial address").map(|p| p.numbers.clone()),
        Some(66..=66)
    );
    assert!(global_param_by_name(1, "serial address").is_none());
    assert!(global_param_by_name(3, "serial address").is_none());
}
