//! CMD-4CR command text, the part of a frame after `@ID` (§3.2.2): parsed
//! into a typed command against the command table, validated, and written
//! back in canonical form. This is the one parser of CMD-4CR command text:
//! the console uses it on what the user types, the simulator on what
//! arrives, so both see the same command and refuse the same text with the
//! same error (and [`CommandError::reply`] is the §4.2 answer to it).
//!
//! What the parser accepts is what the manual writes (§4.1, digest §9):
//! `PX`, `X1000Y2000`, `HSPDX=5000`, `JX+`, `HX+0`, `CIRXYP1000:0`,
//! `SACTRL0=1`, `V5=10`, `STORE`. Letters may be lower case and blanks
//! may separate the parts (`hspdx = 5000`); the canonical text, which is
//! what is sent, is upper case without blanks, with move targets in X, Y,
//! Z, U order as the manual writes them.

use std::fmt;

use super::catalog::{
    Action, Axis, COMMANDS, CommandSpec, Form, FormShape, Format, Kind, POSITION_MAX, POSITION_MIN,
    Register, SPEED_MAX, Values, action_row, keywords_longest_first, motion_row, register_row,
    rows_of,
};
use super::reply::{ErrorCode, ErrorReply};

/// What follows the keyword of a register or action.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Selector {
    /// Nothing: the global setting, the whole word, every axis (`HSPD`,
    /// `DI`, `STOP`).
    All,
    /// One axis (`HSPDX`, `STOPY`).
    Axis(Axis),
    /// A numbered input, output, variable or program (`DI3`, `V12`,
    /// `SACTRL0`), as the manual numbers it.
    Index(u8),
}

/// The direction of a jog, homing or Z move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Direction {
    Plus,
    Minus,
}

impl Direction {
    pub fn sign(self) -> char {
        match self {
            Direction::Plus => '+',
            Direction::Minus => '-',
        }
    }
}

/// The sense of a circle or arc: `P` is clockwise, `N` counter-clockwise
/// (§2.3.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Rotation {
    Clockwise,
    CounterClockwise,
}

impl Rotation {
    pub fn letter(self) -> char {
        match self {
            Rotation::Clockwise => 'P',
            Rotation::CounterClockwise => 'N',
        }
    }
}

/// The largest arc angle taken, in millidegrees (360°). The manual gives
/// the angle as absolute millidegrees (§2.3.2.1) with no range.
pub const ANGLE_MAX: i64 = 360_000;

/// The highest homing mode (Appendix A, modes 0–12).
pub const HOME_MODE_MAX: u8 = 12;

/// A command as the controller understands it.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Cmd4crCommand {
    /// Read a register: `HSPD`, `HSPDX`, `DI3`, `PP`.
    Read {
        register: Register,
        selector: Selector,
    },
    /// Write a register: `HSPDX=5000`, `SACTRL0=1`. The value is in the
    /// register's unit; SLR in thousandths.
    Write {
        register: Register,
        selector: Selector,
        value: i64,
    },
    /// An action: `STOP`, `STOPX`, `CLRY`, `STORE`, `GS5`.
    Action { action: Action, selector: Selector },
    /// `X1000`, `X1000Y2000`: targets of 1–4 axes, indexed X, Y, Z, U.
    Move { targets: [Option<i64>; 4] },
    /// `JX+`.
    Jog { axis: Axis, direction: Direction },
    /// `HY-1`.
    Home {
        axis: Axis,
        direction: Direction,
        mode: u8,
    },
    /// `ZMOVEX+`.
    ZMove { axis: Axis, direction: Direction },
    /// `TX5000`: a new target for a move in flight.
    NewTarget { axis: Axis, target: i64 },
    /// `CIRXZP1000:1000`: a full circle around an absolute centre.
    Circle {
        axes: [Axis; 2],
        rotation: Rotation,
        centre: [i64; 2],
    },
    /// `ARCXYP0:0:90000`: an arc to an absolute angle in millidegrees.
    Arc {
        axes: [Axis; 2],
        rotation: Rotation,
        centre: [i64; 2],
        angle: i64,
    },
    /// `CIRTP0:0:500`: an XY circle with Z moving to an absolute target.
    HelicalCircle {
        rotation: Rotation,
        centre: [i64; 2],
        z: i64,
    },
    /// `ARCTN0:0:90000:500`: an XY arc with Z moving to an absolute target.
    HelicalArc {
        rotation: Rotation,
        centre: [i64; 2],
        angle: i64,
        z: i64,
    },
    /// `I1000:2000:3000:5000`: an XYZ move with its speed, into the buffer.
    BufferMove { target: [i64; 3], speed: i64 },
}

