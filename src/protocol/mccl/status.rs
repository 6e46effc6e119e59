//! The five status words `aTSn` reports (Ch8 TS), bit by bit, as data: the
//! primary word (n = 0, also `LU"STATUS"`), the auxiliary word (64,
//! `LU"AUXSTAT"`), the profile generator (96), the trajectory mode (128)
//! and the encoder fault word (160; its heading misprints "n = 128", digest
//! §19 #18). `TS n` with n = 1–31 above a word's number reports one bit of
//! it as 1 or 0; reserved bits are not listed.

use std::fmt;

/// Which word.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StatusWordKind {
    Primary,
    Auxiliary,
    ProfileGenerator,
    TrajectoryMode,
    EncoderFault,
}

impl StatusWordKind {
    pub const ALL: [StatusWordKind; 5] = [
        StatusWordKind::Primary,
        StatusWordKind::Auxiliary,
        StatusWordKind::ProfileGenerator,
        StatusWordKind::TrajectoryMode,
        StatusWordKind::EncoderFault,
    ];

    /// The `TS` parameter that reports the whole word.
    pub fn selector(self) -> u16 {
        match self {
            StatusWordKind::Primary => 0,
            StatusWordKind::Auxiliary => 64,
            StatusWordKind::ProfileGenerator => 96,
            StatusWordKind::TrajectoryMode => 128,
            StatusWordKind::EncoderFault => 160,
        }
    }

    pub fn title(self) -> &'static str {
        match self {
            StatusWordKind::Primary => "primary status",
            StatusWordKind::Auxiliary => "auxiliary status",
            StatusWordKind::ProfileGenerator => "profile generator status",
            StatusWordKind::TrajectoryMode => "trajectory mode status",
            StatusWordKind::EncoderFault => "encoder fault status",
        }
    }

    pub fn bits(self) -> &'static [StatusBit] {
        match self {
            StatusWordKind::Primary => PRIMARY,
            StatusWordKind::Auxiliary => AUXILIARY,
            StatusWordKind::ProfileGenerator => PROFILE_GENERATOR,
            StatusWordKind::TrajectoryMode => TRAJECTORY_MODE,
            StatusWordKind::EncoderFault => ENCODER_FAULT,
        }
    }
}

/// What `TS n` asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StatusSelector {
    Word(StatusWordKind),
    /// One bit, 1–31 (bit 0 has no query of its own: `TS0` is the word).
    Bit(StatusWordKind, u8),
}

impl StatusSelector {
    /// The selector of `TS n`, if n is one (0–31, 64–191).
    pub fn from_parameter(n: i64) -> Option<StatusSelector> {
        let kind = StatusWordKind::ALL
            .into_iter()
            .find(|k| (i64::from(k.selector())..i64::from(k.selector()) + 32).contains(&n))?;
        let bit = u8::try_from(n - i64::from(kind.selector())).ok()?;
        Some(if bit == 0 {
            StatusSelector::Word(kind)
        } else {
            StatusSelector::Bit(kind, bit)
        })
    }

    pub fn kind(self) -> StatusWordKind {
        match self {
            StatusSelector::Word(kind) | StatusSelector::Bit(kind, _) => kind,
        }
    }
}

/// How a bit reads on a console.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BitClass {
    /// A fault the controller latches until `MN` (primary bits 0, 8–15).
    Error,
    /// The state of an input now (primary bits 24–29).
    Input,
    /// Anything else: a state, a mode, a setting.
    State,
}

/// One bit of a status word.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct StatusBit {
    pub bit: u8,
    /// Short name for a lamp or a flag list.
    pub name: &'static str,
    /// The manual's description.
    pub meaning: &'static str,
    pub class: BitClass,
}

const fn bit(bit: u8, name: &'static str, meaning: &'static str, class: BitClass) -> StatusBit {
    StatusBit {
        bit,
        name,
        meaning,
        class,
    }
}

use BitClass::{Error, Input, State};

