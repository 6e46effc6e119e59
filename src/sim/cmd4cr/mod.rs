//! A faithful simulator of the Nippon Pulse Commander core CMD-4CR (manual
//! V1.0, firmware V126BL) on its RS-485 ASCII link: `@` + two-digit ID +
//! command + CR in, reply + CR out (§3.2.2).
//!
//! A plain state machine: bytes in ([`SimulatedController::feed`]), virtual
//! time ([`SimulatedController::advance`]), bytes out
//! ([`SimulatedController::take_output`]). No clock, no sleeping, no I/O
//! except the optional flash file. Command text is read by the one CMD-4CR
//! parser ([`crate::protocol::cmd4cr::parse_command`]); motion is the
//! [`motion`] engine; the machine behind each axis is a [`motion::stage`].
//!
//! Choices where the manual is silent (each also noted where it is made,
//! and listed by [`Cmd4cr::help_line`]):
//! - Framing: a frame starts at `@` (bytes before it are noise), ends at
//!   CR; LF is ignored. The ID is exactly two digits. A frame for another
//!   ID gets no answer (the natural reading of RS-485 multi-drop, digest
//!   §1.2). ID 00 is an ordinary ID: the manual names no broadcast address
//!   (IDs 00–99, §2.1.1.1, §3.3), so `@00` reaches only a core whose ID is
//!   00. A line longer than 256 bytes without CR is dropped.
//! - Writes and actions answer `OK` (the manual shows it for STORE only,
//!   §3.2.2); [`SimConfig::write_reply`] changes it.
//! - `?Unknown Command: ` echoes the command text as received (after the
//!   ID). A value out of range answers the same (the parser's choice);
//!   an index out of range answers `?Invalid Index`.
//! - `VER` answers `V126BL`, the firmware of the manual's cover.
//! - `P[axis]=`/`E[axis]=` while the axis moves or holds a latched error
//!   answer `?Error Moving` (§4.3.3: counters "can be cleared only when the
//!   axis is normally stopped").
//! - `ID=`, `DB=`, the `*BOOT` values and `SLOAD` act at the next power
//!   cycle ([`Cmd4cr::power_cycle`]); reading them shows the new value.
//!   An explicit address ([`SimConfig::id`] from `--address`) wins over
//!   the stored ID.
//! - StepNLoop (§2.5.3) is simulated on an encoder that follows the
//!   carriage. The motor misses steps (§2.1.2.3: StepNLoop "can help overcome
//!   missed steps") when told from outside: `MISSX=30` (a setting, see
//!   [`inputs`]) puts the carriage and encoder 30 pulses behind the pulse
//!   counter, against the way the move under way drives X
//!   ([`motion::Motion::miss_steps`]; refused while no move drives the
//!   axis, since a motor at rest is sent no steps to miss), and `SLIPX=100`
//!   makes it miss 100 ‰ of the steps of every move from then on (1000: it
//!   does not turn), so that the loop has something to correct (SLS 2) or
//!   report (SLS 8, 9, 10).
//! - Joystick control moves X and Y from AI1 and AI2 (set them with
//!   [`Cmd4cr::set_analog_input`]): linear outside the dead band, JSPD in
//!   pps, JDEL in pps per ms; MPG following: see [`Cmd4cr::turn_mpg`].
//!   `STOP` under joystick control is answered like any other command and
//!   does not stop the joystick motion: §2.5.1.3 says it "will return an
//!   invalid status" but the manual gives that reply nowhere (T4-41 has no
//!   such string), so none is invented. `ESTOP` (and /CEMG) stop a
//!   joystick axis at once; it stays still until CLR clears its EMG flag
//!   and the stick is back in its dead band.
//! - StepNLoop beyond single-axis moves: see [`motion::step_n_loop`].
//! - Inputs driven from outside by a setting ([`Cmd4cr::drive_input`],
//!   names in [`inputs`]): an IO that IOCFG makes an output is refused
//!   (its pin is the core's to drive); forced switches (`L+X=1`) win over
//!   the stage until `=stage`.

pub mod flash;
pub mod inputs;
mod interpreter;
pub mod io;
pub mod motion;
pub mod programs;
mod wire;

#[cfg(test)]
mod tests;

