//! The settings of each axis for the console's parameter table
//! ([`ParameterSet`]), from the read-back table of digest §16: a setting is
//! written with its setup command (`1SV50000`) and read back with its Tell
//! command where there is one (`1TG.5`: SG, SD, SI, IL, VG, SQ) or else
//! from the motor table (`LU"PGMVEL",1RD@0,TR0`, Ch4 "Reading Data from
//! Controller Memory"; which read goes with which variable follows the
//! Ch4 tables, digest §10).
//!
//! A motor-table read loads the accumulator (R0) of the console's
//! interpreter, as any `LU` does: a value the user keeps there is lost.
//!
//! Values are reals; the table holds integers, so each row keeps a fixed
//! number of decimals: the raw value is the real one × 10^decimals (Tell
//! reads give at most 5 decimals, Ch8). MCCL has no store: settings live in
//! the controller's RAM until reset (Ch4: ETH keeps macros, not settings).

use super::catalog::{self, Param};
use super::machine::{AxisKind, Machine};
use crate::protocol::parameters::{
    ParamAccess, ParamError, ParamOp, ParamRange, ParamRefusal, ParamRole, ParamRow, ParamTable,
    ParameterSet, Scope,
};

/// Where a setting is read back from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    /// A Tell command (`TG`), with 5 decimals (`.5`).
    Tell(&'static str),
    /// A motor-table variable, read with the command its table gives.
    Variable(&'static str),
}

/// Which axes have a setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Axes {
    All,
    /// Servos and closed-loop steppers (PID, following error).
    ClosedLoop,
    Servo,
    Stepper,
}

impl Axes {
    fn includes(self, kind: AxisKind) -> bool {
        match self {
            Axes::All => true,
            Axes::ClosedLoop => kind.closed_loop(),
            Axes::Servo => kind == AxisKind::Servo,
            Axes::Stepper => kind != AxisKind::Servo,
        }
    }
}

/// One row: the setup command, what it is, where it is read from, its
/// decimals and unit, and which axes have it. `None` as the command: read
/// only.
struct Setting {
    command: Option<&'static str>,
    name: &'static str,
    source: Source,
    decimals: u32,
    unit: &'static str,
    axes: Axes,
}

const fn setting(
    command: &'static str,
    name: &'static str,
    source: Source,
    decimals: u32,
    unit: &'static str,
    axes: Axes,
) -> Setting {
    Setting {
        command: Some(command),
        name,
        source,
        decimals,
        unit,
        axes,
    }
}

use Source::{Tell, Variable};

