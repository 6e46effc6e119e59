//! Starting a motion: the checks a command must pass before it runs (the
//! refusals of the manual's error list), the step-n-loop goals, and launching
//! single-axis runs, homing procedures, arcs and linked groups.

use super::*;

impl Motion {
    /// A motion command: started, or queued while EXST=1.
    pub fn start(&mut self, start: Start) -> Result<(), Refusal> {
        self.check(&start)?;
        if self.global.external_start {
            if self.start_queue.len() >= EXTERNAL_START_QUEUE {
                return Err(Refusal::Moving);
            }
            self.start_queue.push_back(start);
            self.mark_waiting();
            return Ok(());
        }
        self.begin(start)
    }

    /// The conditions every motion command needs (see the module notes).
    pub(super) fn check(&mut self, start: &Start) -> Result<(), Refusal> {
        let moves = self.directions(start);
        for &(axis, _) in &moves {
            if self.is_busy(axis)
                || self
                    .start_queue
                    .iter()
                    .any(|s| start_axes(s).contains(&axis))
            {
                return Err(Refusal::Moving);
            }
        }
        if self.emg_input {
            if !self.global.ignore_errors {
                for &(axis, _) in &moves {
                    self.axes[axis.index()].errors |= mst::EMG_ERROR;
                }
            }
            return Err(Refusal::Estop);
        }
        for &(axis, direction) in &moves {
            let a = self.axis(axis);
            if a.inputs.alarm {
                return Err(Refusal::Alarm);
            }
            match direction {
                Some(Direction::Plus) if a.limit_on(Direction::Plus) => {
                    return Err(Refusal::PlusLimit);
                }
                Some(Direction::Minus) if a.limit_on(Direction::Minus) => {
                    return Err(Refusal::MinusLimit);
                }
                _ => {}
            }
        }
        for &(axis, _) in &moves {
            let a = self.axis(axis);
            if a.step_n_loop.enabled && a.loop_state.in_error() {
                return Err(Refusal::StepNLoop);
            }
        }
        for &(axis, _) in &moves {
            let a = self.axis(axis);
            if a.errors & mst::BLOCKING_ERRORS != 0 || a.manual_control {
                return Err(Refusal::Moving);
            }
        }
        Ok(())
    }

    /// The axes a command moves, with the direction where it is known.
    pub(super) fn directions(&self, start: &Start) -> Vec<(Axis, Option<Direction>)> {
        match start {
            Start::Jog { axis, direction }
            | Start::Home {
                axis, direction, ..
            }
            | Start::ZMove { axis, direction } => vec![(*axis, Some(*direction))],
            Start::Position { targets } => targets
                .iter()
                .map(|&(axis, value)| (axis, direction_of(self.distance(axis, value))))
                .collect(),
            Start::Arc { axes, helix_z, .. } => {
                let mut v = vec![(axes.0, None), (axes.1, None)];
                if let Some(z) = helix_z {
                    let to = self.counter_value(Axis::Z, *z);
                    v.push((Axis::Z, direction_of(to - self.counter(Axis::Z))));
                    v.push((Axis::U, None));
                }
                v
            }
        }
    }

    /// Pulses from where the axis is to `value` under ABS/INC; with
    /// StepNLoop on, `value` is an encoder position (§2.5.3).
    pub(super) fn distance(&self, axis: Axis, value: i64) -> i64 {
        let a = self.axis(axis);
        if a.step_n_loop.enabled {
            let target = self.loop_goal(axis, value);
            let pulses = (target - a.encoder()) as f64 * a.step_n_loop.pulses_per_count();
            return pulses.round() as i64;
        }
        if self.global.incremental {
            value
        } else {
            value - self.counter(axis)
        }
    }

    /// The encoder target of `value` under ABS/INC (StepNLoop on).
    pub(super) fn loop_goal(&self, axis: Axis, value: i64) -> i64 {
        if self.global.incremental {
            self.axis(axis).loop_target() + value
        } else {
            value
        }
    }