use std::path::PathBuf;
use std::time::Duration;

use crate::protocol::cmd4cr::{Axis, DEFAULT_ID, parse_request};

use super::SimulatedController;
use super::inputs::{Level, Setting, SettingError};
use flash::{Flash, FlashError};
use inputs::Input;
use io::Io;
use motion::Motion;
use motion::stage::Stage;
use programs::Programs;

/// The simulator as `--sim cmd4cr` names it.
pub const KIND: super::SimKind = super::SimKind {
    name: "cmd4cr",
    description: "Nippon Pulse Commander core CMD-4CR (ASCII, 4 axes X/Y/Z/U)",
    build: |options| {
        Box::new(Cmd4cr::new(SimConfig {
            id: options.address,
            flash_file: options.eeprom_file.clone(),
            ..SimConfig::default()
        }))
    },
    input_names: || super::inputs::names(inputs::INPUTS),
    input_help: || super::inputs::help_lines(inputs::INPUTS),
    eeprom_refusal: None,
};

/// The firmware version `VER` answers (the manual's cover: V126BL).
pub const FIRMWARE_VERSION: &str = "V126BL";

/// Longest line kept while waiting for its CR.
pub const MAX_LINE: usize = 256;

/// How the simulated core is set up.
#[derive(Debug, Clone)]
pub struct SimConfig {
    /// The ID to answer to, whatever the flash holds (`--address`); `None`
    /// uses the stored ID, 01 from the factory.
    pub id: Option<u8>,
    /// Where the flash is kept between runs; `None` keeps it in memory.
    pub flash_file: Option<PathBuf>,
    /// The answer to a write or action.
    pub write_reply: String,
    /// The machine behind each axis, X..U.
    pub stages: [Stage; 4],
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            id: None,
            flash_file: None,
            write_reply: "OK".to_string(),
            stages: std::array::from_fn(|_| Stage::demo()),
        }
    }
}

/// MPG following of one axis (§2.5.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mpg {
    pub enabled: bool,
    /// `MPM`, 1..32.
    pub multiplier: i64,
    /// `MPD`, the numerator over 2048.
    pub divider: i64,
    /// `MP`: counts after gearing.
    pub counter: i64,
    /// Geared counts not yet whole (× 2048).
    remainder: i64,
}

impl Default for Mpg {
    fn default() -> Self {
        Mpg {
            enabled: false,
            multiplier: 1,
            divider: 2048,
            counter: 0,
            remainder: 0,
        }
    }
}

/// The least fraction of the stick's speed between the inner and outer
/// soft limits (our choice).
const SOFT_LIMIT_FLOOR: f64 = 0.05;

/// Joystick control (§2.5.1): its settings, and the speed each axis runs
/// at under it.
#[derive(Debug, Clone, PartialEq)]
pub struct Joystick {
    pub enable: i64,
    pub max: [i64; 4],
    pub min: [i64; 4],
    pub tolerance: [i64; 4],
    pub speed: [i64; 4],
    pub delta: [i64; 4],
    /// `JLIM1..8`.
    pub limits: [i64; 8],
    /// Current signed speed of X and Y, pps.
    velocity: [f64; 2],
    /// Pulses not yet whole.
    fraction: [f64; 2],
}

impl Joystick {
    /// The speed the stick asks of axis `i` (0 X, 1 Y) at `millivolts`:
    /// nothing inside MID ± JTOL, then linear up to ±JSPD at JMAX/JMIN
    /// (§2.5.1.1; JMAX < JMIN flips the direction).
    fn demand(&self, i: usize, millivolts: f64) -> f64 {
        let (max, min) = (self.max[i] as f64, self.min[i] as f64);
        let tolerance = self.tolerance[i] as f64;
        let mid = (max - min) / 2.0 + min;
        let offset = millivolts - mid;
        let reach = (max - mid).abs() - tolerance;
        if offset.abs() <= tolerance || reach <= 0.0 {
            return 0.0;
        }
        let fraction = ((offset.abs() - tolerance) / reach).min(1.0);
        let direction = offset.signum() * (max - mid).signum();
        direction * fraction * self.speed[i] as f64
    }