/// Primary status word (n = 0), Ch8 TS.
pub const PRIMARY: &[StatusBit] = &[
    bit(
        0,
        "motor error",
        "Motor Error (limit tripped, max. following error exceeded)",
        Error,
    ),
    bit(1, "motor on", "Motor On", State),
    bit(2, "at target", "At Target", State),
    bit(
        3,
        "trajectory complete",
        "Trajectory Complete (Optimal = Target)",
        State,
    ),
    bit(
        4,
        "direction −",
        "Direction (0 = positive, 1 = negative)",
        State,
    ),
    bit(5, "captured", "Position Captured", State),
    bit(6, "breakpoint", "Breakpoint Reached (IP, IR)", State),
    bit(8, "following error", "Exceeded Max. Following Error", Error),
    bit(
        9,
        "amp fault",
        "Servo Amplifier / Stepper Driver Fault Tripped",
        Error,
    ),
    bit(10, "hard limit +", "Hard Limit Positive Tripped", Error),
    bit(11, "hard limit −", "Hard Limit Negative Tripped", Error),
    bit(
        12,
        "soft limit high",
        "Soft Motion Limit High Tripped",
        Error,
    ),
    bit(13, "soft limit low", "Soft Motion Limit Low Tripped", Error),
    bit(14, "encoder fault", "Primary Encoder Fault Tripped", Error),
    bit(
        15,
        "aux encoder fault",
        "Auxiliary Encoder Fault Tripped (not supported)",
        Error,
    ),
    bit(
        17,
        "looking for index",
        "Looking For Index (FI, WI) / Looking For Edge (FE, WE)",
        State,
    ),
    bit(
        18,
        "index found",
        "Index found (closed loop) / Edge found (open loop stepper)",
        State,
    ),
    bit(
        19,
        "looking for aux index",
        "Looking For Aux. Index (open loop stepper)",
        State,
    ),
    bit(
        20,
        "aux index found",
        "Aux. Encoder Index found (open loop stepper)",
        State,
    ),
    bit(21, "homed", "Motor homed", State),
    bit(
        24,
        "index/home in",
        "Encoder Index (closed loop) / Stepper Home (current state)",
        Input,
    ),
    bit(
        25,
        "coarse home in",
        "Encoder Coarse Home (current state)",
        Input,
    ),
    bit(
        26,
        "aux index in",
        "Auxiliary Encoder Index (current state)",
        Input,
    ),
    bit(
        27,
        "amp fault in",
        "Servo Amplifier / Stepper Driver Fault (current state)",
        Input,
    ),
    bit(
        28,
        "limit + in",
        "Limit Positive Input Active (current state)",
        Input,
    ),
    bit(
        29,
        "limit − in",
        "Limit Negative Input Active (current state)",
        Input,
    ),
];

/// Auxiliary status word (n = 64).
pub const AUXILIARY: &[StatusBit] = &[
    bit(
        0,
        "hard limit + on",
        "Hard Motion Limit Positive Enabled",
        State,
    ),
    bit(
        1,
        "hard limit − on",
        "Hard Motion Limit Negative Enabled",
        State,
    ),
    bit(
        2,
        "hard limit abrupt",
        "Hard Motion Limit Mode Abrupt",
        State,
    ),
    bit(
        3,
        "hard limit smooth",
        "Hard Motion Limit Mode Smooth",
        State,
    ),
    bit(
        4,
        "soft limit high on",
        "Soft Motion Limit High Enabled",
        State,
    ),
    bit(
        5,
        "soft limit low on",
        "Soft Motion Limit Low Enabled",
        State,
    ),
    bit(
        6,
        "soft limit abrupt",
        "Soft Motion Limit Mode Abrupt",
        State,
    ),
    bit(
        7,
        "soft limit smooth",
        "Soft Motion Limit Mode Smooth",
        State,
    ),
    bit(8, "limit + inverted", "Positive Limit Invert", State),
    bit(9, "limit − inverted", "Negative Limit Invert", State),
    bit(
        10,
        "fault check on",
        "Amplifier / Driver Fault Enabled",
        State,
    ),
    bit(
        11,
        "phase reversed",
        "Phasing (0 = Standard, 1 = Reverse)",
        State,
    ),
    bit(12, "backlash on", "Backlash Compensation = On", State),
    bit(
        13,
        "backlash +",
        "Backlash Compensation Positive Direction",
        State,
    ),
    bit(
        14,
        "backlash −",
        "Backlash Compensation Negative Direction",
        State,
    ),
    bit(16, "low speed", "Low Speed", State),
    bit(17, "medium speed", "Medium Speed", State),
    bit(18, "high speed", "High Speed", State),
    bit(
        20,
        "waiting for compare",
        "Waiting For Primary Compare",
        State,
    ),
    bit(
        21,
        "waiting for capture",
        "Waiting For Primary Capture",
        State,
    ),
    bit(22, "sync on", "Synchronization On", State),
    bit(23, "sync ready", "Ready for Synchronized move", State),
    bit(26, "full step", "Full Step (stepper only)", State),
    bit(27, "full current", "Full Current (stepper only)", State),
    bit(
        28,
        "open-loop PID",
        "Open Loop Enable PID changes (stepper only)",
        State,
    ),
];

/// Profile generator status word (n = 96).
pub const PROFILE_GENERATOR: &[StatusBit] = &[
    bit(0, "trajectory complete", "Trajectory Complete", State),
    bit(
        1,
        "direction −",
        "Direction (0 = positive, 1 = negative)",
        State,
    ),
    bit(2, "desired direction", "Desired Direction", State),
    bit(3, "accelerating", "Acceleration Mode", State),
    bit(5, "stopping", "Motor Stopping", State),
    bit(12, "trapezoidal", "Trapezoidal profile", State),
    bit(13, "S-curve", "S-curve profile", State),
    bit(14, "parabolic", "Parabolic profile", State),
];

/// Trajectory mode status word (n = 128).
pub const TRAJECTORY_MODE: &[StatusBit] = &[
    bit(0, "position mode", "Position Mode", State),
    bit(1, "velocity mode", "Velocity Mode", State),
    bit(2, "gain mode", "Gain Mode", State),
    bit(3, "torque mode", "Torque Mode", State),
    bit(4, "contour mode", "Contour Mode", State),
    bit(16, "slave to axis", "Slave to Master Axis", State),
    bit(17, "slave to contour", "Slave to Master Contour", State),
    bit(18, "slave to encoder", "Slave to Master Encoder", State),
    bit(19, "slave to index", "Slave to Master Index Mark", State),
];

