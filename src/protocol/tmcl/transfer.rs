//! Program transfer in TMCL terms: which words may be downloaded, the
//! frames that store and read them back, and what the module's answers
//! say (§3.6.53 control commands 128–135, digest D10.2). Pure: the
//! session's program module (`session::program`) does the talking.
//!
//! Decisions where the manual is silent:
//! - A stored word is answered with status 101 "command loaded into TMCL
//!   program EEPROM" (§3.2.1 Table 4). Status 100 means the module
//!   executed the command instead of storing it (it was not in download
//!   mode): the download has failed, and the command has run.
//! - 134's reply layout is not in the manual (digest D4): the simulator's
//!   is taken, the host address, the stored 7 bytes (opcode, type,
//!   motor/bank, value MSB first) and a checksum over the first eight.
//!   An ordinary reply to 134 with an error status (GP81 code protection:
//!   6) is a refusal.
//! - Only words whose opcode is below 128 are downloaded: the manual's
//!   control commands (128–137) and 138 and 255 are executed even in
//!   download mode (§3.6.53), and other firmwares put more control
//!   commands in that range. A program image holding one is refused before
//!   anything is sent, as is an empty word (opcode 0 is no TMCL command).

use std::fmt;

use super::asm::{PROGRAM_MEMORY_WORDS, ProgramWord, check_program_command};
use super::command::{Command, opcode};
use super::frame::{FRAME_LEN, Reply, Request, Status, checksum};
use super::hex::to_hex;
use super::line::format_command;

/// GP77 "auto start mode" (§5.1 Table 18, §8.7): 1 starts the program at
/// power-up. Stored to EEPROM by SGP itself (access RWA).
pub const GP_AUTOSTART: u8 = 77;
/// GP81 "TMCL code protection" (§5.1): 1/3 forbid reading the program
/// back, 2/3 forbid overwriting it.
pub const GP_CODE_PROTECTION: u8 = 81;
/// GP128 "TMCL application status" (§5.1): 0 stop, 1 run, 2 step, 3 reset.
pub const GP_APPLICATION_STATUS: u8 = 128;

/// The first opcode of the control-command range (§3.6.53).
const FIRST_CONTROL_OPCODE: u8 = opcode::STOP_APPLICATION;

/// Bytes on the wire for one transaction: a request and its reply (§3.1,
/// §3.2; 134's special reply has nine bytes too).
pub const TRANSACTION_BYTES: u64 = 2 * FRAME_LEN as u64;

/// The word as a technician reads it: the line and the stored bytes.
pub fn show_word(word: ProgramWord) -> String {
    format!(
        "{} ({})",
        format_command(&word.command()),
        to_hex(&word.to_bytes())
    )
}

/// Why a word cannot be downloaded.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("word {address} ({shown}) cannot be downloaded: {reason}")]
pub struct Unstorable {
    pub address: usize,
    pub shown: String,
    pub reason: String,
}

/// Check a whole image before anything is sent: it fits the program memory
/// and every word is one the module stores (see the module documentation).
pub fn check_image(words: &[ProgramWord]) -> Result<(), Unstorable> {
    if words.len() > PROGRAM_MEMORY_WORDS {
        return Err(Unstorable {
            address: PROGRAM_MEMORY_WORDS,
            shown: format!("{} words", words.len()),
            reason: format!("program memory holds {PROGRAM_MEMORY_WORDS} words"),
        });
    }
    for (address, word) in words.iter().enumerate() {
        let unstorable = |reason: String| Unstorable {
            address,
            shown: to_hex(&word.to_bytes()),
            reason,
        };
        if word.opcode == 0 {
            return Err(unstorable(
                "instruction 0 is not a TMCL command (an empty memory cell)".into(),
            ));
        }
        if let Err(e) = check_program_command(&word.command()) {
            return Err(unstorable(e.to_string()));
        }
        if word.opcode >= FIRST_CONTROL_OPCODE {
            return Err(unstorable(format!(
                "instruction {} is in the control-command range 128..255, which a module \
                 executes during a download instead of storing (§3.6.53)",
                word.opcode
            )));
        }
    }
    Ok(())
}

/// The frame that stores `word` while the module is in download mode: the
/// word itself as a command (§3.6.53, 132).
pub fn store_request(module: u8, word: ProgramWord) -> Request {
    Request {
        address: module,
        command: word.opcode,
        kind: word.kind,
        motor_bank: word.motor_bank,
        value: word.value,
    }
}

/// What went wrong with a stored word's answer.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum StoreProblem {
    #[error("its answer is unreadable: {0}")]
    Unreadable(String),
    #[error(
        "the module executed it instead of storing it (status 100): it was not in download mode"
    )]
    Executed,
    #[error("the module refused it: {} (status {})", .0.meaning(), .0 .0)]
    Refused(Status),
}