    /// Soft limits (§2.5.1.3): past the inner limit the speed falls off
    /// linearly, but not below 5 % of what the stick asks (Fig. 2-30 is
    /// lost; without a floor the axis would never arrive), and at the outer
    /// one it is 0 in that direction. `position` is the pulse counter.
    fn limited(&self, i: usize, position: i64, velocity: f64) -> f64 {
        let base = i * 4;
        let at = |n: usize| self.limits.get(base + n).copied().unwrap_or(0) as f64;
        let (neg_outer, neg_inner, pos_inner, pos_outer) = (at(0), at(1), at(2), at(3));
        let p = position as f64;
        let scale = |inner: f64, outer: f64| {
            if (outer - p) * (outer - inner).signum() <= 0.0 {
                0.0
            } else if (p - inner) * (outer - inner).signum() > 0.0 {
                ((outer - p) / (outer - inner)).clamp(SOFT_LIMIT_FLOOR, 1.0)
            } else {
                1.0
            }
        };
        if velocity > 0.0 {
            velocity * scale(pos_inner, pos_outer)
        } else if velocity < 0.0 {
            velocity * scale(neg_inner, neg_outer)
        } else {
            0.0
        }
    }
}

/// Joystick defaults, our choice: the full 0–3300 mV span, a ±50 mV dead
/// band, 1000 pps, a speed change (JDEL) of 100 pps per ms, soft limits
/// ±90,000 inner and ±100,000 outer (the demo stage's end limits).
impl Default for Joystick {
    fn default() -> Self {
        Joystick {
            enable: 0,
            max: [3300; 4],
            min: [0; 4],
            tolerance: [50; 4],
            speed: [1000; 4],
            delta: [100; 4],
            limits: [
                -100_000, -90_000, 90_000, 100_000, -100_000, -90_000, 90_000, 100_000,
            ],
            velocity: [0.0; 2],
            fraction: [0.0; 2],
        }
    }
}

/// The simulated core.
pub struct Cmd4cr {
    config: SimConfig,
    motion: Motion,
    io: Io,
    flash: Flash,
    programs: Programs,
    /// The ID it answers to until the next power cycle.
    id: u8,
    /// `ID`: what `ID=` set (and STORE keeps).
    id_setting: u8,
    /// `DB`: baud code 1..5 (T3-39).
    baud_code: i64,
    /// `SLOAD`: programs run at power-on, bit n = program n.
    run_on_boot: i64,
    /// `SAP`.
    sub31_return: i64,
    variables: [i32; 100],
    /// Time not yet run by the program threads.
    program_clock: Duration,
    mpg: [Mpg; 4],
    joystick: Joystick,
    /// The frame being received (from its `@`).
    line: Vec<u8>,
    output: Vec<u8>,
}

/// The factory baud code: 9600 (T3-39).
pub const DEFAULT_BAUD_CODE: i64 = 1;

impl Cmd4cr {
    pub fn new(config: SimConfig) -> Cmd4cr {
        let flash = Flash::open(config.flash_file.clone());
        let motion = Motion::with_stages(config.stages.clone());
        let mut sim = Cmd4cr {
            motion,
            io: Io::default(),
            flash,
            programs: Programs::default(),
            id: config.id.unwrap_or(DEFAULT_ID),
            id_setting: DEFAULT_ID,
            baud_code: DEFAULT_BAUD_CODE,
            run_on_boot: 0,
            sub31_return: 0,
            variables: [0; 100],
            program_clock: Duration::ZERO,
            mpg: [Mpg::default(); 4],
            joystick: Joystick::default(),
            line: Vec::new(),
            output: Vec::new(),
            config,
        };
        if let Some(source) = sim.flash.program().map(str::to_string) {
            match crate::protocol::cmd4cr::ascript::compile(&source) {
                Ok(program) => sim.programs.load(program),
                Err(errors) => {
                    let first = errors.first().map(ToString::to_string).unwrap_or_default();
                    sim.flash
                        .report(format!("its program does not compile: {first}"));
                }
            }
        }
        sim.power_cycle();
        sim
    }

    /// The ID the core answers to now.
    pub fn id(&self) -> u8 {
        self.id
    }

