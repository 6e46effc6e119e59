//! Changing a running motion: a new speed or a new target on the fly.

use super::*;

impl Motion {
    /// `SSPD[axis]=speed` (§2.4.1).
    pub fn change_speed(&mut self, name: Axis, speed: u32) -> Result<(), Refusal> {
        if self.buffer.enabled {
            return Err(Refusal::BufferEnabled);
        }
        let a = self.axis(name);
        let window = profile::window_for_sspdm(a.settings.sspdm).ok_or(Refusal::SpeedWindow)?;
        // With StepNLoop on a single-axis speed is in encoder counts/s; the
        // window is in pulses/s (App. B note: EPS = PPS / ratio).
        let pps = if a.step_n_loop.enabled {
            (f64::from(speed) * a.step_n_loop.pulses_per_count()).round()
        } else {
            f64::from(speed)
        };
        if a.settings.s_curve
            || pps < f64::from(window.min_lspd)
            || pps > f64::from(window.max_speed)
        {
            return Err(Refusal::SpeedWindow);
        }
        let position = a.position;
        match &mut self.activity[name.index()] {
            Activity::Run(run) if run.accepts_override(false) => {
                run.change_speed(position, pps);
                Ok(())
            }
            _ => Err(Refusal::OverrideFailed),
        }
    }

    /// `T[axis]target` (§2.4.2): ABS absolute, INC from the move's start;
    /// with StepNLoop on, in encoder counts like any target (§2.5.3).
    pub fn change_target(&mut self, name: Axis, target: i64) -> Result<(), Refusal> {
        let incremental = self.global.incremental;
        let a = &mut self.axes[name.index()];
        let position = a.position;
        match &mut self.activity[name.index()] {
            Activity::Run(run) if run.accepts_override(true) => {
                let Purpose::Position { start_counter } = run.purpose else {
                    return Err(Refusal::OverrideFailed);
                };
                let machine = if a.step_n_loop.enabled && a.loop_state.start.is_some() {
                    let goal = if incremental {
                        a.loop_state.origin.saturating_add(target)
                    } else {
                        target
                    };
                    let counts = goal.saturating_sub(a.loop_target()) as f64;
                    a.loop_state.target = goal;
                    position
                        .saturating_add((counts * a.step_n_loop.pulses_per_count()).round() as i64)
                } else {
                    let counter = if incremental {
                        start_counter + target
                    } else {
                        target
                    };
                    a.machine_for_counter(counter)
                };
                run.change_target(position, machine);
                Ok(())
            }
            _ => Err(Refusal::OverrideFailed),
        }
    }

    // ---- the buffer ---------------------------------------------------
}
