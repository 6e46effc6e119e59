//! The rules a line must keep beyond its syntax (digest §17, from the
//! manual's pages): which axis a command takes, its parameter's kind and
//! range, where a command may stand (MD first, CP first and its compound,
//! one RP, DM not with HM), jumps inside the line, what a background task
//! may run, the size of a macro, and commands that need care. Each finding
//! names its command and where it is in the text, as an error (the
//! controller refuses it or it must not be sent), a warning (it runs, but
//! likely not as meant) or a note.

use std::collections::BTreeSet;
use std::fmt;
use std::ops::Range;

use super::catalog::{AxisRule, Caution, CommandSpec, Param, allowed_in_task, variable};
use super::line::{AxisRef, Command, Line, NumberBase, ParseErrors, Value, parse_line};
use super::machine::{MAX_AXES, Machine};
use super::profile::LinkProfile;
use super::status::StatusSelector;

/// How bad a finding is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    /// Not to be sent: the controller refuses it, or it must never be sent.
    Error,
    /// It runs, but probably not as meant.
    Warning,
    /// Worth knowing.
    Note,
}

/// One finding.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Diagnostic {
    pub severity: Severity,
    /// Index of the command (0-based, as JP counts), if it is about one.
    pub command: Option<usize>,
    /// Bytes of the text checked.
    pub span: Range<usize>,
    pub message: String,
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

/// What the checker knows of the controller.
#[derive(Debug, Clone, Copy)]
pub struct CheckContext<'a> {
    pub machine: &'a Machine,
    pub profile: &'a LinkProfile,
}

/// Commands 0 = all axes is documented for (Ch2 "only where the command
/// says so"): listed in messages.
const ALL_AXES: &str = "AB, GO, LP, LT, MA, MF, MN, MP, RT, ST, WS";

/// The conditionals that run the next command or skip two (Ch12).
const SKIP_TWO: &[&str] = &["IB", "IC", "IE", "IF", "IG", "IN", "IS", "IU"];

/// What may follow `CP n` in its compound (Ch7 CP table; arcs also take EA,
/// ER and RR, as the CP, EA, ER and RR examples show).
fn contour_members(kind: i64) -> &'static [&'static str] {
    match kind {
        0 => &["CD", "GH", "MA", "MR", "VV"],
        1 => &["GH", "MA", "MR", "VV"],
        _ => &["CA", "CR", "GH", "MA", "MR", "VV", "EA", "ER", "RR"],
    }
}

/// The most bytes a macro holds (Ch4 "Each macro can include as many as
/// 255 bytes").
pub const MACRO_BYTES: usize = 255;

/// Bytes a command takes in macro memory: 2 without a parameter to 10 with
/// a 64-bit real (Ch4); an integer or a register as 6 and a string as its
/// characters and 3 are this checker's estimate [I].
pub fn stored_bytes(command: &Command) -> usize {
    match &command.value {
        None => 2,
        Some(Value::Number(n)) if n.is_integer() => 6,
        Some(Value::Number(_)) => 10,
        Some(Value::Register(_)) => 6,
        Some(Value::Text(t)) => 3 + t.len(),
    }
}

struct Findings<'l> {
    line: &'l Line,
    out: Vec<Diagnostic>,
}

impl Findings<'_> {
    fn at(&mut self, severity: Severity, index: usize, message: String) {
        let span = self
            .line
            .commands
            .get(index)
            .map_or(0..0, |c| c.span.clone());
        self.out.push(Diagnostic {
            severity,
            command: Some(index),
            span,
            message,
        });
    }

    fn error(&mut self, index: usize, message: String) {
        self.at(Severity::Error, index, message);
    }

    fn warning(&mut self, index: usize, message: String) {
        self.at(Severity::Warning, index, message);
    }

    fn note(&mut self, index: usize, message: String) {
        self.at(Severity::Note, index, message);
    }
}