    /// The motion engine, for tests and demos: the stages, forced switch
    /// levels, ALM and INP inputs (`motion_mut().axis_mut(Axis::X).inputs`).
    pub fn motion(&self) -> &Motion {
        &self.motion
    }

    pub fn motion_mut(&mut self) -> &mut Motion {
        &mut self.motion
    }

    pub fn io(&self) -> &Io {
        &self.io
    }

    /// The program slots (the A-Script hook).
    pub fn programs(&self) -> &Programs {
        &self.programs
    }

    pub fn programs_mut(&mut self) -> &mut Programs {
        &mut self.programs
    }

    /// The last problem with the flash file, if any.
    pub fn flash_problem(&self) -> Option<&FlashError> {
        self.flash.problem()
    }

    /// Drive high-speed input DI`n` (1..4); a rising edge triggers the
    /// latch of axis n if armed (T2-3). `false` if there is no such input.
    pub fn set_digital_input(&mut self, n: u8, on: bool) -> bool {
        let Some(axis) = usize::from(n).checked_sub(1).and_then(Axis::from_index) else {
            return false;
        };
        let bit = 1u8 << axis.index();
        let was = self.io.digital_inputs & bit != 0;
        self.io.digital_inputs = io::with_bit(self.io.digital_inputs, axis.index() as u32, on);
        if on && !was {
            self.motion.latch_input(axis);
        }
        true
    }

    /// Drive configurable input IO`n` (1..32). `false` if there is none.
    pub fn set_io_input(&mut self, n: u8, on: bool) -> bool {
        match u32::from(n).checked_sub(1).filter(|&b| b < 32) {
            Some(bit) => {
                self.io.io_inputs = io::with_bit(self.io.io_inputs, bit, on);
                true
            }
            None => false,
        }
    }

    /// Set analog input AI`n` (1..2) in mV (clamped to 0..3300).
    pub fn set_analog_input(&mut self, n: u8, millivolts: u16) -> bool {
        match usize::from(n)
            .checked_sub(1)
            .and_then(|i| self.io.analog.get_mut(i))
        {
            Some(slot) => {
                *slot = millivolts.min(3300);
                true
            }
            None => false,
        }
    }

    /// /CEMG low (`true`): every axis stops, none may start (§2.1.3.1.2).
    pub fn set_emergency_input(&mut self, low: bool) {
        self.motion.set_emergency_input(low);
    }

    /// /CSTA low (`true`): its falling edge starts a move waiting for it.
    pub fn set_start_input(&mut self, low: bool) {
        self.motion.set_start_input(low);
    }

