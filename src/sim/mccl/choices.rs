//! Every choice the simulator makes where the manual is silent (digest
//! §18.3 and the questions met while building it), as data: printed by
//! the simulator's help and copied into docs/mccl.md. The ones marked
//! "setting" can be changed from outside (see [`super::inputs`]).

/// One choice: what the manual leaves open, and what the simulator does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Choice {
    pub topic: &'static str,
    pub choice: &'static str,
}

const fn choice(topic: &'static str, choice: &'static str) -> Choice {
    Choice { topic, choice }
}

#[rustfmt::skip]
pub const CHOICES: &[Choice] = &[
    // ---- the port ----
    choice("echo", "every byte typed is echoed as it arrives, CR as the line terminator (setting ECHO; EN/EF too)"),
    choice("line terminator", "CR LF after every line of output (setting EOL=crlf|cr|lf)"),
    choice("prompt", "`>` (PCn) once a line has completed, after an error report too; it ends no line (setting PROMPTS=line|command)"),
    choice("error reply", "`?code command`, e.g. `?-6 MC10` (setting ERRORS=command|code for `?-6` alone); the line stops at its first error"),
    choice("Tell reply", "`AA value`, the axis as two digits (setting TELLAXIS=1|0 for the bare value)"),
    choice("TR reply field", "the axis in force, 01 when none"),
    choice("TE reply", "the bare code"),
    choice("Tell with axis 0", "-14 (no axis); TC and TA carry their channel in the field"),
    choice("DE", "16 lines `aaaa: hh hh ...` of the scratch pad"),
    choice("LF, TAB, case", "LF is ignored, blanks and tabs around commands are skipped, mnemonics in any case"),
    choice("backspace", "BS or DEL removes the last character, echoed as BS space BS"),
    choice("Escape while typing", "drops the line typed so far"),
    choice("maximum line", "512 characters, longer is error 4"),
    choice("line noise", "a byte that is no 7-bit text in a line is error 3 (I/O error)"),
    choice("Escape", "aborts the running line with `?-7` and the command it was on; motion already started goes on"),
    choice("single-step key", "Ctrl-T (0x14) while a line runs; Space runs the next command, Enter resumes, Escape aborts; display `{C<n>,M<m>} <command> <`"),
    choice("output rate", "the port sends at the line's rate (11520 bytes/s, 115200 Bd, without one); a reporting command waits while 24 bytes are unsent, so a line of many Tells runs while its answer goes out and Escape cuts it short"),
    // ---- error codes ----
    choice("error codes", "1 unknown mnemonic; 2 bad parameter text, empty command, two RP or DM with HM in one line; 3 line noise; 4 line too long; -1 value out of range or a real where an integer is due; -2 command the axis kind does not take; -13 move or wait on an axis that tripped; -14 no axis; -15 axis beyond the machine; -16 CM/SM of an axis already in another group or gearing; -17 an axis twice in a path command or geared to itself; -18 macro memory, 21 tasks or 32 nested calls exceeded; -21 reporting command in a task, BK\"text\" in a task, commands not simulated"),
    // ---- numbers ----
    choice("hex mode", "integers are hex digits starting with a digit (a sign allowed), replies 8 lower-case hex digits of the 32-bit word; reals stay decimal; a line is read in the base in force when it arrives"),
    choice("precision", "values are truncated to the decimals asked (Ch8 example), after rounding at the ninth"),
    choice("register arithmetic", "the result takes the more precise type (Ch4); integers wrap at 32 bits and divide toward zero; bitwise works on the accumulator rounded; AV angles in radians; AV25 truncates"),
    choice("R1 and doubles", "a double in the accumulator does not touch R1"),
    // ---- defaults ----
    choice("servo defaults", "SV 100000, SA/DS 200000, SG 0.04, SD 0.2, SI 0, IL 0, SE 1024, DB 5, DT 0.01 s, high speed (4 kHz), trapezoid"),
    choice("stepper defaults", "SV 10000, SA/DS 100000, MV 100, low speed range, open loop, ES 1"),
    choice("limit defaults", "LN off, LM 0, HL/LL at the 32-bit range; LN adds to the enabled limits, LF removes (LF0 all)"),
    choice("machine", "axes 1-4 servo, 5 stepper; axes n and n+4 share their opto inputs (Ch9 Table 1)"),
    // ---- motion ----
    choice("servo model", "the shaft is a motor of 10^7 counts/s^2 per volt with viscous friction 400/s and Coulomb friction worth 5 mV (it sticks below that), behind a +-10 V amplifier; at SG 0.04 it trails 100 counts at 100000 counts/s and lands within a count when the trajectory completes; the encoder reads it rounded to a count"),
    choice("command output", "each loop sample SG x e + SD x (e - e of FR+1 samples before) + SI x (sum of e, limited to +-IL) + VG x v + AG x a (speeding up) or DG x a (slowing down), then PH, OB and OO, limited to SQ and +-10 V (DQ, ID4); e = optimal - actual in counts, IL in counts x samples; the sum is kept (IO0), frozen (IO1) or zeroed (IO2) while the trajectory runs"),
    choice("loop rate", "HS 4 kHz, MS 2 kHz, LS 1 kHz loop samples inside each 1 ms trajectory tick, the optimal position stepped evenly between ticks (gain mode jumps: a true step)"),
    choice("feed-forward sign", "VG, AG and DG add gain x speed or acceleration as Ch5 VG reckons it (-0.0001 at 10000 counts/s is -1 V): the manual's negative examples brake this motor"),
    choice("recording", "PR samples a servo once a loop sample (HS/MS/LS), a stepper once a 1 ms tick"),
    choice("following error", "checked each loop sample: beyond SE the samples of that tick stop and the axis trips at its end (motor off, status bits 0 and 8)"),
    choice("stepper model", "the shaft turns with every step unless stalled (STALLn); closed loop (IM1) reads it with an encoder of ES steps a count"),
    choice("profiles", "trapezoid re-planned each tick; S-curve a = SA sin(pi t/T) and parabolic a = SA (1 - t/T) planned at the start with peak SA, a new target mid-move goes on as a trapezoid"),
    choice("motor off", "no trajectory: the trajectory-complete bit is set, at target clear; a move only changes the target; the shaft is held where it was (no coasting), the output 0 V"),
    choice("torque mode", "the unloaded servo turns at 1000 counts/s per volt of SQ"),
    choice("user units", "counts = (n + UO + UZ) x US, speeds x US / UR, accelerations x US / UR^2"),
    choice("index", "an encoder index mark every 2000 counts, at 500"),
    choice("waits", "WS/WT end with -13 if a waited axis trips; WI/WE with nothing armed end at once; WP/WR are reached at or past the position"),
    choice("breakpoints", "reached when the position gets to it from the side it was set on"),
    choice("contour", "moves are not blended (each stops at its end); arcs by CA/CR or RR; EA/ER and cubic splines not simulated; a trip stops the whole group"),
    choice("backlash", "BD/BN/BF are kept and shown in the status but do not move the simulated motor"),
    // ---- programs ----
    choice("macro bytes", "2 a command + 4 an integer, 8 a real, 2 @n, a string and its NUL; 510000 bytes in all"),
    choice("TM listing", "`MC<n>,` and the commands as typed (upper-case mnemonics)"),
    choice("axis in macros", "a called macro starts without an axis; the task of GT takes the parent's UA"),
    choice("RP", "commands after RP run once after the last repetition; each line or macro counts its own RP, also when called"),
    choice("GT0", "first on a line: the rest of the line is the task; alone: macro 0"),
    choice("tasks", "IDs count up from 1; 4 slices of 250 us a ms, 10 commands a slice, round robin; NP is taken but not used; a task's error ends it silently"),
    choice("OT from a task", "printed on the port as it happens"),
    choice("RT", "resets axes, registers, tasks, I/O polarity, prompt and DM; PCI macros are lost, ETH ones kept; input wiring stays; ends the line"),
    choice("LU addresses", "tokens above the 64 KB scratch pad, read per axis by aRx@0"),
    choice("FT/FD", "the text, NUL-terminated, in a new scratch-pad block; its address in ACC (0 when full, as ME)"),
    choice("ID, HE, VE texts", "VE is the manual's MFX-PCI1440 text; ID and HE one item a line in the manual's words"),
];

/// One line of every choice, for the help.
pub fn summary() -> String {
    CHOICES
        .iter()
        .map(|c| format!("{}: {}", c.topic, c.choice))
        .collect::<Vec<_>>()
        .join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mccl_page_lists_every_choice() {
        let page = include_str!("../../../docs/mccl.md");
        let section = page
            .split_once("### Choices where the manual is silent")
            .map(|(_, rest)| rest)
            .expect("a section of the simulator's choices");
        for c in CHOICES {
            let line = format!("**{}**: {}", c.topic, c.choice);
            assert!(section.contains(&line), "docs/mccl.md misses {line}");
        }
    }
}