impl Cmd4crCommand {
    /// The row of the command table this command is an instance of.
    pub fn spec(&self) -> &'static CommandSpec {
        let row = match *self {
            Cmd4crCommand::Read { register, selector }
            | Cmd4crCommand::Write {
                register, selector, ..
            } => register_row(register, shape(selector)),
            Cmd4crCommand::Action { action, selector } => action_row(action, shape(selector)),
            Cmd4crCommand::Move { .. } => motion_row(Kind::Move),
            Cmd4crCommand::Jog { .. } => motion_row(Kind::Jog),
            Cmd4crCommand::Home { .. } => motion_row(Kind::Home),
            Cmd4crCommand::ZMove { .. } => motion_row(Kind::ZMove),
            Cmd4crCommand::NewTarget { .. } => motion_row(Kind::NewTarget),
            Cmd4crCommand::Circle { .. } => motion_row(Kind::Circle),
            Cmd4crCommand::Arc { .. } => motion_row(Kind::Arc),
            Cmd4crCommand::HelicalCircle { .. } => motion_row(Kind::HelicalCircle),
            Cmd4crCommand::HelicalArc { .. } => motion_row(Kind::HelicalArc),
            Cmd4crCommand::BufferMove { .. } => motion_row(Kind::BufferMove),
        };
        // Every command the parser makes has its row; a hand-built one
        // with a selector its register lacks falls back to the first row
        // of the kind rather than failing.
        row.or_else(|| COMMANDS.iter().find(|c| c.kind == self.kind()))
            .unwrap_or(&COMMANDS[0])
    }

    fn kind(&self) -> Kind {
        match *self {
            Cmd4crCommand::Read { register, .. } | Cmd4crCommand::Write { register, .. } => {
                Kind::Register(register)
            }
            Cmd4crCommand::Action { action, .. } => Kind::Action(action),
            Cmd4crCommand::Move { .. } => Kind::Move,
            Cmd4crCommand::Jog { .. } => Kind::Jog,
            Cmd4crCommand::Home { .. } => Kind::Home,
            Cmd4crCommand::ZMove { .. } => Kind::ZMove,
            Cmd4crCommand::NewTarget { .. } => Kind::NewTarget,
            Cmd4crCommand::Circle { .. } => Kind::Circle,
            Cmd4crCommand::Arc { .. } => Kind::Arc,
            Cmd4crCommand::HelicalCircle { .. } => Kind::HelicalCircle,
            Cmd4crCommand::HelicalArc { .. } => Kind::HelicalArc,
            Cmd4crCommand::BufferMove { .. } => Kind::BufferMove,
        }
    }

    /// Whether the command only reads (and may be sent again if its answer
    /// is lost).
    pub fn is_query(&self) -> bool {
        matches!(self, Cmd4crCommand::Read { .. })
    }

    /// Whether the command starts motion (the §4.2 `?Error …` replies
    /// answer these).
    pub fn moves(&self) -> bool {
        !matches!(
            self,
            Cmd4crCommand::Read { .. } | Cmd4crCommand::Write { .. } | Cmd4crCommand::Action { .. }
        )
    }

    /// How the answer to this command reads: the register's format for a
    /// read, `None` for everything else (answered `OK` or an error).
    pub fn reply_format(&self) -> Option<Format> {
        match self {
            Cmd4crCommand::Read { .. } => self.spec().values.map(|v| v.format),
            _ => None,
        }
    }
}

fn shape(selector: Selector) -> FormShape {
    match selector {
        Selector::All => FormShape::Bare,
        Selector::Axis(_) => FormShape::Axis,
        Selector::Index(_) => FormShape::Index,
    }
}

fn keyword_of(command: &Cmd4crCommand) -> &'static str {
    command.spec().keyword
}

fn write_selector(f: &mut fmt::Formatter<'_>, selector: Selector) -> fmt::Result {
    match selector {
        Selector::All => Ok(()),
        Selector::Axis(axis) => write!(f, "{}", axis.letter()),
        Selector::Index(n) => write!(f, "{n}"),
    }
}

/// A value as the wire writes it in `format`.
pub fn format_value(value: i64, format: Format) -> String {
    match format {
        Format::TwoDigits => format!("{value:02}"),
        Format::Thousandths => {
            let sign = if value < 0 { "-" } else { "" };
            let whole = value.unsigned_abs() / 1000;
            let fraction = value.unsigned_abs() % 1000;
            if fraction == 0 {
                format!("{sign}{whole}")
            } else {
                let digits = format!("{fraction:03}");
                format!("{sign}{whole}.{}", digits.trim_end_matches('0'))
            }
        }
        Format::Integer | Format::Fields(_) | Format::Text => value.to_string(),
    }
}

