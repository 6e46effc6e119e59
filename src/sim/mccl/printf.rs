//! The formatting of OT / OD / FT / FD (manual Ch4 "Outputting Formatted
//! Message Strings"): "patterned after standard 'C' function printf", with
//! the accumulator as the one variable, `\n` a line feed and `\r` a
//! carriage return.
//!
//! Supported: `%d %i %u %x %X %o %c %f %F %e %E %g %G %%` with the flags
//! `- + space 0 #`, a width and a precision; `\n \r \t \\` escapes. Every
//! conversion takes the accumulator (the manual shows one per string; more
//! than one repeats it). Anything else is printed as typed.

/// The accumulator as the format sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Argument {
    /// OT, FT: the accumulator as an integer.
    Integer(i64),
    /// OD, FD: the accumulator as a double.
    Double(f64),
}

impl Argument {
    fn integer(self) -> i64 {
        match self {
            Argument::Integer(n) => n,
            // C's conversion of a double to an integer truncates.
            Argument::Double(x) if x.is_finite() => x.trunc() as i64,
            Argument::Double(_) => 0,
        }
    }

    fn double(self) -> f64 {
        match self {
            Argument::Integer(n) => n as f64,
            Argument::Double(x) => x,
        }
    }
}

#[derive(Default)]
struct Spec {
    left: bool,
    plus: bool,
    space: bool,
    zero: bool,
    alternate: bool,
    width: usize,
    precision: Option<usize>,
}

/// `format` with every conversion filled from `argument`.
pub fn format(format: &str, argument: Argument) -> String {
    let chars: Vec<char> = format.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < chars.len() {
        match chars[i] {
            '\\' => {
                match chars.get(i + 1) {
                    Some('n') => out.push('\n'),
                    Some('r') => out.push('\r'),
                    Some('t') => out.push('\t'),
                    Some('\\') => out.push('\\'),
                    Some(&other) => {
                        out.push('\\');
                        out.push(other);
                    }
                    None => out.push('\\'),
                }
                i += 2;
            }
            '%' => {
                let (text, next) = conversion(&chars, i + 1, argument);
                out.push_str(&text);
                i = next;
            }
            c => {
                out.push(c);
                i += 1;
            }
        }
    }
    out
}

/// The conversion starting after a `%` at `start`: its text and the index
/// after it. An incomplete one is printed as typed.
fn conversion(chars: &[char], start: usize, argument: Argument) -> (String, usize) {
    let mut spec = Spec::default();
    let mut i = start;
    while let Some(&c) = chars.get(i) {
        match c {
            '-' => spec.left = true,
            '+' => spec.plus = true,
            ' ' => spec.space = true,
            '0' => spec.zero = true,
            '#' => spec.alternate = true,
            _ => break,
        }
        i += 1;
    }
    while let Some(d) = chars.get(i).and_then(|c| c.to_digit(10)) {
        spec.width = (spec.width * 10 + d as usize).min(256);
        i += 1;
    }
    if chars.get(i) == Some(&'.') {
        i += 1;
        let mut precision = 0;
        while let Some(d) = chars.get(i).and_then(|c| c.to_digit(10)) {
            precision = (precision * 10 + d as usize).min(64);
            i += 1;
        }
        spec.precision = Some(precision);
    }
    // Length modifiers mean nothing here.
    while matches!(chars.get(i), Some('l' | 'h' | 'L')) {
        i += 1;
    }
    let Some(&kind) = chars.get(i) else {
        return (chars[start - 1..].iter().collect(), chars.len());
    };
    let body = match kind {
        '%' => return ("%".into(), i + 1),
        'd' | 'i' => signed(argument.integer().to_string(), &spec),
        'u' => (argument.integer() as u32).to_string(),
        'x' => prefixed(format!("{:x}", argument.integer() as u32), "0x", &spec),
        'X' => prefixed(format!("{:X}", argument.integer() as u32), "0X", &spec),
        'o' => prefixed(format!("{:o}", argument.integer() as u32), "0", &spec),
        'c' => char::from_u32(argument.integer() as u32)
            .map(String::from)
            .unwrap_or_default(),
        'f' | 'F' => signed(
            format!("{:.*}", spec.precision.unwrap_or(6), argument.double()),
            &spec,
        ),
        'e' | 'E' => signed(
            exponent(argument.double(), spec.precision.unwrap_or(6), kind == 'E'),
            &spec,
        ),
        'g' | 'G' => signed(general(argument.double(), &spec, kind == 'G'), &spec),
        _ => return (chars[start - 1..=i].iter().collect(), i + 1),
    };
    (pad(body, &spec), i + 1)
}