/// The answer to a stored word: status 101 or the problem.
pub fn judge_store(frame: &[u8]) -> Result<(), StoreProblem> {
    let bytes: &[u8; FRAME_LEN] = frame.try_into().map_err(|_| {
        StoreProblem::Unreadable(format!(
            "a reply has {FRAME_LEN} bytes, this one {}",
            frame.len()
        ))
    })?;
    let reply = Reply::from_bytes(bytes).map_err(|e| StoreProblem::Unreadable(e.to_string()))?;
    match reply.status {
        Status::LOADED => Ok(()),
        Status::OK => Err(StoreProblem::Executed),
        status => Err(StoreProblem::Refused(status)),
    }
}

/// Why a 134 answer holds no program word.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReadBackProblem {
    #[error("the module refused to read it: {} (status {}){}", .0.meaning(), .0 .0, protection_hint(*.0))]
    Refused(Status),
    #[error("a read-back answer has {FRAME_LEN} bytes, this one {0}")]
    WrongLength(usize),
    #[error("wrong checksum: the answer carries {found:#04x}, its bytes sum to {expected:#04x}")]
    Checksum { expected: u8, found: u8 },
}

fn protection_hint(status: Status) -> &'static str {
    if status == Status::NOT_AVAILABLE {
        "; GP81 code protection 1 or 3 forbids reading the program back (§5.1)"
    } else {
        ""
    }
}

/// The word in the answer to `134` sent to `module` (layout in the module
/// documentation), or why there is none. An ordinary reply from `module`
/// to 134 with an error status is a refusal, as the console reads it.
pub fn read_back(module: u8, frame: &[u8]) -> Result<ProgramWord, ReadBackProblem> {
    let frame: &[u8; FRAME_LEN] = frame
        .try_into()
        .map_err(|_| ReadBackProblem::WrongLength(frame.len()))?;
    if let Ok(reply) = Reply::from_bytes(frame)
        && reply.module_address == module
        && reply.command == opcode::READ_MEMORY
        && !reply.status.is_success()
    {
        return Err(ReadBackProblem::Refused(reply.status));
    }
    let expected = checksum(&frame[..8]);
    if frame[8] != expected {
        return Err(ReadBackProblem::Checksum {
            expected,
            found: frame[8],
        });
    }
    let mut bytes = [0u8; ProgramWord::LEN];
    bytes.copy_from_slice(&frame[1..8]);
    Ok(ProgramWord::from_bytes(bytes))
}

/// A memory cell that holds no program word: all zeros (the simulator's
/// erased memory, and a factory reset) or all 0xFF (what erased EEPROM
/// reads on most parts; the manual says nothing of either). Neither is a
/// command a program can hold (opcode 0 is none, 255 is a control command).
pub fn is_blank(word: ProgramWord) -> bool {
    word.is_empty() || word.to_bytes() == [0xFF; ProgramWord::LEN]
}

/// A standalone program's state, GP128 (§5.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ApplicationState {
    Stopped,
    Running,
    /// Single-stepping (130).
    Stepping,
    /// Reset (131) and not started since.
    Reset,
    /// A value the manual does not list.
    Unknown(i64),
}

impl ApplicationState {
    pub fn from_gp128(value: i64) -> Self {
        match value {
            0 => ApplicationState::Stopped,
            1 => ApplicationState::Running,
            2 => ApplicationState::Stepping,
            3 => ApplicationState::Reset,
            other => ApplicationState::Unknown(other),
        }
    }

    /// The program may be executing commands.
    pub fn is_active(self) -> bool {
        matches!(
            self,
            ApplicationState::Running | ApplicationState::Stepping | ApplicationState::Unknown(_)
        )
    }
}

impl fmt::Display for ApplicationState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ApplicationState::Stopped => f.write_str("stopped"),
            ApplicationState::Running => f.write_str("running"),
            ApplicationState::Stepping => f.write_str("single-stepping"),
            ApplicationState::Reset => f.write_str("reset"),
            ApplicationState::Unknown(v) => write!(f, "in state {v} (GP128)"),
        }
    }
}

/// The typed commands of a transfer, so that callers need not build them.
pub mod commands {
    use super::*;

    pub fn enter_download(start: u16) -> Command {
        Command::EnterDownload {
            address: i32::from(start),
        }
    }

    pub fn exit_download() -> Command {
        Command::ExitDownload
    }

    pub fn read_memory(address: u16) -> Command {
        Command::ReadMemory {
            address: i32::from(address),
        }
    }

    pub fn reset_application() -> Command {
        Command::ResetApplication
    }

    /// 129 type 0: run from the current address (after 131: from 0).
    pub fn run_application() -> Command {
        Command::RunApplication { start: None }
    }

    /// GP128 rather than 135 type 0: the manual documents GP128's coding,
    /// not 135's layout (digest D4).
    pub fn application_state() -> Command {
        Command::Ggp {
            param: GP_APPLICATION_STATUS,
            bank: 0,
        }
    }

    pub fn set_autostart(on: bool) -> Command {
        Command::Sgp {
            param: GP_AUTOSTART,
            bank: 0,
            value: i32::from(on),
        }
    }

