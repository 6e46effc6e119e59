//! Property tests of the SIXpack 2 simulator: whatever bytes arrive, in
//! whatever pieces and at whatever times, it never panics, stays silent
//! for other addresses, answers each query for its own with one 8-byte
//! reply echoing the command, and after a BREAK it is back in step.

use std::time::Duration;

use axterm::sim::SimulatedController;
use axterm::sim::sixpack2::command::{COMMANDS, Command, REQUEST_LEN};
use axterm::sim::sixpack2::{RESET_TIME, SimConfig, Sixpack2};
use proptest::prelude::*;

fn sim() -> Sixpack2 {
    Sixpack2::new(SimConfig::default())
}

/// The commands that answer, with where their motor or channel sits and
/// its range (§7).
const QUERIES: &[(u8, u8)] = &[
    (0x20, 6),
    (0x21, 6),
    (0x28, 0),
    (0x30, 8),
    (0x43, 0),
    (0x44, 0),
];

/// Bytes that may be anything, or a frame for address 0 with a command of
/// the instruction set, any parameters and motor numbers mostly in range,
/// cut short now and then.
fn piece() -> impl Strategy<Value = Vec<u8>> {
    let frame = (
        0..COMMANDS.len(),
        any::<[u8; 7]>(),
        0usize..=REQUEST_LEN * 4,
    )
        .prop_map(|(row, mut params, cut)| {
            params[0] %= 7;
            let mut bytes = vec![0, COMMANDS[row].code];
            bytes.extend_from_slice(&params);
            bytes.truncate(cut.max(1));
            bytes
        });
    prop_oneof![prop::collection::vec(any::<u8>(), 0..40), frame]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn any_nine_bytes_are_read_or_refused_without_a_panic(frame in any::<[u8; REQUEST_LEN]>()) {
        let read = Command::read(&frame);
        let known = COMMANDS.iter().any(|c| c.code == frame[1] && c.code < 0xF2);
        if !known {
            prop_assert!(read.is_err());
        }
    }

    #[test]
    fn garbage_in_pieces_never_panics_and_a_break_resynchronises(
        pieces in prop::collection::vec((piece(), 0u64..300), 0..40),
    ) {
        let mut sim = sim();
        for (bytes, pause) in &pieces {
            sim.feed(bytes);
            sim.advance(Duration::from_millis(*pause));
            let _ = sim.take_output();
        }
        // Whatever the garbage set (an address, a switch-over delay, a
        // reset under way), a BREAK, then a $CC to where it listens, brings
        // it back: a $43 to address 0 gets the reply of a fresh unit.
        sim.advance(RESET_TIME);
        sim.line_break();
        let address = sim.address();
        sim.feed(&[address, 0xCC, 0, 0, 0, 0, 0, 0, 0]);
        sim.advance(RESET_TIME);
        let _ = sim.take_output();
        sim.feed(&[0, 0x43, 0, 0, 0, 0, 0, 0, 0]);
        sim.advance(Duration::from_millis(6));
        prop_assert_eq!(sim.take_output(), vec![0x43, 148, 1, 30, 1, 0, 0, 0]);
    }

    #[test]
    fn each_query_for_its_address_gets_one_reply_echoing_it(
        which in 0..QUERIES.len(),
        selector in any::<u8>(),
        rest in any::<[u8; 6]>(),
        address in any::<u8>(),
    ) {
        let (code, range) = QUERIES[which];
        let mut frame = [0u8; REQUEST_LEN];
        frame[1] = code;
        frame[2] = if range > 0 { selector % range } else { selector };
        frame[3..].copy_from_slice(&rest);
        let mut sim = sim();
        sim.feed(&frame);
        sim.advance(Duration::from_millis(6));
        // A $28 waits for idle motors: at power-on they all are.
        let out = sim.take_output();
        prop_assert_eq!(out.len(), 8, "{:02X?}", out);
        prop_assert_eq!(out[0], code);
        // The same frame for another address: nothing.
        if address != 0 {
            frame[0] = address;
            sim.feed(&frame);
            sim.advance(Duration::from_millis(20));
            prop_assert!(sim.take_output().is_empty());
        }
    }
}
