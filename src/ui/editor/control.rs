//! Run control of the program in the controller and what the editor
//! watches while it runs: the tool's control lines (TMCL `RUNAPP`…,
//! A-Script `SACTRL[n]`), its state read back over and over while the
//! program runs (mode, counter, registers), the line the counter is on
//! marked `▶`, and the variables chosen to be watched, shown in a panel
//! beside the text. Everything family-specific comes from the tool
//! ([`ProgramControl`], [`VariableSet`]).

use std::collections::BTreeMap;

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph};

use super::watch::{MAX_WATCHED, load_watch_list, save_watch_list};
use super::{EditorPane, PromptKind, TAG_CONTROL, TAG_STATUS, TAG_STATUS_TIMER, TAG_VARIABLE};
use super::{PANEL_MIN_TEXT, PANEL_WIDTH, WATCH_PERIOD, number_read};
use crate::protocol::program::{ControlKey, CounterMap, ProgramControl, StateSlot, VariableSet};
use crate::ui::field::Field;
use crate::ui::keymap::{Action, Context};
use crate::ui::pane::{Notice, Outcome, PaneEvent, Request, View, key_label};
use crate::ui::theme::Role;

/// A program in the controller as last read.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ProgramState {
    /// The program the run keys act on, where the controller has several.
    pub target: Option<u8>,
    pub mode: Option<i64>,
    pub counter: Option<i64>,
    /// Other registers by name, in the order read.
    pub registers: Vec<(&'static str, Option<i64>)>,
    /// Reading again and again while it runs.
    pub(super) watching: bool,
    /// The last line of the reads under way.
    pub(super) last: Option<String>,
    /// The text as last loaded into the simulator.
    pub loaded: Option<String>,
}

impl ProgramState {
    /// `running PC 3 ACC 0 X 0`, `PRG 0 running SPC 12`: once something
    /// was read.
    pub fn describe(&self, control: &dyn ProgramControl) -> Option<String> {
        let read = self.mode.is_some()
            || self.counter.is_some()
            || self.registers.iter().any(|(_, v)| v.is_some());
        if !read {
            return None;
        }
        let show = |v: Option<i64>| v.map_or_else(|| "-".to_string(), |v| v.to_string());
        let mut text = String::new();
        if let Some(name) = self.target.and_then(|t| control.program_name(t)) {
            text.push_str(&name);
            text.push(' ');
        }
        text.push_str(self.mode.map_or("-", |m| control.mode_name(m)));
        text.push_str(&format!(
            " {} {}",
            control.counter_name(),
            show(self.counter)
        ));
        for (name, value) in &self.registers {
            text.push_str(&format!(" {name} {}", show(*value)));
        }
        Some(text)
    }
}