    /// Drive one input by a setting typed from outside (`IO5=1`, `AI1=1650`,
    /// `ALMX=1`; the names in [`inputs::INPUTS`]): what now holds, or what
    /// was wrong with it. An IO that IOCFG makes an output is refused: the
    /// wiring of an output is the core's to drive (our choice).
    pub fn drive_input(&mut self, text: &str) -> Result<String, SettingError> {
        let setting = inputs::parse(text)?;
        let name = setting.name();
        let on = setting.level == Level::On;
        let said = match (setting.row.input, setting.level) {
            (Input::Digital, _) => {
                self.set_digital_input(setting.which, on);
                format!("{name} {}", setting.level)
            }
            (Input::Io, _) => {
                let bit = u32::from(setting.which).saturating_sub(1);
                if self.io.io_config & (1 << bit) != 0 {
                    return Err(SettingError::Refused {
                        name: name.clone(),
                        why: format!(
                            "IOCFG 0x{:08X} makes {name} an output (bit {bit} set); \
                             the simulator drives inputs only (IOCFG with bit {bit} clear makes it one)",
                            self.io.io_config
                        ),
                    });
                }
                self.set_io_input(setting.which, on);
                format!("{name} {}", setting.level)
            }
            (Input::Analog, level) => {
                // The table reads AI values as numbers (0..3300) only.
                let millivolts = match level {
                    Level::Number(n) => u16::try_from(n).unwrap_or(u16::MAX),
                    _ => 0,
                };
                self.set_analog_input(setting.which, millivolts);
                format!("{name} {} mV", millivolts.min(3300))
            }
            (Input::Emergency, _) => {
                self.set_emergency_input(on);
                if on {
                    format!("{name} on (/CEMG low: every axis stops, none may start)")
                } else {
                    format!("{name} off (/CEMG high)")
                }
            }
            (Input::Start, _) => {
                self.set_start_input(on);
                format!(
                    "{name} {} (/CSTA {})",
                    setting.level,
                    if on { "low" } else { "high" }
                )
            }
            (
                axis_input @ (Input::Alarm
                | Input::PlusLimit
                | Input::MinusLimit
                | Input::Home
                | Input::Slowdown),
                level,
            ) => {
                let axis = self.axis_of(&setting)?;
                let forced = level.is_on();
                let inputs = &mut self.motion.axis_mut(axis).inputs;
                match axis_input {
                    Input::PlusLimit => inputs.plus_limit = forced,
                    Input::MinusLimit => inputs.minus_limit = forced,
                    Input::Home => inputs.home = forced,
                    Input::Slowdown => inputs.slowdown = forced,
                    // Input::Alarm, the one left in this arm.
                    _ => self.motion.set_alarm(axis, on),
                }
                match level {
                    Level::Released => format!("{name} from the stage (where the carriage is)"),
                    _ => format!("{name} {level}"),
                }
            }
            (Input::Limits, level) => {
                let swapped = crate::sim::inputs::limits_swapped(level);
                for axis in motion::Axis::ALL {
                    self.motion.axis_mut(axis).stage.limits_swapped = swapped;
                }
                if swapped {
                    "LIMITS swapped: on every axis the + end turns L- on, the - end L+".into()
                } else {
                    "LIMITS right: on every axis the + end turns L+ on, the - end L-".into()
                }
            }
            (Input::Missed, level) => {
                let axis = self.axis_of(&setting)?;
                let letter = axis.letter();
                // The table reads MISS values as numbers only.
                let steps = match level {
                    Level::Number(n) => n,
                    _ => 0,
                };
                if steps == 0 {
                    format!("{name} 0: no steps missed")
                } else {
                    let Some(direction) = self.motion.miss_steps(axis, steps) else {
                        return Err(SettingError::Refused {
                            name: name.clone(),
                            why: format!(
                                "no move drives {letter} now, and a motor misses steps only while a move sends it pulses: \
                                 start one ({letter}1000, J{letter}+, H{letter}+0, an interpolation) and set {name} while it runs"
                            ),
                        });
                    };
                    let sign = match direction {
                        motion::Direction::Plus => '+',
                        motion::Direction::Minus => '-',
                    };
                    format!(
                        "{name} {steps}: the {letter} motor, moving {sign}, missed {steps} steps: \
                         carriage and encoder are {steps} pulses behind the pulse counter"
                    )
                }
            }
            (Input::Slip, level) => {
                let axis = self.axis_of(&setting)?;
                let letter = axis.letter();
                let per_mille = match level {
                    Level::Number(n) => u16::try_from(n.min(1000)).unwrap_or(1000),
                    _ => 0,
                };
                self.motion.set_slip(axis, per_mille);
                match per_mille {
                    0 => format!("{name} 0: the {letter} motor makes every step"),
                    1000 => format!(
                        "{name} 1000: the {letter} motor misses every step (it does not turn)"
                    ),
                    n => format!(
                        "{name} {n}: the {letter} motor misses {n} of every 1000 steps while it moves"
                    ),
                }
            }
        };
        Ok(said)
    }

    /// The axis a per-axis setting (`ALMY`, `MISSX`) names: the n-th of
    /// its row's list is axis n.
    fn axis_of(&self, setting: &Setting<Input>) -> Result<Axis, SettingError> {
        Axis::from_index(usize::from(setting.which)).ok_or_else(|| SettingError::UnknownName {
            name: setting.name(),
            inputs: super::inputs::summary(inputs::INPUTS),
        })
    }

    /// `counts` from the MPG input of `axis`, after the input stage: with
    /// MPE on, the axis follows by counts × MPM × MPD / 2048 and MP counts
    /// them (§2.5.2.2).
    pub fn turn_mpg(&mut self, axis: Axis, counts: i64) {
        let Some(mpg) = self.mpg.get_mut(axis.index()) else {
            return;
        };
        if !mpg.enabled {
            return;
        }
        let scaled = counts
            .saturating_mul(mpg.multiplier)
            .saturating_mul(mpg.divider)
            .saturating_add(mpg.remainder);
        let geared = scaled.div_euclid(2048);
        mpg.remainder = scaled.rem_euclid(2048);
        mpg.counter = motion::axis::wrap28(mpg.counter + geared);
        self.motion.nudge(axis, geared);
    }