/// The canonical text: what is sent after `@ID`.
impl fmt::Display for Cmd4crCommand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let keyword = keyword_of(self);
        match *self {
            Cmd4crCommand::Read { selector, .. } | Cmd4crCommand::Action { selector, .. } => {
                f.write_str(keyword)?;
                write_selector(f, selector)
            }
            Cmd4crCommand::Write {
                selector, value, ..
            } => {
                f.write_str(keyword)?;
                write_selector(f, selector)?;
                let format = self.spec().values.map_or(Format::Integer, |v| v.format);
                write!(f, "={}", format_value(value, format))
            }
            Cmd4crCommand::Move { targets } => {
                for (axis, target) in Axis::ALL.iter().zip(targets) {
                    if let Some(target) = target {
                        write!(f, "{}{target}", axis.letter())?;
                    }
                }
                Ok(())
            }
            Cmd4crCommand::Jog { axis, direction } | Cmd4crCommand::ZMove { axis, direction } => {
                write!(f, "{keyword}{}{}", axis.letter(), direction.sign())
            }
            Cmd4crCommand::Home {
                axis,
                direction,
                mode,
            } => write!(f, "H{}{}{mode}", axis.letter(), direction.sign()),
            Cmd4crCommand::NewTarget { axis, target } => {
                write!(f, "T{}{target}", axis.letter())
            }
            Cmd4crCommand::Circle {
                axes: [a, b],
                rotation,
                centre: [c1, c2],
            } => write!(
                f,
                "CIR{}{}{}{c1}:{c2}",
                a.letter(),
                b.letter(),
                rotation.letter()
            ),
            Cmd4crCommand::Arc {
                axes: [a, b],
                rotation,
                centre: [c1, c2],
                angle,
            } => write!(
                f,
                "ARC{}{}{}{c1}:{c2}:{angle}",
                a.letter(),
                b.letter(),
                rotation.letter()
            ),
            Cmd4crCommand::HelicalCircle {
                rotation,
                centre: [c1, c2],
                z,
            } => write!(f, "CIRT{}{c1}:{c2}:{z}", rotation.letter()),
            Cmd4crCommand::HelicalArc {
                rotation,
                centre: [c1, c2],
                angle,
                z,
            } => write!(f, "ARCT{}{c1}:{c2}:{angle}:{z}", rotation.letter()),
            Cmd4crCommand::BufferMove {
                target: [x, y, z],
                speed,
            } => write!(f, "I{x}:{y}:{z}:{speed}"),
        }
    }
}

/// Why command text was refused. Messages name the text, what is wrong
/// with it and what the manual allows.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CommandError {
    #[error("empty command: nothing to send")]
    Empty,
    #[error("`{0}` is not a CMD-4CR command (§4.1 Table 4-40)")]
    Unknown(String),
    #[error(
        "`{0}`: give the command without `@` and the ID: they are added when it is sent \
         (--address or :address picks the ID)"
    )]
    Framed(String),
    #[error("{text}: {keyword} needs an axis letter X, Y, Z or U (syntax {syntax})")]
    MissingAxis {
        text: String,
        keyword: &'static str,
        syntax: &'static str,
    },
    #[error("{text}: `{found}` is not an axis: {keyword} takes X, Y, Z or U")]
    NotAnAxis {
        text: String,
        keyword: &'static str,
        found: String,
    },
    #[error("{text}: {keyword} needs a number {first}..{last} after it (syntax {syntax})")]
    MissingIndex {
        text: String,
        keyword: &'static str,
        first: u8,
        last: u8,
        syntax: &'static str,
    },
    #[error("{text}: there is no {keyword}{index}: {keyword} is numbered {first}..{last}")]
    InvalidIndex {
        text: String,
        keyword: &'static str,
        index: String,
        first: u8,
        last: u8,
    },
    #[error("{text}: {keyword} takes no number after it; to set it write {keyword}={index}")]
    NoIndex {
        text: String,
        keyword: &'static str,
        index: String,
    },
    #[error("{text}: {command} only sets a value and cannot be read (syntax {syntax})")]
    WriteOnly {
        text: String,
        command: String,
        syntax: &'static str,
    },
    #[error("{text}: {command} is read-only (syntax {syntax})")]
    ReadOnly {
        text: String,
        command: String,
        syntax: &'static str,
    },
    #[error("{text}: {command} takes no `=` value (syntax {syntax})")]
    TakesNoValue {
        text: String,
        command: String,
        syntax: &'static str,
    },
    #[error("{text}: no value after `=` (syntax {syntax})")]
    MissingValue { text: String, syntax: &'static str },
    #[error("{text}: `{found}` is not {expected}")]
    NotANumber {
        text: String,
        found: String,
        expected: &'static str,
    },
    #[error("{text}: {what} {value} is outside {allowed}")]
    OutOfRange {
        text: String,
        what: String,
        value: String,
        /// `0..15`, `1..6553500 pps`.
        allowed: String,
    },
    #[error("{text}: {problem} (syntax {syntax})")]
    Syntax {
        text: String,
        problem: String,
        syntax: &'static str,
    },
}

