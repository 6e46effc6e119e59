//! The editor's A-Script mode at work: the language followed from the file
//! and the connection, run control of the programs already in a CMD-4CR
//! (`SACTRL[n]`, read back with `SASTAT[n]`, `SPC[n]` and the watched
//! `V[n]`, §2.7.8–§2.7.9), loading the text into the in-process simulator
//! (the only program memory a console can write: the manual documents no
//! download, §2.7.7, §5.1.5), and running the text from the host
//! ([`ConsoleHostRun`]).
//!
//! Which program the run keys act on: the PRG block the cursor is in,
//! else the file's first. `SPC` counts the controller's compiled lines,
//! which map to no source line the manual gives (digest §2.11); only a
//! text this editor loaded into the simulator (the same compiler) has its
//! line marked `▶`.

use std::path::Path;

use super::script::{
    self, Language, NO_DOWNLOAD, control_line, program_at, status_lines, status_name, variable_at,
    variable_line, variable_of_line,
};
use super::{EditorPane, PromptKind, TAG_LOAD, WATCH_PERIOD, Watch, number_read};
use crate::session::ascript_host::{HostProgram, ThreadState};
use crate::session::run_end::{RunEnding, StopOnFailure};
use crate::ui::field::Field;
use crate::ui::host_run::{ConsoleHostRun, HostUpdate};
use crate::ui::keymap::{Action, Context};
use crate::ui::pane::{Notice, Outcome, PaneEvent, Request, View, key_label};
use crate::ui::theme::Role;

/// Tags of this mode's lines and timer.
const TAG_CONTROL: u64 = (1 << 48) + 5;
const TAG_STATUS: u64 = (1 << 48) + 6;
const TAG_STATUS_TIMER: u64 = (1 << 48) + 7;
pub(super) const TAG_VARIABLE: u64 = (1 << 48) + 8;

/// A program in the controller as last read.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ProgramState {
    /// The program the run keys act on (`SACTRL[n]`).
    pub program: Option<u8>,
    /// `SASTAT[n]` (T2-34).
    pub status: Option<i64>,
    /// `SPC[n]`.
    pub pc: Option<i64>,
    /// Reading again and again while it runs.
    watching: bool,
    /// The last line of the reads under way.
    last: Option<String>,
    /// The text as last loaded into the simulator.
    pub loaded: Option<String>,
}

impl ProgramState {
    /// `PRG 0 running SPC 12`, once something was read.
    pub fn describe(&self) -> Option<String> {
        let n = self.program?;
        if self.status.is_none() && self.pc.is_none() {
            return None;
        }
        let status = self.status.map_or("-", status_name);
        let pc = self.pc.map_or_else(|| "-".to_string(), |pc| pc.to_string());
        Some(format!("PRG {n} {status} SPC {pc}"))
    }
}

/// Why the connected module takes no A-Script: it is no CMD-4CR.
fn other_family(view: &View) -> Option<Notice> {
    let family = view.session?.family.name;
    (family != "cmd4cr").then(|| {
        Notice::error(format!(
            "the connected module speaks {family}: A-Script programs are the CMD-4CR's"
        ))
    })
}

impl EditorPane {
    /// The language the file's extension says, if it says one.
    pub(super) fn language_of_file(&mut self, path: &Path) {
        if let Some(language) = Language::of_file(path) {
            self.set_language(language);
            self.language_fixed = true;
        }
    }

    /// Write the text in `language`: checked again, coloured again; the
    /// watched variables are the language's own.
    pub(super) fn set_language(&mut self, language: Language) {
        if language == self.language {
            return;
        }
        self.language = language;
        std::mem::swap(&mut self.variables, &mut self.other_variables);
        self.current = None;
        self.failed_line = None;
        self.script_state = ProgramState::default();
        self.watch = Watch::default();
        self.watching = false;
        self.host_values = None;
        self.assemble();
    }

    /// The language key.
    pub(super) fn switch_language(&mut self, view: &View) -> Outcome {
        if self.host.is_some() {
            self.message = Some(Notice::warning(format!(
                "the text runs from the host: {} stops it first",
                key_label(view.keymap, Context::Editor, Action::Cancel)
            )));
            return Outcome::redraw();
        }
        let to = self.language.other();
        self.set_language(to);
        self.language_fixed = true;
        self.message = Some(Notice::info(format!(
            "the text is {} now ({} switches back)",
            to.name(),
            key_label(view.keymap, Context::Editor, Action::EditorLanguage)
        )));
        Outcome::redraw()
    }

    /// A connection's family decides, unless the file or the user did.
    fn follow_family(&mut self, view: &View) -> bool {
        let Some(session) = view.session else {
            return false;
        };
        let language = Language::of_family(session.family.name);
        if self.language_fixed || language == self.language {
            return false;
        }
        self.set_language(language);
        true
    }