/// Check a parsed line.
pub fn check_line(line: &Line, context: &CheckContext) -> Vec<Diagnostic> {
    let mut f = Findings {
        line,
        out: Vec::new(),
    };
    // Where the commands that run start: after MD (stored) or GT0 (a task).
    let body = usize::from(line.defines_macro() || line.is_task());
    for (index, command) in line.commands.iter().enumerate() {
        check_axis(&mut f, index, command, context.machine);
        check_value(&mut f, index, command);
        check_caution(&mut f, index, command);
        check_flow(&mut f, index, command, body);
    }
    check_placement(&mut f, body);
    check_lookups(&mut f);
    if line.is_task() {
        check_task(&mut f);
    }
    if line.defines_macro() {
        check_macro_size(&mut f);
    }
    if let Some(index) = line.commands.iter().position(|c| c.spaced) {
        f.warning(
            index,
            "blanks between commands: the manual says commas \"with no intervening spaces\" \
             (Ch2); they are not sent"
                .into(),
        );
    }
    let length = line.to_string().len();
    if length > context.profile.max_command_line {
        f.out.push(Diagnostic {
            severity: Severity::Warning,
            command: None,
            span: 0..0,
            message: format!(
                "the line is {length} characters: the controller has an error 4 \"Command string \
                 too long\" at a length the manual does not give"
            ),
        });
    }
    f.out
}

/// Parse and check a line of text read in `base`: parse errors first (as
/// errors), else the checker's findings.
pub fn check_text(text: &str, base: NumberBase, context: &CheckContext) -> Vec<Diagnostic> {
    match parse_line(text, base) {
        Ok(line) => check_line(&line, context),
        Err(errors) => parse_diagnostics(&errors),
    }
}

/// Parse errors as diagnostics.
pub fn parse_diagnostics(errors: &ParseErrors) -> Vec<Diagnostic> {
    errors
        .0
        .iter()
        .map(|e| Diagnostic {
            severity: Severity::Error,
            command: e.command,
            span: e.span.clone(),
            message: e.to_string(),
        })
        .collect()
}

fn check_axis(f: &mut Findings, index: usize, command: &Command, machine: &Machine) {
    let name = command.to_string();
    let mnemonic = command.mnemonic();
    let out_of_range = |axis: u8| axis > MAX_AXES;
    if let Some(axis) = command.axis
        && out_of_range(axis)
    {
        f.error(
            index,
            format!("`{name}`: axis {axis}: a MultiFlex has axes 1–{MAX_AXES}"),
        );
        return;
    }
    match command.spec.axis {
        AxisRule::One | AxisRule::OneOrAll => match f.line.axis_of(index) {
            AxisRef::Default => {
                let message = format!(
                    "`{name}`: no axis on the line yet: {mnemonic} goes to the default axis (UA; \
                     at power-up {})",
                    if command.spec.axis == AxisRule::OneOrAll {
                        "0 = all axes".to_string()
                    } else {
                        format!("0, which {mnemonic} does not take")
                    }
                );
                // A macro without axis numbers is the generic macro of Ch5
                // UA (`MD10,MR1000` + `UA1,MC10`).
                if f.line.defines_macro() {
                    f.note(index, message);
                } else {
                    f.warning(index, message);
                }
            }
            AxisRef::Given(0) | AxisRef::Carried(0) if command.spec.axis == AxisRule::One => f
                .error(
                    index,
                    format!(
                        "`{name}`: {mnemonic} acts on one axis: 0 (all axes) is documented only \
                         for {ALL_AXES} (Ch2)"
                    ),
                ),
            AxisRef::Given(axis) | AxisRef::Carried(axis) if axis != 0 && !machine.has(axis) => f
                .warning(
                    index,
                    format!(
                        "`{name}`: axis {axis} is not one of this controller's axes ({})",
                        machine.span()
                    ),
                ),
            _ => {}
        },
        AxisRule::Optional => {
            if let Some(axis) = command.axis
                && axis != 0
                && !machine.has(axis)
            {
                f.warning(
                    index,
                    format!(
                        "`{name}`: axis {axis} is not one of this controller's axes ({})",
                        machine.span()
                    ),
                );
            }
        }
        AxisRule::None => {
            if let Some(axis) = command.axis {
                f.warning(
                    index,
                    format!(
                        "`{name}`: {mnemonic} takes no axis: {axis} only sets the axis of the \
                         commands after it"
                    ),
                );
            }
        }
    }
}