    /// A power cycle: RAM settings afresh, the stored ones from flash, the
    /// boot values applied, the ID and baud rate written before take effect,
    /// the `SLOAD` programs started (§2.1.5, §2.1.7, §2.7.10).
    pub fn power_cycle(&mut self) {
        self.motion.power_up();
        let wired = (self.io.digital_inputs, self.io.io_inputs, self.io.analog);
        self.io = Io::default();
        (self.io.digital_inputs, self.io.io_inputs, self.io.analog) = wired;
        self.id_setting = DEFAULT_ID;
        self.baud_code = DEFAULT_BAUD_CODE;
        self.run_on_boot = 0;
        self.sub31_return = 0;
        self.variables = [0; 100];
        self.mpg = [Mpg::default(); 4];
        self.joystick = Joystick::default();
        self.load_flash();
        self.io.power_up();
        self.id = self.config.id.unwrap_or(self.id_setting);
        self.line.clear();
        self.programs.stop_all();
        self.program_clock = Duration::ZERO;
        for n in 0..programs::PROGRAM_SLOTS {
            if self.run_on_boot & (1 << n) != 0 {
                // A slot the source does not define is left alone.
                let _ = self
                    .programs
                    .control(n, crate::protocol::cmd4cr::ProgramControl::Start);
            }
        }
    }

    /// One line for the user: what is simulated and our choices where the
    /// manual gives none.
    pub fn help_line(&self) -> String {
        use motion::stage::{DEMO_END_STOP, DEMO_HOME, DEMO_LIMIT, DEMO_Z_INDEX};
        format!(
            "CMD-4CR simulator (firmware {FIRMWARE_VERSION}): ID {:02}, answers only its own ID (00 is no broadcast), \
             writes answer {:?}; defaults chosen: HSPD {} pps, LSPD {} pps, ACC {} ms, DEC {} ms, \
             POL {} on every axis, IOCFG 0x{:08X} (IO17..32 outputs), PWM {} %, \
             SYNC word bits 0-2 condition (1 =, 2 >, 3 <, 4 continuous) bit 3 encoder source; \
             each axis a stage with end limits at ±{DEMO_LIMIT} (LIMITS=swapped wires them the wrong way round) \
             and end stops at ±{DEMO_END_STOP} where the motor stalls, home switch {}..{}, \
             Z index every {} pulses at {}, encoder 1 count per pulse; \
             limits and ALM stop at once; HSPD is the arc speed of circles; \
             StepNLoop defaults SLR 1.000 SLT 10 SLE 1000 SLA 3, interpolated moves (circle centres too) in encoder counts at pulse speeds, \
             verified and corrected per axis, no correction after STOP/ABORT, SLS 4 for one tick after ABORT, \
             BSTART with SL on answers ?Error SNL, LTP stays in pulses, SL=1 leaves SL off under the joystick; \
             MISSX=n makes the X motor miss n steps of the move under way (against its direction; refused at rest), \
             SLIPX=n n per mille of every move's steps (not under the joystick or MPG); \
             STOP under the joystick answers like any command and does not stop it (the manual's \"invalid status\" reply is not given), \
             ESTOP stops it until CLR and the stick is back in its dead band; \
             joystick JSPD 1000 pps, JDEL 100 pps/ms, JTOL 50 mV, JLIM ±90000/±100000; \
             inputs driven from outside (--input, a line on the standard input of `axterm sim`, :sim-input): {}",
            self.id,
            self.config.write_reply,
            motion::DEFAULT_HSPD,
            motion::DEFAULT_LSPD,
            motion::DEFAULT_ACC_MS,
            motion::DEFAULT_DEC_MS,
            motion::axis::DEFAULT_POLARITY,
            io::DEFAULT_IOCFG,
            io::DEFAULT_PWM,
            DEMO_HOME.low,
            DEMO_HOME.high,
            DEMO_Z_INDEX.period,
            DEMO_Z_INDEX.phase,
            super::inputs::summary(inputs::INPUTS),
        )
    }