    /// The lines (0-based) programs running from the host are at.
    pub(super) fn running_lines(&self) -> Vec<usize> {
        self.host.as_ref().map_or_else(Vec::new, |host| {
            host.threads()
                .iter()
                .filter(|t| t.state == ThreadState::Running || t.state == ThreadState::Paused)
                .map(|t| t.line.saturating_sub(1))
                .collect()
        })
    }

    /// The watched variables and their values: the host's own while the
    /// text runs from the host (the controller's V[n] are not its).
    pub(super) fn shown_variables(&self) -> Vec<(u8, Option<i64>)> {
        let host = self.host.as_ref().map(|h| h.variables().to_vec());
        match host.as_ref().or(self.host_values.as_ref()) {
            Some(values) if self.language == Language::AScript => self
                .variables
                .keys()
                .map(|&n| (n, values.get(usize::from(n)).copied().map(i64::from)))
                .collect(),
            _ => self.variables.iter().map(|(n, v)| (*n, *v)).collect(),
        }
    }

    /// Whether the variables shown are the host run's (running, or the
    /// last one's until the controller's are read again).
    pub(super) fn host_variables_shown(&self) -> bool {
        self.language == Language::AScript && (self.host.is_some() || self.host_values.is_some())
    }

    /// The keys that mean something else for A-Script; `None` for those
    /// that do not (or in TMCL mode).
    pub(super) fn script_action(&mut self, action: Action, view: &View) -> Option<Outcome> {
        if action == Action::Cancel
            && let Some(host) = self.end_host_run()
        {
            self.message = Some(Notice::warning(format!(
                "host run of {} stopped: nothing more of it is sent; stopping every axis",
                host.name(),
            )));
            return Some(Outcome::request(Request::EndRun {
                ending: RunEnding::Cancelled,
                policy: StopOnFailure::Stop,
            }));
        }
        if self.language != Language::AScript {
            return None;
        }
        Some(match action {
            Action::EditorAssemble => {
                self.assemble();
                match &self.script.program {
                    Some(program) => {
                        self.message = Some(Notice::info(script::summary(program)));
                    }
                    None => self.next_error_from_top(),
                }
                Outcome::redraw()
            }
            Action::EditorRun => self.program_control(1, view),
            Action::EditorStop | Action::EditorReset => self.program_control(0, view),
            // §5.1 documents no single step: the step key pauses and
            // continues instead (T2-33 codes 2 and 3).
            Action::EditorStep => {
                let code = if self.script_state.status == Some(2) {
                    3
                } else {
                    2
                };
                self.program_control(code, view)
            }
            Action::EditorDownload => self.load_into_simulator(view),
            Action::EditorVerify | Action::EditorUpload => {
                self.message = Some(Notice::warning(format!(
                    "{NO_DOWNLOAD}, nor a read-back: {} runs this text from the host",
                    key_label(view.keymap, Context::Editor, Action::EditorHostRun)
                )));
                Outcome::redraw()
            }
            Action::EditorWatch => {
                let (row, col) = self.cursor();
                let line = self.text.lines().get(row).cloned().unwrap_or_default();
                let byte = line
                    .char_indices()
                    .nth(col)
                    .map_or(line.len(), |(at, _)| at);
                match variable_at(&line, byte) {
                    Some(n) => self.toggle_variable(n, view),
                    None => {
                        self.prompt = Some((PromptKind::WatchScript, Field::default()));
                        Outcome::redraw()
                    }
                }
            }
            Action::EditorHostRun => self.start_host_run(view),
            _ => return None,
        })
    }

    /// The program the run keys act on.
    fn program_here(&self) -> u8 {
        let line = self.cursor().0 + 1;
        self.script
            .program
            .as_ref()
            .and_then(|p| program_at(p, line))
            .or(self.script_state.program)
            .unwrap_or(0)
    }

    /// `SACTRL[n]=code` for the program here, then its state read back.
    fn program_control(&mut self, code: u8, view: &View) -> Outcome {
        if view.session.is_none() {
            self.message = Some(Notice::error(
                "not connected: give :connect --sim cmd4cr (or --port PATH --protocol cmd4cr)",
            ));
            return Outcome::redraw();
        }
        if let Some(wrong) = other_family(view) {
            self.message = Some(wrong);
            return Outcome::redraw();
        }
        let n = self.program_here();
        if self.script_state.program != Some(n) {
            self.script_state = ProgramState {
                program: Some(n),
                loaded: self.script_state.loaded.take(),
                ..ProgramState::default()
            };
        }
        self.script_state.watching = code == 1 || code == 3;
        let what = match code {
            0 => "stop",
            1 => "start",
            2 => "pause",
            _ => "continue",
        };
        self.message = Some(Notice::info(format!(
            "{}: {what} PRG {n} in the controller (a program already there; {} runs this text from the host)",
            control_line(n, code),
            key_label(view.keymap, Context::Editor, Action::EditorHostRun)
        )));
        let read = self.read_state();
        Outcome::Handled(vec![
            Request::Send {
                lines: vec![control_line(n, code)],
                tag: TAG_CONTROL,
            },
            read,
        ])
    }

