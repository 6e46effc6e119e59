//! `axterm sim sixpack2` served over a real pseudo-terminal and over TCP,
//! driven by a client that knows only the bytes of the manual: requests
//! `ADDR CMD P0..P6` written out by hand (§6.2, §7), replies `CMD P0..P6`
//! read as 8 bytes (§6.2.2.3). No axterm code on the client side.
//!
//! The simulator runs on the wall clock here, so the client waits for
//! states by polling ($20), never for time.

mod served_support;

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Command, Stdio};
use std::time::Duration;

use served_support::Served;

/// Only guards against a hung test; a healthy exchange takes milliseconds.
const GIVE_UP_AFTER: Duration = Duration::from_secs(10);

/// Polls before a motion counts as never ending (a ramp of 10000 µsteps
/// at the defaults takes about 0.7 s; a poll at least the 6 ms switch-over).
const MOST_POLLS: usize = 3000;

const START_RAMP_0_10000: [u8; 9] = [0x00, 0x23, 0x00, 0x10, 0x27, 0x00, 0x00, 0x00, 0x00];
const GET_POSITION_0: [u8; 9] = [0x00, 0x20, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00];
const GET_UNIT_INFORMATION: [u8; 9] = [0x00, 0x43, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00];

fn open(pty: &str) -> serialport::TTYPort {
    serialport::new(pty, 19200)
        .timeout(GIVE_UP_AFTER)
        .open_native()
        .expect("open the printed path as a serial port")
}

fn read_reply(port: &mut impl Read) -> [u8; 8] {
    let mut reply = [0u8; 8];
    port.read_exact(&mut reply).expect("an 8-byte reply");
    reply
}

/// A $20 reply: (position, action, stop flag).
fn position_of(reply: &[u8; 8]) -> (i32, u8, u8) {
    assert_eq!(reply[..2], [0x20, 0x00], "{reply:02X?}");
    (
        i32::from_le_bytes([reply[2], reply[3], reply[4], reply[5]]),
        reply[6],
        reply[7],
    )
}

#[test]
fn a_start_ramp_shows_action_5_then_0_and_the_position_reaching_its_target() {
    let served = Served::start("sixpack2", &[]);
    let mut port = open(&served.pty);
    port.write_all(&START_RAMP_0_10000).expect("send StartRamp");
    let mut seen = Vec::new();
    for _ in 0..MOST_POLLS {
        port.write_all(&GET_POSITION_0).expect("send $20");
        let (pos, action, stop) = position_of(&read_reply(&mut port));
        assert_eq!(stop, 0);
        seen.push((pos, action));
        if action == 0 {
            break;
        }
    }
    let first = seen.first().copied().expect("polled");
    assert_eq!(first.1, 5, "moving: {seen:?}");
    assert!(seen.windows(2).all(|w| w[0].0 <= w[1].0), "{seen:?}");
    assert_eq!(seen.last().copied(), Some((10_000, 0)), "{seen:?}");
}

#[test]
fn a_frame_for_another_address_gets_no_answer() {
    // A $43 for unit 1, then a $20 for unit 0: the first reply is the $20's.
    let served = Served::start("sixpack2", &[]);
    let mut port = open(&served.pty);
    let mut other = GET_UNIT_INFORMATION;
    other[0] = 0x01;
    port.write_all(&other).expect("send to unit 1");
    port.write_all(&GET_POSITION_0).expect("send $20");
    assert_eq!(read_reply(&mut port), [0x20, 0, 0, 0, 0, 0, 0, 0]);
    // --address 1 is unit 1.
    let served = Served::start("sixpack2", &["--address", "1"]);
    let mut port = open(&served.pty);
    port.write_all(&GET_POSITION_0).expect("send to unit 0");
    port.write_all(&other).expect("send to unit 1");
    assert_eq!(read_reply(&mut port)[0], 0x43);
}