/// Digest §16's table, in its order. Units are the manual's defaults
/// (Ch5, digest §14: positions in encoder counts, steps on a stepper;
/// velocities per second): user scaling (US, UR) changes them, which the
/// value's note says.
#[rustfmt::skip]
const SETTINGS: &[Setting] = &[
    setting("SV", "velocity", Variable("PGMVEL"), 3, "counts/s", Axes::All),
    setting("SA", "acceleration", Variable("PGMACC"), 3, "counts/s²", Axes::All),
    setting("DS", "deceleration", Variable("PGMDEC"), 3, "counts/s²", Axes::All),
    setting("MV", "minimum velocity", Variable("MINVEL"), 3, "steps/s", Axes::Stepper),
    setting("SE", "following error limit", Variable("MAXERROR"), 3, "counts", Axes::ClosedLoop),
    setting("DB", "deadband", Variable("POSDBAND"), 3, "counts", Axes::Servo),
    setting("DT", "delay at target", Variable("TGTDELAY"), 4, "s", Axes::Servo),
    setting("HL", "high soft limit", Variable("HILIM"), 3, "counts", Axes::All),
    setting("LL", "low soft limit", Variable("LOLIM"), 3, "counts", Axes::All),
    setting("US", "user scale", Variable("SCALE"), 4, "counts/unit", Axes::All),
    setting("UO", "user offset", Variable("OFFSET"), 4, "units", Axes::All),
    setting("UZ", "user zero", Variable("ZERO"), 4, "units", Axes::All),
    setting("UR", "user rate", Variable("RATE"), 4, "s", Axes::All),
    setting("UK", "user output constant", Variable("OUTCONST"), 4, "", Axes::Servo),
    setting("BD", "backlash distance", Variable("BACKLASH"), 3, "counts", Axes::Servo),
    setting("ES", "steps per encoder count", Variable("ENCSCALE"), 4, "", Axes::Stepper),
    setting("SG", "proportional gain", Tell("TG"), 5, "V/count", Axes::ClosedLoop),
    setting("SD", "derivative gain", Tell("TD"), 5, "", Axes::ClosedLoop),
    setting("SI", "integral gain", Tell("TI"), 5, "", Axes::ClosedLoop),
    setting("IL", "integration limit", Tell("TL"), 5, "", Axes::ClosedLoop),
    setting("VG", "velocity feed-forward", Tell("TK"), 5, "V per count/s", Axes::Servo),
    setting("AG", "acceleration feed-forward", Variable("KACC"), 5, "", Axes::Servo),
    setting("DG", "deceleration feed-forward", Variable("KDEC"), 5, "", Axes::Servo),
    setting("OB", "output deadband", Variable("OUTDBAND"), 4, "V", Axes::Servo),
    setting("OO", "output offset", Variable("OUTOFFSET"), 4, "V", Axes::Servo),
    setting("SQ", "output limit (torque)", Tell("TQ"), 5, "V", Axes::Servo),
    setting("VO", "velocity override", Variable("VELOVRD"), 4, "", Axes::All),
    setting("IO", "integral option", Variable("INTEGRALOPT"), 0, "", Axes::ClosedLoop),
    setting("FR", "derivative sampling period", Variable("SFREQ"), 0, "", Axes::Servo),
    setting("IM", "input mode", Variable("INPUTMODE"), 0, "", Axes::Stepper),
    Setting { command: None, name: "primary status", source: Variable("STATUS"), decimals: 0,
        unit: "", axes: Axes::All },
    Setting { command: None, name: "auxiliary status", source: Variable("AUXSTAT"), decimals: 0,
        unit: "", axes: Axes::All },
];

/// The values Ch5 gives a setting "by default" (what power-up and a reset,
/// RT, restore: Ch13 RT "the default conditions … will be restored"), by
/// setup command, in the command's own units. Only these: Ch5 states no
/// number for SV, SA, DS, MV, SE, DB, DT, HL, LL, UO, UZ, BD, SG, SD, IL,
/// VG, AG, DG, OB, OO or IM, so those have no default here.
/// - ES "The default value is 1." (Ch5 ES)
/// - FR "The default value is 0 (0.00025 seconds)." (Ch5 FR)
/// - IO "0 Integral term always on (default)" (Ch5 IO)
/// - SI "The default value is zero." (Ch5 SI)
/// - SQ "(default = 10.0 volts)" (Ch5 SQ)
/// - UK "The default setting is 1.0." (Ch5 UK)
/// - UR "second 1 (default)" (Ch5 UR, Typical User Rate values)
/// - US "The default setting is 1.0." (Ch5 US)
/// - VO "The default setting (multiplying factor) for this command is 1."
///   (Ch5 VO)
const FACTORY_DEFAULTS: &[(&str, f64)] = &[
    ("ES", 1.0),
    ("FR", 0.0),
    ("IO", 0.0),
    ("SI", 0.0),
    ("SQ", 10.0),
    ("UK", 1.0),
    ("UR", 1.0),
    ("US", 1.0),
    ("VO", 1.0),
];

/// A setting's default as a raw value (× 10^decimals), if Ch5 gives one.
fn factory_default(setting: &Setting) -> Option<i64> {
    let command = setting.command?;
    let (_, value) = FACTORY_DEFAULTS.iter().find(|(c, _)| *c == command)?;
    Some((value * scale(setting.decimals)).round() as i64)
}

/// The MultiFlex's axis settings for the console.
#[derive(Debug, Clone, Copy)]
pub struct MclParameters {
    pub machine: Machine,
}

fn scale(decimals: u32) -> f64 {
    10f64.powi(decimals as i32)
}