/// Encoder fault status word (n = 160; bits 0–3 and 12 on axes 1, 3, 5
/// and 7 only).
pub const ENCODER_FAULT: &[StatusBit] = &[
    bit(0, "encoder fault", "Primary Encoder Fault", Error),
    bit(1, "phase A fault", "Primary Encoder Phase A Fault", Error),
    bit(2, "phase B fault", "Primary Encoder Phase B Fault", Error),
    bit(3, "phase Z fault", "Primary Encoder Phase Z Fault", Error),
    bit(
        4,
        "aux encoder fault",
        "Auxiliary Encoder Fault (not supported)",
        Error,
    ),
    bit(
        12,
        "encoder check on",
        "Primary Encoder Fault Enabled",
        State,
    ),
    bit(
        16,
        "aux check on",
        "Auxiliary Encoder Fault Enabled (not supported)",
        State,
    ),
];

/// A status word as read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct StatusWord {
    pub kind: StatusWordKind,
    pub value: u32,
}

impl StatusWord {
    pub fn new(kind: StatusWordKind, value: u32) -> StatusWord {
        StatusWord { kind, value }
    }

    pub fn is_set(&self, bit: u8) -> bool {
        bit < 32 && self.value & (1 << bit) != 0
    }

    /// The listed bits that are set, in bit order.
    pub fn set_bits(&self) -> impl Iterator<Item = &'static StatusBit> + '_ {
        self.kind.bits().iter().filter(|b| self.is_set(b.bit))
    }

    /// Set bits the manual calls reserved (or does not list).
    pub fn unlisted_bits(&self) -> Vec<u8> {
        (0..32)
            .filter(|&b| self.is_set(b) && !self.kind.bits().iter().any(|s| s.bit == b))
            .collect()
    }
}

impl fmt::Display for StatusWord {
    /// The set bits by name (`motor on, trajectory complete`); `none` when
    /// none is set.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut names: Vec<String> = self.set_bits().map(|b| b.name.to_string()).collect();
        names.extend(self.unlisted_bits().into_iter().map(|b| format!("bit {b}")));
        if names.is_empty() {
            f.write_str("none set")
        } else {
            f.write_str(&names.join(", "))
        }
    }
}

/// The bit `n` of word `kind`, if listed.
pub fn describe_bit(kind: StatusWordKind, n: u8) -> Option<&'static StatusBit> {
    kind.bits().iter().find(|b| b.bit == n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_manuals_example_word_decodes_to_its_four_bits() {
        // Ch8 TS: `01 268436489` = bits 28, 10, 3, 0.
        let word = StatusWord::new(StatusWordKind::Primary, 268_436_489);
        let bits: Vec<u8> = word.set_bits().map(|b| b.bit).collect();
        assert_eq!(bits, [0, 3, 10, 28]);
        assert_eq!(
            word.to_string(),
            "motor error, trajectory complete, hard limit +, limit + in"
        );
        // Ch13 DM/HM: 10 = bits 3 and 1.
        let word = StatusWord::new(StatusWordKind::Primary, 10);
        assert_eq!(word.to_string(), "motor on, trajectory complete");
        assert_eq!(
            StatusWord::new(StatusWordKind::Primary, 1 << 30).to_string(),
            "bit 30"
        );
        assert_eq!(
            StatusWord::new(StatusWordKind::Auxiliary, 0).to_string(),
            "none set"
        );
    }

    #[test]
    fn selectors_are_words_and_their_bits() {
        use StatusWordKind::*;
        assert_eq!(
            StatusSelector::from_parameter(0),
            Some(StatusSelector::Word(Primary))
        );
        assert_eq!(
            StatusSelector::from_parameter(3),
            Some(StatusSelector::Bit(Primary, 3))
        );
        assert_eq!(
            StatusSelector::from_parameter(64),
            Some(StatusSelector::Word(Auxiliary))
        );
        assert_eq!(
            StatusSelector::from_parameter(191),
            Some(StatusSelector::Bit(EncoderFault, 31))
        );
        assert_eq!(
            StatusSelector::from_parameter(160),
            Some(StatusSelector::Word(EncoderFault))
        );
        for n in [-1, 32, 63, 192] {
            assert_eq!(StatusSelector::from_parameter(n), None, "{n}");
        }
    }

    #[test]
    fn the_latched_faults_are_the_error_bits() {
        let errors: Vec<u8> = PRIMARY
            .iter()
            .filter(|b| b.class == BitClass::Error)
            .map(|b| b.bit)
            .collect();
        assert_eq!(errors, [0, 8, 9, 10, 11, 12, 13, 14, 15]);
        for kind in StatusWordKind::ALL {
            let bits = kind.bits();
            assert!(bits.windows(2).all(|w| w[0].bit < w[1].bit), "{kind:?}");
        }
    }
}
