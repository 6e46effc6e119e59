//! The standalone-program control codes of `SACTRL[n]=c` and A-Script's
//! `SR[n]=c` (§2.7, T2-33), shared by the simulator and the host runner.

/// What `SACTRL[n]` / `SR[n]` asks of a program.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProgramControl {
    Stop = 0,
    Start = 1,
    Pause = 2,
    Continue = 3,
}

impl ProgramControl {
    /// The control for a code of T2-33, if it is one.
    pub fn from_code(code: i64) -> Option<ProgramControl> {
        match code {
            0 => Some(ProgramControl::Stop),
            1 => Some(ProgramControl::Start),
            2 => Some(ProgramControl::Pause),
            3 => Some(ProgramControl::Continue),
            _ => None,
        }
    }

    /// The verb for messages ("SR0=1 starts PRG0").
    pub fn verb(self) -> &'static str {
        match self {
            ProgramControl::Stop => "stops",
            ProgramControl::Start => "starts",
            ProgramControl::Pause => "pauses",
            ProgramControl::Continue => "continues",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_four_codes_of_t2_33_and_nothing_else() {
        for code in 0..4 {
            let control = ProgramControl::from_code(code).expect("a T2-33 code");
            assert_eq!(control as i64, code);
        }
        assert_eq!(ProgramControl::from_code(4), None);
        assert_eq!(ProgramControl::from_code(-1), None);
        assert_eq!(ProgramControl::Pause.verb(), "pauses");
    }
}
