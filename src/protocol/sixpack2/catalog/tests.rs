use super::*;

#[test]
fn every_command_is_listed_once_in_the_order_of_section_8() {
    let codes: Vec<u8> = COMMANDS.iter().map(|c| c.code).collect();
    assert_eq!(
        codes,
        [
            0x10, 0x11, 0x12, 0x13, 0x14, 0x15, 0x16, 0x17, 0x18, 0x19, 0x20, 0x21, 0x22, 0x23,
            0x24, 0x25, 0x26, 0x27, 0x28, 0x29, 0x2A, 0x2B, 0x30, 0x31, 0x32, 0x33, 0x40, 0x41,
            0x42, 0x43, 0x44, 0x50, 0xCC, 0xF2, 0xF3, 0xF4, 0xF5, 0xF6, 0xF7
        ]
    );
    let mut names: Vec<String> = COMMANDS
        .iter()
        .flat_map(|c| std::iter::once(c.mnemonic).chain(c.aliases.iter().copied()))
        .map(str::to_ascii_lowercase)
        .collect();
    let all = names.len();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), all, "every name is unique");
}

#[test]
fn fields_fit_in_p0_to_p6_without_overlap() {
    for spec in COMMANDS {
        for layout in std::iter::once(spec.fields).chain(spec.reply) {
            let mut used = [false; 7];
            for f in layout {
                assert!(
                    f.width >= 1 && f.offset + f.width <= 7,
                    "{} {}",
                    spec.mnemonic,
                    f.name
                );
                for b in &mut used[f.offset..f.offset + f.width] {
                    assert!(!*b, "{} {} overlaps", spec.mnemonic, f.name);
                    *b = true;
                }
                let (min, max) = f.bounds();
                let bits = 8 * f.width as u32;
                let (lo, hi) = if f.signed() {
                    (-(1i64 << (bits - 1)), (1i64 << (bits - 1)) - 1)
                } else {
                    (0, (1i64 << bits) - 1)
                };
                assert!(
                    lo <= min && max <= hi,
                    "{} {} fits its bytes",
                    spec.mnemonic,
                    f.name
                );
            }
        }
        // Optional operands come last, so that positions stay in field order.
        let first_optional = spec.fields.iter().position(|f| f.default.is_some());
        if let Some(first) = first_optional {
            assert!(
                spec.fields[first..].iter().all(|f| f.default.is_some()),
                "{}",
                spec.mnemonic
            );
        }
    }
}

#[test]
fn only_the_queries_and_service_commands_answer() {
    let replying: Vec<u8> = COMMANDS
        .iter()
        .filter(|c| c.answers())
        .map(|c| c.code)
        .collect();
    assert_eq!(
        replying,
        [
            0x20, 0x21, 0x28, 0x30, 0x43, 0x44, 0xF2, 0xF4, 0xF5, 0xF6, 0xF7
        ]
    );
    assert!(!is_replying(0x00), "no reply starts with $00 (digest D1.4)");
}

#[test]
fn flag_bits_follow_section_7_1_and_the_5_5_3_examples() {
    let word = |names: &[&str]| -> i64 {
        names
            .iter()
            .map(|n| flag_by_name(n).expect("a flag").mask())
            .sum()
    };
    // §5.5.3.2: P5 = $10, P6 = $04.
    assert_eq!(word(&["MT_NULLLEFT", "MT_MECHREF"]), 0x0410);
    // §5.5.3.4: P5 = $50, P6 = $40.
    assert_eq!(word(&["NullLeft", "StopNull", "NullPositive"]), 0x4050);
    // §6.8 factory word.
    assert_eq!(
        word(&["DelayTestNull", "NullCenter", "FilterSwitch", "FastRef"]),
        0x0AA0
    );
    // E13: StopNoRef is P6 bit 5.
    assert_eq!(
        flag_by_name("stopnoref").map(FlagBit::place),
        Some("P6.5".into())
    );
    assert_eq!(MOTOR_FLAGS.len(), 16);
}

#[test]
fn action_codes_read_as_words_and_back() {
    for code in [0u8, 5, 10, 15, 20, 23, 29, 30, 7, 255] {
        assert_eq!(action_from_token(&action_token(code)), Some(code), "{code}");
    }
    assert_eq!(action_token(5), "ramp");
    assert_eq!(action_token(23), "refsearch23");
    assert_eq!(action_token(31), "31");
    assert_eq!(action_from_token("refsearch31"), None);
    assert_eq!(activity(25).map(|a| a.name), Some("ref search"));
}

#[test]
fn current_steps_are_the_0_based_list() {
    let percents: Vec<u8> = CURRENT_STEPS.iter().map(|s| s.percent).collect();
    assert_eq!(percents, [100, 75, 50, 38, 25, 19, 13, 9, 0]);
    // E11: 19 % is index 5.
    assert_eq!(
        CURRENT_STEPS
            .iter()
            .find(|s| s.percent == 19)
            .map(|s| s.index),
        Some(5)
    );
}

#[test]
fn names_and_codes_find_their_rows() {
    assert_eq!(by_name("peakcurrent").map(|c| c.code), Some(0x10));
    assert_eq!(by_name("SetMaxCurrent").map(|c| c.code), Some(0x10));
    assert_eq!(by_name("ramp").map(|c| c.code), Some(0x23));
    assert_eq!(
        by_name("SetTargetPosition").map(|c| c.code),
        Some(0x26),
        "E15"
    );
    assert_eq!(
        by_code(0x31).map(|c| c.mnemonic),
        Some("SetStopSwitchLimits")
    );
    assert_eq!(by_code(0x1A), None);
    assert_eq!(
        by_code(0x23).map(CommandSpec::syntax).as_deref(),
        Some("StartRamp motno target")
    );
    assert_eq!(
        by_code(0x20).map(CommandSpec::syntax).as_deref(),
        Some("GetPositionAndActivity motno [resp]")
    );
    assert_eq!(motor_name(2), "motor 2 (Motor 3)");
}