    pub fn autostart() -> Command {
        Command::Ggp {
            param: GP_AUTOSTART,
            bank: 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::tmcl::validate::validate;

    fn word(opcode: u8, kind: u8, motor_bank: u8, value: i32) -> ProgramWord {
        ProgramWord {
            opcode,
            kind,
            motor_bank,
            value,
        }
    }

    #[test]
    fn words_show_as_line_and_bytes() {
        assert_eq!(
            show_word(word(4, 0, 0, 1000)),
            "MVP ABS, 0, 1000 (04 00 00 00 00 03 E8)"
        );
    }

    #[test]
    fn control_commands_and_empty_words_are_refused_before_sending() {
        assert_eq!(
            check_image(&[word(4, 0, 0, 1000), word(28, 0, 0, 0)]),
            Ok(())
        );
        let refused = check_image(&[word(28, 0, 0, 0), word(133, 0, 0, 0)]).unwrap_err();
        assert_eq!(refused.address, 1);
        assert!(refused.reason.contains("control command"), "{refused}");
        let empty = check_image(&[word(0, 0, 0, 0)]).unwrap_err();
        assert!(
            empty
                .to_string()
                .starts_with("word 0 (00 00 00 00 00 00 00)"),
            "{empty}"
        );
        for opcode in [138, 200, 255] {
            let refused = check_image(&[word(opcode, 0, 0, 0)]).unwrap_err();
            assert!(
                refused.to_string().contains("cannot be downloaded"),
                "{refused}"
            );
        }
        let too_long = vec![word(28, 0, 0, 0); PROGRAM_MEMORY_WORDS + 1];
        assert!(check_image(&too_long).unwrap_err().reason.contains("2048"));
    }

    #[test]
    fn stored_words_must_answer_101() {
        let reply = |status| {
            Reply {
                host_address: 2,
                module_address: 1,
                status: Status(status),
                command: 4,
                value: 0,
            }
            .to_bytes()
        };
        assert_eq!(judge_store(&reply(101)), Ok(()));
        assert_eq!(judge_store(&reply(100)), Err(StoreProblem::Executed));
        let refused = judge_store(&reply(2)).unwrap_err();
        assert_eq!(
            refused.to_string(),
            "the module refused it: invalid command (status 2)"
        );
        let mut bad = reply(101);
        bad[8] ^= 1;
        assert!(matches!(
            judge_store(&bad),
            Err(StoreProblem::Unreadable(_))
        ));
        assert!(matches!(judge_store(&[]), Err(StoreProblem::Unreadable(_))));
    }

    #[test]
    fn a_store_request_is_the_word_addressed_to_the_module() {
        let request = store_request(3, word(4, 1, 0, -10000));
        assert_eq!(
            request.to_bytes(),
            [3, 4, 1, 0, 0xFF, 0xFF, 0xD8, 0xF0, 0xCE]
        );
    }

    #[test]
    fn read_back_takes_the_special_layout_and_refusals() {
        // host, opcode, type, motor, value MSB..LSB, checksum (the simulator's
        // layout, see execute.rs)
        let frame = [0x02, 0x04, 0x01, 0x00, 0xFF, 0xFF, 0xD8, 0xF0, 0xCD];
        assert_eq!(read_back(1, &frame), Ok(word(4, 1, 0, -10000)));
        let mut bad = frame;
        bad[8] ^= 1;
        assert!(matches!(
            read_back(1, &bad),
            Err(ReadBackProblem::Checksum { .. })
        ));
        assert_eq!(
            read_back(1, &frame[..8]),
            Err(ReadBackProblem::WrongLength(8))
        );
        let refusal = Reply {
            host_address: 2,
            module_address: 1,
            status: Status::NOT_AVAILABLE,
            command: 134,
            value: 0,
        }
        .to_bytes();
        let problem = read_back(1, &refusal).unwrap_err();
        assert_eq!(problem, ReadBackProblem::Refused(Status::NOT_AVAILABLE));
        assert!(problem.to_string().contains("GP81"), "{problem}");
    }

    #[test]
    fn blank_cells_are_zeros_or_erased_eeprom() {
        assert!(is_blank(ProgramWord::default()));
        assert!(is_blank(word(0xFF, 0xFF, 0xFF, -1)));
        assert!(!is_blank(word(28, 0, 0, 0)));
        assert!(!is_blank(word(0, 0, 0, 1)));
    }

    #[test]
    fn application_states_follow_gp128() {
        assert_eq!(ApplicationState::from_gp128(1), ApplicationState::Running);
        assert!(ApplicationState::from_gp128(2).is_active());
        assert!(!ApplicationState::from_gp128(0).is_active());
        assert!(!ApplicationState::from_gp128(3).is_active());
        assert_eq!(
            ApplicationState::from_gp128(9).to_string(),
            "in state 9 (GP128)"
        );
    }

    #[test]
    fn the_transfer_commands_pass_the_modules_tables() {
        for command in [
            commands::enter_download(0),
            commands::exit_download(),
            commands::read_memory(2047),
            commands::reset_application(),
            commands::run_application(),
            commands::application_state(),
            commands::set_autostart(true),
            commands::autostart(),
        ] {
            assert_eq!(validate(&command), Ok(()), "{command:?}");
        }
    }
}
