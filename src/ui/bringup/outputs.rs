//! The outputs and inputs the pane watches: which points the status poll
//! reads, and an output toggled with Enter after its confirmation.

use super::*;

impl BringUpPane {
    /// Read the outputs once, those no watched line reads already.
    pub(super) fn read_outputs(&mut self, view: &View) -> Vec<Request> {
        let Some(plan) = Self::io(view) else {
            return Vec::new();
        };
        if self.outputs_read.is_some() || view.session.is_none() {
            return Vec::new();
        }
        let mut lines: Vec<String> = Vec::new();
        for point in plan.points().iter().filter(|p| p.is_output()) {
            let Some(line) = point.read else { continue };
            if !self.io_watched.iter().any(|(_, l, _)| l == line)
                && !lines.iter().any(|l| l == line)
            {
                lines.push(line.to_string());
            }
        }
        let tag = self.tag();
        self.outputs_read = Some(tag);
        if lines.is_empty() {
            return Vec::new();
        }
        vec![Request::Send { lines, tag }]
    }

    /// The answer to an output's read line sent on taking the keyboard.
    pub(super) fn output_read(
        &mut self,
        line: &str,
        result: &Result<crate::session::LineResult, crate::session::SessionError>,
        view: &View,
    ) -> Outcome {
        let (Some(plan), Ok(result)) = (Self::io(view), result) else {
            return Outcome::Ignored;
        };
        for (index, point) in plan.points().iter().enumerate() {
            if point.is_output()
                && point.read == Some(line)
                && let Some(state) = plan.state(point, &result.value)
            {
                self.read_states.retain(|(i, _)| *i != index);
                self.read_states.push((index, state));
            }
        }
        Outcome::redraw()
    }