    /// Something needs every tick: a program or the joystick.
    fn ticking(&self) -> bool {
        self.programs.any_running()
            || self.joystick.enable & 3 != 0
            || self.joystick.velocity.iter().any(|&v| v != 0.0)
    }

    /// One tick of joystick control of X (AI1) and Y (AI2): the speed
    /// follows the stick, at most JDEL pps per ms faster or slower
    /// (§2.5.1.2; the unit is not stated, pps per ms is our choice).
    fn run_joystick(&mut self) {
        let tick = motion::TICK.as_secs_f64();
        for (i, axis) in [(0, Axis::X), (1, Axis::Y)] {
            let enabled = self.joystick.enable & (1 << i) != 0;
            let demand = if enabled {
                let millivolts = f64::from(self.io.analog[i]);
                let wanted = self.joystick.demand(i, millivolts);
                self.joystick.limited(i, self.motion.counter(axis), wanted)
            } else {
                0.0
            };
            let step = self.joystick.delta[i].max(1) as f64 * 1000.0 * tick;
            let current = self.joystick.velocity[i];
            let velocity = current + (demand - current).clamp(-step, step);
            self.joystick.velocity[i] = velocity;
            self.joystick.fraction[i] += velocity * tick;
            let mut whole = self.joystick.fraction[i].trunc();
            self.joystick.fraction[i] -= whole;
            // Never past the outer soft limit.
            if enabled {
                let position = self.motion.counter(axis) as f64;
                let outer = |n: usize| self.joystick.limits.get(i * 4 + n).copied().unwrap_or(0);
                let (low, high) = (outer(0) as f64, outer(3) as f64);
                if whole > 0.0 && high > low {
                    whole = whole.min((high - position).max(0.0));
                } else if whole < 0.0 && high > low {
                    whole = whole.max((low - position).min(0.0));
                }
            }
            self.motion.joystick_move(axis, whole as i64, velocity);
        }
    }

    // ---- framing ----------------------------------------------------

    fn receive(&mut self, byte: u8) {
        match byte {
            b'@' => {
                self.line.clear();
                self.line.push(byte);
            }
            b'\r' => {
                if !self.line.is_empty() {
                    let line = std::mem::take(&mut self.line);
                    self.handle_line(&line);
                }
            }
            b'\n' => {}
            _ if self.line.is_empty() => {}
            _ if self.line.len() >= MAX_LINE => self.line.clear(),
            _ => self.line.push(byte),
        }
    }

    fn handle_line(&mut self, line: &[u8]) {
        let Ok(request) = parse_request(line) else {
            return;
        };
        if request.id != self.id {
            return;
        }
        let reply = self.answer(&request.text);
        self.output.extend_from_slice(reply.as_bytes());
        self.output.push(b'\r');
    }
}

impl SimulatedController for Cmd4cr {
    fn refused_memory_file(&self) -> Option<String> {
        self.flash.refused().map(ToString::to_string)
    }

    fn feed(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.receive(byte);
        }
    }

    fn advance(&mut self, dt: Duration) {
        if !self.ticking() {
            self.motion.advance(dt);
            return;
        }
        // Programs, the joystick and motion take turns tick by tick.
        self.program_clock += dt;
        while self.program_clock >= motion::TICK {
            self.program_clock -= motion::TICK;
            self.run_threads();
            self.run_joystick();
            self.motion.advance(motion::TICK);
            if !self.ticking() {
                let rest = std::mem::take(&mut self.program_clock);
                self.motion.advance(rest);
                return;
            }
        }
    }

    fn take_output(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.output)
    }

    fn help(&self) -> String {
        self.help_line()
    }

    fn drive_input(&mut self, setting: &str) -> Result<String, String> {
        Cmd4cr::drive_input(self, setting).map_err(|e| e.to_string())
    }

    fn load_program(&mut self, source: &str) -> Result<(), Vec<String>> {
        Cmd4cr::load_program(self, source)
            .map_err(|errors| errors.iter().map(ToString::to_string).collect())
    }
}
