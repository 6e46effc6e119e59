//! A command of the instruction set with its operand values, and how it
//! becomes a request and is read back from one.

use std::fmt;

use super::catalog::{
    ALL_MOTORS, CURRENT_STEPS, CommandSpec, Field, FieldKind, MOTOR_FLAGS, Radix, by_code,
};
use super::frame::{PARAMS, Request, get_le, put_le};

/// A documented command and a value for each of its fields, in field
/// order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Command {
    pub spec: &'static CommandSpec,
    pub values: Vec<i64>,
}

/// Why a value does not fit its field.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{command}: {field} {shown} is outside {allowed}")]
pub struct RangeError {
    pub command: &'static str,
    pub field: &'static str,
    /// The value as the console writes it.
    pub shown: String,
    /// What the field takes (`0..5 (Motor 1..6)`).
    pub allowed: String,
}

/// What a field takes, as error messages and help say it.
pub fn allowed(field: &Field) -> String {
    let (min, max) = field.bounds();
    match field.kind {
        FieldKind::Motor => format!("{min}..{max} (Motor 1..6)"),
        FieldKind::OneOf(values) => values
            .iter()
            .map(i64::to_string)
            .collect::<Vec<_>>()
            .join(", "),
        FieldKind::MotorMask => "motors 0..5 (a list such as 0,2,5, all or none)".into(),
        FieldKind::Flags(_) => format!("flag names or 0..${max:X}"),
        FieldKind::CurrentIndex => "0..8 or 100%, 75%, 50%, 38%, 25%, 19%, 13%, 9%, 0%".into(),
        _ if field.radix == Radix::Hex => format!("${min:X}..${max:X}"),
        _ => format!("{min}..{max}"),
    }
}

impl Command {
    /// A command with every value checked against its field.
    pub fn new(spec: &'static CommandSpec, values: Vec<i64>) -> Result<Command, RangeError> {
        for (field, &value) in spec.fields.iter().zip(&values) {
            check(spec, field, value)?;
        }
        let mut values = values;
        values.resize(spec.fields.len(), 0);
        Ok(Command { spec, values })
    }

    /// The value of the field called `name`.
    pub fn value(&self, name: &str) -> Option<i64> {
        let (index, _) = self.spec.field(name)?;
        self.values.get(index).copied()
    }

    /// The motor the command is for, if it has a motno field.
    pub fn motor(&self) -> Option<u8> {
        self.spec
            .fields
            .iter()
            .zip(&self.values)
            .find(|(f, _)| f.kind == FieldKind::Motor)
            .and_then(|(_, v)| u8::try_from(*v).ok())
    }

    /// The frame for the unit at `address`: every field at its place,
    /// LSB first, unused bytes `$00`.
    pub fn to_request(&self, address: u8) -> Request {
        let mut params = [0; PARAMS];
        for (field, &value) in self.spec.fields.iter().zip(&self.values) {
            put_le(&mut params, field.offset, field.width, value);
        }
        Request {
            address,
            command: self.spec.code,
            params,
        }
    }

    /// The documented command a request carries, its values checked.
    /// `Ok(None)`: the command byte is not in §7.
    pub fn from_request(request: &Request) -> Result<Option<Command>, RangeError> {
        let Some(spec) = by_code(request.command) else {
            return Ok(None);
        };
        let values = spec
            .fields
            .iter()
            .map(|f| field_value(f, &request.params))
            .collect();
        Command::new(spec, values).map(Some)
    }

    /// Bytes of a request that no field of its command covers and that
    /// are not `$00` (§6.2: unused bytes are sent as `$00`), as `P5`.
    pub fn stray_bytes(spec: &CommandSpec, params: &[u8; PARAMS]) -> Vec<String> {
        (0..PARAMS)
            .filter(|&i| {
                params[i] != 0
                    && !spec
                        .fields
                        .iter()
                        .any(|f| (f.offset..f.offset + f.width).contains(&i))
            })
            .map(|i| format!("P{i}"))
            .collect()
    }
}

/// A field's value in a request or reply's parameter bytes.
pub fn field_value(field: &Field, params: &[u8; PARAMS]) -> i64 {
    let raw = get_le(params, field.offset, field.width, field.signed());
    match field.kind {
        // Only bit 0 carries the value (§7: "bit 0: …").
        FieldKind::Bit => raw & 1,
        _ => raw,
    }
}

