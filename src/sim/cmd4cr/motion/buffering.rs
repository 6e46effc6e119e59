//! The interpolation buffer: filling it, starting it and feeding its moves
//! to the axes.

use super::*;

impl Motion {
    /// `BO` / `BF`. Turning it off stops feeding and drops what is queued;
    /// the move in progress ends normally.
    pub fn set_buffer(&mut self, on: bool) {
        self.buffer.enabled = on;
        if !on {
            self.buffer.started = false;
            self.buffer.queue.clear();
            self.buffer.head = 0;
        }
    }

    pub fn buffer_status(&self) -> BufferStatus {
        self.buffer.status()
    }

    /// `I…`, or a circle or arc while buffer mode is on.
    pub fn buffer_push(&mut self, mut entry: BufferedMove) -> Result<(), Refusal> {
        if !self.buffer.enabled {
            return Err(Refusal::BufferDisabled);
        }
        if self.buffer.queue.len() >= BUFFER_SIZE {
            return Err(Refusal::BufferFull);
        }
        if let BufferedMove::Linear { target, .. } = &mut entry
            && self.global.incremental
        {
            // Relative to where the previous queued move ends.
            let base = self.buffer_end_point();
            for (t, b) in target.iter_mut().zip(base) {
                *t += b;
            }
        }
        self.buffer.queue.push_back(entry);
        Ok(())
    }

    /// The X, Y, Z counters where the queued moves leave the axes (linear
    /// moves only; a queued arc leaves them where it started).
    pub(super) fn buffer_end_point(&self) -> [i64; 3] {
        let mut point = [
            self.counter(Axis::X),
            self.counter(Axis::Y),
            self.counter(Axis::Z),
        ];
        for entry in &self.buffer.queue {
            if let BufferedMove::Linear { target, .. } = entry {
                point = *target;
            }
        }
        point
    }

    /// `BSTART`.
    pub fn buffer_start(&mut self) -> Result<(), Refusal> {
        if !self.buffer.enabled {
            return Err(Refusal::BufferDisabled);
        }
        if self.buffer_step_n_loop() {
            return Err(Refusal::StepNLoop);
        }
        if self.buffer_group.is_none() {
            for axis in [Axis::X, Axis::Y, Axis::Z] {
                if self.is_busy(axis) || self.axis(axis).errors & mst::BLOCKING_ERRORS != 0 {
                    return Err(Refusal::Moving);
                }
            }
            if self.emg_input {
                return Err(Refusal::Estop);
            }
        }
        self.buffer.started = true;
        self.feed_buffer();
        Ok(())
    }

    /// "The buffered move operation cannot be used while StepNLoop is
    /// enabled" (§2.3.4) on an axis the buffer drives.
    pub(super) fn buffer_step_n_loop(&self) -> bool {
        [Axis::X, Axis::Y, Axis::Z]
            .iter()
            .any(|&a| self.axis(a).step_n_loop.enabled)
    }

    /// Start the next buffered move if the buffer runs and nothing it fed
    /// is moving.
    pub(super) fn feed_buffer(&mut self) {
        if self.buffer_step_n_loop() {
            // SL turned on while the buffer ran: it stops feeding.
            self.buffer.started = false;
        }
        while self.buffer.started && self.buffer_group.is_none() {
            let Some(entry) = self.buffer.pop() else {
                return;
            };
            let group = match entry {
                BufferedMove::Linear { target, speed } => {
                    let legs = [Axis::X, Axis::Y, Axis::Z]
                        .into_iter()
                        .zip(target)
                        .map(|(axis, t)| (axis, self.axis(axis).position, t - self.counter(axis)))
                        .collect();
                    Ok(Group::new(
                        Path::linear(legs),
                        self.global_ramps(Axis::X),
                        Some(f64::from(speed.max(1))),
                    ))
                }
                BufferedMove::Arc {
                    axes,
                    rotation,
                    centre,
                    end_mdeg,
                    helix_z,
                    speed,
                } => self.arc_group(
                    axes,
                    rotation,
                    centre,
                    end_mdeg,
                    helix_z,
                    Some(f64::from(speed.max(1))),
                ),
            };
            match group {
                Ok(group) if group.path.length() > 0.0 => {
                    let busy = group.members().iter().any(|&a| self.is_busy(a));
                    if busy {
                        self.buffer.started = false;
                        return;
                    }
                    self.buffer_group = Some(self.launch_group(group));
                }
                // Nothing to do for this one (already there, or no circle).
                _ => {}
            }
        }
    }

    // ---- time ---------------------------------------------------------
}