impl CommandError {
    /// The §4.2 error the controller answers this text with. The manual
    /// names two: `?Invalid Index` for an index out of range and
    /// `?Unknown Command: [Command]` for text it does not understand; it
    /// names none for a value out of range, which is taken as not
    /// understood too (our choice, digest §1.4).
    pub fn reply(&self) -> ErrorReply {
        match self {
            CommandError::InvalidIndex { .. } => ErrorReply::Known(ErrorCode::InvalidIndex),
            other => ErrorReply::UnknownCommand(other.text().to_string()),
        }
    }

    /// The command text the error is about, as it was given.
    pub fn text(&self) -> &str {
        match self {
            CommandError::Empty => "",
            CommandError::Unknown(text)
            | CommandError::Framed(text)
            | CommandError::MissingAxis { text, .. }
            | CommandError::NotAnAxis { text, .. }
            | CommandError::MissingIndex { text, .. }
            | CommandError::InvalidIndex { text, .. }
            | CommandError::NoIndex { text, .. }
            | CommandError::WriteOnly { text, .. }
            | CommandError::ReadOnly { text, .. }
            | CommandError::TakesNoValue { text, .. }
            | CommandError::MissingValue { text, .. }
            | CommandError::NotANumber { text, .. }
            | CommandError::OutOfRange { text, .. }
            | CommandError::Syntax { text, .. } => text,
        }
    }
}

/// Parse and validate command text (without `@ID` and CR).
pub fn parse_command(text: &str) -> Result<Cmd4crCommand, CommandError> {
    let original = text.trim().to_string();
    if original.is_empty() {
        return Err(CommandError::Empty);
    }
    if !original.is_ascii() {
        return Err(CommandError::Unknown(original));
    }
    if original.starts_with('@') {
        return Err(CommandError::Framed(original));
    }
    let compact: String = original
        .chars()
        .filter(|c| !c.is_ascii_whitespace())
        .map(|c| c.to_ascii_uppercase())
        .collect();
    let parser = Parser {
        text: original,
        compact: &compact,
    };
    parser.parse()
}

struct Parser<'a> {
    /// The text as given, for messages.
    text: String,
    /// Upper case, no blanks.
    compact: &'a str,
}

/// How the rest of a line after a keyword fits that keyword's rows.
enum Fit {
    /// Parsed.
    Command(Cmd4crCommand),
    /// Wrong for this keyword, but a shorter keyword may fit.
    No,
    /// Wrong, and what is wrong is known.
    Error(CommandError),
}