fn check(spec: &'static CommandSpec, field: &'static Field, value: i64) -> Result<(), RangeError> {
    if field.accepts(value) {
        return Ok(());
    }
    Err(RangeError {
        command: spec.mnemonic,
        field: field.name,
        shown: show_out_of_range(field, value),
        allowed: allowed(field),
    })
}

/// An out-of-range value as the user would have typed it.
fn show_out_of_range(field: &Field, value: i64) -> String {
    match field.kind {
        FieldKind::MotorMask | FieldKind::Flags(_) => format!("${value:X}"),
        _ if field.radix == Radix::Hex && value >= 0 => format!("${value:X}"),
        _ => value.to_string(),
    }
}

/// A value as the console writes it: flags and masks by name, currents as
/// percentages, hex where the field reads better so.
pub fn format_value(field: &Field, value: i64) -> String {
    match field.kind {
        FieldKind::MotorMask => format_mask(value),
        FieldKind::Flags(flags) => {
            let mut names: Vec<&str> = flags
                .iter()
                .filter(|f| value & f.mask() != 0)
                .map(|f| f.name)
                .collect();
            let named: i64 = flags.iter().map(|f| f.mask()).sum();
            let rest = value & !named;
            let rest = (rest != 0).then(|| format!("${rest:X}"));
            names.extend(rest.as_deref());
            if names.is_empty() {
                "none".into()
            } else {
                names.join(",")
            }
        }
        FieldKind::CurrentIndex => CURRENT_STEPS
            .iter()
            .find(|s| i64::from(s.index) == value)
            .map_or_else(|| value.to_string(), |s| format!("{}%", s.percent)),
        _ if field.radix == Radix::Hex && value >= 0 => {
            let digits = 2 * field.width;
            format!("${value:0digits$X}")
        }
        _ => value.to_string(),
    }
}

/// A motor mask as a list: `0,2,5`, `all`, `none` (bits 6–7, which name
/// no motor, in hex).
pub fn format_mask(mask: i64) -> String {
    if mask == 0 {
        return "none".into();
    }
    if mask == ALL_MOTORS {
        return "all".into();
    }
    let mut items: Vec<String> = (0..6)
        .filter(|n| mask & (1 << n) != 0)
        .map(|n: i64| n.to_string())
        .collect();
    let rest = mask & !ALL_MOTORS;
    if rest != 0 {
        items.push(format!("${rest:X}"));
    }
    items.join(",")
}

impl fmt::Display for Command {
    /// The canonical console line: the mnemonic and the operands in field
    /// order, trailing operands left out where they hold their default.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let fields = self.spec.fields;
        let mut shown = fields.len();
        while shown > 0 {
            let i = shown - 1;
            match fields[i].default {
                Some(default) if self.values.get(i) == Some(&default) => shown -= 1,
                _ => break,
            }
        }
        f.write_str(self.spec.mnemonic)?;
        for (field, &value) in fields.iter().zip(&self.values).take(shown) {
            write!(f, " {}", format_value(field, value))?;
        }
        Ok(())
    }
}

