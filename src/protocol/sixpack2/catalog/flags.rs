//! The named bits of the `$15` motor flags, the `$11` current steps and
//! the activity codes of `$21`/`$22` (§7.1), as data.

use super::*;

/// `$15` P5/P6, the motor type word (§7.1; bit places confirmed by the
/// §5.5.3 examples, digest D4). Default `$0AA0` (§6.8).
pub const MOTOR_FLAGS: &[FlagBit] = &[
    FlagBit {
        bit: 0,
        name: "PIMode",
        sqpack: None,
        meaning: "1 = PI controller, 0 = trapezoidal ramp",
    },
    FlagBit {
        bit: 1,
        name: "Rotary",
        sqpack: Some("MT_ROTARY"),
        meaning: "rotary axis: positions wrap modulo poslimit (§6.6.6)",
    },
    FlagBit {
        bit: 2,
        name: "AutonullCmd",
        sqpack: None,
        meaning: "starts a reference search, the same action as $22: writing it homes the motor",
    },
    FlagBit {
        bit: 3,
        name: "TestNull",
        sqpack: Some("MT_TESTNULL"),
        meaning: "stop flag (and a reference search unless StopNoRef) when the motor rests at \
                  zero but the switch stays inactive (§6.4.4)",
    },
    FlagBit {
        bit: 4,
        name: "NullLeft",
        sqpack: Some("MT_NULLLEFT"),
        meaning: "1 = zero point left of the driving range (positions >= 0), 0 = right \
                  (positions <= 0)",
    },
    FlagBit {
        bit: 5,
        name: "NullCenter",
        sqpack: None,
        meaning: "zero point at the centre of the switch's active zone (rotary axes)",
    },
    FlagBit {
        bit: 6,
        name: "StopNull",
        sqpack: Some("MT_STOPNULL"),
        meaning: "stop (and stop flag) when the switch is active outside ±testnullrange or an \
                  A_In limit ($31) is passed (§6.5.2)",
    },
    FlagBit {
        bit: 7,
        name: "FilterSwitch",
        sqpack: None,
        meaning: "debounce the reference input with the $16 mask (2-30 ms)",
    },
    FlagBit {
        bit: 8,
        name: "WayOptimization",
        sqpack: Some("MT_OPTIMIZEWAY"),
        meaning: "rotary axis: take the shorter way round",
    },
    FlagBit {
        bit: 9,
        name: "FastRef",
        sqpack: Some("MT_FASTREF"),
        meaning: "search the switch at vrefmax ($16); needs a correct poslimit (§6.4.8)",
    },
    FlagBit {
        bit: 10,
        name: "MechRef",
        sqpack: Some("MT_MECHREF"),
        meaning: "mechanical reference: drive 5/4·poslimit against the stop (linear axes, §5.5.1)",
    },
    FlagBit {
        bit: 11,
        name: "DelayTestNull",
        sqpack: Some("MT_DELAYTESTNULL"),
        meaning: "delay the zero-point check by T0 ($11, §6.4.6)",
    },
    FlagBit {
        bit: 12,
        name: "StopSoft",
        sqpack: None,
        meaning: "on a stop condition decelerate with amax instead of stopping abruptly",
    },
    FlagBit {
        bit: 13,
        name: "StopNoRef",
        sqpack: None,
        meaning: "on a stop condition just stop: no automatic reference search (P6 bit 5, \
                  digest E13)",
    },
    FlagBit {
        bit: 14,
        name: "NullPositive",
        sqpack: Some("MT_NULLPOSITIVE"),
        meaning: "1 = reference switch active high (a normally closed switch to GND, §5.5.2.3)",
    },
    FlagBit {
        bit: 15,
        name: "StopAtFullsteps",
        sqpack: None,
        meaning: "ramps stop only at the nearest full-step position",
    },
];

/// The flag called `name` (§7.1 name or SQPack's `MT_…`, any case).
pub fn flag_by_name(name: &str) -> Option<&'static FlagBit> {
    MOTOR_FLAGS.iter().find(|f| {
        f.name.eq_ignore_ascii_case(name) || f.sqpack.is_some_and(|s| s.eq_ignore_ascii_case(name))
    })
}

/// One step of the `$11` current control: index and percentage of the
/// peak current (§7.1; 0-based as the §6.7 example counts, digest E11).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CurrentStep {
    pub index: u8,
    pub percent: u8,
}

pub const CURRENT_STEPS: &[CurrentStep] = &[
    CurrentStep {
        index: 0,
        percent: 100,
    },
    CurrentStep {
        index: 1,
        percent: 75,
    },
    CurrentStep {
        index: 2,
        percent: 50,
    },
    CurrentStep {
        index: 3,
        percent: 38,
    },
    CurrentStep {
        index: 4,
        percent: 25,
    },
    CurrentStep {
        index: 5,
        percent: 19,
    },
    CurrentStep {
        index: 6,
        percent: 13,
    },
    CurrentStep {
        index: 7,
        percent: 9,
    },
    CurrentStep {
        index: 8,
        percent: 0,
    },
];

/// What a motor is doing, as `$20`, `$21` and `$28` report it (§7.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Activity {
    pub first: u8,
    pub last: u8,
    /// A word without blanks, for reply values (`action=ramp`).
    pub token: &'static str,
    /// How the console shows it.
    pub name: &'static str,
    pub meaning: &'static str,
}

pub const ACTIONS: &[Activity] = &[
    Activity {
        first: 0,
        last: 0,
        token: "inactive",
        name: "inactive",
        meaning: "the motor stands",
    },
    Activity {
        first: 5,
        last: 5,
        token: "ramp",
        name: "ramp",
        meaning: "trapezoidal ramp ($23, $29, $50)",
    },
    Activity {
        first: 10,
        last: 10,
        token: "PI",
        name: "PI",
        meaning: "PI controller ($24)",
    },
    Activity {
        first: 15,
        last: 15,
        token: "rotation",
        name: "rotation",
        meaning: "constant rotation ($25)",
    },
    Activity {
        first: 20,
        last: 29,
        token: "refsearch",
        name: "ref search",
        meaning: "reference switch search ($22; the manual does not say what each of 20-29 means)",
    },
    Activity {
        first: 30,
        last: 30,
        token: "mechref",
        name: "mech ref",
        meaning: "mechanical reference ($28 calls it mechanical calibration)",
    },
];

/// The activity of an action code, if the manual names it.
pub fn activity(code: u8) -> Option<&'static Activity> {
    ACTIONS.iter().find(|a| (a.first..=a.last).contains(&code))
}

/// An action code as a reply value shows it: `ramp`, `refsearch23`, or
/// the number when the manual gives it no meaning.
pub fn action_token(code: u8) -> String {
    match activity(code) {
        Some(a) if a.first != a.last => format!("{}{code}", a.token),
        Some(a) => a.token.to_string(),
        None => code.to_string(),
    }
}

/// The action code a reply value's token stands for.
pub fn action_from_token(token: &str) -> Option<u8> {
    if let Ok(code) = token.parse::<u8>() {
        return Some(code);
    }
    ACTIONS.iter().find_map(|a| {
        if a.first == a.last {
            a.token.eq_ignore_ascii_case(token).then_some(a.first)
        } else {
            let rest = token.get(a.token.len()..)?;
            let head = token.get(..a.token.len())?;
            let code = rest.parse::<u8>().ok()?;
            (head.eq_ignore_ascii_case(a.token) && (a.first..=a.last).contains(&code))
                .then_some(code)
        }
    })
}