    /// The pulse counter value an absolute position means: the value
    /// itself, or with StepNLoop on an encoder position (§2.5.3: "this
    /// applies to individual as well as interpolated moves"), reached from
    /// where the encoder is at SLR pulses a count.
    pub(super) fn counter_value(&self, axis: Axis, value: i64) -> i64 {
        let a = self.axis(axis);
        if !a.step_n_loop.enabled {
            return value;
        }
        let pulses = (value.saturating_sub(a.encoder())) as f64 * a.step_n_loop.pulses_per_count();
        // `as` saturates: an absurd value gives an absurd, harmless radius.
        a.counter().saturating_add(pulses.round() as i64)
    }

    /// The encoder position a StepNLoop axis should reach when it stands
    /// at machine position `end`.
    pub(super) fn loop_goal_at(&self, axis: Axis, end: i64) -> i64 {
        let a = self.axis(axis);
        let counts = (end - a.position) as f64 / a.step_n_loop.pulses_per_count();
        a.encoder() + counts.round() as i64
    }

    /// Note `code` in SLS of those of `axes` whose loop follows a motion.
    pub(super) fn loop_note(&mut self, axes: &[Axis], code: u8) {
        for &axis in axes {
            let a = &mut self.axes[axis.index()];
            if a.step_n_loop.enabled && a.loop_state.start.is_some() && !a.loop_state.in_error() {
                a.loop_state.status = code;
            }
        }
    }

    /// A StepNLoop axis stopped by an end limit: SLS 11 (Table 27).
    pub(super) fn loop_limit_error(&mut self, axes: &[Axis]) {
        for &axis in axes {
            let a = &mut self.axes[axis.index()];
            let at_limit = a.limit_on(Direction::Plus) || a.limit_on(Direction::Minus);
            if a.step_n_loop.enabled && at_limit && !a.loop_state.in_error() {
                a.loop_state.status = sls::LIMIT_ERROR;
            }
        }
    }

    /// A commanded motion of `axis` starts: the loop follows it.
    pub(super) fn loop_starts(&mut self, axis: Axis, code: u8, goal: Option<i64>) {
        let a = &mut self.axes[axis.index()];
        if !a.step_n_loop.enabled {
            return;
        }
        let origin = a.loop_target();
        a.loop_state = step_n_loop::LoopState {
            status: code,
            target: goal.unwrap_or(origin),
            origin,
            start: Some((a.counter(), a.encoder())),
            tries: 0,
        };
    }

    /// `SL[axis]=on`: the loop starts from where the encoder is.
    pub fn enable_step_n_loop(&mut self, axis: Axis, on: bool) {
        let a = &mut self.axes[axis.index()];
        if on && !a.step_n_loop.enabled {
            a.loop_state = step_n_loop::LoopState {
                target: a.encoder(),
                ..step_n_loop::LoopState::default()
            };
        }
        a.step_n_loop.enabled = on;
    }

    /// `SLS[axis]` (Table 27).
    pub fn loop_status(&self, axis: Axis) -> u8 {
        let a = self.axis(axis);
        if a.step_n_loop.enabled {
            a.loop_state.status
        } else {
            sls::NOT_ENABLED
        }
    }

    /// `P[axis]` as read: the pulse counter, or with StepNLoop on the
    /// real-time target in encoder counts (§2.6.1.1).
    pub fn position_reading(&self, axis: Axis) -> i64 {
        let a = self.axis(axis);
        if a.step_n_loop.enabled {
            a.loop_target()
        } else {
            a.counter()
        }
    }

    /// The motor misses `pulses` steps (a stall the encoder sees): the
    /// carriage lags the pulse counter by that much (+ leaves it short of
    /// a + move). For tests and demos of StepNLoop.
    pub fn lose_steps(&mut self, axis: Axis, pulses: i64) {
        self.axes[axis.index()].miss(pulses);
        let pulses = pulses.clamp(-(1 << 27), 1 << 27);
        // The pulses still to come start from where the carriage is now.
        match &mut self.activity[axis.index()] {
            Activity::Run(run) => run.shift(-pulses),
            Activity::Group(id) => {
                let id = *id;
                if let Some((_, group)) = self.groups.iter_mut().find(|(g, _)| *g == id) {
                    group.path.shift(axis, -pulses);
                }
            }
            Activity::Idle | Activity::WaitInp => {}
        }
    }

