//! Lines the family wants confirmed: what waits for the user's yes, and
//! the keys that give or refuse it; the family's warnings shown with a line.

use super::*;

/// What is sent once the user says yes.
#[derive(Debug)]
pub(super) enum Deferred {
    /// A typed line.
    Line(String),
    /// A checked batch, and what becomes of the axes if it fails.
    Batch {
        batch: Batch,
        policy: Option<StopOnFailure>,
    },
    /// A checked host run.
    Host {
        program: HostStart,
        file: String,
        policy: Option<StopOnFailure>,
    },
}

/// A question before sending: why each line needs the user's yes.
#[derive(Debug)]
pub(super) struct Confirming {
    pub(super) then: Deferred,
    pub(super) reasons: Vec<String>,
}

impl CommandPane {
    /// The family's warnings about a line about to be sent, with what the
    /// session knows of the settings written before.
    pub(super) fn say_warnings(&mut self, session: &Snapshot, line: &PreparedLine) {
        for warning in session.family.console.warnings(line, &session.settings) {
            self.say(Role::Warning, format!("  warning: {warning}"));
        }
    }

    /// Hold `then` until the user says yes (or no).
    pub(super) fn ask(&mut self, then: Deferred, reasons: Vec<String>) -> Outcome {
        self.confirming = Some(Confirming { then, reasons });
        Outcome::redraw()
    }

    /// A key while a question is open: y sends, n or the cancel key
    /// drops it; other keys go to the app (the focus keys still work).
    pub(super) fn confirm_key(&mut self, key: &KeyEvent, view: &View) -> Outcome {
        let yes = matches!(key.code, KeyCode::Char('y' | 'Y'));
        let no = matches!(key.code, KeyCode::Char('n' | 'N'))
            || view.keymap.action_for(Context::Command, key) == Some(Action::Cancel);
        if !yes && !no {
            return Outcome::Ignored;
        }
        let Some(Confirming { then, .. }) = self.confirming.take() else {
            return Outcome::Ignored;
        };
        if no {
            let what = match &then {
                Deferred::Line(line) => format!("  not sent: {line}"),
                Deferred::Batch { batch, .. } => format!("{}: not run, nothing sent", batch.name()),
                Deferred::Host { file, .. } => format!("{file}: not run, nothing sent"),
            };
            self.say(Role::Warning, what);
            return Outcome::redraw();
        }
        if view.session.is_none() {
            return self.fail(not_connected());
        }
        match then {
            Deferred::Line(line) => self.send_typed(line),
            Deferred::Batch { batch, policy } => {
                self.run_policy = policy;
                self.run_batch(batch, view)
            }
            Deferred::Host {
                program,
                file,
                policy,
            } => {
                self.run_policy = policy;
                self.begin_host_run(program, &file, view)
            }
        }
    }
}
