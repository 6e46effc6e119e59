//! Simulated controllers. Each is a plain state machine driven by bytes in
//! (`feed`) and virtual time (`advance`); what it answers is collected with
//! `take_output`. Nothing here sleeps or touches a clock, so tests are
//! deterministic; the real-time servers in `cli` drive them from the wall clock.

use std::time::Duration;

pub mod cmd4cr;
pub mod faults;
pub mod inputs;
pub mod mccl;
pub mod sixpack2;
pub mod stored_file;
pub mod tmcm1110;

/// A controller that can stand behind a link in place of hardware.
pub trait SimulatedController: Send {
    /// Bytes arriving from the host, in order, possibly split anywhere.
    fn feed(&mut self, bytes: &[u8]);
    /// Let `dt` of virtual time pass (motion, timers, delayed replies).
    fn advance(&mut self, dt: Duration);
    /// Bytes the controller has sent since the last call.
    fn take_output(&mut self) -> Vec<u8>;
    /// One line for the user: what is simulated and the defaults we chose
    /// where the manual gives none.
    fn help(&self) -> String;
    /// Take the faults of `plan` that happen inside the controller (a
    /// program word stored corrupted, `corrupt-store`), replacing any armed
    /// before; the line calls this whenever a connection opens, so they
    /// count per connection. Controllers without such faults ignore it.
    fn arm_faults(&mut self, plan: &faults::FaultPlan) {
        let _ = plan;
    }
    /// Drive one of the controller's inputs from outside by a setting
    /// such as `IO5=1` (`--input`, a line on the standard input of `axterm
    /// sim`, the console's `:sim-input`; the names are the kind's
    /// [`SimKind::input_help`]): a line saying what now holds ("IO5 on"),
    /// or what was wrong, listing the inputs there are. Controllers
    /// without such inputs refuse.
    fn drive_input(&mut self, setting: &str) -> Result<String, String> {
        let _ = setting;
        Err("this simulator has no inputs to drive".to_string())
    }
    /// Load standalone-program source into the controller, as a vendor's
    /// tool would write it into its memory (`axterm sim KIND --program
    /// FILE`); the problems, one per line, if it cannot. Controllers
    /// without such programs refuse.
    fn load_program(&mut self, source: &str) -> Result<(), Vec<String>> {
        let _ = source;
        Err(vec!["this simulator runs no A-Script programs".to_string()])
    }
    /// A BREAK on the line: the host held it at space for longer than a
    /// character, which a UART reports apart from the bytes (a line
    /// `BREAK` on the standard input of `axterm sim`). Protocols that
    /// resynchronise with one act on it; to the others it is line noise,
    /// and they ignore it.
    fn line_break(&mut self) {}
    /// Why the file given for its non-volatile memory
    /// ([`SimOptions::eeprom_file`]) was refused: it is there but is not
    /// this simulator's own (another program's file, another kind's,
    /// damaged), so it was left untouched and the memory is kept in RAM
    /// only; `axterm sim` then serves nothing. `None` when no file was
    /// given, or it was missing, empty or loaded. A simulator with a
    /// memory file reads it through [`stored_file`] and answers here.
    fn refused_memory_file(&self) -> Option<String> {
        None
    }
}

/// Options common to every simulator kind.
#[derive(Debug, Clone, Default)]
pub struct SimOptions {
    /// Module address on the simulated bus; the family's default when `None`.
    pub address: Option<u8>,
    /// File keeping the simulated EEPROM/flash between runs.
    pub eeprom_file: Option<std::path::PathBuf>,
}

/// One built-in simulator: its name on the command line and how to make it.
pub struct SimKind {
    pub name: &'static str,
    pub description: &'static str,
    /// The protocol family it speaks (a name in `protocol::FAMILIES`).
    pub family: &'static str,
    pub build: fn(&SimOptions) -> Box<dyn SimulatedController>,
    /// The names of the inputs [`SimulatedController::drive_input`] drives
    /// (`IO5`, `ALMX`, …), for completion.
    pub input_names: fn() -> Vec<String>,
    /// One line per kind of input: its settings and what it is, for help.
    pub input_help: fn() -> Vec<String>,
    /// Why `axterm sim KIND --eeprom FILE` is refused, for a controller
    /// that keeps nothing a host sets between power-ups; `None` when the
    /// file keeps its non-volatile memory.
    pub eeprom_refusal: Option<&'static str>,
}