impl Parser<'_> {
    fn parse(&self) -> Result<Cmd4crCommand, CommandError> {
        let (head, value) = match self.compact.split_once('=') {
            Some((head, value)) => (head, Some(value)),
            None => (self.compact, None),
        };
        let mut chars = head.chars();
        let first_is_axis = chars.next().and_then(Axis::from_letter).is_some();
        if first_is_axis
            && chars
                .next()
                .is_some_and(|c| c.is_ascii_digit() || c == '-' || c == '+')
        {
            return self
                .no_value(Kind::Move, value)
                .and_then(|()| self.moves(head));
        }
        let mut error = None;
        for keyword in keywords_longest_first() {
            let Some(rest) = head.strip_prefix(keyword) else {
                continue;
            };
            match self.fit(keyword, rest, value) {
                Fit::Command(command) => return Ok(command),
                // Only the longest keyword that prefixes the text explains
                // what is wrong with it; a shorter one may still fit.
                Fit::Error(e) if error.is_none() => error = Some(e),
                Fit::Error(_) => {}
                Fit::No => {
                    error.get_or_insert_with(|| CommandError::Unknown(self.text.clone()));
                }
            }
        }
        Err(error.unwrap_or_else(|| CommandError::Unknown(self.text.clone())))
    }

    fn fit(&self, keyword: &'static str, rest: &str, value: Option<&str>) -> Fit {
        let rows: Vec<&'static CommandSpec> = rows_of(keyword).collect();
        if let Some(row) = rows.iter().find(|r| r.form == Form::Motion) {
            return match self.motion(row, rest, value) {
                Ok(command) => Fit::Command(command),
                Err(e) => Fit::Error(e),
            };
        }
        let mut letters = rest.chars();
        let (selector_shape, selector) = match (letters.next(), letters.next()) {
            (None, _) => (FormShape::Bare, Selector::All),
            (Some(letter), None) if letter.is_ascii_alphabetic() => match Axis::from_letter(letter)
            {
                Some(axis) => (FormShape::Axis, Selector::Axis(axis)),
                None if rows.iter().any(|r| r.form == Form::Axis) => {
                    return Fit::Error(CommandError::NotAnAxis {
                        text: self.text.clone(),
                        keyword,
                        found: letter.to_string(),
                    });
                }
                None => return Fit::No,
            },
            _ if rest.chars().all(|c| c.is_ascii_digit()) => {
                let Some(row) = rows.iter().find(|r| matches!(r.form, Form::Index { .. })) else {
                    // Table 4-40 prints `HSPD[value]` and `SAP[0-1]` for
                    // writes that every example writes with `=`.
                    return if rows
                        .iter()
                        .any(|r| r.form == Form::Bare && r.access.writes())
                    {
                        Fit::Error(CommandError::NoIndex {
                            text: self.text.clone(),
                            keyword,
                            index: rest.to_string(),
                        })
                    } else {
                        Fit::No
                    };
                };
                let Form::Index { first, last } = row.form else {
                    return Fit::No;
                };
                match rest.parse::<u8>() {
                    Ok(n) if (first..=last).contains(&n) => (FormShape::Index, Selector::Index(n)),
                    _ => {
                        return Fit::Error(CommandError::InvalidIndex {
                            text: self.text.clone(),
                            keyword,
                            index: rest.to_string(),
                            first,
                            last,
                        });
                    }
                }
            }
            _ => return Fit::No,
        };
        let Some(row) = rows.iter().find(|r| selector_shape.fits(r.form)) else {
            return Fit::Error(self.wrong_selector(keyword, &rows, selector_shape));
        };
        match self.register_or_action(row, selector, value) {
            Ok(command) => Fit::Command(command),
            Err(e) => Fit::Error(e),
        }
    }

    /// The keyword exists but not in this shape (`SYNO` without its axis,
    /// `STOP1`).
    fn wrong_selector(
        &self,
        keyword: &'static str,
        rows: &[&'static CommandSpec],
        given: FormShape,
    ) -> CommandError {
        let first = rows.first().copied();
        let axis_row = rows.iter().find(|r| r.form == Form::Axis);
        let index_row = rows.iter().find_map(|r| match r.form {
            Form::Index { first, last } => Some((r, first, last)),
            _ => None,
        });
        match (given, axis_row, index_row) {
            (FormShape::Bare, Some(row), _) => CommandError::MissingAxis {
                text: self.text.clone(),
                keyword,
                syntax: row.syntax,
            },
            (FormShape::Bare, None, Some((row, first, last))) => CommandError::MissingIndex {
                text: self.text.clone(),
                keyword,
                first,
                last,
                syntax: row.syntax,
            },
            _ => CommandError::Syntax {
                text: self.text.clone(),
                problem: format!("{keyword} takes no {}", describe_shape(given)),
                syntax: first.map_or("", |r| r.syntax),
            },
        }
    }

    fn register_or_action(
        &self,
        row: &'static CommandSpec,
        selector: Selector,
        value: Option<&str>,
    ) -> Result<Cmd4crCommand, CommandError> {
        let command = || command_name(row.keyword, selector);
        match (row.kind, value) {
            (Kind::Action(action), None) => Ok(Cmd4crCommand::Action { action, selector }),
            (Kind::Action(_), Some(_)) => Err(CommandError::TakesNoValue {
                text: self.text.clone(),
                command: command(),
                syntax: row.syntax,
            }),
            (Kind::Register(register), None) if row.access.reads() => {
                Ok(Cmd4crCommand::Read { register, selector })
            }
            (Kind::Register(_), None) => Err(CommandError::WriteOnly {
                text: self.text.clone(),
                command: command(),
                syntax: row.syntax,
            }),
            (Kind::Register(register), Some(value)) if row.access.writes() => {
                let values = row.values.ok_or_else(|| CommandError::ReadOnly {
                    text: self.text.clone(),
                    command: command(),
                    syntax: row.syntax,
                })?;
                let value = self.value(&command(), value, values, row.syntax)?;
                Ok(Cmd4crCommand::Write {
                    register,
                    selector,
                    value,
                })
            }
            (Kind::Register(_), Some(_)) => Err(CommandError::ReadOnly {
                text: self.text.clone(),
                command: command(),
                syntax: row.syntax,
            }),
            _ => Err(CommandError::Unknown(self.text.clone())),
        }
    }

    fn value(
        &self,
        command: &str,
        text: &str,
        values: Values,
        syntax: &'static str,
    ) -> Result<i64, CommandError> {
        if text.is_empty() {
            return Err(CommandError::MissingValue {
                text: self.text.clone(),
                syntax,
            });
        }
        let (parsed, expected) = match values.format {
            Format::Thousandths => (parse_thousandths(text), "a number with at most 3 decimals"),
            _ => (parse_integer(text), "a whole number"),
        };
        let Some(value) = parsed else {
            return Err(CommandError::NotANumber {
                text: self.text.clone(),
                found: text.to_string(),
                expected,
            });
        };
        if !values.contains(value) {
            return Err(CommandError::OutOfRange {
                text: self.text.clone(),
                what: command.to_string(),
                value: format_value(value, values.format),
                allowed: format!(
                    "{}..{}{}",
                    format_value(values.min, values.format),
                    format_value(values.max, values.format),
                    unit_suffix(values.unit)
                ),
            });
        }
        Ok(value)
    }

    fn no_value(&self, kind: Kind, value: Option<&str>) -> Result<(), CommandError> {
        match value {
            None => Ok(()),
            Some(_) => Err(CommandError::Syntax {
                text: self.text.clone(),
                problem: "a motion command takes no `=`".into(),
                syntax: motion_row(kind).map_or("", |r| r.syntax),
            }),
        }
    }

    fn syntax(&self, kind: Kind, problem: impl Into<String>) -> CommandError {
        CommandError::Syntax {
            text: self.text.clone(),
            problem: problem.into(),
            syntax: motion_row(kind).map_or("", |r| r.syntax),
        }
    }

    /// A signed number in `range`, or an error naming `what`.
    fn number(
        &self,
        kind: Kind,
        what: &str,
        text: &str,
        min: i64,
        max: i64,
        unit: &str,
    ) -> Result<i64, CommandError> {
        if text.is_empty() {
            return Err(self.syntax(kind, format!("no {what} given")));
        }
        let Some(value) = parse_integer(text) else {
            return Err(CommandError::NotANumber {
                text: self.text.clone(),
                found: text.to_string(),
                expected: "a whole number",
            });
        };
        if !(min..=max).contains(&value) {
            return Err(CommandError::OutOfRange {
                text: self.text.clone(),
                what: what.to_string(),
                value: value.to_string(),
                allowed: format!("{min}..{max}{}", unit_suffix(unit)),
            });
        }
        Ok(value)
    }

    fn position(&self, kind: Kind, what: &str, text: &str) -> Result<i64, CommandError> {
        self.number(kind, what, text, POSITION_MIN, POSITION_MAX, "pulses")
    }

    fn axis(&self, kind: Kind, letter: Option<char>) -> Result<Axis, CommandError> {
        match letter {
            Some(c) if c.is_ascii_digit() || matches!(c, '-' | '+' | ':') => {
                Err(self.syntax(kind, format!("no axis given (X, Y, Z or U) before `{c}`")))
            }
            Some(c) => Axis::from_letter(c)
                .ok_or_else(|| self.syntax(kind, format!("`{c}` is not an axis (X, Y, Z or U)"))),
            None => Err(self.syntax(kind, "no axis given")),
        }
    }

    fn direction(&self, kind: Kind, sign: Option<char>) -> Result<Direction, CommandError> {
        match sign {
            Some('+') => Ok(Direction::Plus),
            Some('-') => Ok(Direction::Minus),
            Some(c) => Err(self.syntax(kind, format!("`{c}` is not a direction: give + or -"))),
            None => Err(self.syntax(kind, "no direction given: + or -")),
        }
    }

    fn rotation(&self, kind: Kind, letter: Option<char>) -> Result<Rotation, CommandError> {
        match letter {
            Some('P') => Ok(Rotation::Clockwise),
            Some('N') => Ok(Rotation::CounterClockwise),
            Some(c) => Err(self.syntax(
                kind,
                format!("`{c}` is not a direction: P (clockwise) or N (counter-clockwise)"),
            )),
            None => Err(self.syntax(kind, "no direction given: P (clockwise) or N")),
        }
    }

    /// `count` numbers separated by `:`.
    fn fields<'t>(
        &self,
        kind: Kind,
        text: &'t str,
        names: &[&str],
    ) -> Result<Vec<&'t str>, CommandError> {
        let fields: Vec<&str> = text.split(':').collect();
        if fields.len() != names.len() {
            return Err(self.syntax(
                kind,
                format!(
                    "{} values separated by `:` needed ({}), {} given",
                    names.len(),
                    names.join(":"),
                    fields.len()
                ),
            ));
        }
        Ok(fields)
    }

    fn two_axes(
        &self,
        kind: Kind,
        chars: &mut std::str::Chars<'_>,
    ) -> Result<[Axis; 2], CommandError> {
        let a = self.axis(kind, chars.next())?;
        let b = self.axis(kind, chars.next())?;
        if a == b {
            return Err(self.syntax(
                kind,
                format!("two different axes needed, {} given twice", a.letter()),
            ));
        }
        Ok([a, b])
    }

    fn motion(
        &self,
        row: &'static CommandSpec,
        rest: &str,
        value: Option<&str>,
    ) -> Result<Cmd4crCommand, CommandError> {
        let kind = row.kind;
        self.no_value(kind, value)?;
        let mut chars = rest.chars();
        match kind {
            Kind::Jog | Kind::ZMove => {
                let axis = self.axis(kind, chars.next())?;
                let direction = self.direction(kind, chars.next())?;
                if let Some(extra) = chars.next() {
                    return Err(
                        self.syntax(kind, format!("unexpected `{extra}` after the direction"))
                    );
                }
                Ok(if kind == Kind::Jog {
                    Cmd4crCommand::Jog { axis, direction }
                } else {
                    Cmd4crCommand::ZMove { axis, direction }
                })
            }
            Kind::Home => {
                let axis = self.axis(kind, chars.next())?;
                let direction = self.direction(kind, chars.next())?;
                let mode = self.number(
                    kind,
                    "homing mode",
                    chars.as_str(),
                    0,
                    i64::from(HOME_MODE_MAX),
                    "",
                )?;
                Ok(Cmd4crCommand::Home {
                    axis,
                    direction,
                    mode: u8::try_from(mode).unwrap_or(HOME_MODE_MAX),
                })
            }
            Kind::NewTarget => {
                let axis = self.axis(kind, chars.next())?;
                let target = self.position(kind, "target", chars.as_str())?;
                Ok(Cmd4crCommand::NewTarget { axis, target })
            }
            Kind::Circle | Kind::Arc => {
                let axes = self.two_axes(kind, &mut chars)?;
                let rotation = self.rotation(kind, chars.next())?;
                let names: &[&str] = if kind == Kind::Circle {
                    &["C1", "C2"]
                } else {
                    &["C1", "C2", "θ"]
                };
                let fields = self.fields(kind, chars.as_str(), names)?;
                let centre = [
                    self.position(kind, "centre C1", fields.first().copied().unwrap_or(""))?,
                    self.position(kind, "centre C2", fields.get(1).copied().unwrap_or(""))?,
                ];
                if kind == Kind::Circle {
                    return Ok(Cmd4crCommand::Circle {
                        axes,
                        rotation,
                        centre,
                    });
                }
                let angle = self.angle(kind, fields.get(2).copied().unwrap_or(""))?;
                Ok(Cmd4crCommand::Arc {
                    axes,
                    rotation,
                    centre,
                    angle,
                })
            }
            Kind::HelicalCircle | Kind::HelicalArc => {
                let rotation = self.rotation(kind, chars.next())?;
                let names: &[&str] = if kind == Kind::HelicalCircle {
                    &["C1", "C2", "Z target"]
                } else {
                    &["C1", "C2", "θ", "Z target"]
                };
                let fields = self.fields(kind, chars.as_str(), names)?;
                let field = |i: usize| fields.get(i).copied().unwrap_or("");
                let centre = [
                    self.position(kind, "centre C1", field(0))?,
                    self.position(kind, "centre C2", field(1))?,
                ];
                if kind == Kind::HelicalCircle {
                    let z = self.position(kind, "Z target", field(2))?;
                    return Ok(Cmd4crCommand::HelicalCircle {
                        rotation,
                        centre,
                        z,
                    });
                }
                let angle = self.angle(kind, field(2))?;
                let z = self.position(kind, "Z target", field(3))?;
                Ok(Cmd4crCommand::HelicalArc {
                    rotation,
                    centre,
                    angle,
                    z,
                })
            }
            Kind::BufferMove => {
                let fields = self.fields(kind, rest, &["X", "Y", "Z", "speed"])?;
                let field = |i: usize| fields.get(i).copied().unwrap_or("");
                let target = [
                    self.position(kind, "X target", field(0))?,
                    self.position(kind, "Y target", field(1))?,
                    self.position(kind, "Z target", field(2))?,
                ];
                let speed = self.number(kind, "speed", field(3), 1, SPEED_MAX, "pps")?;
                Ok(Cmd4crCommand::BufferMove { target, speed })
            }
            Kind::Move => self.moves(rest),
            Kind::Register(_) | Kind::Action(_) => Err(CommandError::Unknown(self.text.clone())),
        }
    }

    fn angle(&self, kind: Kind, text: &str) -> Result<i64, CommandError> {
        self.number(kind, "angle θ", text, 0, ANGLE_MAX, " millidegrees")
    }

    /// `X1000Y-2000`: axis letters each followed by a target, each axis once.
    fn moves(&self, text: &str) -> Result<Cmd4crCommand, CommandError> {
        let kind = Kind::Move;
        let mut targets = [None; 4];
        let mut rest = text;
        while let Some(letter) = rest.chars().next() {
            let axis = Axis::from_letter(letter).ok_or_else(|| {
                self.syntax(kind, format!("`{letter}` is not an axis (X, Y, Z or U)"))
            })?;
            let after = rest.get(1..).unwrap_or("");
            let end = after
                .char_indices()
                .find(|&(i, c)| c.is_ascii_alphabetic() || (i > 0 && (c == '-' || c == '+')))
                .map_or(after.len(), |(i, _)| i);
            let number = after.get(..end).unwrap_or("");
            let target = self.position(kind, &format!("{letter} target"), number)?;
            let slot = targets
                .get_mut(axis.index())
                .ok_or_else(|| CommandError::Unknown(self.text.clone()))?;
            if slot.is_some() {
                return Err(self.syntax(kind, format!("axis {letter} given twice")));
            }
            *slot = Some(target);
            rest = after.get(end..).unwrap_or("");
        }
        Ok(Cmd4crCommand::Move { targets })
    }
}