    pub(super) fn io(view: &View) -> Option<&'static dyn IoPlan> {
        view.session.and_then(|s| s.family.console.io())
    }

    /// The read lines the pane needs polled now: every module point's
    /// and the selected axis's, each once.
    pub(super) fn io_wanted(view: &View, on: bool) -> Vec<(usize, String, bool)> {
        let (Some(session), Some(plan), true) = (view.session, Self::io(view), on) else {
            return Vec::new();
        };
        let mut wanted: Vec<(usize, String, bool)> = Vec::new();
        for point in plan.points() {
            // Outputs are read once, not polled (see `read_outputs`).
            if point.axis.is_some_and(|a| a != session.axis) || point.is_output() {
                continue;
            }
            let Some(line) = point.read else { continue };
            match wanted.iter_mut().find(|(_, l, _)| l == line) {
                Some(entry) => entry.2 |= point.fast,
                None => wanted.push((point.axis.unwrap_or(0), line.to_string(), point.fast)),
            }
        }
        wanted
    }

    /// Watch what is wanted now and no longer what is not.
    pub(super) fn sync_watches(&mut self, view: &View, on: bool) -> Vec<Request> {
        let wanted = Self::io_wanted(view, on);
        let mut requests = Vec::new();
        for (axis, line, fast) in &self.io_watched {
            if !wanted.contains(&(*axis, line.clone(), *fast)) {
                requests.push(Request::Watch {
                    axis: *axis,
                    line: line.clone(),
                    on: false,
                    fast: *fast,
                });
            }
        }
        for (axis, line, fast) in &wanted {
            if !self.io_watched.contains(&(*axis, line.clone(), *fast)) {
                requests.push(Request::Watch {
                    axis: *axis,
                    line: line.clone(),
                    on: true,
                    fast: *fast,
                });
            }
        }
        self.io_watched = wanted;
        requests
    }

    /// The indices of the plan's outputs.
    pub(super) fn outputs(plan: &dyn IoPlan) -> Vec<usize> {
        plan.points()
            .iter()
            .enumerate()
            .filter(|(_, p)| p.is_output())
            .map(|(i, _)| i)
            .collect()
    }

    /// The state of `point` as known: read back after a switch, else from
    /// the poll, else as last set (for an output that cannot be read).
    pub(super) fn point_state(
        &self,
        plan: &dyn IoPlan,
        index: usize,
        session: &Snapshot,
    ) -> Option<i64> {
        let point = &plan.points()[index];
        if let Some(line) = point.read {
            let polled = session
                .status
                .iter()
                .flat_map(|s| s.watched.iter())
                .find(|w| w.line == line && w.reply.is_some())
                .and_then(|w| w.reply.as_ref())
                .and_then(|reply| plan.state(point, reply));
            if polled.is_some() {
                return polled;
            }
            return self
                .read_states
                .iter()
                .find(|(i, _)| *i == index)
                .map(|(_, v)| *v);
        }
        self.set_states
            .iter()
            .find(|(i, _)| *i == index)
            .map(|(_, on)| i64::from(*on))
    }

    /// Choose the next (or previous) output.
    pub(super) fn choose_output(&mut self, forward: bool, view: &View) -> Outcome {
        let Some(plan) = Self::io(view) else {
            return Outcome::Ignored;
        };
        let count = Self::outputs(plan).len();
        if count == 0 {
            return Outcome::Ignored;
        }
        self.output = if forward {
            (self.output + 1) % count
        } else {
            (self.output + count - 1) % count
        };
        Outcome::redraw()
    }

    /// Enter on the chosen output: ask before switching it.
    pub(super) fn ask_output(&mut self, view: &View) -> Outcome {
        let (Some(plan), Some(session)) = (Self::io(view), view.session) else {
            return self.not_connected();
        };
        let outputs = Self::outputs(plan);
        let Some(&index) = outputs.get(self.output.min(outputs.len().saturating_sub(1))) else {
            self.say(Role::Error, "this module lists no outputs");
            return Outcome::redraw();
        };
        if self.switching.is_some() {
            self.say(
                Role::Error,
                "an output is being switched: wait for its answer",
            );
            return Outcome::redraw();
        }
        let on = self.point_state(plan, index, session) != Some(1);
        self.confirm = Some((index, on));
        let name = plan.points()[index].name;
        let note = plan.output_note();
        let note = if note.is_empty() {
            String::new()
        } else {
            format!(" ({note})")
        };
        self.say(
            Role::Warning,
            format!(
                "set {name} {}? an output can move machinery: y/n{note}",
                if on { "on" } else { "off" }
            ),
        );
        Outcome::redraw()
    }

    /// The answer to the question: `y` switches the output, anything
    /// else sends nothing.
    pub(super) fn confirmed(&mut self, yes: bool, view: &View) -> Outcome {
        let Some((index, on)) = self.confirm.take() else {
            return Outcome::Ignored;
        };
        let Some(plan) = Self::io(view) else {
            return self.not_connected();
        };
        let point: &IoPoint = &plan.points()[index];
        if !yes {
            self.say(
                Role::Muted,
                format!("{} left as it is: nothing sent", point.name),
            );
            return Outcome::redraw();
        }
        let Some([off, on_line]) = point.set else {
            return Outcome::Ignored;
        };
        let mut lines = vec![if on { on_line } else { off }.to_string()];
        lines.extend(point.read.map(str::to_string));
        let left = lines.len();
        let (tag, send) = self.send(lines);
        self.switching = Some((tag, index, on, left));
        self.say(
            Role::Accent,
            format!("setting {} {}", point.name, if on { "on" } else { "off" }),
        );
        Outcome::request(send)
    }

    /// An answer to a line of an output switch.
    pub(super) fn output_answer(
        &mut self,
        result: &Result<crate::session::LineResult, crate::session::SessionError>,
        view: &View,
    ) -> Outcome {
        let Some((tag, index, on, left)) = self.switching else {
            return Outcome::Ignored;
        };
        let Some(plan) = Self::io(view) else {
            self.switching = None;
            return Outcome::Ignored;
        };
        let point = &plan.points()[index];
        let value = match result {
            Err(e) => {
                self.switching = None;
                self.say(Role::Error, format!("{}: {e}", point.name));
                return Outcome::redraw();
            }
            Ok(result) => result.value.clone(),
        };
        let total = 1 + usize::from(point.read.is_some());
        if left == total {
            // The set line's answer.
            self.set_states.retain(|(i, _)| *i != index);
            self.set_states.push((index, on));
        }
        if left > 1 {
            self.switching = Some((tag, index, on, left - 1));
            return Outcome::redraw();
        }
        self.switching = None;
        if point.read.is_none() {
            self.say(
                Role::Ok,
                format!(
                    "{} set {} (the module cannot read it back)",
                    point.name,
                    if on { "on" } else { "off" }
                ),
            );
            return Outcome::redraw();
        }
        match plan.state(point, &value) {
            Some(state) => {
                self.read_states.retain(|(i, _)| *i != index);
                self.read_states.push((index, state));
                let role = if (state != 0) == on {
                    Role::Ok
                } else {
                    Role::Error
                };
                self.say(
                    role,
                    format!(
                        "{} reads {} after the switch",
                        point.name,
                        if state != 0 { "on" } else { "off" }
                    ),
                );
            }
            None => self.say(
                Role::Error,
                format!("{} read back as {value}: no state in it", point.name),
            ),
        }
        Outcome::redraw()
    }
}
