//! Property tests of the SIXpack 2 codec: the reply cutter under garbage,
//! short frames and late `$28` answers between the others; the console
//! line parser (never panics, canonical lines round-trip); the reply
//! decoder on any bytes.

use axterm::protocol::console::{FamilyConsole, ReplyValue};
use axterm::protocol::sixpack2::catalog::{COMMANDS, FieldKind, is_replying};
use axterm::protocol::sixpack2::{
    Command, ReplyFields, ReplyFraming, Request, Sixpack2Console, Sixpack2Framer,
    Sixpack2ReplyRule, Sixpack2Wire, canonical, parse_line, send_to_pack,
};
use axterm::protocol::wire::{Framer, ReplyRule, Verdict, WireFormat};
use proptest::prelude::*;
use proptest::sample::select;

fn framing() -> impl Strategy<Value = ReplyFraming> {
    select(ReplyFraming::ALL.to_vec())
}

/// A reply of any command that answers, with any parameter bytes.
fn reply8() -> impl Strategy<Value = Vec<u8>> {
    let codes: Vec<u8> = COMMANDS
        .iter()
        .filter(|c| c.answers())
        .map(|c| c.code)
        .collect();
    (select(codes), proptest::array::uniform7(any::<u8>())).prop_map(|(code, params)| {
        let mut frame = vec![code];
        frame.extend_from_slice(&params);
        frame
    })
}

/// A late `$28`: six action codes and P6.
fn late_28() -> impl Strategy<Value = Vec<u8>> {
    proptest::array::uniform7(any::<u8>()).prop_map(|params| {
        let mut frame = vec![0x28];
        frame.extend_from_slice(&params);
        frame
    })
}

/// Line noise that cannot start a reply in any framing: no replying
/// command byte, no $00 (the Auto address byte).
fn noise() -> impl Strategy<Value = Vec<u8>> {
    proptest::collection::vec(
        any::<u8>().prop_filter("no reply start", |b| *b != 0 && !is_replying(*b)),
        0..12,
    )
}

/// `frame` as the framing sends it.
fn framed(frame: &[u8], framing: ReplyFraming) -> Vec<u8> {
    match framing {
        ReplyFraming::Cmd8 => frame.to_vec(),
        ReplyFraming::Addr9 | ReplyFraming::Auto => {
            let mut bytes = vec![0];
            bytes.extend_from_slice(frame);
            bytes
        }
    }
}

/// Feed `stream` in pieces cut at `cuts`.
fn feed(framer: &mut dyn Framer, stream: &[u8], cuts: &[usize]) -> (Vec<Vec<u8>>, usize) {
    let mut frames = Vec::new();
    let mut skipped = 0;
    let mut at = 0;
    let mut cuts: Vec<usize> = cuts.iter().map(|c| c % (stream.len() + 1)).collect();
    cuts.sort_unstable();
    for cut in cuts.into_iter().chain([stream.len()]) {
        if cut < at {
            continue;
        }
        frames.extend(framer.push(&stream[at..cut]));
        skipped += framer.take_skipped().len();
        at = cut;
    }
    (frames, skipped)
}

/// Values for every field of a command, each in its field's range.
fn command() -> impl Strategy<Value = Command> {
    (0..COMMANDS.len()).prop_flat_map(|index| {
        let spec = &COMMANDS[index];
        let values: Vec<BoxedStrategy<i64>> = spec
            .fields
            .iter()
            .map(|field| match field.kind {
                FieldKind::OneOf(values) => select(values.to_vec()).boxed(),
                _ => {
                    let (min, max) = field.bounds();
                    (min..=max).boxed()
                }
            })
            .collect();
        values.prop_map(move |values| Command::new(spec, values).expect("in range"))
    })
}