impl EditorPane {
    /// The variables the text's tool can watch, if any.
    fn variable_set(&self) -> Option<&'static VariableSet> {
        self.tool.variables()
    }

    /// The watched variables of the text's tool, and their values.
    pub(super) fn variables(&self) -> Option<&BTreeMap<u8, Option<i64>>> {
        self.variables.get(self.variable_set()?.key)
    }

    fn variables_mut(&mut self) -> Option<&mut BTreeMap<u8, Option<i64>>> {
        let key = self.variable_set()?.key;
        Some(self.variables.entry(key).or_default())
    }

    /// The tool's list from the data directory, if not loaded yet.
    pub(super) fn load_variables(&mut self) {
        let Some(set) = self.variable_set() else {
            return;
        };
        if self.variables.contains_key(set.key) {
            return;
        }
        let list = self
            .data_dir
            .as_deref()
            .map(|dir| load_watch_list(dir, set.key))
            .unwrap_or_default();
        self.variables
            .insert(set.key, list.into_iter().map(|n| (n, None)).collect());
    }

    /// The numbers watched, in order.
    fn watched_numbers(&self) -> Vec<u8> {
        self.variables()
            .map(|v| v.keys().copied().collect())
            .unwrap_or_default()
    }

    /// The user variables watched, with their values as last read.
    pub fn watched_variables(&self) -> Vec<(u8, Option<i64>)> {
        self.variables()
            .map(|v| v.iter().map(|(n, v)| (*n, *v)).collect())
            .unwrap_or_default()
    }

    /// Whether the connected module runs this text's programs (its lines
    /// may be read there).
    fn connected_to_tool(&self, view: &View) -> bool {
        view.session.is_some() && self.other_family(view).is_none()
    }

    /// The program the run keys act on: the one the cursor is in, else the
    /// one last acted on, else the first.
    fn program_here(&self) -> u8 {
        let line = self.cursor().0 + 1;
        self.checked
            .program
            .as_ref()
            .and_then(|p| p.program_at(line))
            .or(self.state.target)
            .unwrap_or(0)
    }

    /// A run key: its control line, then the program's state read back.
    pub(super) fn control(&mut self, key: ControlKey, view: &View) -> Outcome {
        let Some(control) = self.tool.control() else {
            self.message = Some(Notice::warning(format!(
                "{} programs have no run control over the wire",
                self.tool.name()
            )));
            return Outcome::redraw();
        };
        if let Some(wrong) = self.other_family(view) {
            self.message = Some(wrong);
            return Outcome::redraw();
        }
        let target = self.program_here();
        if self.state.target != Some(target) {
            self.state = ProgramState {
                target: Some(target),
                loaded: self.state.loaded.take(),
                ..ProgramState::default()
            };
        }
        let sent = control.control(key, target, self.state.mode);
        self.state.watching = sent.watch;
        if let (Some(verb), Some(_)) = (sent.verb, view.session) {
            let name = control
                .program_name(target)
                .unwrap_or_else(|| "the program".into());
            let host = if self.tool.runs_from_host() {
                format!(
                    "; {} runs this text from the host",
                    key_label(view.keymap, Context::Editor, Action::EditorHostRun)
                )
            } else {
                String::new()
            };
            self.message = Some(Notice::info(format!(
                "{}: {verb} {name} in the controller (a program already there{host})",
                sent.line
            )));
        }
        let read = self.read_state(control);
        Outcome::Handled(vec![
            Request::Send {
                lines: vec![sent.line],
                tag: TAG_CONTROL,
            },
            read,
        ])
    }

    /// Read the program's state and the variables watched.
    fn read_state(&mut self, control: &dyn ProgramControl) -> Request {
        let target = self.state.target.unwrap_or(0);
        let reads = control.state_reads(target);
        self.state.registers = reads
            .iter()
            .filter_map(|r| match r.slot {
                StateSlot::Register(name) => {
                    let old = self.state.registers.iter().find(|(n, _)| *n == name);
                    Some((name, old.and_then(|(_, v)| *v)))
                }
                _ => None,
            })
            .collect();
        let read_line = self.variable_set().map(|set| set.read_line);
        let lines: Vec<String> = reads
            .into_iter()
            .map(|r| r.line)
            .chain(
                self.watched_numbers()
                    .into_iter()
                    .filter_map(|n| read_line.map(|read| read(n))),
            )
            .collect();
        self.state.last = lines.last().cloned();
        Request::Send {
            lines,
            tag: TAG_STATUS,
        }
    }

    /// One answer of [`EditorPane::read_state`].
    fn state_reply(&mut self, line: &str, value: Option<i64>) -> Vec<Request> {
        let Some(control) = self.tool.control() else {
            return Vec::new();
        };
        let shown = self.state.describe(control);
        let requests = self.take_state(control, line, value);
        if self.state.describe(control) != shown {
            self.state_changed();
        }
        requests
    }

    fn take_state(
        &mut self,
        control: &dyn ProgramControl,
        line: &str,
        value: Option<i64>,
    ) -> Vec<Request> {
        let target = self.state.target.unwrap_or(0);
        let slot = control
            .state_reads(target)
            .into_iter()
            .find(|r| r.line == line)
            .map(|r| r.slot);
        match slot {
            Some(StateSlot::Mode) => self.state.mode = value,
            Some(StateSlot::Counter) => {
                self.state.counter = value;
                let maps = match control.counter_map() {
                    CounterMap::Always => true,
                    CounterMap::WhenLoadedHere => {
                        self.state.loaded.as_deref() == Some(self.text().as_str())
                    }
                };
                self.current = match (&self.checked.program, value) {
                    (Some(program), Some(counter)) if maps => program
                        .line_of_counter(counter)
                        .map(|line| line.saturating_sub(1)),
                    _ => None,
                };
            }
            Some(StateSlot::Register(name)) => {
                if let Some(slot) = self.state.registers.iter_mut().find(|(n, _)| *n == name) {
                    slot.1 = value;
                }
            }
            None => self.variable_reply(line, value),
        }
        if self.state.last.as_deref() != Some(line) {
            return Vec::new();
        }
        // The last of the batch: again later while the program runs.
        if self.state.watching && self.state.mode.is_some_and(|m| control.keeps_running(m)) {
            vec![Request::WakeAfter {
                after: WATCH_PERIOD,
                tag: TAG_STATUS_TIMER,
            }]
        } else {
            self.state.watching = false;
            if !control.marks_where_stopped() {
                self.current = None;
            }
            Vec::new()
        }
    }

    /// A watched variable's value came (`None`: it could not be read).
    fn variable_reply(&mut self, line: &str, value: Option<i64>) {
        let Some(set) = self.variable_set() else {
            return;
        };
        let Some(n) = (set.of_line)(line) else {
            return;
        };
        if let Some(slot) = self.variables_mut().and_then(|v| v.get_mut(&n)) {
            *slot = value;
            self.host_values = None;
        }
    }

    /// The watch key: the variable the cursor names, else ask for one.
    pub(super) fn watch_key(&mut self, view: &View) -> Outcome {
        if self.variable_set().is_none() {
            self.message = Some(Notice::warning(format!(
                "{} programs have no variables to watch",
                self.tool.name()
            )));
            return Outcome::redraw();
        }
        let (row, col) = self.cursor();
        let line = self.text.lines().get(row).cloned().unwrap_or_default();
        let byte = line
            .char_indices()
            .nth(col)
            .map_or(line.len(), |(at, _)| at);
        let named = match &self.checked.program {
            Some(program) => program.variable_at(row + 1, &line, byte),
            None => self.tool.variable_on_line(&line, byte),
        };
        match named {
            Some(n) => self.toggle_variable(n, view),
            None => {
                self.prompt = Some((PromptKind::Watch, Field::default()));
                Outcome::redraw()
            }
        }
    }

    /// The number typed at the watch prompt.
    pub(super) fn watch_typed(&mut self, text: &str, view: &View) -> Outcome {
        let Some(set) = self.variable_set() else {
            return Outcome::redraw();
        };
        match (set.parse)(text) {
            Ok(n) => self.toggle_variable(n, view),
            Err(message) => {
                self.message = Some(Notice::error(message.to_string()));
                Outcome::redraw()
            }
        }
    }

    /// Watch variable `n`, or stop watching it; the list is kept in the
    /// data directory, one per tool.
    pub(super) fn toggle_variable(&mut self, n: u8, view: &View) -> Outcome {
        let Some(set) = self.variable_set() else {
            return Outcome::redraw();
        };
        let name = (set.name)(n);
        let read = (set.read_line)(n);
        let reads = self.connected_to_tool(view);
        let mut requests = Vec::new();
        let watched = self.watched_numbers();
        if watched.contains(&n) {
            if let Some(v) = self.variables_mut() {
                v.remove(&n);
            }
            self.message = Some(Notice::info(format!("{name} no longer watched")));
        } else if watched.len() >= MAX_WATCHED {
            self.message = Some(Notice::warning(format!(
                "{MAX_WATCHED} variables are watched already: stop watching one first ({} on its line)",
                key_label(view.keymap, Context::Editor, Action::EditorWatch)
            )));
            return Outcome::redraw();
        } else {
            if let Some(v) = self.variables_mut() {
                v.insert(n, None);
            }
            self.message = Some(Notice::info(if read == name {
                format!("watching {name}")
            } else {
                format!("watching {name} ({read})")
            }));
            if reads {
                requests.push(Request::Send {
                    lines: vec![read],
                    tag: TAG_VARIABLE,
                });
            }
        }
        if let Some(dir) = self.data_dir.as_deref() {
            let list = self.watched_numbers();
            if let Err(e) = save_watch_list(dir, set.key, &list) {
                self.message = Some(Notice::error(e));
            }
        }
        Outcome::Handled(requests)
    }

    /// The watched variables and their values: the host's own while the
    /// text runs from the host (the controller's are not its).
    pub(super) fn shown_variables(&self) -> Vec<(u8, Option<i64>)> {
        let host = self.host.as_ref().map(|h| h.variables().to_vec());
        match host.as_ref().or(self.host_values.as_ref()) {
            Some(values) => self
                .watched_numbers()
                .into_iter()
                .map(|n| (n, values.get(usize::from(n)).copied().map(i64::from)))
                .collect(),
            None => self.watched_variables(),
        }
    }

    /// Whether the variables shown are a host run's (running, or the last
    /// one's until the controller's are read again).
    pub(super) fn host_variables_shown(&self) -> bool {
        self.host.is_some() || self.host_values.is_some()
    }

    /// Whether the watch panel has room beside the text in `width`.
    pub(super) fn panel_shown(&self, width: u16) -> bool {
        self.variables().is_some_and(|v| !v.is_empty()) && width >= PANEL_MIN_TEXT + PANEL_WIDTH
    }

    /// The watch panel: each variable watched and its value.
    pub(super) fn render_panel(&self, frame: &mut Frame, area: Rect, view: &View) {
        let Some(set) = self.variable_set() else {
            return;
        };
        let theme = view.theme;
        let block = Block::default()
            .borders(Borders::LEFT)
            .border_style(theme.style(Role::Border));
        let inner = block.inner(area);
        frame.render_widget(block, area);
        let width = usize::from(inner.width);
        let heading = if self.host_variables_shown() {
            format!(" {} (host)", set.heading)
        } else {
            format!(" {}", set.heading)
        };
        let mut lines = vec![Line::styled(heading, theme.style(Role::Title))];
        for (n, value) in self.shown_variables() {
            let label = format!(" {}{n}", set.mark);
            let shown = value.map_or_else(|| "—".to_string(), |v: i64| v.to_string());
            let pad = width.saturating_sub(label.chars().count() + shown.chars().count() + 1);
            lines.push(Line::from(vec![
                Span::styled(label, theme.style(Role::Muted)),
                Span::raw(" ".repeat(pad)),
                Span::styled(shown, theme.style(Role::Accent)),
            ]));
        }
        let note = if view.session.is_none() {
            " not connected".to_string()
        } else {
            format!(
                " {}: add/remove",
                key_label(view.keymap, Context::Editor, Action::EditorWatch)
            )
        };
        lines.push(Line::styled(note, theme.style(Role::Muted)));
        frame.render_widget(Paragraph::new(lines), inner);
    }

    /// The variables on the bottom line when the panel has no room.
    pub(super) fn variables_inline(&self) -> Option<String> {
        let set = self.variable_set()?;
        let values: Vec<String> = self
            .shown_variables()
            .into_iter()
            .map(|(n, v)| {
                format!(
                    "{}{n}={}",
                    set.mark,
                    v.map_or_else(|| "—".to_string(), |v| v.to_string())
                )
            })
            .collect();
        (!values.is_empty()).then(|| values.join(" "))
    }

    /// The events of run control and watching; `None` for the others.
    pub(super) fn control_event(&mut self, event: &PaneEvent, view: &View) -> Option<Outcome> {
        match event {
            PaneEvent::Reply { tag, line, result } if *tag == TAG_STATUS => {
                if result.is_err() {
                    self.state.watching = false;
                }
                Some(Outcome::Handled(
                    self.state_reply(line, number_read(result)),
                ))
            }
            PaneEvent::Reply {
                tag,
                line,
                result: Err(e),
            } if *tag == TAG_CONTROL => {
                self.state.watching = false;
                self.message = Some(Notice::error(format!("{line}: {e}")));
                Some(Outcome::redraw())
            }
            PaneEvent::Wake { tag } if *tag == TAG_STATUS_TIMER => {
                if !self.state.watching {
                    return Some(Outcome::Ignored);
                }
                let control = self.tool.control()?;
                Some(Outcome::request(self.read_state(control)))
            }
            PaneEvent::Reply { tag, line, result } if *tag == TAG_VARIABLE => {
                if let Err(e) = result {
                    self.message = Some(Notice::error(format!("{line}: {e}")));
                }
                self.variable_reply(line, number_read(result));
                Some(Outcome::redraw())
            }
            PaneEvent::Connected { .. } => {
                // Another module: its own state and values, read once.
                self.state = ProgramState::default();
                let numbers = self.watched_numbers();
                if let Some(values) = self.variables_mut() {
                    for value in values.values_mut() {
                        *value = None;
                    }
                }
                let read_line = self.variable_set().map(|set| set.read_line);
                Some(match read_line {
                    Some(read) if !numbers.is_empty() && self.connected_to_tool(view) => {
                        Outcome::request(Request::Send {
                            lines: numbers.into_iter().map(read).collect(),
                            tag: TAG_VARIABLE,
                        })
                    }
                    _ => Outcome::redraw(),
                })
            }
            PaneEvent::Stopping => {
                self.state.watching = false;
                None
            }
            PaneEvent::EmergencyStop(_) => {
                // The stop ends the programs too (TMCL 128, SACTRL): the
                // state shown was read before it, so read where each
                // stopped, once, rather than leave `running` up.
                self.state.watching = false;
                let control = self.tool.control()?;
                if self.state.describe(control).is_none() || !self.connected_to_tool(view) {
                    return None;
                }
                Some(Outcome::request(self.read_state(control)))
            }
            _ => None,
        }
    }
}
