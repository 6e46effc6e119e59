//! Simulated buses: `axterm sim KIND --pty --address 1-4` and `--sim KIND
//! --address 1-4` put four modules on one line, each its own simulator.
//! Scanned, all four are found and an absent address stays silent; bytes
//! written out by hand from each manual show that every module keeps its
//! own state and that only the addressed one answers; a fault given to one
//! module (`--fault 3:drop=1`) hides that module alone.
//!
//! The served simulator runs on the wall clock: the client reads answers
//! as they come, and checks silence by what arrives first after it.

mod cli_support;
mod served_support;

use std::io::{Read, Write};
use std::time::Duration;

use cli_support::{axterm, stderr, stdout};
use served_support::Served;

/// Only guards against a hung test; a healthy exchange takes milliseconds.
const GIVE_UP_AFTER: Duration = Duration::from_secs(10);

/// The families with a module address on their link: the simulator, the
/// protocol family, and the identity line `scan` prints for each module.
const BUSES: [(&str, &str, &str); 3] = [
    ("tmcm1110", "tmcl", "1110V112"),
    ("cmd4cr", "cmd4cr", "V126BL"),
    (
        "sixpack2",
        "sixpack2",
        "firmware=148 reset=1 temperature=30 serial=1",
    ),
];

fn open(pty: &str) -> serialport::TTYPort {
    serialport::new(pty, 9600)
        .timeout(GIVE_UP_AFTER)
        .open_native()
        .expect("open the printed path as a serial port")
}

fn exchange<const N: usize>(port: &mut serialport::TTYPort, request: &[u8]) -> [u8; N] {
    port.write_all(request).expect("write the request");
    let mut reply = [0u8; N];
    port.read_exact(&mut reply).expect("a whole reply");
    reply
}

/// The text lines `scan` prints for the modules at `addresses`.
fn found_at(addresses: &[u8], identity: &str) -> String {
    addresses
        .iter()
        .map(|a| format!("address {a}: {identity}\n"))
        .collect()
}

#[test]
fn a_served_bus_of_four_is_scanned_whole_and_an_absent_address_is_silent() {
    for (kind, family, identity) in BUSES {
        let served = Served::start(kind, &["--address", "1-4"]);
        let out = axterm(&[
            "scan",
            "--port",
            &served.pty,
            "--protocol",
            family,
            "--addresses",
            "1-6",
        ]);
        assert_eq!(out.status.code(), Some(0), "{kind}: {}", stderr(&out));
        assert_eq!(stdout(&out), found_at(&[1, 2, 3, 4], identity), "{kind}");
        assert!(
            stderr(&out).contains("4 modules found at 6 addresses"),
            "{kind}: {}",
            stderr(&out)
        );
    }
}

#[test]
fn an_in_process_bus_of_four_is_scanned_whole() {
    for (kind, _, identity) in BUSES {
        let out = axterm(&[
            "scan",
            "--sim",
            kind,
            "--address",
            "1-4",
            "--addresses",
            "1-6",
        ]);
        assert_eq!(out.status.code(), Some(0), "{kind}: {}", stderr(&out));
        assert_eq!(stdout(&out), found_at(&[1, 2, 3, 4], identity), "{kind}");
    }
}

#[test]
fn without_addresses_scan_tries_the_modules_the_list_names() {
    let out = axterm(&["scan", "--sim", "cmd4cr", "--address", "2,5,9"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), found_at(&[2, 5, 9], "V126BL"));
    assert!(stderr(&out).contains("3 modules found at 3 addresses"));
}

#[test]
fn a_module_given_a_drop_fault_is_not_found_while_the_others_are() {
    // Served: the fault travels with `axterm sim`.
    let served = Served::start("tmcm1110", &["--address", "1-4", "--fault", "3:drop=1"]);
    let out = axterm(&["scan", "--port", &served.pty, "--addresses", "1-4"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), found_at(&[1, 2, 4], "1110V112"));
    // In-process, for every family with addresses.
    for (kind, _, identity) in BUSES {
        let out = axterm(&[
            "scan",
            "--sim",
            kind,
            "--address",
            "1-4",
            "--fault",
            "3:drop=1",
        ]);
        assert_eq!(out.status.code(), Some(0), "{kind}: {}", stderr(&out));
        assert_eq!(stdout(&out), found_at(&[1, 2, 4], identity), "{kind}");
    }
}

