//! The standalone programs (§2.7): the compiled A-Script source the core
//! holds, its four program threads PRG0–PRG3 (§2.7.3: "four independent
//! processors") and the state the ASCII side reads and controls:
//! `SACTRL[0-3]`, `SASTAT[0-3]`, `SPC[0-3]`, `GS[0-31]` (§2.7.8–§2.7.9).
//! The interpreter that runs the threads is `interpreter.rs`.
//!
//! Choices where the manual is silent:
//! - A slot whose program the source does not define reads `SASTAT` 3
//!   ("N/A", T2-34) and `SPC` 0; `SACTRL` to it is answered OK and changes
//!   nothing.
//! - `?Program Error` (T4-41: "the command cannot be processed because a
//!   standalone program is in error state") answers `SACTRL` start, pause
//!   or continue to a program in the error state; `SACTRL=0` (stop) clears
//!   the error and leaves it idle.
//! - `SPC` counts compiled steps (IF, WHILE, each action one step, ELSEIF
//!   two), the ascript compiler's form of the manual's "assembled lines".
//! - `SACTRL=1` (start) to a running program leaves it running (Ex 8
//!   sends `SR0=1` on every pass of its loop); to a paused one it starts
//!   over.
//! - `GS n` runs subroutine n in a fifth thread of its own, not visible
//!   through SASTAT; a second GS while one runs restarts it. With no
//!   subroutine n it answers `?Sub not Initialized`.

use std::sync::Arc;
use std::time::Duration;

use crate::protocol::cmd4cr::ascript::Program;
use crate::protocol::cmd4cr::{ErrorCode, ProgramControl};

use super::motion::Axis;

/// Program threads (§2.7.8) and the GS thread.
pub const PROGRAM_SLOTS: usize = 4;
const GS_THREAD: usize = PROGRAM_SLOTS;

/// `SASTAT` values (T2-34).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ProgramStatus {
    #[default]
    Idle = 0,
    Running = 1,
    Paused = 2,
    NotAvailable = 3,
    Error = 4,
}

/// What holds a thread.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wait {
    /// `DELAY`: time still to wait.
    Delay(Duration),
    /// `WAIT[axis]`, with the axis' error flags when the wait began.
    Axis { axis: Axis, errors_before: u32 },
}

/// Inside SUB 31: where the error happened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Handler {
    /// The step that failed.
    pub failed_step: usize,
    /// The call depth when SUB 31 was entered.
    pub depth: usize,
}

/// One program thread.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Thread {
    pub status: ProgramStatus,
    /// The step to run next (`SPC`).
    pub pc: usize,
    /// The first step of its PRG (or SUB, for GS).
    pub entry: usize,
    /// Return steps of the GOSUBs under way.
    pub stack: Vec<usize>,
    pub wait: Option<Wait>,
    pub handler: Option<Handler>,
    /// Why it stopped in the error state, for the console and tests.
    pub fault: Option<String>,
}

impl Thread {
    fn restart(&mut self, entry: usize, status: ProgramStatus) {
        *self = Thread {
            status,
            pc: entry,
            entry,
            ..Thread::default()
        };
    }
}

/// The loaded source and its threads.
#[derive(Debug, Clone, Default)]
pub struct Programs {
    pub(super) source: Option<Arc<Program>>,
    pub(super) threads: [Thread; PROGRAM_SLOTS + 1],
}

impl Programs {
    /// Put compiled A-Script in place of what was loaded; every thread
    /// stops.
    pub fn load(&mut self, program: Program) {
        self.source = Some(Arc::new(program));
        self.threads = Default::default();
    }

    /// Whether program `n` exists in the loaded source.
    pub fn defines(&self, n: usize) -> bool {
        self.entry(n).is_some()
    }

    fn entry(&self, n: usize) -> Option<usize> {
        let n = u8::try_from(n).ok()?;
        self.source.as_ref()?.program(n).map(|e| e.start)
    }

    /// A thread, for the console and tests (`None` past PRG3).
    pub fn thread(&self, n: usize) -> Option<&Thread> {
        self.threads.get(n).filter(|_| n < PROGRAM_SLOTS)
    }

    /// `SASTAT[n]`.
    pub fn status(&self, n: usize) -> ProgramStatus {
        match self.threads.get(n) {
            Some(t) if n < PROGRAM_SLOTS && self.defines(n) => t.status,
            _ => ProgramStatus::NotAvailable,
        }
    }

