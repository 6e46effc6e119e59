//! For every family: a line that starts an axis moving until told to
//! stop, a line that reads that axis's speed, and what it reads at rest,
//! for tests that an axis left moving is stopped (generic over
//! `families::FAMILIES`: a family missing here fails them).
#![allow(dead_code)]

use axterm::protocol::Family;

pub struct Motion {
    pub start: &'static str,
    pub speed: &'static str,
    pub at_rest: &'static str,
    /// A line that reads the axis's position.
    pub position: &'static str,
    /// Lines that make the axis ready to move (a servo's motor on).
    pub ready: &'static [&'static str],
}

const MOTIONS: &[(&str, Motion)] = &[
    (
        "tmcl",
        Motion {
            start: "ROR 0, 500",
            speed: "GAP 3, 0",
            at_rest: "0",
            position: "GAP 1, 0",
            ready: &[],
        },
    ),
    (
        "sixpack2",
        Motion {
            start: "ConstantRotation 0 100",
            speed: "GetVelocityAndActivity 0",
            at_rest: "vact=0 action=inactive",
            position: "GetPositionAndActivity 0",
            ready: &[],
        },
    ),
    (
        "cmd4cr",
        Motion {
            start: "JX+",
            speed: "PSX",
            at_rest: "0",
            position: "PX",
            ready: &[],
        },
    ),
    (
        "mccl",
        Motion {
            start: "1MN,1VM,1DI0,1GO",
            speed: "1TV",
            at_rest: "0",
            position: "1TP",
            ready: &["1MN"],
        },
    ),
];

/// The motion of `family`; panics for a family this table lacks.
pub fn motion_of(family: &Family) -> &'static Motion {
    MOTIONS
        .iter()
        .find(|(name, _)| *name == family.name)
        .map(|(_, motion)| motion)
        .unwrap_or_else(|| {
            panic!(
                "no motion for the {} family in tests/motion_support",
                family.name
            )
        })
}

impl Motion {
    /// The batch-file line that holds once the axis is at rest.
    pub fn wait_at_rest(&self) -> String {
        format!(":wait-until {} == {} timeout 10s", self.speed, self.at_rest)
    }
}