#[test]
fn scan_lists_address_and_identity_as_json() {
    let out = axterm(&[
        "scan",
        "--sim",
        "tmcm1110",
        "--address",
        "1,3",
        "--addresses",
        "1-3",
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_str(&stdout(&out)).expect("one JSON object");
    assert_eq!(json["family"], "tmcl");
    assert_eq!(json["tried"], 3);
    assert_eq!(
        json["modules"],
        serde_json::json!([
            {"address": 1, "identity": "1110V112"},
            {"address": 3, "identity": "1110V112"},
        ])
    );
}

/// TMCL (§3.1): `ADDR CMD TYPE MOTOR V3 V2 V1 V0 CHECKSUM`, the checksum
/// the low byte of the sum of the first eight. The manual's §3.6.5 example
/// is `SAP 4, 0, 1000` to module 1, `01 05 04 00 00 00 03 E8 F5`; here
/// module 2 is set to 500 (01F4), which no module has from the factory.
#[test]
fn tmcl_modules_keep_their_own_parameters_and_only_the_addressed_one_answers() {
    let served = Served::start("tmcm1110", &["--address", "1-4"]);
    let mut port = open(&served.pty);
    const GAP_4_MODULE_2: [u8; 9] = [0x02, 0x06, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0C];
    const GAP_4_MODULE_3: [u8; 9] = [0x03, 0x06, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0D];
    const GAP_4_MODULE_5: [u8; 9] = [0x05, 0x06, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0F];
    const SAP_4_500_MODULE_2: [u8; 9] = [0x02, 0x05, 0x04, 0x00, 0x00, 0x00, 0x01, 0xF4, 0x00];
    // Reply (§3.2): host 02, module, status 100, command, value, checksum.
    let module_3_before: [u8; 9] = exchange(&mut port, &GAP_4_MODULE_3);
    assert_eq!(module_3_before[..4], [0x02, 0x03, 0x64, 0x06]);
    assert_ne!(module_3_before[4..8], [0x00, 0x00, 0x01, 0xF4]);
    let set: [u8; 9] = exchange(&mut port, &SAP_4_500_MODULE_2);
    assert_eq!(set[..4], [0x02, 0x02, 0x64, 0x05], "module 2 took it");
    assert_eq!(
        exchange::<9>(&mut port, &GAP_4_MODULE_2),
        [0x02, 0x02, 0x64, 0x06, 0x00, 0x00, 0x01, 0xF4, 0x63]
    );
    assert_eq!(
        exchange::<9>(&mut port, &GAP_4_MODULE_3),
        module_3_before,
        "module 3 keeps its own"
    );
    // No module 5: the first answer after its frame is module 2's.
    port.write_all(&GAP_4_MODULE_5).expect("write");
    assert_eq!(
        exchange::<9>(&mut port, &GAP_4_MODULE_2),
        [0x02, 0x02, 0x64, 0x06, 0x00, 0x00, 0x01, 0xF4, 0x63]
    );
}

/// CMD-4CR (§3.2.2): `@` + two-digit ID + command + CR; the answer + CR.
#[test]
fn cmd4cr_modules_keep_their_own_speeds_and_only_the_addressed_one_answers() {
    let served = Served::start("cmd4cr", &["--address", "1-4"]);
    let mut port = open(&served.pty);
    let mut ask = |line: &[u8]| -> String {
        port.write_all(line).expect("write");
        let mut answer = Vec::new();
        let mut byte = [0u8; 1];
        while byte[0] != b'\r' {
            port.read_exact(&mut byte).expect("an answer");
            answer.push(byte[0]);
        }
        String::from_utf8_lossy(&answer).into_owned()
    };
    let module_3_before = ask(b"@03HSPD\r");
    assert_ne!(module_3_before, "4321\r");
    assert_eq!(ask(b"@02HSPD=4321\r"), "OK\r");
    assert_eq!(ask(b"@02HSPD\r"), "4321\r");
    assert_eq!(ask(b"@03HSPD\r"), module_3_before, "module 3 keeps its own");
    // No module 5: the first answer after its line is module 2's.
    assert_eq!(ask(b"@05HSPD\r@02HSPD\r"), "4321\r");
}

/// SIXpack 2 (§6.2, §7): requests `ADDR CMD P0..P6`, values LSB first;
/// replies `CMD P0..P6` (§6.2.2.3). $27 sets motor 0's actual position on
/// unit 2 to 1234 (04D2); $20 reads position, action and stop flag.
#[test]
fn sixpack2_units_keep_their_own_positions_and_only_the_addressed_one_answers() {
    let served = Served::start("sixpack2", &["--address", "1-4"]);
    let mut port = open(&served.pty);
    const SET_POSITION_1234_UNIT_2: [u8; 9] =
        [0x02, 0x27, 0x00, 0xD2, 0x04, 0x00, 0x00, 0x00, 0x00];
    const GET_POSITION_UNIT_2: [u8; 9] = [0x02, 0x20, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00];
    const GET_POSITION_UNIT_3: [u8; 9] = [0x03, 0x20, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00];
    const GET_POSITION_UNIT_5: [u8; 9] = [0x05, 0x20, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00];
    const AT_0: [u8; 8] = [0x20, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00];
    const AT_1234: [u8; 8] = [0x20, 0x00, 0xD2, 0x04, 0x00, 0x00, 0x00, 0x00];
    assert_eq!(exchange::<8>(&mut port, &GET_POSITION_UNIT_3), AT_0);
    // Setting commands are not answered (§7).
    port.write_all(&SET_POSITION_1234_UNIT_2).expect("write");
    assert_eq!(exchange::<8>(&mut port, &GET_POSITION_UNIT_2), AT_1234);
    assert_eq!(
        exchange::<8>(&mut port, &GET_POSITION_UNIT_3),
        AT_0,
        "unit 3 keeps its own"
    );
    // No unit 5: the first answer after its frame is unit 2's.
    port.write_all(&GET_POSITION_UNIT_5).expect("write");
    assert_eq!(exchange::<8>(&mut port, &GET_POSITION_UNIT_2), AT_1234);
}

#[test]
fn single_module_work_goes_to_the_first_address_of_the_list() {
    // TMCL GGP 66: the module's own serial address (§5.1).
    let out = axterm(&[
        "exec",
        "--sim",
        "tmcm1110",
        "--address",
        "3,1-2",
        "GGP 66, 0",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "3\n");
}

#[test]
fn mccl_refuses_an_address_list() {
    for args in [
        &["sim", "mccl", "--pty", "--address", "1-4"][..],
        &["sim", "mccl-eth", "--pty", "--address", "1,2"][..],
        &["exec", "--sim", "mccl", "--address", "1-4", "1TP"][..],
    ] {
        let out = axterm(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(stdout(&out), "", "{args:?}: nothing served or sent");
        let said = stderr(&out);
        assert!(
            said.contains("MultiFlex") && said.contains("no module address on its link"),
            "{said}"
        );
    }
}

#[test]
fn an_address_list_or_a_fault_on_a_real_line_is_refused_before_anything_is_sent() {
    let out = axterm(&[
        "exec",
        "--port",
        "/dev/null",
        "--address",
        "1-4",
        "GAP 1, 0",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("--address 1-4 names several modules"),
        "{}",
        stderr(&out)
    );
    let out = axterm(&[
        "exec",
        "--port",
        "/dev/null",
        "--fault",
        "3:drop=1",
        "GAP 1, 0",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--fault 3:drop=1 injects faults"));
}

#[test]
fn a_fault_for_a_module_not_on_the_bus_is_refused() {
    for args in [
        &[
            "sim",
            "cmd4cr",
            "--pty",
            "--address",
            "1-4",
            "--fault",
            "7:drop=1",
        ][..],
        &[
            "exec",
            "--sim",
            "cmd4cr",
            "--address",
            "1-4",
            "--fault",
            "7:drop=1",
            "VER",
        ][..],
    ] {
        let out = axterm(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(stdout(&out), "", "{args:?}");
        assert!(
            stderr(&out).contains(
                "--fault 7:drop=1: no module at address 7 on this bus \
                 (modules at addresses 1, 2, 3, 4)"
            ),
            "{}",
            stderr(&out)
        );
    }
}