    /// `SPC[n]`.
    pub fn pc(&self, n: usize) -> usize {
        if self.defines(n) {
            self.threads.get(n).map_or(0, |t| t.pc)
        } else {
            0
        }
    }

    /// `SACTRL[n]=control` / `SR[n]=control` (T2-33).
    pub fn control(&mut self, n: usize, control: ProgramControl) -> Result<(), ErrorCode> {
        if n >= PROGRAM_SLOTS {
            return Err(ErrorCode::InvalidIndex);
        }
        let Some(entry) = self.entry(n) else {
            return Ok(());
        };
        let Some(thread) = self.threads.get_mut(n) else {
            return Err(ErrorCode::InvalidIndex);
        };
        if thread.status == ProgramStatus::Error && control != ProgramControl::Stop {
            return Err(ErrorCode::ProgramError);
        }
        match (control, thread.status) {
            (ProgramControl::Stop, _) => thread.restart(entry, ProgramStatus::Idle),
            // Ex 8 sends SR0=1 on every pass of a loop: starting a program
            // that runs leaves it running.
            (ProgramControl::Start, ProgramStatus::Running) => {}
            (ProgramControl::Start, _) => thread.restart(entry, ProgramStatus::Running),
            (ProgramControl::Pause, ProgramStatus::Running) => {
                thread.status = ProgramStatus::Paused
            }
            (ProgramControl::Continue, ProgramStatus::Paused) => {
                thread.status = ProgramStatus::Running
            }
            _ => {}
        }
        Ok(())
    }

    /// `GS[n]`: run subroutine n in the GS thread (§2.7.4).
    pub fn call_subroutine(&mut self, n: usize) -> Result<(), ErrorCode> {
        let entry = u8::try_from(n)
            .ok()
            .and_then(|n| self.source.as_ref()?.subroutine(n))
            .ok_or(ErrorCode::SubNotInitialized)?;
        if let Some(thread) = self.threads.get_mut(GS_THREAD) {
            thread.restart(entry.start, ProgramStatus::Running);
        }
        Ok(())
    }

    /// Whether any thread runs (or waits).
    pub fn any_running(&self) -> bool {
        self.threads
            .iter()
            .any(|t| t.status == ProgramStatus::Running)
    }

    /// Stop every thread (power cycle, ESTOP of the console).
    pub fn stop_all(&mut self) {
        for n in 0..self.threads.len() {
            let entry = if n < PROGRAM_SLOTS {
                self.entry(n).unwrap_or(0)
            } else {
                0
            };
            if let Some(thread) = self.threads.get_mut(n) {
                thread.restart(entry, ProgramStatus::Idle);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::cmd4cr::ascript::compile;

    fn loaded(source: &str) -> Programs {
        let mut programs = Programs::default();
        programs.load(compile(source).expect("compiles"));
        programs
    }

    #[test]
    fn a_program_the_source_lacks_is_not_available() {
        let mut programs = loaded("PRG 1\nEND\nSUB 3\nENDSUB\n");
        assert_eq!(programs.status(0), ProgramStatus::NotAvailable);
        assert_eq!(programs.control(0, ProgramControl::Start), Ok(()));
        assert_eq!(programs.status(0), ProgramStatus::NotAvailable);
        assert_eq!(programs.status(1), ProgramStatus::Idle);
        assert_eq!(
            programs.call_subroutine(2),
            Err(ErrorCode::SubNotInitialized)
        );
        assert_eq!(programs.call_subroutine(3), Ok(()));
        assert!(programs.any_running());
        assert_eq!(Programs::default().status(1), ProgramStatus::NotAvailable);
    }

    #[test]
    fn control_follows_table_2_33() {
        let mut programs = loaded("PRG 1\nEND\n");
        programs.control(1, ProgramControl::Start).expect("start");
        programs.control(1, ProgramControl::Pause).expect("pause");
        assert_eq!(programs.status(1), ProgramStatus::Paused);
        programs
            .control(1, ProgramControl::Continue)
            .expect("continue");
        assert_eq!(programs.status(1), ProgramStatus::Running);
        programs.threads[1].status = ProgramStatus::Error;
        assert_eq!(
            programs.control(1, ProgramControl::Start),
            Err(ErrorCode::ProgramError)
        );
        assert_eq!(programs.control(1, ProgramControl::Stop), Ok(()));
        assert_eq!(programs.status(1), ProgramStatus::Idle);
    }
}