    /// Which way a move of the engine drives `axis` now: a single-axis run
    /// (positioning, jog, homing, correction, braking) its direction, an
    /// interpolation the way its path takes the axis at this point. `None`
    /// if no move sends it pulses (at rest, waiting for INP, U held by a
    /// helical move, an axis with no distance in its interpolation, the
    /// joystick or MPG, which are no moves of the engine).
    pub fn heading(&self, axis: Axis) -> Option<Direction> {
        match &self.activity[axis.index()] {
            Activity::Run(run) => direction_of(run.dir),
            Activity::Group(id) => self
                .groups
                .iter()
                .find(|(g, _)| g == id)
                .and_then(|(_, g)| direction_of(g.path.heading(axis, g.covered))),
            Activity::Idle | Activity::WaitInp => None,
        }
    }

    /// The motor of `axis` misses `pulses` steps of the move under way:
    /// the carriage (and the encoder) falls behind the pulse counter by
    /// that many, against the way the move drives it. The direction it
    /// was moving, or `None` (and nothing done) if no move drives it now
    /// ([`Motion::heading`]).
    pub fn miss_steps(&mut self, axis: Axis, pulses: u32) -> Option<Direction> {
        let direction = self.heading(axis)?;
        self.lose_steps(axis, sign(direction) * i64::from(pulses));
        Some(direction)
    }

    /// From now on the motor of `axis` misses `per_mille` of the steps of
    /// every move (0 none, 1000 all: it does not turn).
    pub fn set_slip(&mut self, axis: Axis, per_mille: u16) {
        let a = self.axis_mut(axis);
        a.inputs.slip = per_mille.min(1000);
        a.slip_carry = 0;
    }

    /// Start a checked command now.
    pub(super) fn begin(&mut self, start: Start) -> Result<(), Refusal> {
        match start {
            Start::Jog { axis, direction } => {
                let ramps = self.axis_ramps(axis);
                let position = self.axis(axis).position;
                let run = Run::new(
                    position,
                    sign(direction),
                    ramps,
                    Goal::Endless,
                    Purpose::Jog,
                );
                self.loop_starts(axis, sls::JOGGING, None);
                self.launch(axis, run);
            }
            Start::Position { targets } => {
                let legs: Vec<(Axis, i64, i64)> = targets
                    .iter()
                    .map(|&(axis, value)| {
                        (axis, self.axis(axis).position, self.distance(axis, value))
                    })
                    .collect();
                let goals: Vec<(Axis, i64)> = targets
                    .iter()
                    .map(|&(axis, value)| (axis, self.loop_goal(axis, value)))
                    .collect();
                for (axis, goal) in goals {
                    self.loop_starts(axis, sls::MOVING, Some(goal));
                }
                if legs.len() >= 2 && self.global.interpolate {
                    let lead = legs
                        .iter()
                        .max_by_key(|&&(_, _, d)| d.abs())
                        .map_or(Axis::X, |&(a, _, _)| a);
                    let ramps = self.global_ramps(lead);
                    self.launch_group(Group::new(Path::linear(legs), ramps, None));
                } else {
                    for (axis, from, distance) in legs {
                        let ramps = self.axis_ramps(axis);
                        let purpose = Purpose::Position {
                            start_counter: self.counter(axis),
                        };
                        let dir = if distance < 0 { -1 } else { 1 };
                        let run =
                            Run::new(from, dir, ramps, Goal::Target(from + distance), purpose);
                        if distance == 0 {
                            // Already there: the move ends as it starts, so the
                            // axis is never seen busy with MST reading 0.
                            self.finish(axis, Some(&run), true);
                        } else {
                            self.launch(axis, run);
                        }
                    }
                }
            }
            Start::Home {
                axis,
                direction,
                mode,
            } => {
                let Some(procedure) = homing::procedure(mode) else {
                    return Err(Refusal::Moving);
                };
                self.launch_procedure(axis, direction, procedure);
            }
            Start::ZMove { axis, direction } => {
                self.launch_procedure(axis, direction, &homing::Z_MOVE);
            }
            Start::Arc {
                axes,
                rotation,
                centre,
                end_mdeg,
                helix_z,
            } => {
                let group = self.arc_group(axes, rotation, centre, end_mdeg, helix_z, None)?;
                for (axis, end) in group.path.positions(group.path.length()) {
                    let goal = self.loop_goal_at(axis, end);
                    self.loop_starts(axis, sls::MOVING, Some(goal));
                }
                self.launch_group(group);
            }
        }
        Ok(())
    }

