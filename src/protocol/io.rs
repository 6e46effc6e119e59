//! A module's inputs and outputs as its manual lists them, for the
//! bring-up pane's lamps: each point with its name, its kind, the console
//! line that reads it and how its state comes out of the answer, and for
//! an output the lines that switch it. Tables are data in
//! `protocol/<family>/io.rs`; the pane watches the read lines with the
//! status poll ([`crate::session::Session::watch_at`]) and decides nothing
//! about a family.

use super::console::ReplyValue;

/// What a point is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IoKind {
    /// A switch of an axis or of the module: limit or stop switch,
    /// home/reference, emergency, alarm.
    Switch,
    /// A general digital input (or a jumper read back).
    DigitalInput,
    /// An analog input; `volts` where the manual gives the scale.
    AnalogInput { volts: Option<VoltScale> },
    /// A digital output: switched with [`IoPoint::set`].
    DigitalOutput,
}

/// Volts from a reading: `(count - zero) * volts_per_count`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VoltScale {
    pub zero: i64,
    pub volts_per_count: f64,
}

impl VoltScale {
    pub fn volts(&self, count: i64) -> f64 {
        (count - self.zero) as f64 * self.volts_per_count
    }
}

/// How a point's state comes out of its read line's answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadRule {
    /// The number read is the state (0/1, or an analog count).
    Value,
    /// Bit `n` of the number read (bit 0 the lowest).
    Bit(u8),
    /// A named field of a text answer (`ttlio1=1`).
    Field(&'static str),
    /// Bit `n` of a named field of a text answer.
    FieldBit(&'static str, u8),
}

/// One input or output.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IoPoint {
    /// As the manual names it (`PWMD0`, `DI1`, `+limit`).
    pub name: &'static str,
    pub kind: IoKind,
    /// The axis (index into the console's axes) a switch belongs to;
    /// `None` for the module's own inputs and outputs.
    pub axis: Option<usize>,
    /// The line that reads it, in its console's canonical form; `None`
    /// where the module cannot read it back (it is shown as last set).
    pub read: Option<&'static str>,
    pub rule: ReadRule,
    /// Read with the fast status items (a switch, a digital input: the
    /// lamp must follow a change within 200 ms) rather than the slow ones.
    pub fast: bool,
    /// For an output: the lines that switch it off and on.
    pub set: Option<[&'static str; 2]>,
    /// What it is, and the manual's section.
    pub what: &'static str,
}

/// A family's inputs and outputs.
pub trait IoPlan: Sync {
    /// Every point, the module's own and every axis's.
    fn points(&self) -> &'static [IoPoint];

    /// What a setting of an output also changes, said before it is sent
    /// (the SIXpack 2 writes all its outputs at once).
    fn output_note(&self) -> &'static str {
        ""
    }

    /// Field `name` of a text answer (`name=value` words), as a number.
    fn field(&self, text: &str, name: &str) -> Option<i64> {
        text.split_whitespace()
            .filter_map(|word| word.split_once('='))
            .find(|(n, _)| *n == name)
            .and_then(|(_, v)| v.parse().ok())
    }

    /// The state of `point` in `reply`, its read line's answer.
    fn state(&self, point: &IoPoint, reply: &ReplyValue) -> Option<i64> {
        let bit = |value: i64, n: u8| (value >> n) & 1;
        match (point.rule, reply) {
            (ReadRule::Value, ReplyValue::Number(v)) => Some(*v),
            (ReadRule::Bit(n), ReplyValue::Number(v)) => Some(bit(*v, n)),
            (ReadRule::Field(name), ReplyValue::Text(text)) => self.field(text, name),
            (ReadRule::FieldBit(name, n), ReplyValue::Text(text)) => {
                self.field(text, name).map(|v| bit(v, n))
            }
            _ => None,
        }
    }
}

impl IoPoint {
    pub fn is_output(&self) -> bool {
        self.kind == IoKind::DigitalOutput
    }
}

/// Const helpers for the family tables.
pub const fn input(
    name: &'static str,
    kind: IoKind,
    axis: Option<usize>,
    read: &'static str,
    rule: ReadRule,
    fast: bool,
    what: &'static str,
) -> IoPoint {
    IoPoint {
        name,
        kind,
        axis,
        read: Some(read),
        rule,
        fast,
        set: None,
        what,
    }
}

/// An output switched by `set` (off, on) and read back by `read`.
pub const fn output(
    name: &'static str,
    read: Option<&'static str>,
    rule: ReadRule,
    set: [&'static str; 2],
    what: &'static str,
) -> IoPoint {
    IoPoint {
        name,
        kind: IoKind::DigitalOutput,
        axis: None,
        read,
        rule,
        fast: false,
        set: Some(set),
        what,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::FAMILIES;
    use crate::protocol::console::Effect;

    /// Every family lists its inputs and outputs; every read line is a
    /// read its console takes, written as the console writes it (the pane
    /// finds its value among the watched lines by it); every set line is
    /// one its console takes.
    #[test]
    fn every_familys_io_lines_are_lines_its_console_takes() {
        for family in FAMILIES {
            let console = family.console;
            let plan = console
                .io()
                .unwrap_or_else(|| panic!("{} has no io plan", family.name));
            let address = console.default_address();
            let points = plan.points();
            assert!(
                points.iter().any(|p| p.kind == IoKind::Switch),
                "{}",
                family.name
            );
            assert!(points.iter().any(IoPoint::is_output), "{}", family.name);
            for point in points {
                if let Some(axis) = point.axis {
                    assert!(
                        axis < console.axes().len(),
                        "{}: {}",
                        family.name,
                        point.name
                    );
                }
                if let Some(line) = point.read {
                    let prepared = console
                        .prepare(line, address)
                        .unwrap_or_else(|e| panic!("{}: {line}: {e}", family.name));
                    assert_eq!(prepared.canonical, line, "{}", family.name);
                    assert_eq!(prepared.effect, Effect::Reads, "{}: {line}", family.name);
                }
                assert_eq!(point.set.is_some(), point.is_output(), "{}", point.name);
                for line in point.set.iter().flatten() {
                    assert!(
                        console.prepare(line, address).is_ok(),
                        "{}: {line}: {:?}",
                        family.name,
                        console.prepare(line, address).err()
                    );
                }
            }
        }
    }

    #[test]
    fn states_come_out_of_numbers_and_fields() {
        struct Plain;
        impl IoPlan for Plain {
            fn points(&self) -> &'static [IoPoint] {
                &[]
            }
        }
        let bit2 = input(
            "x",
            IoKind::DigitalInput,
            None,
            "r",
            ReadRule::Bit(2),
            true,
            "",
        );
        assert_eq!(Plain.state(&bit2, &ReplyValue::Number(4)), Some(1));
        assert_eq!(Plain.state(&bit2, &ReplyValue::Number(3)), Some(0));
        let field = input(
            "y",
            IoKind::DigitalInput,
            None,
            "r",
            ReadRule::Field("jp1"),
            true,
            "",
        );
        let text = ReplyValue::Text("analog=512 jp1=1".into());
        assert_eq!(Plain.state(&field, &text), Some(1));
        assert_eq!(Plain.state(&field, &ReplyValue::Number(1)), None);
        let scale = VoltScale {
            zero: 32768,
            volts_per_count: 10.0 / 32768.0,
        };
        assert!((scale.volts(65536) - 10.0).abs() < 1e-9);
    }
}