/// `n` as the message shows it: the value written, or "nothing (0)".
fn shown(command: &Command) -> String {
    match &command.value {
        Some(value) => value.to_string(),
        None => "nothing, which is 0".into(),
    }
}

fn check_value(f: &mut Findings, index: usize, command: &Command) {
    let spec: &CommandSpec = command.spec;
    let name = command.to_string();
    let mnemonic = spec.mnemonic;
    match (&spec.param, &command.value) {
        (Param::None, Some(_)) => {
            f.error(index, format!("`{name}`: {mnemonic} takes no parameter"));
            return;
        }
        (Param::None, None) => return,
        (Param::Undocumented, _) => {
            f.warning(
                index,
                format!(
                    "`{name}`: {mnemonic} ({}) is listed in Ch3 only: what it takes is not \
                     described",
                    spec.name
                ),
            );
            return;
        }
        (Param::Text, Some(Value::Text(_)))
        | (Param::OptionalText, None | Some(Value::Text(_)))
        | (Param::Help, None | Some(Value::Text(_) | Value::Register(_))) => return,
        (Param::Text | Param::OptionalText, _) => {
            f.error(
                index,
                format!("`{name}`: {mnemonic} takes a string in double quotes"),
            );
            return;
        }
        (_, Some(Value::Text(_))) => {
            f.error(
                index,
                format!("`{name}`: {mnemonic} takes a number, not a string"),
            );
            return;
        }
        (_, Some(Value::Register(register))) => {
            if *register > 999 {
                f.error(index, format!("`{name}`: registers are 0–999 (Ch4)"));
            }
            return;
        }
        _ => {}
    }
    let value = command.number().unwrap_or(0.0);
    let integer = match &command.value {
        Some(Value::Number(n)) => n.as_integer(),
        _ => Some(0),
    };
    let fits = match spec.param {
        Param::Integer { min, max } => {
            let Some(n) = integer else {
                f.error(
                    index,
                    format!(
                        "`{name}`: {mnemonic} takes an integer, not {}",
                        shown(command)
                    ),
                );
                return;
            };
            if (min..=max).contains(&n) {
                return check_special(f, index, command, n);
            }
            format!("{min}..{max}")
        }
        Param::OneOf(values) => {
            if integer.is_some_and(|n| values.contains(&n)) {
                return;
            }
            let list: Vec<String> = values.iter().map(i64::to_string).collect();
            format!("one of {}", list.join(", "))
        }
        Param::Real(range) => {
            if range.contains(value) {
                return;
            }
            range.to_string()
        }
        Param::Precision => {
            let tenths = value * 10.0;
            if (0.0..=5.0).contains(&tenths) && tenths.fract() == 0.0 {
                return;
            }
            "0, .1, .2, .3, .4 or .5 (decimals in the reply)".into()
        }
        Param::RegisterPrecision => {
            let (register, tenths) = (value.trunc(), value.fract() * 10.0);
            if (0.0..=999.0).contains(&register)
                && (0.0..=5.0).contains(&tenths)
                && (tenths - tenths.round()).abs() < 1e-6
            {
                return;
            }
            "a register 0..999 with precision .1 … .5 at most (TRn.p, Ch4)".into()
        }
        Param::Status => {
            if integer.and_then(StatusSelector::from_parameter).is_some() {
                return;
            }
            "0–31 or 64–191 (a word or one of its bits 1–31)".into()
        }
        Param::Help => {
            if integer.is_some_and(|n| n == 0 || n == 1) {
                return;
            }
            "0, 1 or \"mnemonic\"".into()
        }
        Param::None | Param::Text | Param::OptionalText | Param::Undocumented => return,
    };
    let code = if mnemonic == "RP" && value < 0.0 {
        " (−3 Negative Repeat Count)"
    } else if matches!(mnemonic, "MD" | "MC" | "MJ" | "GT") {
        " (−5 Macro Number Out of Range)"
    } else {
        ""
    };
    f.error(
        index,
        format!(
            "`{name}`: {mnemonic} must be {fits}, not {}{code}",
            shown(command)
        ),
    );
}

