//! The axis parameters the motion model owns and their power-up values.

/// Axis parameters whose values the motion model owns (others are plain
/// storage in the module).
pub const MOTION_PARAMS: &[u8] = &[
    0, 1, 2, 3, 4, 5, 6, 8, 9, 10, 11, 12, 13, 130, 135, 138, 140, 149, 153, 154, 168, 169, 170,
    171, 172, 173, 174, 180, 181, 182, 183, 193, 194, 195, 196, 197, 206, 207, 208, 209, 210, 212,
];

/// A power-up value of a motion parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MotionDefault {
    pub number: u8,
    pub value: i32,
    /// True when the manual states this default; false when it's our choice.
    pub from_manual: bool,
    pub why: &'static str,
}

/// Power-up values of the stored motion parameters. The manual states only
/// AP140 (§6.1.4) and AP174 (§4); the rest are chosen so that
/// `MVP ABS, 0, 51200` (one turn) takes about 2.3 s.
pub const MOTION_DEFAULTS: &[MotionDefault] = &[
    MotionDefault {
        number: 0,
        value: 0,
        from_manual: false,
        why: "target = actual position at power-up, so AP8 = 1",
    },
    MotionDefault {
        number: 2,
        value: 0,
        from_manual: false,
        why: "no target speed",
    },
    MotionDefault {
        number: 4,
        value: 1000,
        from_manual: false,
        why: "30518 pps with pulse divisor 3 (0.6 turns/s at 256 µsteps)",
    },
    MotionDefault {
        number: 5,
        value: 100,
        from_manual: false,
        why: "46566 pps² with divisors 7/3, the §6.1.2 example",
    },
    MotionDefault {
        number: 6,
        value: 128,
        from_manual: false,
        why: "run current, half scale",
    },
    MotionDefault {
        number: 12,
        value: 0,
        from_manual: false,
        why: "right limit switch active",
    },
    MotionDefault {
        number: 13,
        value: 0,
        from_manual: false,
        why: "left limit switch active",
    },
    MotionDefault {
        number: 130,
        value: 1,
        from_manual: false,
        why: "minimum speed; the mangled §4 row reads like 1",
    },
    MotionDefault {
        number: 138,
        value: 0,
        from_manual: false,
        why: "position mode",
    },
    MotionDefault {
        number: 140,
        value: 8,
        from_manual: true,
        why: "§6.1.4: 256 microsteps",
    },
    MotionDefault {
        number: 149,
        value: 0,
        from_manual: false,
        why: "hard stop at a limit switch",
    },
    MotionDefault {
        number: 153,
        value: 7,
        from_manual: false,
        why: "ramp divisor of the §6.1.2 example",
    },
    MotionDefault {
        number: 154,
        value: 3,
        from_manual: false,
        why: "pulse divisor of the §6.1.1 example",
    },
    MotionDefault {
        number: 168,
        value: 0,
        from_manual: false,
        why: "CoolStep minimum 1/2 of the run current",
    },
    MotionDefault {
        number: 169,
        value: 0,
        from_manual: false,
        why: "CoolStep slowest decrement",
    },
    MotionDefault {
        number: 170,
        value: 0,
        from_manual: false,
        why: "CoolStep narrowest hysteresis",
    },
    MotionDefault {
        number: 171,
        value: 0,
        from_manual: false,
        why: "CoolStep slowest increment",
    },
    MotionDefault {
        number: 172,
        value: 0,
        from_manual: true,
        why: "§4: \"Setting this to 0 (default) turns off CoolStep\"",
    },
    MotionDefault {
        number: 173,
        value: 0,
        from_manual: false,
        why: "StallGuard2 filter off (standard mode)",
    },
    MotionDefault {
        number: 174,
        value: 0,
        from_manual: true,
        why: "§4: \"Zero is the starting value\"",
    },
    MotionDefault {
        number: 181,
        value: 0,
        from_manual: false,
        why: "stop on stall off",
    },
    MotionDefault {
        number: 182,
        value: 0,
        from_manual: false,
        why: "CoolStep at any speed once AP172 turns it on",
    },
    MotionDefault {
        number: 183,
        value: 128,
        from_manual: false,
        why: "slow run current = run current",
    },
    MotionDefault {
        number: 193,
        value: 1,
        from_manual: false,
        why: "search the left stop switch",
    },
    MotionDefault {
        number: 194,
        value: 1000,
        from_manual: false,
        why: "search speed = positioning speed",
    },
    MotionDefault {
        number: 195,
        value: 100,
        from_manual: false,
        why: "switch speed a tenth of the search speed",
    },
    MotionDefault {
        number: 196,
        value: 0,
        from_manual: false,
        why: "no search done yet",
    },
    MotionDefault {
        number: 197,
        value: 0,
        from_manual: false,
        why: "no search done yet",
    },
    MotionDefault {
        number: 207,
        value: 0,
        from_manual: false,
        why: "no errors",
    },
    MotionDefault {
        number: 210,
        value: 512,
        from_manual: false,
        why: "prescaler 512/512 = 1: AP209 follows AP1",
    },
    MotionDefault {
        number: 212,
        value: 0,
        from_manual: false,
        why: "deviation stop off",
    },
];