    /// Read the program's state and the watched variables.
    fn read_state(&mut self) -> Request {
        let n = self.script_state.program.unwrap_or(0);
        let lines: Vec<String> = status_lines(n)
            .into_iter()
            .chain(self.variables.keys().map(|&v| variable_line(v)))
            .collect();
        self.script_state.last = lines.last().cloned();
        Request::Send {
            lines,
            tag: TAG_STATUS,
        }
    }

    /// One answer of [`EditorPane::read_state`].
    fn state_reply(&mut self, line: &str, value: Option<i64>) -> Vec<Request> {
        if line.starts_with("SASTAT") {
            self.script_state.status = value;
        } else if line.starts_with("SPC") {
            self.script_state.pc = value;
            let same_text = self.script_state.loaded.as_deref() == Some(self.text().as_str());
            self.current = match (&self.script.program, value) {
                (Some(program), Some(pc)) if same_text => usize::try_from(pc)
                    .ok()
                    .and_then(|pc| program.step(pc))
                    .map(|step| step.line.saturating_sub(1)),
                _ => None,
            };
        } else if let Some(slot) = variable_of_line(line).and_then(|n| self.variables.get_mut(&n)) {
            *slot = value;
            self.host_values = None;
        }
        if self.script_state.last.as_deref() != Some(line) {
            return Vec::new();
        }
        // Running or paused: read again later.
        if self.script_state.watching && matches!(self.script_state.status, Some(1 | 2)) {
            vec![Request::WakeAfter {
                after: WATCH_PERIOD,
                tag: TAG_STATUS_TIMER,
            }]
        } else {
            self.script_state.watching = false;
            if self.script_state.status != Some(1) {
                self.current = None;
            }
            Vec::new()
        }
    }

    /// The download key: the simulator in this process takes the text;
    /// a controller cannot (the manual documents no way), and the editor
    /// says what can be done instead.
    fn load_into_simulator(&mut self, view: &View) -> Outcome {
        let host = key_label(view.keymap, Context::Editor, Action::EditorHostRun);
        if view.session.is_none() {
            self.message = Some(Notice::warning(format!(
                "not connected; {NO_DOWNLOAD}. With --sim cmd4cr this key loads the simulator; {host} runs the text from the host"
            )));
            return Outcome::redraw();
        }
        if let Some(wrong) = other_family(view) {
            self.message = Some(wrong);
            return Outcome::redraw();
        }
        self.assemble();
        if self.script.program.is_none() {
            self.next_error_from_top();
            if let Some(message) = self.message.take() {
                self.message = Some(Notice::error(format!(
                    "does not check, nothing loaded: {}",
                    message.text
                )));
            }
            return Outcome::redraw();
        }
        self.message = Some(Notice::info("loading the text into the simulator…"));
        Outcome::request(Request::LoadProgram {
            source: self.text(),
            tag: TAG_LOAD,
        })
    }

    /// Start running the text from the host.
    fn start_host_run(&mut self, view: &View) -> Outcome {
        if self.host.is_some() {
            self.message = Some(Notice::warning(format!(
                "the text runs from the host already: {} stops it",
                key_label(view.keymap, Context::Editor, Action::Cancel)
            )));
            return Outcome::redraw();
        }
        if view.session.is_none() {
            self.message = Some(Notice::error(
                "not connected: give :connect --port PATH --protocol cmd4cr (or --sim cmd4cr)",
            ));
            return Outcome::redraw();
        }
        if let Some(wrong) = other_family(view) {
            self.message = Some(wrong);
            return Outcome::redraw();
        }
        self.assemble();
        let program = match HostProgram::check(&self.source_name(), &self.text(), None) {
            Ok(program) => program,
            Err(problems) => {
                self.next_error_from_top();
                let more = problems.len().saturating_sub(1);
                let first = problems.into_iter().next().unwrap_or_default();
                self.message = Some(Notice::error(if more > 0 {
                    format!("nothing was sent: {first} (and {more} more)")
                } else {
                    format!("nothing was sent: {first}")
                }));
                return Outcome::redraw();
            }
        };
        let (run, update) = ConsoleHostRun::start(&program, &mut self.host_tag);
        self.host = Some(run);
        self.host_update(update)
    }

