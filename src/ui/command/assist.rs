//! Help and completion on the command line: `:help TOPIC`, F1 on the
//! word under the cursor, Tab through the candidates, from the tables of
//! the family connected (or chosen on the connect screen).

use super::*;

impl CommandPane {
    pub(super) fn help_topic(&mut self, topic: &str, view: &View) {
        if topic.is_empty() {
            // The list is longer than a short terminal: the key lines come
            // last, where the pane shows the newest, so the emergency stop
            // is on screen however many commands there are.
            for (syntax, what) in CONSOLE_COMMANDS {
                self.say(Role::Normal, format!("  {syntax:<24} {what}"));
            }
            let key = |action| key_label(view.keymap, Context::Command, action);
            self.say(
                Role::Accent,
                format!(
                    "Type a command (`MVP ABS, 0, 51200`); {} completes, {} on a word explains it, {}/{} recall.",
                    key(Action::Complete),
                    key(Action::Help),
                    key(Action::HistoryPrevious),
                    key(Action::HistoryNext),
                ),
            );
            self.say(
                Role::Accent,
                format!(
                    "{} stops every axis and any running program; {} quits; {} next pane; {}/{} scroll.",
                    key(Action::EmergencyStop),
                    key(Action::Quit),
                    key(Action::NextPane),
                    key(Action::ScrollPageUp),
                    key(Action::ScrollPageDown),
                ),
            );
            return;
        }
        if topic.starts_with(':') {
            let word = topic.split_whitespace().next().unwrap_or(topic);
            let found: Vec<_> = CONSOLE_COMMANDS
                .iter()
                .filter(|(syntax, _)| {
                    syntax
                        .split_whitespace()
                        .next()
                        .is_some_and(|w| w.eq_ignore_ascii_case(word))
                })
                .collect();
            if found.is_empty() {
                self.say(
                    Role::Error,
                    format!("no console command `{word}` (`:help` lists them)"),
                );
            }
            for (syntax, what) in found {
                self.say(Role::Normal, format!("{syntax}: {what}"));
            }
            if word.eq_ignore_ascii_case(":sim-input") {
                for line in sim_input_help(self.family(view)) {
                    self.say(Role::Normal, format!("  {line}"));
                }
            }
            return;
        }
        let Some(family) = self.family(view) else {
            self.say(Role::Error, not_connected());
            return;
        };
        self.offline_note(view);
        let lines = family.console.help(topic, topic.len());
        if lines.is_empty() {
            self.say(Role::Warning, format!("no help on `{topic}`"));
        }
        for line in lines {
            self.say(Role::Normal, line);
        }
    }

    /// F1: help on the word under the cursor, read in its line.
    pub(super) fn help_here(&mut self, view: &View) {
        let line = self.input.trim_end().to_string();
        if line.trim().is_empty() {
            self.help_topic("", view);
        } else if let Some(topic) = line.strip_prefix(":help") {
            self.help_topic(topic.trim(), view);
        } else if line.starts_with(':') {
            self.help_topic(&line, view);
        } else if let Some(family) = self.family(view) {
            self.offline_note(view);
            self.explained = Some(self.input.clone());
            let lines = family
                .console
                .help(&self.input, self.cursor.min(self.input.len()));
            if lines.is_empty() {
                self.say(Role::Warning, format!("no help on `{}`", line.trim()));
            }
            for l in lines {
                self.say(Role::Normal, l);
            }
        } else {
            self.say(Role::Error, not_connected());
        }
    }

    pub(super) fn complete(&mut self, view: &View) {
        self.hint = None;
        // Tab again: the next candidate.
        if let Some(c) = self.completing.as_mut()
            && c.line == self.input
            && !c.candidates.is_empty()
        {
            let next = c.chosen.map_or(0, |i| (i + 1) % c.candidates.len());
            let text = c
                .candidates
                .get(next)
                .map(|k| k.text.clone())
                .unwrap_or_default();
            let end = c.start + c.len;
            if self.input.is_char_boundary(c.start) && self.input.is_char_boundary(end) {
                self.input.replace_range(c.start..end, &text);
                c.len = text.len();
                c.chosen = Some(next);
                self.cursor = c.start + c.len;
                c.line = self.input.clone();
            }
            return;
        }
        self.completing = None;
        let completions = self.completions(view);
        let Completions {
            start,
            end,
            candidates,
            separator,
        } = completions;
        if candidates.is_empty() {
            self.hint = Some(Output {
                role: Role::Muted,
                text: "nothing to complete here".into(),
            });
            return;
        }
        if !(self.input.is_char_boundary(start) && self.input.is_char_boundary(end) && start <= end)
        {
            return;
        }
        let at_end = self
            .input
            .get(end..)
            .is_none_or(|rest| rest.trim().is_empty());
        if let [only] = candidates.as_slice() {
            let mut text = only.text.clone();
            if at_end {
                text.push_str(separator);
                self.input.truncate(end);
            }
            self.input.replace_range(start..end, &text);
            self.cursor = start + text.len();
            return;
        }
        let typed = self
            .input
            .get(start..self.cursor.max(start).min(end))
            .unwrap_or("");
        let common = common_prefix(&candidates);
        let len = if common.len() > typed.len() {
            self.input.replace_range(start..end, &common);
            self.cursor = start + common.len();
            common.len()
        } else {
            end - start
        };
        self.completing = Some(Completing {
            start,
            len,
            candidates,
            chosen: None,
            line: self.input.clone(),
        });
    }

