//! A stand-in for the TMCL wire format until `tmcl::wire` lands: 9-byte
//! frames, replies matched by module address and echoed opcode, status
//! 128 of command 138 as news (§3.6.52). To be replaced by `TmclWire`.

use std::sync::Arc;
use std::time::Duration;

use super::frame::{FRAME_LEN, FrameAssembler, Reply, Request, Status};
use crate::protocol::wire::{Frame, Framer, ReplyRule, Verdict, WireFormat};

struct Assembler(FrameAssembler);

impl Framer for Assembler {
    fn push(&mut self, bytes: &[u8]) -> Vec<Frame> {
        self.0.push(bytes).into_iter().map(|f| f.to_vec()).collect()
    }
    fn pending(&self) -> usize {
        self.0.partial_len()
    }
    fn discard_pending(&mut self) -> Vec<u8> {
        let n = self.0.partial_len();
        self.0.resync();
        vec![0; n]
    }
}

struct Wire;

impl WireFormat for Wire {
    fn name(&self) -> &'static str {
        "tmcl"
    }
    fn framer(&self) -> Box<dyn Framer> {
        Box::new(Assembler(FrameAssembler::new()))
    }
    fn unsolicited(&self, frame: &[u8]) -> Option<String> {
        let frame: &[u8; FRAME_LEN] = frame.try_into().ok()?;
        let reply = Reply::from_bytes(frame).ok()?;
        (reply.status == Status::TARGET_REACHED).then(|| "target position reached".to_string())
    }
    fn silence(&self, byte_time: Option<Duration>) -> Duration {
        byte_time.map_or(Duration::from_millis(5), |t| t * 3)
    }
}

#[derive(Debug)]
struct Rule(Request);

impl ReplyRule for Rule {
    fn examine(&self, _accepted: &[Frame], frame: &[u8]) -> Verdict {
        let Ok(frame) = <&[u8; FRAME_LEN]>::try_from(frame) else {
            return Verdict::NotMine;
        };
        // 136 type 0 and 134 answer in layouts of their own.
        if self.0.command == 134 || (self.0.command == 136 && self.0.kind == 0) {
            return Verdict::Complete;
        }
        match Reply::from_bytes(frame) {
            Ok(r)
                if r.module_address == self.0.address
                    && r.command == self.0.command
                    && r.status != Status::TARGET_REACHED =>
            {
                Verdict::Complete
            }
            _ => Verdict::NotMine,
        }
    }
}

pub fn wire() -> Arc<dyn WireFormat> {
    Arc::new(Wire)
}

pub fn reply_rule(request: &Request) -> Arc<dyn ReplyRule> {
    Arc::new(Rule(*request))
}