/// Every flag word bit named, for messages.
pub fn flag_names() -> String {
    MOTOR_FLAGS
        .iter()
        .map(|f| f.name)
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::sixpack2::catalog::by_name;
    use crate::protocol::sixpack2::frame::to_hex;

    fn command(name: &str, values: &[i64]) -> Command {
        Command::new(by_name(name).expect("a command"), values.to_vec()).expect("in range")
    }

    #[test]
    fn fields_land_at_their_bytes_lsb_first() {
        let ramp = command("StartRamp", &[0, 10_000]);
        assert_eq!(
            to_hex(&ramp.to_request(0).to_bytes()),
            "00 23 00 10 27 00 00 00 00"
        );
        let params = command("SetMotorParameters", &[0, 10_000, 0x0410]);
        assert_eq!(
            to_hex(&params.to_request(0).to_bytes()),
            "00 15 00 10 27 00 00 10 04"
        );
        let rotation = command("ConstantRotation", &[5, -511]);
        assert_eq!(
            to_hex(&rotation.to_request(3).to_bytes()),
            "03 25 05 01 FE 00 00 00 00"
        );
    }

    #[test]
    fn requests_read_back_as_their_command() {
        let ramp = command("StartRamp", &[4, -123_456]);
        let request = ramp.to_request(9);
        assert_eq!(Command::from_request(&request), Ok(Some(ramp)));
        let unknown = Request {
            address: 0,
            command: 0x1A,
            params: [0; 7],
        };
        assert_eq!(Command::from_request(&unknown), Ok(None));
        let bad = Request {
            address: 0,
            command: 0x23,
            params: [6, 0, 0, 0, 0, 0, 0],
        };
        let error = Command::from_request(&bad).unwrap_err();
        assert_eq!(
            error.to_string(),
            "StartRamp: motno 6 is outside 0..5 (Motor 1..6)"
        );
    }

    #[test]
    fn out_of_range_values_are_refused_naming_the_field() {
        let spec = by_name("SetAMaxVMax").expect("a command");
        let error = Command::new(spec, vec![0, 500, 2000]).unwrap_err();
        assert_eq!(
            error.to_string(),
            "SetAMaxVMax: vmax 2000 is outside 1..511"
        );
        let spec = by_name("StopMotors").expect("a command");
        let error = Command::new(spec, vec![0xFF]).unwrap_err();
        assert!(error.to_string().contains("$FF"), "{error}");
        let spec = by_name("WriteMotorTable").expect("a command");
        let error = Command::new(spec, vec![3, 0, 0, 0, 0]).unwrap_err();
        assert!(error.to_string().contains("0, 4, 8, 12"), "{error}");
    }

    #[test]
    fn canonical_lines_name_flags_masks_and_currents() {
        assert_eq!(
            command("SetMotorParameters", &[0, 10_000, 0x0410]).to_string(),
            "SetMotorParameters 0 10000 NullLeft,MechRef"
        );
        assert_eq!(
            command("SetMotorParameters", &[1, 0, 0]).to_string(),
            "SetMotorParameters 1 0 none"
        );
        assert_eq!(
            command("StopMotors", &[0b100101]).to_string(),
            "StopMotors 0,2,5"
        );
        assert_eq!(command("StopMotors", &[0x3F]).to_string(), "StopMotors all");
        assert_eq!(
            command("SetCurrentControl", &[0, 8, 2, 1, 0, 500]).to_string(),
            "SetCurrentControl 0 0% 50% 75% 100% 500"
        );
        assert_eq!(
            command("SetRefSearchParameters", &[0, 100, 0x0FFF, 0]).to_string(),
            "SetRefSearchParameters 0 100 $0FFF 0"
        );
        // Trailing defaults are left out.
        assert_eq!(
            command("GetPositionAndActivity", &[2, 0]).to_string(),
            "GetPositionAndActivity 2"
        );
        assert_eq!(
            command("GetPositionAndActivity", &[2, 5]).to_string(),
            "GetPositionAndActivity 2 5"
        );
        assert_eq!(
            command("GetAllActivities", &[0, 0]).to_string(),
            "GetAllActivities"
        );
        assert_eq!(
            command("GetAllActivities", &[0, 3]).to_string(),
            "GetAllActivities 0 0,1"
        );
    }

    #[test]
    fn stray_bytes_are_the_unused_ones_not_zero() {
        let spec = by_name("StartRamp").expect("a command");
        assert!(Command::stray_bytes(spec, &[0, 1, 2, 3, 4, 0, 0]).is_empty());
        assert_eq!(
            Command::stray_bytes(spec, &[0, 1, 2, 3, 4, 9, 1]),
            ["P5", "P6"]
        );
    }

    #[test]
    fn only_bit_zero_of_a_bit_field_counts() {
        let spec = by_name("GetPositionAndActivity").expect("a command");
        let stop = spec.reply.expect("a reply")[3];
        assert_eq!(field_value(&stop, &[0, 0, 0, 0, 0, 0, 0xFE]), 0);
        assert_eq!(field_value(&stop, &[0, 0, 0, 0, 0, 0, 0x03]), 1);
    }
}