/// The range of a row in raw units, from the command's page.
fn raw_range(setting: &Setting) -> ParamRange {
    let command = setting.command.and_then(catalog::find);
    let limit = 1e15;
    let s = scale(setting.decimals);
    let raw = |v: f64| (v * s).round().clamp(-limit, limit) as i64;
    match command.map(|c| c.param) {
        Some(Param::Integer { min, max }) => ParamRange::Span { min, max },
        Some(Param::OneOf(values)) => ParamRange::OneOf(values),
        Some(Param::Real(range)) => {
            let min = range
                .min
                .map_or(-limit as i64, |b| raw(b.value) + i64::from(!b.inclusive));
            let max = range
                .max
                .map_or(limit as i64, |b| raw(b.value) - i64::from(!b.inclusive));
            ParamRange::Span { min, max }
        }
        _ => ParamRange::Span {
            min: i64::from(i32::MIN),
            max: i64::from(u32::MAX),
        },
    }
}

impl MclParameters {
    fn row(&self, axis: u8, number: usize, setting: &Setting, kind: AxisKind) -> ParamRow {
        // Values are shown in their unit with the row's decimals
        // ([`ParameterSet::value_text`]), not as the raw integer.
        let unit = unit_on(setting, kind);
        let description = setting
            .command
            .and_then(catalog::find)
            .map_or("read from the motor table (Ch4)", |c| c.meaning);
        ParamRow {
            scope: Scope::Axis(axis),
            number: u16::try_from(number).unwrap_or(u16::MAX),
            name: match setting.command {
                Some(command) => format!("{command} {}", setting.name),
                None => setting.name.to_string(),
            },
            unit,
            range: raw_range(setting),
            access: ParamAccess {
                read: true,
                write: setting.command.is_some(),
                store: false,
                auto_stored: false,
            },
            role: if setting.command.is_some() {
                ParamRole::Setting
            } else {
                ParamRole::State
            },
            default: factory_default(setting),
            description,
        }
    }
}

/// A setting's unit on an axis of `kind`: an open-loop stepper counts
/// steps where an axis with an encoder counts encoder counts (Ch5: "counts
/// (steps) per second"); the following error (closed loop only) is always
/// in encoder counts.
fn unit_on(setting: &Setting, kind: AxisKind) -> &'static str {
    if kind != AxisKind::OpenLoopStepper {
        return setting.unit;
    }
    match setting.unit {
        "counts/s" => "steps/s",
        "counts/s²" => "steps/s²",
        "counts" => "steps",
        "counts/unit" => "steps/unit",
        unit => unit,
    }
}

/// Rows whose values are in user units (Ch5 US, UR): positions,
/// distances, velocities and accelerations.
fn in_user_units(setting: &Setting) -> bool {
    setting.unit.starts_with("counts") || setting.unit.starts_with("steps")
}

/// The value of the user-units setting `command` (US, UR) of `axis` as
/// read, a real number.
fn user_setting(
    command: &str,
    axis: u8,
    value_of: &dyn Fn(Scope, u16) -> Option<i64>,
) -> Option<f64> {
    let (number, setting) = SETTINGS
        .iter()
        .enumerate()
        .find(|(_, s)| s.command == Some(command))?;
    let raw = value_of(Scope::Axis(axis), u16::try_from(number).ok()?)?;
    Some(raw as f64 / scale(setting.decimals))
}

/// The row number of the user-scaling setting `command` (US, UR) and the
/// factor its value is held scaled by, for the unit law.
pub(crate) fn user_setting_row(command: &str) -> Option<(u16, f64)> {
    let (number, setting) = SETTINGS
        .iter()
        .enumerate()
        .find(|(_, s)| s.command == Some(command))?;
    Some((u16::try_from(number).ok()?, scale(setting.decimals)))
}

fn setting_of(row: &ParamRow) -> Option<&'static Setting> {
    SETTINGS.get(usize::from(row.number))
}

/// A raw value as the real number the controller takes, with the row's
/// decimals.
fn real_text(setting: &Setting, value: i64) -> String {
    let decimals = setting.decimals as usize;
    if decimals == 0 {
        value.to_string()
    } else {
        format!("{:.decimals$}", value as f64 / scale(setting.decimals))
    }
}

impl ParameterSet for MclParameters {
    fn tables(&self, axis: u8) -> Vec<ParamTable> {
        let Some(kind) = self.machine.kind(axis) else {
            return Vec::new();
        };
        let rows = SETTINGS
            .iter()
            .enumerate()
            .filter(|(_, s)| s.axes.includes(kind))
            .map(|(number, s)| self.row(axis, number, s, kind))
            .collect();
        vec![ParamTable {
            scope: Scope::Axis(axis),
            title: format!("Axis {axis} ({}): settings and motor table", kind.name()),
            rows,
        }]
    }