/// Rules of single commands beyond a range.
fn check_special(f: &mut Findings, index: usize, command: &Command, n: i64) {
    let name = command.to_string();
    match command.mnemonic() {
        // LM = hard (0 off, 1 abrupt, 2 decelerate) + soft (0, 4, 8) + 128
        // (invert): Ch5 LM.
        "LM" => {
            let code = n & !128;
            if code & 3 == 3 || code & 12 == 12 || code > 15 {
                f.error(
                    index,
                    format!(
                        "`{name}`: LM is hard 0/1/2 + soft 0/4/8 + 128 to invert; {n} is not \
                         such a sum"
                    ),
                );
            }
        }
        "RP" if n == 0 => f.note(
            index,
            format!("`{name}`: RP without a count repeats for ever, until Escape (Ch12)"),
        ),
        _ => {}
    }
}

fn check_caution(f: &mut Findings, index: usize, command: &Command) {
    let name = command.to_string();
    let mnemonic = command.mnemonic();
    match command.spec.caution {
        Some(Caution::McapiOnly) => f.error(
            index,
            format!(
                "`{name}`: {mnemonic} is for the MCAPI only: \"Issuing … via WinControl will cause \
                 a malfunction\" (Ch5)"
            ),
        ),
        Some(Caution::FactoryOnly) => f.warning(
            index,
            format!("`{name}`: {mnemonic} is \"reserved for factory use only\""),
        ),
        Some(Caution::Resets) => f.warning(
            index,
            format!(
                "`{name}`: RT resets {}, motors off",
                match command.axis {
                    Some(axis) if axis != 0 => format!("axis {axis}"),
                    _ => "the whole controller".into(),
                }
            ),
        ),
        None => {}
    }
}

/// JP and JR targets inside the line; what follows a conditional.
fn check_flow(f: &mut Findings, index: usize, command: &Command, body: usize) {
    let name = command.to_string();
    let count = f.line.commands.len();
    let literal = match &command.value {
        Some(Value::Number(n)) => n.as_integer(),
        None => Some(0),
        _ => None,
    };
    match (command.mnemonic(), literal) {
        ("JP", Some(n)) => {
            let target = body as i64 + n;
            if target >= count as i64 {
                f.error(
                    index,
                    format!(
                        "`{name}`: there is no command {n} to jump to (commands count from 0, {} \
                         here)",
                        count - body
                    ),
                );
            }
        }
        ("JR", Some(n)) => {
            let target = index as i64 + n;
            if target < body as i64 || target >= count as i64 {
                f.error(
                    index,
                    format!(
                        "`{name}`: jumps to command {} of a line of {}",
                        target - body as i64,
                        count - body
                    ),
                );
            } else if n == 0 {
                f.warning(index, format!("`{name}`: JR0 jumps to itself for ever"));
            }
        }
        (mnemonic, _) if SKIP_TWO.contains(&mnemonic) => {
            let after = count - index - 1;
            if after < 2 {
                f.warning(
                    index,
                    format!(
                        "`{name}`: {mnemonic} runs the next command or skips two (Ch12): {after} \
                         follow it"
                    ),
                );
            } else if let Some(next) = f.line.commands.get(index + 1)
                && !matches!(next.mnemonic(), "MJ" | "BK" | "JP" | "JR" | "MC" | "NO")
            {
                f.note(
                    index,
                    format!(
                        "`{name}`: when it holds, `{next}` and the command after it run; when it \
                         does not, both are skipped"
                    ),
                );
            }
        }
        _ => {}
    }
}