/// Every built-in simulator. A new family adds one line here.
pub const SIM_KINDS: &[SimKind] = &[
    SimKind {
        name: "tmcm1110",
        description: "Trinamic TMCM-1110 StepRocker (TMCL, 1 axis)",
        family: "tmcl",
        build: |options| {
            let mut config = tmcm1110::SimConfig::default();
            if let Some(address) = options.address {
                config.address = address;
            }
            config.eeprom_file = options.eeprom_file.clone();
            let mut sim = tmcm1110::Tmcm1110::new(config);
            if let Some(address) = options.address {
                sim.set_module_address(address);
            }
            Box::new(sim)
        },
        input_names: || inputs::names(tmcm1110::inputs::INPUTS),
        input_help: || inputs::help_lines(tmcm1110::inputs::INPUTS),
        eeprom_refusal: None,
    },
    SimKind {
        name: "cmd4cr",
        description: "Nippon Pulse Commander core CMD-4CR (ASCII, 4 axes X/Y/Z/U)",
        family: "cmd4cr",
        build: |options| {
            Box::new(cmd4cr::Cmd4cr::new(cmd4cr::SimConfig {
                id: options.address,
                flash_file: options.eeprom_file.clone(),
                ..cmd4cr::SimConfig::default()
            }))
        },
        input_names: || inputs::names(cmd4cr::inputs::INPUTS),
        input_help: || inputs::help_lines(cmd4cr::inputs::INPUTS),
        eeprom_refusal: None,
    },
    SimKind {
        name: "sixpack2",
        description: "Trinamic SIXpack 2 (9-byte binary frames, 6 axes)",
        family: "sixpack2",
        build: |options| {
            let mut config = sixpack2::SimConfig::default();
            if let Some(address) = options.address {
                config.rotary_address = address;
            }
            Box::new(sixpack2::Sixpack2::new(config))
        },
        input_names: || inputs::names(sixpack2::inputs::INPUTS),
        input_help: || inputs::help_lines(sixpack2::inputs::INPUTS),
        eeprom_refusal: Some(sixpack2::NOTHING_STORED),
    },
    // MultiFlex PCI and ETH differ in one thing the host can see: the ETH
    // keeps its macros (non-volatile, `--eeprom FILE`), the PCI loses them
    // at a reset. Two kinds of one family, as the two products are.
    SimKind {
        name: "mccl",
        description: "PMC MultiFlex PCI (MCCL ASCII, axes 1-4 servo, 5 stepper; volatile macros)",
        family: "mccl",
        build: |_| Box::new(mccl::Mccl::new(mccl::SimConfig::pci())),
        input_names: || inputs::names(mccl::inputs::INPUTS),
        input_help: || inputs::help_lines(mccl::inputs::INPUTS),
        eeprom_refusal: Some(mccl::PCI_KEEPS_NOTHING),
    },
    SimKind {
        name: "mccl-eth",
        description: "PMC MultiFlex ETH (MCCL ASCII, axes 1-4 servo, 5 stepper; macros kept in --eeprom FILE)",
        family: "mccl",
        build: |options| {
            Box::new(mccl::Mccl::new(mccl::SimConfig::eth(
                options.eeprom_file.clone(),
            )))
        },
        input_names: || inputs::names(mccl::inputs::INPUTS),
        input_help: || inputs::help_lines(mccl::inputs::INPUTS),
        eeprom_refusal: None,
    },
];

/// The simulator called `name` (case-insensitive), if there is one.
pub fn find_kind(name: &str) -> Option<&'static SimKind> {
    SIM_KINDS.iter().find(|k| k.name.eq_ignore_ascii_case(name))
}