    pub(super) fn launch_procedure(
        &mut self,
        axis: Axis,
        direction: Direction,
        procedure: &'static homing::Procedure,
    ) {
        let ramps = self.axis_ramps(axis);
        let position = self.axis(axis).position;
        let purpose = Purpose::Procedure(ProcedureRun {
            procedure,
            home_dir: sign(direction),
            leg: 0,
            braking: false,
            index_seen: 0,
            seen_on: false,
            returning: false,
        });
        let run = Run::new(position, sign(direction), ramps, Goal::Endless, purpose);
        // Table 27: ZMOVE is Z-homing, modes on an end limit limit homing.
        let code = if procedure.mode == homing::Z_MOVE.mode {
            sls::Z_HOMING
        } else if procedure.uses_limit {
            sls::LIMIT_HOMING
        } else {
            sls::HOMING
        };
        self.loop_starts(axis, code, None);
        self.launch(axis, run);
    }

    pub(super) fn arc_group(
        &self,
        axes: (Axis, Axis),
        rotation: Rotation,
        centre: (i64, i64),
        end_mdeg: Option<i64>,
        helix_z: Option<i64>,
        buffered_speed: Option<f64>,
    ) -> Result<Group, Refusal> {
        // With StepNLoop on, the centre and Z are encoder positions: the
        // circle is laid in pulses from where the encoder is.
        let centre = (
            self.counter_value(axes.0, centre.0),
            self.counter_value(axes.1, centre.1),
        );
        let helix_z = helix_z.map(|z| self.counter_value(Axis::Z, z));
        let from = (self.counter(axes.0), self.counter(axes.1));
        // Counters and machine positions differ by an offset: lay the
        // circle in counter space, move in machine space.
        let offsets = (
            self.axis(axes.0).counter_offset,
            self.axis(axes.1).counter_offset,
        );
        let Some(mut arc) = Arc::new(axes, from, centre, rotation, end_mdeg) else {
            // Radius 0 or beyond the largest: "could not be processed".
            return Err(Refusal::Moving);
        };
        arc.centre.0 += offsets.0 as f64;
        arc.centre.1 += offsets.1 as f64;
        let mut helpers = Vec::new();
        if let Some(z) = helix_z {
            let zaxis = self.axis(Axis::Z);
            arc.helix = Some((zaxis.position, z - zaxis.counter()));
            helpers.push(Axis::U);
        }
        let ramps = self.global_ramps(axes.0);
        let mut group = Group::new(Path::Arc(arc), ramps, buffered_speed);
        group.helpers = helpers;
        Ok(group)
    }

    pub(super) fn launch(&mut self, axis: Axis, mut run: Run) {
        let a = &mut self.axes[axis.index()];
        a.levels = a.levels_at(a.position);
        a.waiting_for_inp = false;
        if a.slowdown_enabled() && a.levels.slowdown {
            // Started on the slow-down cam: run at LSPD (A.1 operation 2).
            run.slowed = true;
            let low = run.ramps.low;
            run.plan(a.position, low, true);
        }
        a.rate = run.speed();
        a.phase = run.phase();
        self.activity[axis.index()] = Activity::Run(Box::new(run));
    }

    pub(super) fn launch_group(&mut self, group: Group) -> u64 {
        let id = self.next_group;
        self.next_group += 1;
        let (phase, rates) = (group.phase(), group.rates());
        for axis in group.members() {
            let a = &mut self.axes[axis.index()];
            a.levels = a.levels_at(a.position);
            a.waiting_for_inp = false;
            a.phase = phase;
            a.rate = rates
                .iter()
                .find(|(m, _)| *m == axis)
                .map_or(0.0, |&(_, r)| r);
            self.activity[axis.index()] = Activity::Group(id);
        }
        self.groups.push((id, group));
        id
    }
}