proptest! {
    #[test]
    fn the_cutter_keeps_or_skips_every_byte_and_never_panics(
        chunks in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..30), 0..20),
        framing in framing(),
    ) {
        let mut framer = Sixpack2Wire { framing }.framer();
        let mut fed = 0;
        let mut out = 0;
        for chunk in &chunks {
            fed += chunk.len();
            for frame in framer.push(chunk) {
                prop_assert!(frame.len() == 8 || frame.len() == 9);
                let command = if frame.len() == 9 { frame[1] } else { frame[0] };
                prop_assert!(is_replying(command));
                out += frame.len();
            }
            out += framer.take_skipped().len();
        }
        prop_assert!(framer.pending() <= 9);
        prop_assert_eq!(fed, out + framer.pending());
        let pending = framer.pending();
        prop_assert_eq!(framer.discard_pending().len(), pending);
        prop_assert_eq!(framer.pending(), 0);
    }

    #[test]
    fn replies_and_late_28s_between_noise_are_cut_exactly_however_the_bytes_arrive(
        parts in proptest::collection::vec((noise(), prop_oneof![reply8(), late_28()]), 1..8),
        tail in noise(),
        cuts in proptest::collection::vec(any::<usize>(), 0..10),
        framing in framing(),
    ) {
        let mut stream = Vec::new();
        let mut sent = Vec::new();
        let mut noise_len = tail.len();
        for (garbage, reply) in &parts {
            stream.extend_from_slice(garbage);
            noise_len += garbage.len();
            let bytes = framed(reply, framing);
            stream.extend_from_slice(&bytes);
            sent.push(bytes);
        }
        stream.extend_from_slice(&tail);
        let mut framer = Sixpack2Framer::new(framing);
        let (frames, skipped) = feed(&mut framer, &stream, &cuts);
        prop_assert_eq!(&frames, &sent);
        prop_assert_eq!(skipped + framer.pending(), noise_len);
    }

    #[test]
    fn a_short_frame_dropped_at_silence_leaves_the_next_reply_whole(
        cut in reply8(),
        len in 1usize..8,
        reply in reply8(),
        framing in framing(),
    ) {
        let short = framed(&cut, framing);
        let short = &short[..len.min(short.len() - 1)];
        let mut framer = Sixpack2Framer::new(framing);
        prop_assert!(framer.push(short).is_empty());
        // The device task drops a partial frame after line silence.
        framer.discard_pending();
        framer.take_skipped();
        let whole = framed(&reply, framing);
        prop_assert_eq!(framer.push(&whole), vec![whole]);
    }

    #[test]
    fn only_the_answer_to_the_query_in_flight_is_taken_and_a_late_28_is_news(
        motor in 0u8..6,
        other in 0u8..6,
        late in late_28(),
        params in proptest::array::uniform6(any::<u8>()),
        framing in framing(),
    ) {
        let request = Request { address: 0, command: 0x20, params: [motor, 0, 0, 0, 0, 0, 0] };
        let rule = Sixpack2ReplyRule { request, framing };
        let mut answer = vec![0x20, other];
        answer.extend_from_slice(&params);
        let verdict = rule.examine(&[], &framed(&answer, framing));
        prop_assert_eq!(verdict == Verdict::Complete, motor == other);
        prop_assert_eq!(rule.examine(&[], &framed(&late, framing)), Verdict::NotMine);
        let wire = Sixpack2Wire { framing };
        prop_assert!(wire.unsolicited(&framed(&late, framing)).is_some());
        prop_assert!(wire.unsolicited(&framed(&answer, framing)).is_none());
    }

    #[test]
    fn the_line_parser_never_panics(text in "\\PC{0,60}", address: Option<u8>) {
        let _ = parse_line(&text, address);
        let _ = axterm::protocol::sixpack2::assist::complete(&text, text.len());
        let _ = axterm::protocol::sixpack2::assist::help(&text, text.len() / 2);
    }

    #[test]
    fn mnemonic_soup_never_panics(
        head in select(COMMANDS.iter().map(|c| c.mnemonic).collect::<Vec<_>>()),
        rest in "[ 0-9a-zA-Z$,=%+\\-]{0,40}",
    ) {
        let line = format!("{head} {rest}");
        if let Ok(parsed) = parse_line(&line, None) {
            let again = parse_line(&parsed.canonical(), None);
            prop_assert_eq!(again.map(|p| p.request), Ok(parsed.request));
        }
    }

    #[test]
    fn canonical_lines_round_trip(command in command(), address: u8) {
        let request = command.to_request(address);
        let line = canonical(&request);
        let parsed = parse_line(&line, Some(address)).map_err(|e| TestCaseError::fail(format!("{line}: {e}")))?;
        prop_assert_eq!(parsed.request, request);
        prop_assert_eq!(parsed.command, Some(command));
        // The same bytes pasted as SQPack writes them.
        let pasted = parse_line(&send_to_pack(&request), None).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(pasted.request, request);
        prop_assert_eq!(pasted.canonical(), line);
    }

    #[test]
    fn any_frame_pasted_parses_or_is_refused_and_what_parses_round_trips(bytes: [u8; 9]) {
        let line = format!(
            "SendToPack({})",
            bytes.iter().map(|b| format!("${b:02X}")).collect::<Vec<_>>().join(", ")
        );
        if let Ok(parsed) = parse_line(&line, None) {
            prop_assert_eq!(parsed.request.to_bytes(), bytes);
            let again = parse_line(&parsed.canonical(), Some(bytes[0]))
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert_eq!(again.request.to_bytes(), bytes);
        }
    }

    #[test]
    fn any_reply_bytes_are_read_or_refused_never_a_panic(
        command in command(),
        frame in proptest::collection::vec(any::<u8>(), 0..12),
        framing in framing(),
    ) {
        let console = Sixpack2Console { framing };
        let line = console.prepare_command(&command, 0);
        if let Ok(reading) = console.interpret(&line, &[frame]) {
            let _ = console.status_update(&line, &reading);
            if let ReplyValue::Text(text) = &reading.value
                && command.spec.answers()
            {
                prop_assert!(ReplyFields::parse_value(command.spec, text).is_some(), "{}", text);
            }
        }
        let _ = console.describe_reply(&[], None);
    }

    #[test]
    fn reply_values_read_back_field_by_field(command in command(), params: [u8; 7]) {
        if let Some(fields) = ReplyFields::read(command.spec, &params) {
            let text = fields.value_text();
            let back = ReplyFields::parse_value(command.spec, &text).expect("reads back");
            for (name, value) in back {
                if let Some(expected) = fields.get(name) {
                    prop_assert_eq!(value, expected, "{} in {}", name, text);
                }
            }
            let _ = fields.describe();
        }
    }
}