    /// What the host run said: the last line as the message; its requests.
    fn host_update(&mut self, update: HostUpdate) -> Outcome {
        if let Some((role, text)) = update.said.last() {
            self.message = Some(match role {
                Role::Error => Notice::error(text.clone()),
                Role::Warning => Notice::warning(text.clone()),
                _ => Notice::info(text.clone()),
            });
        }
        let mut requests = update.requests;
        if let Some(end) = update.ended {
            self.end_host_run();
            // A program that failed may have left an axis moving.
            if !end.ok() {
                requests.push(Request::EndRun {
                    ending: RunEnding::Failed,
                    policy: StopOnFailure::Stop,
                });
            }
        }
        Outcome::Handled(requests)
    }

    /// Let the host run go; its variables stay shown until the
    /// controller's are read.
    pub(super) fn end_host_run(&mut self) -> Option<ConsoleHostRun> {
        let host = self.host.take()?;
        self.host_values = Some(host.variables().to_vec());
        Some(host)
    }

    /// The events of this mode; `None` for the others.
    pub(super) fn script_event(&mut self, event: &PaneEvent, view: &View) -> Option<Outcome> {
        if let Some(host) = self.host.as_mut()
            && let Some(update) = host.on_event(event, &mut self.host_tag)
        {
            return Some(self.host_update(update));
        }
        match event {
            PaneEvent::Snapshot => self.follow_family(view).then(Outcome::redraw),
            PaneEvent::Connected { .. } if self.language == Language::AScript => {
                self.script_state = ProgramState::default();
                for value in self.variables.values_mut() {
                    *value = None;
                }
                let cmd4cr = view.session.is_some_and(|s| s.family.name == "cmd4cr");
                Some(if cmd4cr && !self.variables.is_empty() {
                    Outcome::request(Request::Send {
                        lines: self.variables.keys().map(|&n| variable_line(n)).collect(),
                        tag: TAG_VARIABLE,
                    })
                } else {
                    Outcome::redraw()
                })
            }
            PaneEvent::ProgramLoaded { tag, result } if *tag == TAG_LOAD => {
                let host = key_label(view.keymap, Context::Editor, Action::EditorHostRun);
                self.message = Some(match result {
                    Ok(said) => {
                        self.script_state.loaded = Some(self.text());
                        let n = self.program_here();
                        Notice::info(format!(
                            "{said}: {} starts PRG {n} (SACTRL{n}=1); a real CMD-4CR takes no download, {host} runs from the host",
                            key_label(view.keymap, Context::Editor, Action::EditorRun)
                        ))
                    }
                    // A real controller (or a served simulator): `why`
                    // says only that it is no simulator here.
                    Err(_) => Notice::warning(format!(
                        "{NO_DOWNLOAD}: {host} runs this text from the host, {}/{} start/stop a program already in it",
                        key_label(view.keymap, Context::Editor, Action::EditorRun),
                        key_label(view.keymap, Context::Editor, Action::EditorStop)
                    )),
                });
                Some(Outcome::redraw())
            }
            PaneEvent::Reply { tag, line, result } if *tag == TAG_STATUS => {
                if result.is_err() {
                    self.script_state.watching = false;
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
                self.script_state.watching = false;
                self.message = Some(Notice::error(format!("{line}: {e}")));
                Some(Outcome::redraw())
            }
            PaneEvent::Reply { tag, line, result } if *tag == TAG_VARIABLE => {
                if let Err(e) = result {
                    self.message = Some(Notice::error(format!("{line}: {e}")));
                }
                if let Some(slot) = variable_of_line(line).and_then(|n| self.variables.get_mut(&n))
                {
                    *slot = number_read(result);
                    self.host_values = None;
                }
                Some(Outcome::redraw())
            }
            PaneEvent::Wake { tag } if *tag == TAG_STATUS_TIMER => {
                Some(if self.script_state.watching {
                    Outcome::request(self.read_state())
                } else {
                    Outcome::Ignored
                })
            }
            PaneEvent::RunEnded(aftermath) => {
                let summary = aftermath.summary();
                self.message = Some(if aftermath.settled() {
                    Notice::info(summary)
                } else {
                    Notice::error(format!(
                        "{summary}: check the axes ({} stops everything)",
                        key_label(view.keymap, Context::Global, Action::EmergencyStop)
                    ))
                });
                Some(Outcome::redraw())
            }
            PaneEvent::Stopping => {
                self.script_state.watching = false;
                let host = self.end_host_run()?;
                self.message = Some(Notice::warning(format!(
                    "the emergency stop ended the host run of {}: nothing more of it is sent",
                    host.name()
                )));
                Some(Outcome::redraw())
            }
            _ => None,
        }
    }
}