#[test]
fn a_masked_28_answers_only_when_its_motors_are_idle() {
    // §7.2 $28 with mask bit 0: the reply waits for motor 0; on RS-232 the
    // other requests go on meanwhile (§6.2.1.7).
    let served = Served::start("sixpack2", &[]);
    let mut port = open(&served.pty);
    port.write_all(&START_RAMP_0_10000).expect("send StartRamp");
    port.write_all(&[0x00, 0x28, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00])
        .expect("send $28");
    let mut answered_meanwhile = 0;
    let activities = 'polling: {
        for _ in 0..MOST_POLLS {
            port.write_all(&GET_POSITION_0).expect("send $20");
            let reply = read_reply(&mut port);
            if reply[0] == 0x28 {
                break 'polling reply;
            }
            let (pos, action, _) = position_of(&reply);
            assert_eq!(action, 5, "the $28 waits while motor 0 ramps (at {pos})");
            assert!(pos < 10_000);
            answered_meanwhile += 1;
        }
        panic!("no $28 reply");
    };
    assert!(answered_meanwhile > 0);
    assert_eq!(activities, [0x28, 0, 0, 0, 0, 0, 0, 0]);
    // The $20 sent before the $28 reply came is answered after it.
    assert_eq!(position_of(&read_reply(&mut port)), (10_000, 0, 0));
}

#[test]
fn a_break_on_the_standard_input_abandons_the_frame_in_progress() {
    // No packet timeout (TIMEOUT=0), so that only the BREAK can drop the
    // five bytes of an unfinished StartRamp.
    let mut served = Served::start_driven("sixpack2", &["--input", "TIMEOUT=0"]);
    assert_eq!(
        served.next_answer(),
        "TIMEOUT 0: no packet timeout, now and after a reset"
    );
    let mut port = open(&served.pty);
    // One write: a whole $20, then the first five bytes of a StartRamp. The
    // $20's reply leaves 6 ms after the simulator had all fourteen.
    let mut bytes = GET_POSITION_0.to_vec();
    bytes.extend_from_slice(&START_RAMP_0_10000[..5]);
    port.write_all(&bytes).expect("send");
    assert_eq!(position_of(&read_reply(&mut port)), (0, 0, 0));
    assert_eq!(served.drive("BREAK"), "a BREAK on the line");
    // Without the BREAK the five bytes and four of this $20 would make a
    // StartRamp, and the rest of it wait for more.
    port.write_all(&GET_POSITION_0).expect("send $20");
    assert_eq!(
        position_of(&read_reply(&mut port)),
        (0, 0, 0),
        "the StartRamp was abandoned"
    );
}

#[test]
fn eeprom_is_refused_because_the_unit_keeps_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let output = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["sim", "sixpack2", "--pty", "--eeprom"])
        .arg(dir.path().join("sixpack2.json"))
        .output()
        .expect("run axterm sim");
    assert_eq!(output.status.code(), Some(2));
    assert!(output.stdout.is_empty(), "nothing served");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("the sixpack2 simulator keeps no memory file")
            && stderr.contains("keeps nothing a host sets between power-ups"),
        "{stderr}"
    );
}

#[test]
fn tcp_serves_addr9_replies_when_asked() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args([
            "sim",
            "sixpack2",
            "--tcp",
            "127.0.0.1:0",
            "--input",
            "ADDR9=1",
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start axterm sim");
    let mut endpoint = String::new();
    BufReader::new(child.stdout.take().expect("stdout"))
        .read_line(&mut endpoint)
        .expect("the endpoint line");
    let mut stream = std::net::TcpStream::connect(endpoint.trim()).expect("connect");
    stream
        .set_read_timeout(Some(GIVE_UP_AFTER))
        .expect("timeout");
    let mut request = GET_UNIT_INFORMATION;
    request[2] = 0x7E; // response address
    stream.write_all(&request).expect("send $43");
    let mut reply = [0u8; 9];
    stream.read_exact(&mut reply).expect("a 9-byte reply");
    // Response address, $43, firmware 148, reset flag 1, 30 °C, serial 1.
    assert_eq!(reply, [0x7E, 0x43, 148, 1, 30, 1, 0, 0, 0]);
    let _ = child.kill();
    let _ = child.wait();
}