/// Names of every simulator, for error messages and help.
pub fn kind_names() -> String {
    SIM_KINDS
        .iter()
        .map(|k| k.name)
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::tmcl::{Reply, Request, Status};

    fn gap_actual_position(sim: &mut dyn SimulatedController, address: u8) -> Option<Reply> {
        let frame = Request {
            address,
            command: 6,
            kind: 1,
            motor_bank: 0,
            value: 0,
        }
        .to_bytes();
        sim.feed(&frame);
        let out = sim.take_output();
        let bytes: [u8; 9] = out.as_slice().try_into().ok()?;
        Reply::from_bytes(&bytes).ok()
    }

    #[test]
    fn an_explicit_address_wins_over_the_one_in_the_eeprom_file() {
        let dir = tempfile::tempdir().expect("temp dir");
        let file = dir.path().join("eeprom.json");
        let kind = find_kind("TMCM1110").expect("registered");
        let remembered = SimOptions {
            address: Some(5),
            eeprom_file: Some(file.clone()),
        };
        drop((kind.build)(&remembered));

        let mut sim = (kind.build)(&SimOptions {
            address: None,
            eeprom_file: Some(file.clone()),
        });
        let reply = gap_actual_position(sim.as_mut(), 5).expect("answers at the stored address");
        assert_eq!(reply.status, Status::OK);
        drop(sim);

        let mut sim = (kind.build)(&SimOptions {
            address: Some(3),
            eeprom_file: Some(file),
        });
        assert!(gap_actual_position(sim.as_mut(), 5).is_none());
        let reply = gap_actual_position(sim.as_mut(), 3).expect("answers at --address");
        assert_eq!(reply.module_address, 3);
    }

    #[test]
    fn every_kind_speaks_a_known_family() {
        for kind in SIM_KINDS {
            assert!(
                crate::protocol::find_family(kind.family).is_some(),
                "{}: {}",
                kind.name,
                kind.family
            );
        }
    }

    #[test]
    fn the_cmd4cr_kind_answers_at_its_address_and_keeps_its_flash() {
        let dir = tempfile::tempdir().expect("temp dir");
        let file = dir.path().join("flash.json");
        let kind = find_kind("CMD4CR").expect("registered");
        let mut sim = (kind.build)(&SimOptions {
            address: Some(7),
            eeprom_file: Some(file.clone()),
        });
        sim.feed(b"@01PX\r@07POLX=3\r@07STORE\r");
        assert_eq!(sim.take_output(), b"OK\rOK\r");
        drop(sim);
        let mut sim = (kind.build)(&SimOptions {
            address: None,
            eeprom_file: Some(file),
        });
        sim.feed(b"@01POLX\r");
        assert_eq!(sim.take_output(), b"3\r");
        assert!(sim.help().contains("CMD-4CR"));
    }

    #[test]
    fn the_sixpack2_kind_answers_at_its_rotary_address_and_stores_nothing() {
        let kind = find_kind("SIXpack2").expect("registered");
        let mut sim = (kind.build)(&SimOptions {
            address: Some(3),
            eeprom_file: None,
        });
        sim.feed(&[0, 0x43, 0, 0, 0, 0, 0, 0, 0]);
        sim.feed(&[3, 0x43, 0, 0, 0, 0, 0, 0, 0]);
        sim.advance(std::time::Duration::from_millis(6));
        assert_eq!(sim.take_output(), [0x43, 148, 1, 30, 1, 0, 0, 0]);
        assert!(sim.help().contains("SIXpack 2"));
        assert!(kind.eeprom_refusal.is_some());
        assert!(
            SIM_KINDS
                .iter()
                .filter(|k| k.eeprom_refusal.is_none())
                .count()
                >= 2
        );
    }

    #[test]
    fn only_the_cmd4cr_loads_a_script_programs() {
        let options = SimOptions::default();
        let mut tmcl = (find_kind("tmcm1110").expect("registered").build)(&options);
        assert!(tmcl.load_program("PRG 0\nEND\n").is_err());
        let mut cmd4cr = (find_kind("cmd4cr").expect("registered").build)(&options);
        assert_eq!(cmd4cr.load_program("PRG 0\n    V1=5\nEND\n"), Ok(()));
        let problems = cmd4cr.load_program("PRG 0\n").expect_err("no END");
        assert!(problems[0].contains("Missing END"), "{problems:?}");
    }

    #[test]
    fn every_input_a_kind_names_can_be_driven() {
        for kind in SIM_KINDS {
            let mut sim = (kind.build)(&SimOptions::default());
            for name in (kind.input_names)() {
                let result = sim.drive_input(&format!("{name}=0"));
                // CMD-4CR IO17..IO32 are outputs at power-on (IOCFG).
                let output = kind.name == "cmd4cr"
                    && name
                        .strip_prefix("IO")
                        .and_then(|n| n.parse::<u8>().ok())
                        .is_some_and(|n| n >= 17);
                assert_eq!(result.is_ok(), !output, "{} {name}: {result:?}", kind.name);
            }
            assert!(!(kind.input_help)().is_empty(), "{}", kind.name);
            let unknown = sim.drive_input("NOSUCH=1").expect_err("no such input");
            assert!(unknown.contains("the inputs are"), "{unknown}");
        }
    }

    #[test]
    fn unknown_kinds_are_not_found() {
        assert!(find_kind("tmcm9999").is_none());
        assert_eq!(kind_names(), "tmcm1110, cmd4cr, sixpack2, mccl, mccl-eth");
    }
}
