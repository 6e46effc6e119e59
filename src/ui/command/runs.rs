//! Runs started from the command pane: batch files (`:run`) and host runs
//! of a program tool (`:run-ascript`, `:run-macro`), and how each ends.

use super::*;

impl CommandPane {
    /// Start a run (`:run`, `:run-ascript`) whose end, if it fails or is
    /// cancelled, goes to the session under `policy`. Typed directives
    /// (`:expect` alone) have none: a check typed by hand stops nothing.
    pub(super) fn with_run_policy(
        &mut self,
        policy: StopOnFailure,
        start: impl FnOnce(&mut CommandPane) -> Outcome,
    ) -> Outcome {
        if self.batch.is_some() || self.host.is_some() {
            // Refused, with its message: the run going keeps its policy.
            return start(self);
        }
        self.run_policy = Some(policy);
        let outcome = start(self);
        if self.batch.is_none() && self.host.is_none() {
            // Not started, or over already (its end was asked for).
            self.run_policy = None;
        }
        outcome
    }

    /// The request that ends the run going, if it has a policy.
    pub(super) fn end_run(&mut self, ending: RunEnding) -> Option<Request> {
        let policy = self.run_policy.take()?;
        (ending != RunEnding::Completed).then_some(Request::EndRun { ending, policy })
    }

    /// `:run-ascript FILE [N…]`, `:run-macro FILE`: check the whole file,
    /// then run it from the host, as the connected family's program tool
    /// whose command it is offers it ([`crate::protocol::program::HostRun`]).
    pub(super) fn start_host_run(&mut self, command: &str, rest: &str, view: &View) -> Outcome {
        if self.batch.is_some() || self.host.is_some() {
            return self.fail("a batch or a host run is going: wait for it, or stop it (Esc)");
        }
        let Some(session) = view.session else {
            return self.fail(not_connected());
        };
        let Some(tool) = session
            .family
            .console
            .program()
            .filter(|tool| tool.runs_from_host() && tool.host_command() == Some(command))
        else {
            return self.fail(no_host_run(session.family, command));
        };
        // Trailing numbers are the PRG blocks to start.
        let mut words: Vec<&str> = rest.split_whitespace().collect();
        let mut start = Vec::new();
        while words.len() > 1 {
            match words.last().and_then(|w| w.parse::<u8>().ok()) {
                Some(n) => {
                    start.insert(0, n);
                    words.pop();
                }
                None => break,
            }
        }
        let file = words.join(" ");
        if file.is_empty() {
            return self.fail(format!(
                ":{command} needs a file name (and the programs to start, if not all)"
            ));
        }
        let text = match crate::files::read_text(&file) {
            Ok(text) => text,
            Err(e) => return self.fail(format!("cannot read {file}: {e}")),
        };
        let chosen = (!start.is_empty()).then_some(start.as_slice());
        let program = match tool.host_run(&file, &text, chosen) {
            Some(Ok(program)) => program,
            Some(Err(problems)) => {
                for problem in problems {
                    self.say(Role::Error, problem);
                }
                return self.fail(format!("{file}: nothing was sent"));
            }
            None => return self.fail(no_host_run(session.family, command)),
        };
        for warning in &program.warnings {
            self.say(Role::Warning, warning.clone());
        }
        if !program.confirm.is_empty() {
            let reasons = program.confirm.clone();
            let policy = self.run_policy;
            return self.ask(
                Deferred::Host {
                    program,
                    file,
                    policy,
                },
                reasons,
            );
        }
        self.begin_host_run(program, &file, view)
    }

    /// Run a checked program from the host.
    pub(super) fn begin_host_run(
        &mut self,
        program: HostStart,
        file: &str,
        view: &View,
    ) -> Outcome {
        self.say(
            Role::Accent,
            format!(
                "running {file} from the host: {} ({} stops it, {} stops everything)",
                program.started,
                key_label(view.keymap, Context::Command, Action::Cancel),
                key_label(view.keymap, Context::Global, Action::EmergencyStop),
            ),
        );
        let (run, update) = ConsoleHostRun::start(program, &mut self.next_tag);
        self.host = Some(run);
        self.host_update(update)
    }

    /// Show what the host run said, pass on its requests.
    pub(super) fn host_update(&mut self, update: HostUpdate) -> Outcome {
        for (role, text) in update.said {
            self.say(role, text);
        }
        let mut requests = update.requests;
        if let Some(end) = update.ended {
            self.host = None;
            requests.extend(self.end_run(RunEnding::from_success(end.ok)));
        }
        Outcome::Handled(requests)
    }