    fn line(&self, row: &ParamRow, op: ParamOp) -> Result<String, ParamError> {
        let setting = setting_of(row).ok_or_else(|| no_setting(row))?;
        let Scope::Axis(axis) = row.scope else {
            return Err(ParamError::new(
                ParamRefusal::NotDone,
                "MCCL settings belong to an axis",
            ));
        };
        match op {
            ParamOp::Read => Ok(match setting.source {
                Tell(tell) => format!("{axis}{tell}.5"),
                Variable(name) => {
                    let read = catalog::variable(name).unwrap_or("RD");
                    format!("LU\"{name}\",{axis}{read}@0,TR0")
                }
            }),
            ParamOp::Write(value) => {
                let Some(command) = setting.command else {
                    return Err(ParamError::new(
                        ParamRefusal::ReadOnly,
                        format!("{} is read only", row.name),
                    ));
                };
                if !row.range.contains(value) {
                    return Err(ParamError::new(
                        ParamRefusal::OutOfRange,
                        format!(
                            "{} {} is outside {}",
                            row.name,
                            real_text(setting, value),
                            catalog::find(command).map_or(String::new(), |c| c.values())
                        ),
                    ));
                }
                Ok(format!("{axis}{command}{}", real_text(setting, value)))
            }
            ParamOp::Store | ParamOp::Restore => Err(ParamError::new(
                ParamRefusal::NotStorable,
                "MCCL keeps settings in the controller's RAM: there is nothing to store or \
                 restore (a reset loads the defaults)",
            )),
        }
    }

    /// The real number with the row's decimals, as `line` writes it and
    /// `parse_value` reads it (`150000.000`, not `150000000`).
    fn value_text(&self, row: &ParamRow, value: i64) -> String {
        match setting_of(row) {
            Some(setting) => real_text(setting, value),
            None => value.to_string(),
        }
    }

    /// The command's range as the manual gives it (`0.000153..10`, `≥ 0`).
    fn range_text(&self, row: &ParamRow) -> String {
        match setting_of(row)
            .and_then(|s| s.command)
            .and_then(catalog::find)
        {
            Some(command) => match command.param {
                Param::Real(range) => range.to_string(),
                _ => row.range.to_string(),
            },
            None => row.range.to_string(),
        }
    }

    fn store_place(&self) -> &'static str {
        "RAM (MCCL has no store)"
    }

    fn value_note(
        &self,
        row: &ParamRow,
        value: i64,
        value_of: &dyn Fn(Scope, u16) -> Option<i64>,
    ) -> Option<String> {
        let setting = setting_of(row)?;
        if setting.command.is_none() {
            let kind = if setting.source == Variable("STATUS") {
                super::status::StatusWordKind::Primary
            } else {
                super::status::StatusWordKind::Auxiliary
            };
            let word = super::status::StatusWord::new(kind, value as u32);
            return Some(word.to_string());
        }
        // The unit shown is right only without user scaling (Ch5: US
        // counts per user unit, UR seconds per user time unit).
        let Scope::Axis(axis) = row.scope else {
            return None;
        };
        let user_scale = user_setting("US", axis, value_of);
        let user_rate = user_setting("UR", axis, value_of);
        let scaled = |v: Option<f64>| v.is_some_and(|v| v != 1.0);
        (in_user_units(setting) && (scaled(user_scale) || scaled(user_rate))).then(|| {
            let text = |v: Option<f64>| v.map_or_else(|| "?".to_string(), |v| v.to_string());
            format!(
                "in user units, not {}: US {} {} per unit, UR {} s per time unit (Ch5)",
                row.unit,
                text(user_scale),
                if row.unit.starts_with("steps") {
                    "steps"
                } else {
                    "counts"
                },
                text(user_rate)
            )
        })
    }

    fn parse_value(
        &self,
        row: &ParamRow,
        text: &str,
        _axis_value: &dyn Fn(u16) -> Option<i64>,
    ) -> Result<i64, ParamError> {
        let setting = setting_of(row).ok_or_else(|| no_setting(row))?;
        let text = text.trim();
        // A typed value may carry the unit the table shows
        // (`150000 counts/s`).
        let bare = match text.strip_suffix(row.unit) {
            Some(rest) if !row.unit.is_empty() => rest.trim_end(),
            _ => text,
        };
        // A reply line (`01 0.04000`) or a typed value (`0.04`).
        let number = bare.rsplit([' ', '\t']).next().unwrap_or(bare);
        let value: f64 = number
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| {
                ParamError::new(
                    ParamRefusal::NotANumber,
                    format!("`{text}` is not a number"),
                )
            })?;
        Ok((value * scale(setting.decimals)).round() as i64)
    }
}

