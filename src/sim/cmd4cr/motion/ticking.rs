//! Time: advancing the simulation tick by tick.

use super::*;

impl Motion {
    /// Let `dt` of virtual time pass.
    pub fn advance(&mut self, dt: Duration) {
        self.pending += dt;
        if self.pending >= TICK {
            self.end_aborts();
        }
        while self.pending >= TICK {
            self.pending -= TICK;
            if self.idle() {
                // Nothing moves and no output pulse runs: whole ticks
                // change nothing.
                self.pending =
                    Duration::from_nanos((self.pending.as_nanos() % TICK.as_nanos()) as u64);
                break;
            }
            self.tick();
        }
    }

    /// An aborted StepNLoop axis is idle from the tick after ABORT.
    pub(super) fn end_aborts(&mut self) {
        for (i, a) in self.axes.iter_mut().enumerate() {
            if a.loop_state.status == sls::ABORTING && self.activity[i] == Activity::Idle {
                a.loop_state.status = sls::IDLE;
            }
        }
    }

    pub(super) fn idle(&self) -> bool {
        self.activity.iter().all(|a| *a == Activity::Idle)
            && self.axes.iter().all(|a| a.erc.is_none())
            && self.groups.is_empty()
    }

    pub(super) fn tick(&mut self) {
        let ierr = self.global.ignore_errors;
        // Pulses started during this tick last at least until the next one.
        for axis in &mut self.axes {
            axis.run_erc(TICK);
        }
        // ALM stops a moving axis at once (§2.1.2.2).
        for axis in Axis::ALL {
            let moving = matches!(
                self.activity[axis.index()],
                Activity::Run(_) | Activity::Group(_)
            );
            if moving && self.axes[axis.index()].inputs.alarm {
                let stopped = self.halt(axis);
                let a = &mut self.axes[axis.index()];
                if !ierr {
                    a.errors |= mst::ALARM_ERROR;
                }
                self.error_stop(&stopped);
            }
        }
        let counters_before: [(i64, i64); 4] =
            std::array::from_fn(|i| (self.axes[i].counter(), self.axes[i].encoder()));
        for axis in Axis::ALL {
            let i = axis.index();
            if !matches!(self.activity[i], Activity::Run(_)) {
                continue;
            }
            let Activity::Run(mut run) = std::mem::replace(&mut self.activity[i], Activity::Idle)
            else {
                continue;
            };
            let outcome = run.tick(&mut self.axes[i], ierr);
            let a = &mut self.axes[i];
            match outcome {
                Outcome::Running => {
                    a.rate = run.speed();
                    a.phase = run.phase();
                    self.activity[i] = Activity::Run(run);
                }
                Outcome::Completed => {
                    let targeted = matches!(run.purpose, Purpose::Position { .. });
                    self.finish(axis, Some(&run), targeted);
                }
                Outcome::Stopped => self.settle(axis),
                Outcome::LimitStop => {
                    self.settle(axis);
                    self.loop_limit_error(&[axis]);
                    self.error_stop(&[axis]);
                }
            }
        }
        let mut index = 0;
        while index < self.groups.len() {
            let (id, group) = &mut self.groups[index];
            let id = *id;
            let outcome = group.tick(&mut self.axes, ierr);
            match outcome {
                GroupOutcome::Running => {
                    let phase = group.phase();
                    let rates = group.rates();
                    for member in group.members() {
                        let a = &mut self.axes[member.index()];
                        a.phase = phase;
                        a.rate = rates
                            .iter()
                            .find(|(m, _)| *m == member)
                            .map_or(0.0, |&(_, r)| r);
                    }
                    index += 1;
                }
                other => {
                    let (_, group) = self.groups.remove(index);
                    let members = group.members();
                    let buffered = self.buffer_group == Some(id);
                    if buffered {
                        self.buffer_group = None;
                    }
                    match other {
                        GroupOutcome::Completed => {
                            // Every StepNLoop member is verified on its own.
                            for &m in &members {
                                self.finish(m, None, !group.buffered);
                            }
                            if buffered {
                                self.feed_buffer();
                            }
                        }
                        GroupOutcome::LimitStop => {
                            if buffered {
                                self.buffer.started = false;
                            }
                            for &m in &members {
                                self.settle(m);
                            }
                            self.loop_limit_error(&members);
                            self.error_stop(&members);
                        }
                        _ => {
                            for &m in &members {
                                self.settle(m);
                            }
                        }
                    }
                }
            }
        }
        for (i, axis) in self.axes.iter_mut().enumerate() {
            if axis.waiting_for_inp && axis.inputs.in_position {
                axis.waiting_for_inp = false;
                self.activity[i] = Activity::Idle;
            }
            let (p0, e0) = counters_before[i];
            let (from, to) = if axis.sync.uses_encoder() {
                (e0, axis.encoder())
            } else {
                (p0, axis.counter())
            };
            axis.sync.compare(from, to);
        }
        self.watch_loops();
    }
}