fn check_placement(f: &mut Findings, body: usize) {
    let line = f.line;
    for (index, command) in line.commands.iter().enumerate() {
        let name = command.to_string();
        match command.mnemonic() {
            "MD" if index > 0 => f.error(
                index,
                format!("`{name}`: MD must be the first command of a line (−4)"),
            ),
            "GT" if index > 0 && command.number() == Some(0.0) => f.warning(
                index,
                format!(
                    "`{name}`: GT0 makes the rest of a line a task only as its first command; \
                     here it starts macro 0"
                ),
            ),
            "CP" if index != body => f.error(
                index,
                format!("`{name}`: CP must be the first command of its line (−8)"),
            ),
            _ => {}
        }
    }
    if let Some(cp) = line.commands.get(body).filter(|c| c.mnemonic() == "CP") {
        let kind = cp.number().map_or(1, |n| n as i64);
        let members = contour_members(kind);
        for (index, command) in line.commands.iter().enumerate().skip(body + 1) {
            if !members.contains(&command.mnemonic()) {
                f.error(
                    index,
                    format!(
                        "`{command}`: a CP{kind} compound takes only {} (Ch7 CP)",
                        members.join(", ")
                    ),
                );
            }
        }
        if kind == 0 {
            match line.commands.iter().rposition(|c| c.mnemonic() == "CD") {
                Some(at) if at + 1 != line.commands.len() => f.error(
                    at,
                    format!(
                        "`{}`: CD must be the last command of a CP0 compound",
                        line.commands[at]
                    ),
                ),
                None => f.warning(
                    body,
                    format!("`{cp}`: a CP0 compound ends with its contour distance CD"),
                ),
                _ => {}
            }
        }
    }
    let repeats: Vec<usize> = line
        .commands
        .iter()
        .enumerate()
        .filter(|(_, c)| c.mnemonic() == "RP")
        .map(|(i, _)| i)
        .collect();
    if let Some(&second) = repeats.get(1) {
        f.error(
            second,
            "there can be only one RP in a line or macro (Ch12 RP)".into(),
        );
    } else if let Some(&at) = repeats.first()
        && at + 1 != line.commands.len()
    {
        f.warning(
            at,
            format!(
                "`{}`: what follows RP is not documented (RP repeats the commands before it)",
                line.commands[at]
            ),
        );
    }
    if line.contains("DM") && line.contains("HM") {
        let at = line
            .commands
            .iter()
            .position(|c| c.mnemonic() == "HM" || c.mnemonic() == "DM")
            .unwrap_or(0);
        f.error(
            at,
            "DM and HM cannot be in the same command string (Ch13)".into(),
        );
    }
}

/// `LU"name"` names from the Ch4 table, read with the command of their
/// width, on an axis.
fn check_lookups(f: &mut Findings) {
    let line = f.line;
    for (index, command) in line.commands.iter().enumerate() {
        let Some(name) = command.text().filter(|_| command.mnemonic() == "LU") else {
            continue;
        };
        let Some(read) = variable(name) else {
            f.warning(
                index,
                format!(
                    "`{command}`: {name} is not in the Ch4 motor table (the controller answers \
                     −19 to a name it does not know)"
                ),
            );
            continue;
        };
        let Some(next) = line.commands.get(index + 1) else {
            continue;
        };
        let reads_it = matches!(next.mnemonic(), "RB" | "RW" | "RL" | "RV" | "RD")
            && next.value == Some(Value::Register(0));
        if !reads_it {
            continue;
        }
        if next.mnemonic() != read {
            f.warning(
                index + 1,
                format!("`{next}`: {name} is read with {read} (Ch4 motor table)"),
            );
        }
        if next.axis.is_none() {
            f.warning(
                index + 1,
                format!("`{next}`: a motor-table read \"must include the axis specifier\" (Ch4)"),
            );
        }
    }
}

