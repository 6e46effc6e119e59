//! Simulated controllers. Each is a plain state machine driven by bytes in
//! (`feed`) and virtual time (`advance`); what it answers is collected with
//! `take_output`. Nothing here sleeps or touches a clock, so tests are
//! deterministic; the real-time servers in `cli` drive them from the wall clock.

use std::time::Duration;

pub mod bus;
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
    /// The time one byte takes on the line it is connected by (`None`:
    /// bytes pass at once); the line tells it whenever a connection opens.
    /// A controller whose commands wait for room in its own transmit
    /// buffer (MCCL's Tells) sends at that rate; the others ignore it.
    fn line_byte_time(&mut self, byte_time: Option<Duration>) {
        let _ = byte_time;
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
/// Listed beside its protocol family in the registry
/// ([`crate::families::FAMILIES`]), so that registering a family and its
/// simulators is one entry.
pub struct SimKind {
    pub name: &'static str,
    pub description: &'static str,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::{find_kind, kind_names, kinds};
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
        for kind in kinds() {
            assert!(crate::families::family_of(kind).is_some(), "{}", kind.name);
        }
        let tmcl = find_kind("tmcm1110").and_then(crate::families::family_of);
        assert_eq!(tmcl.map(|f| f.name), Some("tmcl"));
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
        assert!(kinds().filter(|k| k.eeprom_refusal.is_none()).count() >= 2);
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
        for kind in kinds() {
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
