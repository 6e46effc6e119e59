//! Stopping: a deceleration stop, an abort, the emergency stop, an error
//! stop, and what an axis keeps when its run ends (the step-n-loop check
//! of its position included).

use super::*;

impl Motion {
    /// `STOP` (`None`) or `STOP[axis]`: decelerate to LSPD and stop; every
    /// axis of an interpolation stops with it (§2.2.3).
    pub fn stop(&mut self, name: Option<Axis>) {
        let axes: Vec<Axis> = name.map_or_else(|| Axis::ALL.to_vec(), |a| vec![a]);
        for axis in axes {
            let holders = self.holders(axis);
            self.loop_note(&holders, sls::STOPPING);
            let position = self.axes[axis.index()].position;
            match &mut self.activity[axis.index()] {
                Activity::Run(run) => run.stop(position),
                Activity::Group(id) => {
                    let id = *id;
                    if Some(id) == self.buffer_group {
                        self.buffer.started = false;
                    }
                    if let Some((_, group)) = self.groups.iter_mut().find(|(g, _)| *g == id)
                        && !group.halting
                    {
                        group.stop();
                    }
                }
                Activity::WaitInp | Activity::Idle => {}
            }
        }
        if name.is_none() {
            self.start_queue.clear();
            self.clear_waiting();
        }
    }

    /// `ABORT` (`None`) or `ABORT[axis]`: stop at once (§2.2.3).
    pub fn abort(&mut self, name: Option<Axis>) {
        let axes: Vec<Axis> = name.map_or_else(|| Axis::ALL.to_vec(), |a| vec![a]);
        for axis in axes {
            // The stop is at once: SLS 4 shows until the next tick.
            let holders = self.holders(axis);
            self.loop_note(&holders, sls::ABORTING);
            self.halt(axis);
        }
        if name.is_none() {
            self.start_queue.clear();
            self.clear_waiting();
        }
    }

    pub(super) fn clear_waiting(&mut self) {
        for a in &mut self.axes {
            a.waiting_for_start = false;
        }
    }

    /// Stop `axis` (and its interpolation) at once; the axes that were in
    /// motion.
    pub(super) fn halt(&mut self, axis: Axis) -> Vec<Axis> {
        let members = self.holders(axis);
        if let Activity::Group(id) = self.activity[axis.index()] {
            if Some(id) == self.buffer_group {
                self.buffer.started = false;
                self.buffer_group = None;
            }
            self.groups.retain(|(g, _)| *g != id);
        }
        for &m in &members {
            self.settle(m);
        }
        members
    }

    /// The axes the motion of `axis` holds: itself, or its interpolation.
    pub(super) fn holders(&self, axis: Axis) -> Vec<Axis> {
        match &self.activity[axis.index()] {
            Activity::Idle => Vec::new(),
            Activity::Run(_) | Activity::WaitInp => vec![axis],
            Activity::Group(id) => self
                .groups
                .iter()
                .find(|(g, _)| g == id)
                .map(|(_, g)| g.members())
                .unwrap_or_default(),
        }
    }

    /// The axis stands still and is free.
    pub(super) fn settle(&mut self, axis: Axis) {
        self.activity[axis.index()] = Activity::Idle;
        let a = &mut self.axes[axis.index()];
        a.rate = 0.0;
        a.phase = None;
        a.waiting_for_inp = false;
        if a.loop_state.start.is_some() {
            // The target is where the pulses stopped; a move that completes
            // takes its goal back (finish).
            a.loop_state.target = a.loop_target();
            let state = &mut a.loop_state;
            state.start = None;
            // ABORT's code lasts until the next tick (end_aborts).
            if !state.in_error() && state.status != sls::ABORTING {
                state.status = sls::IDLE;
            }
        }
    }

