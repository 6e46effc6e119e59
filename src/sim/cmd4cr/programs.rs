//! The four standalone-program slots (§2.7.8–§2.7.10) as the ASCII side
//! sees them: `SACTRL[0-3]`, `SASTAT[0-3]`, `SPC[0-3]` and `GS[0-31]`.
//! This is the hook the A-Script interpreter fills: a slot holds a program
//! or nothing, and reports its state and program counter.
//!
//! Choices where the manual is silent:
//! - A slot with no program reads `SASTAT` 3 ("N/A", T2-34) and `SPC` 0;
//!   `SACTRL` to it is answered OK and changes nothing.
//! - `?Program Error` (T4-41: "the command cannot be processed because a
//!   standalone program is in error state") answers `SACTRL` start, pause
//!   or continue to a program in the error state; `SACTRL=0` (stop) clears
//!   the error and leaves it idle.
//! - `GS n` with no subroutine n loaded answers `?Sub not Initialized`.

use crate::protocol::cmd4cr::ErrorCode;

/// Programs and subroutines the core holds.
pub const PROGRAM_SLOTS: usize = 4;
pub const SUBROUTINES: usize = 32;

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

/// `SACTRL` / `SR` codes (T2-33).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    Stop = 0,
    Start = 1,
    Pause = 2,
    Continue = 3,
}

impl Control {
    pub fn from_code(code: i64) -> Option<Control> {
        match code {
            0 => Some(Control::Stop),
            1 => Some(Control::Start),
            2 => Some(Control::Pause),
            3 => Some(Control::Continue),
            _ => None,
        }
    }
}

/// One slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Slot {
    pub loaded: bool,
    pub status: ProgramStatus,
    /// `SPC`: the program counter.
    pub pc: u16,
}

/// The slots and which subroutines exist.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Programs {
    pub slots: [Slot; PROGRAM_SLOTS],
    pub subroutines: [bool; SUBROUTINES],
}

impl Programs {
    /// `SASTAT[n]`.
    pub fn status(&self, n: usize) -> ProgramStatus {
        match self.slots.get(n) {
            Some(slot) if slot.loaded => slot.status,
            _ => ProgramStatus::NotAvailable,
        }
    }

    /// `SPC[n]`.
    pub fn pc(&self, n: usize) -> u16 {
        self.slots.get(n).map_or(0, |s| s.pc)
    }

    /// `SACTRL[n]=control` (T2-33).
    pub fn control(&mut self, n: usize, control: Control) -> Result<(), ErrorCode> {
        let Some(slot) = self.slots.get_mut(n) else {
            return Err(ErrorCode::InvalidIndex);
        };
        if !slot.loaded {
            return Ok(());
        }
        if slot.status == ProgramStatus::Error && control != Control::Stop {
            return Err(ErrorCode::ProgramError);
        }
        slot.status = match (control, slot.status) {
            (Control::Stop, _) => {
                slot.pc = 0;
                ProgramStatus::Idle
            }
            (Control::Start, _) => {
                slot.pc = 0;
                ProgramStatus::Running
            }
            (Control::Pause, ProgramStatus::Running) => ProgramStatus::Paused,
            (Control::Continue, ProgramStatus::Paused) => ProgramStatus::Running,
            (_, status) => status,
        };
        Ok(())
    }

    /// `GS[n]`: whether subroutine n may be called.
    pub fn check_subroutine(&self, n: usize) -> Result<(), ErrorCode> {
        if self.subroutines.get(n).copied().unwrap_or(false) {
            Ok(())
        } else {
            Err(ErrorCode::SubNotInitialized)
        }
    }

    /// Stop every program (power cycle).
    pub fn stop_all(&mut self) {
        for slot in &mut self.slots {
            slot.status = ProgramStatus::Idle;
            slot.pc = 0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_slot_is_not_available() {
        let mut programs = Programs::default();
        assert_eq!(programs.status(0), ProgramStatus::NotAvailable);
        assert_eq!(programs.control(0, Control::Start), Ok(()));
        assert_eq!(programs.status(0), ProgramStatus::NotAvailable);
        assert_eq!(
            programs.check_subroutine(3),
            Err(ErrorCode::SubNotInitialized)
        );
    }

    #[test]
    fn a_program_in_error_only_accepts_stop() {
        let mut programs = Programs::default();
        programs.slots[1] = Slot {
            loaded: true,
            status: ProgramStatus::Error,
            pc: 7,
        };
        assert_eq!(
            programs.control(1, Control::Start),
            Err(ErrorCode::ProgramError)
        );
        assert_eq!(programs.control(1, Control::Stop), Ok(()));
        assert_eq!(programs.status(1), ProgramStatus::Idle);
        programs.control(1, Control::Start).expect("start");
        programs.control(1, Control::Pause).expect("pause");
        assert_eq!(programs.status(1), ProgramStatus::Paused);
        programs.control(1, Control::Continue).expect("continue");
        assert_eq!(programs.status(1), ProgramStatus::Running);
    }
}
