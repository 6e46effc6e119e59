//! Register values and their arithmetic (manual Ch4 "Controller User
//! Registers", Ch11), and how numbers are printed (Ch8 precision p,
//! Ch13 DM/HM).
//!
//! Each register holds a 32-bit integer, a 32-bit float or a 64-bit double.
//! The manual gives two rules for the type of a result: Ch4 says the
//! result "will have the same precision as the command parameter or the
//! accumulator, whichever is more precise"; the AA/AD/AM/AS pages say an
//! integer parameter gives an integer result. The simulator follows Ch4
//! (an integer added to a double stays a double); integers wrap at 32
//! bits and divide toward zero; bitwise operations and shifts work on the
//! accumulator rounded to a 32-bit integer.

use super::lexer::Radix;

/// What a register holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    Int(i32),
    Float(f32),
    Double(f64),
}

impl Default for Value {
    fn default() -> Self {
        Value::Int(0)
    }
}

/// The four arithmetic commands: AA, AS, AM, AD.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arithmetic {
    Add,
    Subtract,
    Multiply,
    Divide,
}

/// The bitwise commands: AN, AO, AE.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bitwise {
    And,
    Or,
    ExclusiveOr,
}

impl Value {
    pub fn as_f64(self) -> f64 {
        match self {
            Value::Int(n) => f64::from(n),
            Value::Float(x) => f64::from(x),
            Value::Double(x) => x,
        }
    }

    /// Rounded to the nearest integer (Ch4: a real register used where an
    /// integer is due), saturating at the 32-bit range.
    pub fn rounded(self) -> i32 {
        match self {
            Value::Int(n) => n,
            real => round_to_i32(real.as_f64()),
        }
    }

    /// Truncated toward zero (C's conversion; AV25, OT's `%d`).
    pub fn rounded_toward_zero(self) -> i32 {
        match self {
            Value::Int(n) => n,
            real => {
                let x = real.as_f64();
                if x.is_nan() {
                    0
                } else {
                    x.trunc().clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32
                }
            }
        }
    }

    pub fn is_real(self) -> bool {
        !matches!(self, Value::Int(_))
    }

    /// Integer < float < double.
    fn precision(self) -> u8 {
        match self {
            Value::Int(_) => 0,
            Value::Float(_) => 1,
            Value::Double(_) => 2,
        }
    }

    /// `self op n` with the type of the more precise of the two. Dividing
    /// by zero is no operation (Ch11 AD).
    pub fn arithmetic(self, op: Arithmetic, n: Value) -> Value {
        if op == Arithmetic::Divide && n.as_f64() == 0.0 {
            return self;
        }
        match self.precision().max(n.precision()) {
            0 => {
                let (a, b) = (self.rounded(), n.rounded());
                Value::Int(match op {
                    Arithmetic::Add => a.wrapping_add(b),
                    Arithmetic::Subtract => a.wrapping_sub(b),
                    Arithmetic::Multiply => a.wrapping_mul(b),
                    Arithmetic::Divide => a.wrapping_div(b),
                })
            }
            precision => {
                let (a, b) = (self.as_f64(), n.as_f64());
                let result = match op {
                    Arithmetic::Add => a + b,
                    Arithmetic::Subtract => a - b,
                    Arithmetic::Multiply => a * b,
                    Arithmetic::Divide => a / b,
                };
                if precision == 1 {
                    Value::Float(result as f32)
                } else {
                    Value::Double(result)
                }
            }
        }
    }

    pub fn bitwise(self, op: Bitwise, n: Value) -> Value {
        let (a, b) = (self.rounded(), n.rounded());
        Value::Int(match op {
            Bitwise::And => a & b,
            Bitwise::Or => a | b,
            Bitwise::ExclusiveOr => a ^ b,
        })
    }
}

pub fn round_to_i32(x: f64) -> i32 {
    if x.is_nan() {
        0
    } else {
        x.round().clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32
    }
}

/// Number of decimals a precision parameter asks for: "the tenths digit
/// will be interpreted as the number of decimal digits" (Ch8); 0 or none
/// is an integer. `None` outside 0 ≤ p < 0.6 (the syntax lists 0 … .5).
pub fn precision_digits(p: f64) -> Option<u8> {
    if !(0.0..0.6).contains(&p) {
        return None;
    }
    Some((p * 10.0 + 1e-9).floor() as u8)
}

/// `value` with `digits` decimals, truncated toward zero as the manual's
/// example shows (123.4567 with `.3` is 123.456), or an integer for 0.
/// Rounded at the ninth decimal first, so that 21.68 stays 21.68.
pub fn fixed(value: f64, digits: u8) -> String {
    if !value.is_finite() {
        return "0".into();
    }
    let text = format!("{value:.9}");
    let (whole, fraction) = text.split_once('.').unwrap_or((&text, ""));
    let cut = if digits == 0 {
        whole.to_string()
    } else {
        format!(
            "{whole}.{}",
            &fraction[..usize::from(digits).min(fraction.len())]
        )
    };
    // A truncated negative that became zero prints without its sign.
    if cut.starts_with('-') && cut[1..].bytes().all(|b| matches!(b, b'0' | b'.')) {
        cut[1..].to_string()
    } else {
        cut
    }
}