fn signed(text: String, spec: &Spec) -> String {
    if text.starts_with('-') {
        text
    } else if spec.plus {
        format!("+{text}")
    } else if spec.space {
        format!(" {text}")
    } else {
        text
    }
}

fn prefixed(text: String, prefix: &str, spec: &Spec) -> String {
    if spec.alternate && text != "0" {
        format!("{prefix}{text}")
    } else {
        text
    }
}

/// C's `%e`: one digit, the fraction, `e`, a sign and two digits at least.
fn exponent(x: f64, precision: usize, upper: bool) -> String {
    let text = format!("{x:.precision$e}");
    let (mantissa, exp) = text.split_once('e').unwrap_or((&text, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let sign = if exp < 0 { '-' } else { '+' };
    let out = format!("{mantissa}e{sign}{:02}", exp.abs());
    if upper { out.to_uppercase() } else { out }
}

/// C's `%g`: `%e` or `%f` by the exponent, trailing zeros dropped.
fn general(x: f64, spec: &Spec, upper: bool) -> String {
    let precision = spec.precision.unwrap_or(6).max(1);
    if x == 0.0 {
        return "0".into();
    }
    let exp = x.abs().log10().floor() as i32;
    let text = if exp < -4 || exp >= precision as i32 {
        exponent(x, precision - 1, upper)
    } else {
        let decimals = (precision as i32 - 1 - exp).max(0) as usize;
        format!("{x:.decimals$}")
    };
    if spec.alternate {
        return text;
    }
    let (number, tail) = match text.find(['e', 'E']) {
        Some(at) => text.split_at(at),
        None => (text.as_str(), ""),
    };
    let number = if number.contains('.') {
        number.trim_end_matches('0').trim_end_matches('.')
    } else {
        number
    };
    format!("{number}{tail}")
}

fn pad(body: String, spec: &Spec) -> String {
    let len = body.chars().count();
    if len >= spec.width {
        return body;
    }
    let fill = spec.width - len;
    if spec.left {
        format!("{body}{}", " ".repeat(fill))
    } else if spec.zero {
        let (sign, digits) = match body.chars().next() {
            Some(c @ ('-' | '+' | ' ')) => (c.to_string(), body[1..].to_string()),
            _ => (String::new(), body),
        };
        format!("{sign}{}{digits}", "0".repeat(fill))
    } else {
        format!("{}{body}", " ".repeat(fill))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn the_manuals_examples() {
        // Ch4: OT with a plain message and \n (a line feed).
        assert_eq!(
            format(
                "The Safety gate is open, machine operation has stopped \\n",
                Argument::Integer(0)
            ),
            "The Safety gate is open, machine operation has stopped \n"
        );
        // Ch4: OD with %f of the position.
        assert_eq!(
            format(
                "The current position of Axis #1 %f \\n",
                Argument::Double(1234.5)
            ),
            "The current position of Axis #1 1234.500000 \n"
        );
        // Ch13: the part count with %d.
        assert_eq!(
            format("The part count = %d \\r\\n", Argument::Integer(42)),
            "The part count = 42 \r\n"
        );
    }

    #[test]
    fn c_conversions_flags_and_widths() {
        let cases = [
            ("%5d|", Argument::Integer(42), "   42|"),
            ("%-5d|", Argument::Integer(42), "42   |"),
            ("%05d", Argument::Integer(-42), "-0042"),
            ("%+d", Argument::Integer(7), "+7"),
            ("%x %X %#x %o", Argument::Integer(255), "ff FF 0xff 377"),
            ("%.2f", Argument::Double(1.23456), "1.23"),
            ("%e", Argument::Double(1234.5), "1.234500e+03"),
            ("%g %g", Argument::Double(0.0001), "0.0001 0.0001"),
            ("%g", Argument::Double(1e-5), "1e-05"),
            ("%d", Argument::Double(-2.9), "-2"),
            ("100%%", Argument::Integer(0), "100%"),
            ("%c", Argument::Integer(65), "A"),
            ("%q", Argument::Integer(1), "%q"),
            ("50%", Argument::Integer(1), "50%"),
            ("a\\qb\\", Argument::Integer(1), "a\\qb\\"),
        ];
        for (fmt, arg, expected) in cases {
            assert_eq!(format(fmt, arg), expected, "{fmt}");
        }
    }

    proptest! {
        #[test]
        fn no_format_panics(fmt in "[ -~]{0,30}", n in any::<i64>(), x in any::<f64>()) {
            let _ = format(&fmt, Argument::Integer(n));
            let _ = format(&fmt, Argument::Double(x));
        }
    }
}