    /// Stop the host run, if one goes: nothing more of it is sent.
    pub(super) fn stop_host_run(&mut self) -> Option<String> {
        self.host.take().map(|run| run.name().to_string())
    }

    pub(super) fn start_batch(&mut self, name: &str, text: &str, view: &View) -> Outcome {
        if self.host.is_some() {
            return self.fail("a host run is going: wait for it, or stop it (Esc)");
        }
        if self.batch.is_some() {
            return self.fail("a batch is running: wait for it, or cancel it (Esc)");
        }
        let Some(session) = view.session else {
            return self.fail(not_connected());
        };
        match Batch::check(name, text, session.family, session.address) {
            Err(problems) => {
                for problem in problems {
                    self.say(Role::Error, problem);
                }
                self.fail(format!("{name}: nothing was sent"))
            }
            Ok(batch) => {
                if !batch.confirmations().is_empty() {
                    let reasons = batch.confirmations().to_vec();
                    let policy = self.run_policy;
                    return self.ask(Deferred::Batch { batch, policy }, reasons);
                }
                self.run_batch(batch, view)
            }
        }
    }

    /// Run a checked batch.
    pub(super) fn run_batch(&mut self, batch: Batch, view: &View) -> Outcome {
        if batch.len() > 1 {
            self.say(
                Role::Muted,
                format!("{}: {} steps", batch.name(), batch.len()),
            );
        }
        self.batch = Some(batch);
        let steps = self.batch.as_mut().map(Batch::advance).unwrap_or_default();
        self.batch_steps(steps, view)
    }

    /// Carry out what the batch asks for next.
    pub(super) fn batch_steps(&mut self, steps: Vec<BatchStep>, view: &View) -> Outcome {
        let mut requests = Vec::new();
        for step in steps {
            match step {
                BatchStep::Send(line) => {
                    if let Some(session) = view.session
                        && let Ok(prepared) = session.family.console.prepare(&line, session.address)
                    {
                        self.say_warnings(session, &prepared);
                    }
                    let tag = self.tag(Origin::Batch);
                    requests.push(Request::Send {
                        lines: vec![line],
                        tag,
                    });
                }
                BatchStep::Wake(after) => {
                    self.next_tag += 1;
                    self.batch_wake = Some(self.next_tag);
                    requests.push(Request::WakeAfter {
                        after,
                        tag: self.next_tag,
                    });
                }
                BatchStep::Echo(text) => self.say(Role::Normal, text),
                BatchStep::Failed(message) => {
                    self.batch = None;
                    self.say(Role::Error, message);
                    requests.extend(self.end_run(RunEnding::Failed));
                }
                BatchStep::Done => {
                    let Some(batch) = self.batch.take() else {
                        continue;
                    };
                    if batch.len() > 1 {
                        self.say(Role::Ok, "batch done");
                    }
                    // A run (not a typed directive) that may have left an
                    // axis moving: the session looks, as `axterm run` does.
                    if let Some(policy) = self.run_policy.take()
                        && batch.at_the_end() != AtTheEnd::Nothing
                    {
                        requests.push(Request::CheckRunEnd {
                            check: batch.at_the_end(),
                            policy,
                        });
                    }
                }
            }
        }
        Outcome::Handled(requests)
    }
}

/// Whether `command` runs some family's programs from the host
/// ([`crate::protocol::program::ProgramTool::host_command`]).
pub(super) fn is_host_command(command: &str) -> bool {
    FAMILIES
        .iter()
        .filter_map(|f| f.console.program())
        .any(|t| t.runs_from_host() && t.host_command() == Some(command))
}

/// Why `:COMMAND` runs nothing on a module of `family`: whose programs it
/// runs from the host.
fn no_host_run(family: &Family, command: &str) -> String {
    let offered: Vec<String> = FAMILIES
        .iter()
        .filter_map(|f| {
            let tool = f
                .console
                .program()
                .filter(|t| t.runs_from_host() && t.host_command() == Some(command))?;
            Some(format!("{} ({})", tool.name(), f.name))
        })
        .collect();
    format!(
        ":{command} runs {} from the host; this module speaks {}",
        offered.join(", "),
        family.name
    )
}
