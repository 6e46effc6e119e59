//! What can be driven on the MultiFlex simulator from outside (`--input
//! IN18=1`, a line on the standard input of `axterm sim mccl`,
//! `:sim-input`): the digital inputs 1–32 (Ch9), the A/D inputs, the axis
//! inputs by name (mapped to their channels by Ch9 Table 1), a stalled
//! motor and an encoder fault, and the port's wire form where the manual
//! is silent (echo, line terminator, prompts, error text, Tell axis field).
//!
//! `IN18=1` sets the electrical level of channel 18 (conducting); what TC
//! and the status words read follows CH/CL (and LM + 128 for the limits).

use super::Mccl;
use super::io::{self, LAST_INPUT};
use super::link::{Eol, ErrorText, PromptGranularity};
use super::stage::Stage;
use crate::sim::inputs::{self, InputRow, Level, Names, Setting, SettingError, Values};

/// Which input a setting drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// Digital input channel 1–32, electrical level.
    Channel,
    /// A/D input 1–8.
    Analog,
    /// The axis' limit + input (its channel in Table 1).
    LimitPlus,
    LimitMinus,
    /// Coarse home (servo) or home sensor (stepper).
    Home,
    /// Amplifier / driver fault input.
    Fault,
    /// The motor's shaft held still.
    Stall,
    /// The axis' encoder reports a fault (EE1 trips on it).
    EncoderFault,
    Echo,
    LineEnd,
    Prompts,
    Errors,
    TellAxis,
    OutputRate,
    /// The demo stage on, its end switches wired right or swapped.
    Limits,
    /// The demo stage off again.
    Stage,
}

const AXES: u8 = 8;

const fn per_axis(stem: &'static str) -> Names {
    Names::Numbered {
        stem,
        first: 1,
        last: AXES,
    }
}

/// Every input a setting can drive.
pub const INPUTS: &[InputRow<Input>] = &[
    InputRow {
        input: Input::Channel,
        names: Names::Numbered {
            stem: "IN",
            first: 1,
            last: LAST_INPUT,
        },
        values: Values::OnOff,
        what: "digital input channel n (Ch9: 1-16 TTL, 17-32 opto: home, limits, amp fault of the axes), \
               electrical level; TC reads it through CH/CL",
    },
    InputRow {
        input: Input::Analog,
        names: Names::Numbered {
            stem: "AD",
            first: 1,
            last: 8,
        },
        values: Values::Number {
            max: 65535,
            unit: "counts",
        },
        what: "A/D input n (Ch8 TA: 0 = -10 V, 32768 = 0 V, 65535 = +10 V)",
    },
    InputRow {
        input: Input::LimitPlus,
        names: per_axis("LIM+"),
        values: Values::OnOff,
        what: "limit + input of axis n (its channel of Ch9 Table 1, shared by axes n and n+4)",
    },
    InputRow {
        input: Input::LimitMinus,
        names: per_axis("LIM-"),
        values: Values::OnOff,
        what: "limit - input of axis n (its channel of Ch9 Table 1)",
    },
    InputRow {
        input: Input::Home,
        names: per_axis("HOME"),
        values: Values::OnOff,
        what: "coarse home (servo) or home sensor (stepper) input of axis n",
    },
    InputRow {
        input: Input::Fault,
        names: per_axis("FAULT"),
        values: Values::OnOff,
        what: "amplifier / driver fault input of axis n (FN trips on it)",
    },
    InputRow {
        input: Input::Stall,
        names: per_axis("STALL"),
        values: Values::OnOff,
        what: "the motor of axis n is held still: a servo or closed-loop stepper builds a following error \
               (SE trips), an open-loop stepper loses its steps",
    },
    InputRow {
        input: Input::EncoderFault,
        names: per_axis("ENCFAULT"),
        values: Values::OnOff,
        what: "the encoder of axis n reports a fault (TS160; EE1 trips the axis)",
    },
    InputRow {
        input: Input::Echo,
        names: Names::Listed(&["ECHO"]),
        values: Values::OnOff,
        what: "the port echoes what it is sent (the manual: on)",
    },
    InputRow {
        input: Input::LineEnd,
        names: Names::Listed(&["EOL"]),
        values: Values::Choice(&["crlf", "cr", "lf"]),
        what: "what ends each line the port sends (not in the manual; crlf)",
    },
    InputRow {
        input: Input::Prompts,
        names: Names::Listed(&["PROMPTS"]),
        values: Values::Choice(&["line", "command"]),
        what: "the prompt after each line or after each command of it (not in the manual; line)",
    },
    InputRow {
        input: Input::Errors,
        names: Names::Listed(&["ERRORS"]),
        values: Values::Choice(&["command", "code"]),
        what: "an error report `?code command` or `?code` (not in the manual; command)",
    },
    InputRow {
        input: Input::TellAxis,
        names: Names::Listed(&["TELLAXIS"]),
        values: Values::OnOff,
        what: "Tell replies start with the two-digit axis (`01 1000`) or are the bare value",
    },
    InputRow {
        input: Input::OutputRate,
        names: Names::Listed(&["OUTRATE"]),
        values: Values::Number {
            max: 1_000_000,
            unit: "bytes/s",
        },
        what: "the rate the port sends at, bytes/s: a reporting command waits for it; the line's \
               (--baud / 10) from each connection, else 11520 (115200 Bd)",
    },
    InputRow {
        input: Input::Limits,
        names: Names::Listed(&["LIMITS"]),
        values: inputs::LIMITS_WIRING,
        what: "puts every axis on a demo stage (limits from +/-50000, home -500..500, end stops at \
               +/-60000, shaft counts or steps) with its end switches wired right, or swapped: the + \
               end closes limit -, the - end limit +; LN/LM act on them as on any limit input",
    },
    InputRow {
        input: Input::Stage,
        names: Names::Listed(&["STAGE"]),
        values: Values::Choice(&["off"]),
        what: "takes the demo stage away: the inputs read only what is driven from outside",
    },
];