    /// What Tab offers here: console commands and their arguments, or the
    /// family's completions of a console line.
    pub(super) fn completions(&self, view: &View) -> Completions {
        let line = self.input.as_str();
        let cursor = self.cursor.min(line.len());
        if let Some(body) = line.strip_prefix(':') {
            let head_end = body.find(char::is_whitespace).map_or(line.len(), |i| i + 1);
            if cursor <= head_end {
                let typed = line.get(..cursor).unwrap_or("");
                return Completions {
                    start: 0,
                    end: head_end,
                    candidates: CONSOLE_COMMANDS
                        .iter()
                        .filter_map(|(syntax, what)| {
                            let word = syntax.split_whitespace().next()?;
                            word.starts_with(&typed.to_ascii_lowercase())
                                .then(|| Candidate {
                                    text: word.to_string(),
                                    note: what.to_string(),
                                })
                        })
                        .collect(),
                    separator: " ",
                };
            }
            let head = line.get(1..head_end).unwrap_or("").to_ascii_lowercase();
            let offset = line.get(head_end..).map_or(line.len(), |rest| {
                head_end + (rest.len() - rest.trim_start().len())
            });
            return match (head.as_str(), view.session) {
                ("axis" | "clear", Some(session)) => {
                    let typed = line.get(offset..cursor).unwrap_or("");
                    Completions {
                        start: offset,
                        end: line.len(),
                        candidates: session
                            .axes
                            .iter()
                            .filter(|a| a.number.to_string().starts_with(typed))
                            .map(|a| Candidate {
                                text: a.number.to_string(),
                                note: a.name.to_string(),
                            })
                            .collect(),
                        separator: "",
                    }
                }
                ("sim-input", _) => {
                    let typed = line.get(offset..cursor).unwrap_or("").to_ascii_uppercase();
                    Completions {
                        start: offset,
                        end: line.len(),
                        candidates: sim_input_names(self.family(view))
                            .into_iter()
                            .filter(|name| name.starts_with(&typed))
                            .map(|name| Candidate {
                                text: format!("{name}="),
                                note: String::new(),
                            })
                            .collect(),
                        separator: "",
                    }
                }
                // `:help SAP 4`, `:expect GAP 8, 0 == 1`: the console line
                // inside.
                ("help" | "expect" | "wait-until", _) if cursor >= offset => {
                    let Some(family) = self.family(view) else {
                        return Completions::default();
                    };
                    let inner = line.get(offset..).unwrap_or("");
                    let inner_line = inner.split("==").next().unwrap_or(inner);
                    if cursor - offset > inner_line.len() {
                        return Completions::default();
                    }
                    let mut c = family.console.complete(inner_line, cursor - offset);
                    c.start += offset;
                    c.end += offset;
                    c
                }
                _ => Completions::default(),
            };
        }
        match self.family(view) {
            Some(family) => family.console.complete(line, cursor),
            None => Completions::default(),
        }
    }
}

/// The simulator of `family` (the one built-in simulator speaking it).
fn simulator_of(family: Option<&'static Family>) -> Option<&'static crate::sim::SimKind> {
    crate::families::simulators_of(family?).first()
}

/// The input names `:sim-input` completes: those of the simulator of the
/// family in use (the settings themselves are the simulator's to read).
fn sim_input_names(family: Option<&'static Family>) -> Vec<String> {
    simulator_of(family).map_or_else(Vec::new, |kind| (kind.input_names)())
}

/// One line per kind of input of that simulator, for `:help :sim-input`.
fn sim_input_help(family: Option<&'static Family>) -> Vec<String> {
    simulator_of(family).map_or_else(Vec::new, |kind| (kind.input_help)())
}

/// The longest start all candidates share (case-insensitive), in the
/// first candidate's spelling.
fn common_prefix(candidates: &[Candidate]) -> String {
    let Some(first) = candidates.first() else {
        return String::new();
    };
    let mut len = first.text.len();
    for c in candidates.iter().skip(1) {
        len = first
            .text
            .char_indices()
            .zip(c.text.chars())
            .take_while(|((_, a), b)| a.eq_ignore_ascii_case(b))
            .map(|((i, a), _)| i + a.len_utf8())
            .last()
            .unwrap_or(0)
            .min(len);
    }
    first.text.get(..len).unwrap_or("").to_string()
}