fn no_setting(row: &ParamRow) -> ParamError {
    ParamError::new(
        ParamRefusal::NotAParameter,
        format!("no setting {}", row.number),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::console::FamilyConsole;
    use crate::protocol::mccl::machine::DEFAULT_MACHINE;
    use crate::protocol::mccl::{MclConsole, console::ADDRESS};

    const PARAMETERS: MclParameters = MclParameters {
        machine: DEFAULT_MACHINE,
    };

    fn row(axis: u8, command: &str) -> ParamRow {
        PARAMETERS.tables(axis)[0]
            .rows
            .iter()
            .find(|r| r.name.starts_with(command))
            .cloned()
            .unwrap_or_else(|| panic!("{command} on axis {axis}"))
    }

    #[test]
    fn each_axis_has_the_settings_of_its_kind() {
        let servo = &PARAMETERS.tables(1)[0];
        assert!(servo.title.starts_with("Axis 1 (servo)"));
        let names: Vec<&str> = servo.rows.iter().map(|r| r.name.as_str()).collect();
        assert!(names.contains(&"SG proportional gain") && !names.contains(&"MV minimum velocity"));
        let stepper: Vec<String> = PARAMETERS.tables(5)[0]
            .rows
            .iter()
            .map(|r| r.name.clone())
            .collect();
        assert!(stepper.iter().any(|n| n == "MV minimum velocity"));
        assert!(
            !stepper.iter().any(|n| n.starts_with("SG")),
            "open loop: no PID"
        );
        assert!(PARAMETERS.tables(6).is_empty());
    }

    #[test]
    fn the_defaults_chapter_5_states_are_the_rows_defaults_in_raw_units() {
        // Written out from Ch5, raw = value × 10^decimals: SQ "default =
        // 10.0 volts" (5 decimals), SI "default value is zero", US and UK
        // "default setting is 1.0" and VO 1 (4 decimals), UR "second 1
        // (default)", FR "default value is 0", IO 0 "(default)"; ES "default
        // value is 1" on the stepper.
        for (axis, command, raw) in [
            (1, "SQ", 1_000_000),
            (1, "SI", 0),
            (2, "US", 10_000),
            (2, "UK", 10_000),
            (3, "VO", 10_000),
            (3, "UR", 10_000),
            (4, "FR", 0),
            (4, "IO", 0),
            (5, "ES", 10_000),
            (5, "US", 10_000),
        ] {
            assert_eq!(row(axis, command).default, Some(raw), "{command} {axis}");
        }
        // Ch5 gives no number for these (its examples are not defaults).
        for (axis, command) in [(1, "SV"), (1, "SG"), (1, "SD"), (1, "SE"), (5, "MV")] {
            assert_eq!(row(axis, command).default, None, "{command} {axis}");
        }
        assert_eq!(row(1, "primary status").default, None);
        // The table's own text of the default reads as the manual's number.
        let sq = row(1, "SQ");
        assert_eq!(PARAMETERS.value_text(&sq, sq.default.unwrap()), "10.00000");
    }

    #[test]
    fn reads_use_the_tell_command_or_the_motor_table() {
        assert_eq!(
            PARAMETERS.line(&row(1, "SG"), ParamOp::Read).as_deref(),
            Ok("1TG.5")
        );
        assert_eq!(
            PARAMETERS.line(&row(2, "SV"), ParamOp::Read).as_deref(),
            Ok("LU\"PGMVEL\",2RD@0,TR0")
        );
        assert_eq!(
            PARAMETERS.line(&row(1, "AG"), ParamOp::Read).as_deref(),
            Ok("LU\"KACC\",1RV@0,TR0")
        );
        assert_eq!(
            PARAMETERS.line(&row(1, "IO"), ParamOp::Read).as_deref(),
            Ok("LU\"INTEGRALOPT\",1RW@0,TR0")
        );
        // Every line the table sends parses and checks.
        for axis in 1..=5 {
            for r in &PARAMETERS.tables(axis)[0].rows {
                let read = PARAMETERS.line(r, ParamOp::Read).expect("read");
                MclConsole::DEFAULT
                    .prepare(&read, ADDRESS)
                    .unwrap_or_else(|e| panic!("{read}: {e}"));
            }
        }
    }

    #[test]
    fn writes_scale_back_and_check_the_range() {
        let sg = row(1, "SG");
        assert_eq!(sg.unit, "V/count");
        assert_eq!(
            PARAMETERS.line(&sg, ParamOp::Write(4000)).as_deref(),
            Ok("1SG0.04000")
        );
        let e = PARAMETERS
            .line(&sg, ParamOp::Write(2_000_000))
            .unwrap_err()
            .to_string();
        assert!(e.contains("0.000153..10"), "{e}");
        let ds = row(1, "DS");
        assert!(PARAMETERS.line(&ds, ParamOp::Write(0)).is_err(), "DS > 0");
        assert_eq!(
            PARAMETERS.line(&ds, ParamOp::Write(1)).as_deref(),
            Ok("1DS0.001")
        );
        assert_eq!(
            PARAMETERS
                .line(&row(5, "IM"), ParamOp::Write(128))
                .as_deref(),
            Ok("5IM128")
        );
        assert!(PARAMETERS.line(&row(5, "IM"), ParamOp::Write(2)).is_err());
        assert!(
            PARAMETERS
                .line(&row(1, "primary"), ParamOp::Write(1))
                .is_err()
        );
        assert!(
            PARAMETERS
                .line(&sg, ParamOp::Store)
                .unwrap_err()
                .message
                .contains("RAM")
        );
        for write in [
            PARAMETERS.line(&sg, ParamOp::Write(4000)),
            PARAMETERS.line(&ds, ParamOp::Write(1)),
        ] {
            let write = write.expect("write");
            MclConsole::DEFAULT
                .prepare(&write, ADDRESS)
                .unwrap_or_else(|e| panic!("{write}: {e}"));
        }
    }

    #[test]
    fn values_read_as_reals_and_notes_show_them() {
        let sg = row(1, "SG");
        let none = |_: u16| None;
        assert_eq!(PARAMETERS.parse_value(&sg, "0.04000", &none), Ok(4000));
        assert_eq!(PARAMETERS.parse_value(&sg, "01 0.00032", &none), Ok(32));
        assert!(PARAMETERS.parse_value(&sg, "x", &none).is_err());
        let sv = row(1, "SV");
        assert_eq!(
            PARAMETERS.parse_value(&sv, "100000", &none),
            Ok(100_000_000)
        );
        // Shown in the unit, in the text an edit starts from and reads back.
        assert_eq!(PARAMETERS.value_text(&sv, 150_000_000), "150000.000");
        assert_eq!(sv.unit, "counts/s");
        assert_eq!(
            PARAMETERS.parse_value(&sv, "150000 counts/s", &none),
            Ok(150_000_000)
        );
        assert!(
            PARAMETERS
                .parse_value(&sv, "150000 steps/s", &none)
                .is_err()
        );
        assert_eq!(row(5, "SV").unit, "steps/s", "an open-loop stepper");
        for r in &PARAMETERS.tables(1)[0].rows {
            let value = 1_234_567;
            let text = PARAMETERS.value_text(r, value);
            assert_eq!(
                PARAMETERS.parse_value(r, &text, &none),
                Ok(value),
                "{}",
                r.name
            );
        }
        let no = |_: Scope, _: u16| None;
        assert_eq!(
            PARAMETERS.value_note(&sg, 4000, &no),
            None,
            "no user units read"
        );
        // US (row 9) 2.0: velocities are in user units, not counts/s.
        let scaled = |_: Scope, n: u16| (n == 9).then_some(20_000);
        assert_eq!(
            PARAMETERS.value_note(&sv, 100_000_000, &scaled).as_deref(),
            Some("in user units, not counts/s: US 2 counts per unit, UR ? s per time unit (Ch5)")
        );
        assert_eq!(PARAMETERS.value_note(&sg, 4000, &scaled), None, "volts");
        let status = row(1, "primary");
        assert_eq!(
            PARAMETERS.value_note(&status, 10, &no).as_deref(),
            Some("motor on, trajectory complete")
        );
    }
}