/// A `GT0` line runs as a task: no reporting commands, no single step.
fn check_task(f: &mut Findings) {
    let line = f.line;
    for (index, command) in line.commands.iter().enumerate().skip(1) {
        if !allowed_in_task(command.spec) {
            f.error(
                index,
                format!(
                    "`{command}`: a background task cannot run reporting commands (Ch4 \
                     \"MCCL Multi-Tasking\")"
                ),
            );
        } else if command.mnemonic() == "BK" && command.text().is_some() {
            f.error(
                index,
                format!("`{command}`: single stepping is not supported in a background task (Ch4)"),
            );
        }
    }
}

/// A macro holds at most 255 bytes (Ch4): certain when even 2 bytes a
/// command is too much, estimated otherwise.
fn check_macro_size(f: &mut Findings) {
    let body = &f.line.commands[1..];
    let least = 2 * body.len();
    let estimate: usize = body.iter().map(stored_bytes).sum();
    if least > MACRO_BYTES {
        f.error(
            0,
            format!(
                "the macro has {} commands: at 2 bytes or more each it exceeds {MACRO_BYTES} bytes \
                 (Ch4)",
                body.len()
            ),
        );
    } else if estimate > MACRO_BYTES {
        f.warning(
            0,
            format!(
                "the macro takes about {estimate} bytes, more than the {MACRO_BYTES} a macro holds \
                 (Ch4; estimated at 2 + 4 per integer, 8 per real)"
            ),
        );
    }
}

/// Check a text file of lines (WinControl File-Open, Ch4): every line, and
/// macro calls to macros the file does not define. `defined` lists macros
/// known to be in the controller already.
pub fn check_file(
    text: &str,
    context: &CheckContext,
    defined: &BTreeSet<i64>,
) -> Vec<(usize, Diagnostic)> {
    let mut findings = Vec::new();
    let mut lines = Vec::new();
    let mut known = defined.clone();
    for (number, raw) in text.lines().enumerate() {
        let number = number + 1;
        let body = raw[..super::line::comment_start(raw).unwrap_or(raw.len())].trim();
        if body.is_empty() {
            continue;
        }
        match parse_line(raw, NumberBase::Decimal) {
            Ok(line) => {
                findings.extend(check_line(&line, context).into_iter().map(|d| (number, d)));
                if line.defines_macro()
                    && let Some(n) = line.commands[0].number()
                {
                    known.insert(n as i64);
                }
                lines.push((number, line));
            }
            Err(errors) => {
                findings.extend(parse_diagnostics(&errors).into_iter().map(|d| (number, d)));
            }
        }
    }
    for (number, line) in &lines {
        for (index, command) in line.commands.iter().enumerate() {
            let called = match (command.mnemonic(), command.axis) {
                ("MC" | "MJ", _) | ("GT", _) => command.number().map(|n| n as i64),
                ("HO", Some(axis)) => Some(i64::from(axis)),
                ("HO", None) => Some(9),
                _ => None,
            };
            if let Some(n) = called
                && !(command.mnemonic() == "GT" && n == 0 && index == 0)
                && !known.contains(&n)
            {
                findings.push((
                    *number,
                    Diagnostic {
                        severity: Severity::Warning,
                        command: Some(index),
                        span: command.span.clone(),
                        message: format!(
                            "`{command}`: macro {n} is not defined in this file (−6 Macro \
                             Doesn't Exist if the controller has none)"
                        ),
                    },
                ));
            }
        }
    }
    findings.sort_by_key(|(number, d)| (*number, d.span.start));
    findings
}