    /// A positioning move of a StepNLoop axis ended: in position, a
    /// correction move, or an error (Table 2-26). True if a correction
    /// started.
    pub(super) fn verify_position(&mut self, axis: Axis) -> bool {
        let a = &mut self.axes[axis.index()];
        if !a.step_n_loop.enabled {
            return false;
        }
        let delta = a.loop_state.target - a.encoder();
        match step_n_loop::verdict(&a.step_n_loop, delta, a.loop_state.tries) {
            Verdict::InPosition => false,
            Verdict::RangeError => {
                a.loop_state.status = sls::RANGE_ERROR;
                false
            }
            Verdict::AttemptError => {
                a.loop_state.status = sls::ATTEMPT_ERROR;
                false
            }
            Verdict::Correct => {
                let tries = a.loop_state.tries + 1;
                let pulses = (delta as f64 * a.step_n_loop.pulses_per_count()).round() as i64;
                a.loop_state.status = sls::CORRECTING;
                a.loop_state.tries = tries;
                a.loop_state.start = Some((a.counter(), a.encoder()));
                let from = a.position;
                let purpose = Purpose::Position {
                    start_counter: a.counter(),
                };
                let ramps = self.axis_ramps(axis);
                let dir = if pulses < 0 { -1 } else { 1 };
                let run = Run::new(from, dir, ramps, Goal::Target(from + pulses), purpose);
                self.launch(axis, run);
                true
            }
        }
    }

    /// Stall detection: a StepNLoop axis in motion whose encoder is further
    /// than SLE from the real-time target stops (Table 2-26, SLS 10).
    pub(super) fn watch_loops(&mut self) {
        for axis in Axis::ALL {
            let a = &self.axes[axis.index()];
            if !a.step_n_loop.enabled || a.loop_state.start.is_none() || !self.is_busy(axis) {
                continue;
            }
            if a.deviation().abs() > a.step_n_loop.error_range {
                self.halt(axis);
                self.axes[axis.index()].loop_state.status = sls::STALL_ERROR;
            }
        }
    }

    /// `ESTOP` or /CEMG going low: every axis stops at once; those that were
    /// moving get the EMG error flag unless IERR=1 (§2.1.3.1.2).
    pub fn emergency_stop(&mut self) {
        self.buffer.started = false;
        self.start_queue.clear();
        self.clear_waiting();
        for axis in Axis::ALL {
            let moving = matches!(
                self.activity[axis.index()],
                Activity::Run(_) | Activity::Group(_)
            );
            let mut stopped = self.halt(axis);
            // An axis under joystick control stops too (it is no Run): it
            // stays still until the stick is back in its dead band.
            let a = &mut self.axes[axis.index()];
            let joystick = a.manual_control && !moving && (a.rate != 0.0 || a.phase.is_some());
            if joystick {
                a.rate = 0.0;
                a.phase = None;
                a.joystick_held = true;
                stopped.push(axis);
            }
            if (moving || joystick) && !self.global.ignore_errors {
                for m in stopped {
                    self.axes[m.index()].errors |= mst::EMG_ERROR;
                    if self.axes[m.index()].settings.erc & 1 != 0 {
                        self.axes[m.index()].pulse_erc();
                    }
                }
            }
        }
    }

    /// An error stop of these axes: ERC pulse where ERC bit 0 asks for it
    /// (T2-13).
    pub(super) fn error_stop(&mut self, axes: &[Axis]) {
        for &axis in axes {
            let a = &mut self.axes[axis.index()];
            if a.settings.erc & 1 != 0 {
                a.pulse_erc();
            }
        }
    }

    /// A motion ended normally: position verification of a `targeted`
    /// move, homing completion actions, then wait for INP if asked
    /// (§2.1.6.2).
    pub(super) fn finish(&mut self, axis: Axis, run: Option<&Run>, targeted: bool) {
        let state = self.axes[axis.index()].loop_state;
        self.settle(axis);
        // Only a move the loop followed from its start is verified.
        let followed = state.start.is_some()
            && matches!(state.status, sls::MOVING | sls::CORRECTING)
            && self.axes[axis.index()].step_n_loop.enabled;
        if targeted && followed {
            // The goal, not where the pulses rounded to.
            self.axes[axis.index()].loop_state.target = state.target;
            if self.verify_position(axis) {
                return;
            }
        }
        let a = &mut self.axes[axis.index()];
        if let Some(Purpose::Procedure(p)) = run.map(|r| &r.purpose)
            && p.procedure.mode != homing::Z_MOVE.mode
            && a.settings.erc & 2 != 0
        {
            a.pulse_erc();
            if p.procedure.uses_limit {
                // A.7 note: ERC clears the limit flag in the homing direction.
                a.errors &= !if p.home_dir > 0 {
                    mst::PLUS_LIMIT_ERROR
                } else {
                    mst::MINUS_LIMIT_ERROR
                };
            }
        }
        if a.settings.inp && !a.inputs.in_position {
            a.waiting_for_inp = true;
            self.activity[axis.index()] = Activity::WaitInp;
        }
    }
}