/// An integer in the number base in force: decimal, or (HM) eight
/// lower-case hex digits of its 32-bit word (Ch13: status 10 prints as
/// `0000000a`).
pub fn integer(value: i64, radix: Radix) -> String {
    match radix {
        Radix::Decimal => value.to_string(),
        Radix::Hex => format!("{:08x}", value as i32 as u32),
    }
}

/// A Tell value: `digits` decimals, or an integer in the number base.
pub fn tell_value(value: f64, digits: u8, radix: Radix) -> String {
    let text = fixed(value, digits);
    if digits == 0 && radix == Radix::Hex {
        return integer(text.parse::<i64>().unwrap_or(0), radix);
    }
    text
}

/// A register as `TR` prints it: an integer in the number base, a real
/// as C's `%f` (six decimals, as the manual's listing `0.100000` does).
pub fn register_text(value: Value, radix: Radix) -> String {
    match value {
        Value::Int(n) => integer(i64::from(n), radix),
        real => format!("{:.6}", real.as_f64()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use Arithmetic::*;

    #[test]
    fn the_manuals_precision_example() {
        // Ch8: position 123.4567 → 123, 123, 123.4, 123.456.
        let p = 123.4567;
        assert_eq!(tell_value(p, 0, Radix::Decimal), "123");
        assert_eq!(
            tell_value(p, precision_digits(0.1).expect("p"), Radix::Decimal),
            "123.4"
        );
        assert_eq!(
            tell_value(p, precision_digits(0.3).expect("p"), Radix::Decimal),
            "123.456"
        );
        assert_eq!(fixed(21.68, 2), "21.68", "no binary fraction noise");
        assert_eq!(fixed(10.0, 2), "10.00");
        assert_eq!(fixed(-0.4, 0), "0");
        assert_eq!(fixed(-1.25, 1), "-1.2");
        assert_eq!(precision_digits(0.5), Some(5));
        assert_eq!(precision_digits(0.0), Some(0));
        assert_eq!(precision_digits(1.0), None);
        assert_eq!(precision_digits(-0.1), None);
    }

    #[test]
    fn hex_mode_prints_eight_digits_of_the_32_bit_word() {
        assert_eq!(integer(10, Radix::Hex), "0000000a");
        assert_eq!(integer(268_436_489, Radix::Hex), "10000409");
        assert_eq!(integer(-1, Radix::Hex), "ffffffff");
        assert_eq!(tell_value(1000.0, 0, Radix::Hex), "000003e8");
        assert_eq!(tell_value(1.5, 1, Radix::Hex), "1.5", "reals stay decimal");
    }

    #[test]
    fn results_take_the_more_precise_type() {
        let int = Value::Int(7);
        assert_eq!(int.arithmetic(Add, Value::Int(5)), Value::Int(12));
        assert_eq!(int.arithmetic(Divide, Value::Int(2)), Value::Int(3));
        assert_eq!(
            Value::Int(-7).arithmetic(Divide, Value::Int(2)),
            Value::Int(-3)
        );
        assert_eq!(
            int.arithmetic(Multiply, Value::Double(0.5)),
            Value::Double(3.5)
        );
        assert_eq!(
            Value::Double(1.5).arithmetic(Add, Value::Int(1)),
            Value::Double(2.5)
        );
        assert_eq!(
            Value::Float(1.5).arithmetic(Add, Value::Int(1)),
            Value::Float(2.5)
        );
        assert_eq!(
            int.arithmetic(Divide, Value::Int(0)),
            int,
            "AD0 does nothing"
        );
        assert_eq!(int.arithmetic(Divide, Value::Double(0.0)), int);
        assert_eq!(
            Value::Int(i32::MAX).arithmetic(Add, Value::Int(1)),
            Value::Int(i32::MIN),
            "32-bit wrap"
        );
        assert_eq!(
            Value::Double(2.6).bitwise(Bitwise::Or, Value::Int(4)),
            Value::Int(7),
            "bitwise on the rounded integer"
        );
    }

    #[test]
    fn registers_print_integers_in_the_base_and_reals_as_percent_f() {
        assert_eq!(register_text(Value::Int(15), Radix::Decimal), "15");
        assert_eq!(register_text(Value::Int(15), Radix::Hex), "0000000f");
        assert_eq!(
            register_text(Value::Double(0.1), Radix::Decimal),
            "0.100000"
        );
        assert_eq!(Value::Double(-2.5).rounded(), -3);
        assert_eq!(Value::Double(1e20).rounded(), i32::MAX);
    }
}