/// The findings that stop a line from being sent.
pub fn errors(diagnostics: &[Diagnostic]) -> impl Iterator<Item = &Diagnostic> {
    diagnostics.iter().filter(|d| d.severity == Severity::Error)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::mccl::machine::DEFAULT_MACHINE;

    const CONTEXT: CheckContext = CheckContext {
        machine: &DEFAULT_MACHINE,
        profile: &LinkProfile::MANUAL,
    };

    fn findings(text: &str) -> Vec<Diagnostic> {
        check_text(text, NumberBase::Decimal, &CONTEXT)
    }

    fn of(text: &str, severity: Severity) -> Vec<String> {
        findings(text)
            .into_iter()
            .filter(|d| d.severity == severity)
            .map(|d| d.message)
            .collect()
    }

    fn clean(text: &str) {
        let found: Vec<String> = findings(text)
            .into_iter()
            .filter(|d| d.severity != Severity::Note)
            .map(|d| d.message)
            .collect();
        assert!(found.is_empty(), "{text}: {found:?}");
    }

    #[test]
    fn the_manuals_lines_are_clean() {
        for text in [
            "2MR1000,WS0.5,MR-1000,WS0.5,RP6",
            "1CP2,1CA10000,2CA0,1MA20000,2MA0",
            "1CP0,1MA1000,2MA1000,3MA1000,1CD10000",
            "MD13,1IA1000,MC24,1WI,1ST,1WS.01,MJ14",
            "LU\"STATUS\",1RL@0,IC6,NO,JR-4",
            "IE0,JP5,NO,1MR1000,1WS,1MR2000,1WS",
            "1LM130",
            "1TP.3",
            "1TS64",
            "GT0,1MR1000,1WS",
            "0ST,0WS.1",
        ] {
            clean(text);
        }
    }

    #[test]
    fn ranges_and_kinds_are_the_pages() {
        let e = of("1DS0", Severity::Error);
        assert_eq!(e, ["`1DS0`: DS must be > 0, not 0"]);
        let e = of("1CM", Severity::Error);
        assert_eq!(e, ["`1CM`: CM must be 1..8, not nothing, which is 0"]);
        assert_eq!(
            of("1FR0.00025", Severity::Error),
            ["`1FR0.00025`: FR takes an integer, not 0.00025"]
        );
        assert_eq!(
            of("RP-1", Severity::Error),
            ["`RP-1`: RP must be 0..2147483647, not -1 (−3 Negative Repeat Count)"]
        );
        assert_eq!(of("MC1000", Severity::Error).len(), 1);
        assert_eq!(
            of("1SG20", Severity::Error),
            ["`1SG20`: SG must be 0.000153..10, not 20"]
        );
        assert_eq!(of("1TP.6", Severity::Error).len(), 1);
        assert_eq!(of("1TS40", Severity::Error).len(), 1);
        assert_eq!(
            of("1MN5", Severity::Error),
            ["`1MN5`: MN takes no parameter"]
        );
        assert_eq!(
            of("LU5", Severity::Error),
            ["`LU5`: LU takes a string in double quotes"]
        );
        assert_eq!(
            of("1MA\"x\"", Severity::Error),
            ["`1MA\"x\"`: MA takes a number, not a string"]
        );
        assert_eq!(
            of("1MR@1000", Severity::Error),
            ["`1MR@1000`: registers are 0–999 (Ch4)"]
        );
        assert!(of("1IM2", Severity::Error)[0].contains("one of 0, 1, 128"));
        assert!(of("1LM3", Severity::Error)[0].contains("hard 0/1/2"));
        clean("1LM138");
        clean("1MR@10");
        clean("HE\"id\"");
        clean("BK");
    }

    #[test]
    fn axes_follow_the_line() {
        assert!(of("0SV100", Severity::Error)[0].contains("acts on one axis"));
        clean("0MA,0MN,AB");
        assert!(of("9MA5", Severity::Error)[0].contains("axes 1–8"));
        assert!(
            of("6MA5", Severity::Warning)[0].contains("not one of this controller's axes (1–5)")
        );
        assert!(of("TP,RP999", Severity::Warning)[0].contains("default axis"));
        assert!(of("1JR-3,NO,NO,NO", Severity::Warning)[0].contains("JR takes no axis"));
    }

    #[test]
    fn placement_rules() {
        assert!(of("1MN,MD5,1MR5", Severity::Error)[0].contains("−4"));
        assert!(of("1MN,1CP1,1MA5", Severity::Error)[0].contains("−8"));
        clean("MD7,1CP1,1MA5,2MA6");
        assert!(of("1CP1,1MA5,1WS", Severity::Error)[0].contains("takes only GH, MA, MR, VV"));
        assert!(of("1CP0,1CD5,1MA5", Severity::Error)[0].contains("CD must be the last"));
        assert!(of("1CP0,1MA5", Severity::Warning)[0].contains("ends with its contour distance"));
        assert!(of("1TP,RP2,2TP,RP3", Severity::Error)[0].contains("only one RP"));
        assert!(of("1TP,RP2,2TP", Severity::Warning)[0].contains("what follows RP"));
        assert_eq!(
            of("DM,HM", Severity::Error),
            ["DM and HM cannot be in the same command string (Ch13)"]
        );
        assert!(of("1MN,GT0", Severity::Warning)[0].contains("starts macro 0"));
    }

    #[test]
    fn flow_stays_inside_the_line() {
        assert!(of("IE0,JP7,NO,1MR1000", Severity::Error)[0].contains("no command 7"));
        assert!(of("NO,JR-2", Severity::Error)[0].contains("jumps to command -1"));
        clean("MD100,IN4,MJ101,NO,JR-3");
        assert!(of("IN5,MJ10", Severity::Warning)[0].contains("1 follow it"));
        let notes = of("IN5,1MR5,1WS,NO", Severity::Note);
        assert!(notes[0].contains("when it holds"), "{notes:?}");
    }

    #[test]
    fn tasks_macros_and_cautions() {
        assert!(of("GT0,1TP", Severity::Error)[0].contains("reporting commands"));
        assert!(of("GT0,BK\"x\"", Severity::Error)[0].contains("single stepping"));
        clean("GT0,AL5,OT\"%d\\n\"");
        assert!(of("1EI9", Severity::Error)[0].contains("malfunction"));
        assert!(of("DW", Severity::Warning)[0].contains("factory use"));
        assert!(of("RT", Severity::Warning)[0].contains("whole controller"));
        let long = format!("MD1{}", ",1MR1.5".repeat(30));
        assert!(
            of(&long, Severity::Warning)[0].contains("about"),
            "estimate"
        );
        let longer = format!("MD1{}", ",NO".repeat(130));
        assert!(of(&longer, Severity::Error)[0].contains("130 commands"));
    }

    #[test]
    fn lookups_name_their_read() {
        assert!(of("LU\"STATUSX\",1RL@0", Severity::Warning)[0].contains("−19"));
        assert!(of("LU\"STATUS\",1RD@0", Severity::Warning)[0].contains("read with RL"));
        assert!(of("LU\"STATUS\",RL@0", Severity::Warning)[0].contains("axis specifier"));
        clean("LU\"POSITION\",3RD@0");
    }

    #[test]
    fn a_file_checks_every_line_and_its_macro_calls() {
        let text = "; homing\nMD5,5LM2,5LN3,MJ10 ;enable limits\nMD10,5VM,5D10\n\n5HO\nMC5,MC11\n";
        let found = check_file(text, &CONTEXT, &BTreeSet::new());
        let lines: Vec<(usize, Severity)> = found.iter().map(|(n, d)| (*n, d.severity)).collect();
        assert!(lines.contains(&(3, Severity::Error)), "5D10: {found:?}");
        let calls: Vec<&str> = found
            .iter()
            .filter(|(_, d)| d.message.contains("not defined"))
            .map(|(_, d)| d.message.as_str())
            .collect();
        assert_eq!(calls.len(), 2, "{calls:?}");
        assert!(calls[0].contains("macro 10"), "MJ10 (MD10 did not parse)");
        assert!(calls[1].contains("macro 11"));
        assert!(found.iter().all(|(n, _)| *n > 1), "comments are skipped");
    }
}