fn describe_shape(shape: FormShape) -> &'static str {
    match shape {
        FormShape::Bare => "bare form",
        FormShape::Axis => "axis letter",
        FormShape::Index => "number",
    }
}

/// `HSPDX`, `DI3`, `STOP`: a keyword with its selector.
fn command_name(keyword: &str, selector: Selector) -> String {
    match selector {
        Selector::All => keyword.to_string(),
        Selector::Axis(axis) => format!("{keyword}{}", axis.letter()),
        Selector::Index(n) => format!("{keyword}{n}"),
    }
}

fn unit_suffix(unit: &str) -> String {
    if unit.is_empty() || unit.starts_with(' ') {
        unit.to_string()
    } else {
        format!(" {unit}")
    }
}

/// A signed decimal integer as the manual writes them: optional sign,
/// digits only.
pub fn parse_integer(text: &str) -> Option<i64> {
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    text.strip_prefix('+').unwrap_or(text).parse().ok()
}

/// A decimal with at most three places, in thousandths (`1.5` → 1500).
pub fn parse_thousandths(text: &str) -> Option<i64> {
    let (negative, unsigned) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let (whole, fraction) = unsigned.split_once('.').unwrap_or((unsigned, ""));
    if (whole.is_empty() && fraction.is_empty())
        || fraction.len() > 3
        || !whole
            .bytes()
            .chain(fraction.bytes())
            .all(|b| b.is_ascii_digit())
    {
        return None;
    }
    let whole: i64 = if whole.is_empty() {
        0
    } else {
        whole.parse().ok()?
    };
    let fraction: i64 = if fraction.is_empty() {
        0
    } else {
        format!("{fraction:0<3}").parse().ok()?
    };
    let value = whole.checked_mul(1000)?.checked_add(fraction)?;
    Some(if negative { -value } else { value })
}

impl crate::protocol::line_error::FamilyLineError for CommandError {
    fn mistake(&self) -> crate::protocol::line_error::Mistake {
        use crate::protocol::line_error::Mistake;
        match self {
            CommandError::Empty => Mistake::Empty,
            CommandError::OutOfRange { .. } | CommandError::InvalidIndex { .. } => Mistake::Range,
            _ => Mistake::Syntax,
        }
    }
}

/// A controller ID no CMD-4CR can have (§2.1.1.1: 00..99).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("controller ID {0} is outside 00..99 (§2.1.1.1): pick one with :address")]
pub struct IdOutOfRange(pub u8);

impl crate::protocol::line_error::FamilyLineError for IdOutOfRange {
    fn mistake(&self) -> crate::protocol::line_error::Mistake {
        crate::protocol::line_error::Mistake::Address
    }
}

#[cfg(test)]
#[path = "command_tests.rs"]
mod tests;
