//! `:record-macro FILE | off`: the lines sent from the command pane kept
//! as a program of the connected family's language.

use super::*;

/// A recording of the lines sent (SQPack's "Record Macro", §5.4.6).
#[derive(Debug)]
pub(super) struct Recording {
    pub(super) path: PathBuf,
    /// The language's lines so far, written to the file after each.
    pub(super) lines: Vec<String>,
    pub(super) tool: &'static dyn ProgramTool,
}

impl CommandPane {
    /// `:record-macro FILE | off`: record every line sent from here (typed
    /// or from a batch, once sent) as the connected family's program tool
    /// writes it, into FILE, rewritten after each line so that nothing
    /// recorded is lost; `off` ends it. An existing file is not
    /// overwritten.
    pub(super) fn record_command(&mut self, rest: &str, view: &View) -> Outcome {
        if rest.eq_ignore_ascii_case("off") {
            return match self.recording.take() {
                Some(recording) => {
                    self.say(
                        Role::Ok,
                        format!(
                            "recording ended: {} line(s) in {}",
                            recording.lines.len(),
                            recording.path.display()
                        ),
                    );
                    Outcome::redraw()
                }
                None => self.fail("nothing is being recorded"),
            };
        }
        if rest.is_empty() {
            return self.fail(":record-macro needs a file name (or off)");
        }
        let Some(session) = view.session else {
            return self.fail(not_connected());
        };
        // The tool records if it can say the family's own identity query.
        let probe = session.family.console.identify(session.address).bytes;
        let Some(tool) = session
            .family
            .console
            .program()
            .filter(|t| t.record(&probe).is_some())
        else {
            return self.fail(format!(
                "the {} family's program language cannot record the lines sent",
                session.family.name
            ));
        };
        let path = PathBuf::from(rest);
        if path.exists() {
            return self.fail(format!(
                "{} exists: give a new file name (nothing is overwritten)",
                path.display()
            ));
        }
        if let Err(e) = crate::files::write_atomically(&path, b"") {
            return self.fail(format!("cannot write {}: {e}", path.display()));
        }
        if let Some(before) = self.recording.take() {
            self.say(
                Role::Muted,
                format!(
                    "recording to {} ended: {} line(s)",
                    before.path.display(),
                    before.lines.len()
                ),
            );
        }
        self.say(
            Role::Accent,
            format!(
                "recording every line sent from here to {} as {} ({} off ends it)",
                path.display(),
                tool.name(),
                ":record-macro"
            ),
        );
        self.recording = Some(Recording {
            path,
            lines: Vec::new(),
            tool,
        });
        Outcome::redraw()
    }

    /// Add a line that was sent to the recording, if one goes.
    pub(super) fn record_sent(&mut self, request: &[u8]) {
        let Some(recording) = self.recording.as_mut() else {
            return;
        };
        let Some(line) = recording.tool.record(request) else {
            return;
        };
        recording.lines.push(line);
        let mut text = recording.lines.join("\n");
        text.push('\n');
        if let Err(e) = crate::files::write_atomically(&recording.path, text.as_bytes()) {
            let path = recording.path.display().to_string();
            self.recording = None;
            self.say(
                Role::Error,
                format!("recording stopped: cannot write {path}: {e}"),
            );
        }
    }
}
