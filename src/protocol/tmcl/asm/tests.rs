use super::*;

#[test]
fn words_are_the_frame_without_address_and_checksum() {
    let command = Command::Jc {
        condition: crate::protocol::tmcl::Condition::Ge,
        address: 10,
    };
    let word = ProgramWord::from(command);
    // §3.6.18: JC GE, Label with Label at 10.
    assert_eq!(word.to_bytes(), [0x15, 0x05, 0x00, 0x00, 0x00, 0x00, 0x0A]);
    assert_eq!(ProgramWord::from_bytes(word.to_bytes()), word);
    assert_eq!(word.command(), command);
    let frame = command.to_request(1).to_bytes();
    assert_eq!(frame.get(1..8), Some(&word.to_bytes()[..]));
}

#[test]
fn programs_hold_no_control_commands_and_jump_inside_memory() {
    let check = |line: &str| check_program_command(&parse_syntax(line, None).unwrap());
    assert_eq!(check("JA 2047"), Ok(()));
    assert!(matches!(
        check("JA 2048"),
        Err(AsmErrorKind::AddressOutsideMemory { address: 2048, .. })
    ));
    assert!(matches!(
        check("VECT 0, -1"),
        Err(AsmErrorKind::AddressOutsideMemory { address: -1, .. })
    ));
    assert!(matches!(
        check("RUNAPP"),
        Err(AsmErrorKind::NotStorable { command }) if command == "RUNAPP"
    ));
    assert!(matches!(
        check("129 1 0 5"),
        Err(AsmErrorKind::NotStorable { command }) if command == "instruction 129 (RUNAPP)"
    ));
    // Raw frames are the way to store anything else.
    assert_eq!(check("22 0 0 5000"), Ok(()));
    assert_eq!(check("200 1 2 3"), Ok(()));
}

#[test]
fn edit_distance_counts_slips() {
    assert_eq!(edit_distance("Loop", "Lop"), 1);
    assert_eq!(edit_distance("Loop", "Lopo"), 2);
    assert_eq!(edit_distance("", "abc"), 3);
    assert_eq!(edit_distance("SubW", "SubW"), 0);
    assert_eq!(edit_distance("kitten", "sitting"), 3);
}