/// Read a setting (`IN18=1`) against [`INPUTS`].
pub fn parse(text: &str) -> Result<Setting<Input>, SettingError> {
    inputs::parse(INPUTS, text)
}

impl Mccl {
    /// Drive one input by a setting typed from outside: what now holds, or
    /// what was wrong with it.
    pub fn drive_input(&mut self, text: &str) -> Result<String, SettingError> {
        let setting = parse(text)?;
        let name = setting.name();
        let on = setting.level == Level::On;
        let choice = match setting.level {
            Level::Choice(i) => usize::from(i),
            _ => 0,
        };
        let which = setting.which;
        let said = match setting.row.input {
            Input::Channel => {
                self.io.drive_input(which, on);
                let axes = io::axes_on_channel(which);
                let reads = if self.io.is_on(which) { "on" } else { "off" };
                let mut said = format!("{name} {} (channel {which} reads {reads})", setting.level);
                if !axes.is_empty() {
                    let list: Vec<String> = axes.iter().map(u8::to_string).collect();
                    said.push_str(&format!(", an input of axes {}", list.join(" and ")));
                }
                said
            }
            Input::Analog => {
                let value = match setting.level {
                    Level::Number(n) => u16::try_from(n).unwrap_or(u16::MAX),
                    _ => 0,
                };
                if let Some(slot) = self.io.analog_in.get_mut(usize::from(which) - 1) {
                    *slot = value;
                }
                format!("{name} {value}")
            }
            Input::LimitPlus | Input::LimitMinus | Input::Home | Input::Fault => {
                let channels = io::channels_of(which).ok_or_else(|| SettingError::Refused {
                    name: name.clone(),
                    why: format!("the machine has no axis {which}"),
                })?;
                let channel = match setting.row.input {
                    Input::LimitPlus => channels.limit_plus,
                    Input::LimitMinus => channels.limit_minus,
                    Input::Home => channels.home,
                    _ => channels.fault,
                };
                self.io.drive_input(channel, on);
                let shared: Vec<String> = io::axes_on_channel(channel)
                    .into_iter()
                    .filter(|&a| a != which)
                    .map(|a| a.to_string())
                    .collect();
                let mut said = format!("{name} {} (channel {channel})", setting.level);
                if !shared.is_empty() {
                    said.push_str(&format!(", shared with axis {}", shared.join(" and ")));
                }
                said
            }
            Input::Stall | Input::EncoderFault => {
                let stall = setting.row.input == Input::Stall;
                let Some(axis) = self.axis_mut(which) else {
                    if !on {
                        return Ok(format!("{name} off (the machine has no axis {which})"));
                    }
                    return Err(SettingError::Refused {
                        name: name.clone(),
                        why: format!("the machine has no axis {which}"),
                    });
                };
                if stall {
                    axis.stalled = on;
                } else {
                    axis.encoder_fault = on;
                }
                format!("{name} {}", setting.level)
            }
            Input::Echo => {
                self.link.profile.echo = on;
                format!("{name} {}", setting.level)
            }
            Input::LineEnd => {
                self.link.profile.eol = [Eol::CrLf, Eol::Cr, Eol::Lf][choice.min(2)];
                format!("{name} {}", ["crlf", "cr", "lf"][choice.min(2)])
            }
            Input::Prompts => {
                self.link.profile.prompts =
                    [PromptGranularity::Line, PromptGranularity::Command][choice.min(1)];
                format!("{name} {}", ["line", "command"][choice.min(1)])
            }
            Input::Errors => {
                self.link.profile.errors =
                    [ErrorText::CodeAndCommand, ErrorText::Code][choice.min(1)];
                format!("{name} {}", ["command", "code"][choice.min(1)])
            }
            Input::TellAxis => {
                self.link.profile.tell_axis = on;
                format!("{name} {}", setting.level)
            }
            Input::OutputRate => {
                let rate = match setting.level {
                    Level::Number(n) => n.max(1),
                    _ => 1,
                };
                self.link.profile.output_rate = f64::from(rate);
                format!("{name} {rate} bytes/s")
            }
            Input::Limits => {
                let swapped = inputs::limits_swapped(setting.level);
                self.set_stage(Some(Stage { swapped }));
                if swapped {
                    format!(
                        "{name} swapped: on every axis' stage the + end closes limit -, the - end limit +"
                    )
                } else {
                    format!(
                        "{name} right: on every axis' stage the + end closes limit +, the - end limit -"
                    )
                }
            }
            Input::Stage => {
                self.set_stage(None);
                format!("{name} off: no stage, no end stops")
            }
        };
        Ok(said)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_inputs_are_read_by_name() {
        let read = |text: &str| {
            let s = parse(text).unwrap_or_else(|e| panic!("{text}: {e}"));
            (s.row.input, s.which, s.level)
        };
        assert_eq!(read("in18=1"), (Input::Channel, 18, Level::On));
        assert_eq!(read("LIM+5=1"), (Input::LimitPlus, 5, Level::On));
        assert_eq!(read("LIM-1=0"), (Input::LimitMinus, 1, Level::Off));
        assert_eq!(read("AD2=65535"), (Input::Analog, 2, Level::Number(65535)));
        assert_eq!(read("EOL=lf"), (Input::LineEnd, 0, Level::Choice(2)));
        assert!(parse("IN33=1").is_err(), "an output");
        assert!(parse("LIM+9=1").is_err());
    }
}
