//! `:run FILE` and the run directives typed one at a time (`:expect`,
//! `:wait-until`, `:sleep`, `:echo`) inside the console: the batch syntax
//! of `axterm run` ([`crate::script`]), checked whole before anything is
//! sent, then run step by step through the pane's requests.

use std::time::Duration;

use tokio::time::Instant;

use crate::protocol::Family;
use crate::protocol::console::{FamilyConsole, PreparedLine, ReplyValue};
use crate::script::{Action, Step, WAIT_INTERVAL, check_script, result_matches};
use crate::session::run_end::AtTheEnd;
use crate::session::run_end::{NO_STOP_FLAG, StopOnFailure};
use crate::session::{LineResult, SessionError, confirms_reads};

/// The options of `:run` and `:run-ascript` before the file name: only
/// [`NO_STOP_FLAG`], as `axterm run` takes it. What a run that fails or is
/// cancelled does to the axes, and the rest of the arguments.
pub fn run_options(rest: &str) -> (StopOnFailure, &str) {
    let rest = rest.trim();
    match rest.strip_prefix(NO_STOP_FLAG) {
        Some(after) if after.is_empty() || after.starts_with(char::is_whitespace) => {
            (StopOnFailure::Leave, after.trim_start())
        }
        _ => (StopOnFailure::Stop, rest),
    }
}

/// Why the console's `:run` refuses `:params`: applying a parameter file
/// is `axterm run`'s; the console has the parameter pane's import.
const PARAMS_IN_RUN_ONLY: &str = ":params applies a parameter file in `axterm run` only; in \
     the console use the parameter pane's import";

/// The tool directives run only in `axterm run`: the console's own panes
/// (bring-up's wiring check, the tuning pane) run them with their screens,
/// and a batch stepping one line at a time has no place for a tool that
/// holds the line for seconds.
const TOOL_IN_RUN_ONLY: &str = "runs in `axterm run` only; in the console use the bring-up      pane's wiring check or the tuning pane";

/// Why `action` cannot run in the console's `:run`, if it cannot.
fn run_only(action: &Action) -> Option<String> {
    let tool = match action {
        Action::ApplyParams { .. } => return Some(PARAMS_IN_RUN_ONLY.to_string()),
        Action::Wiring(_) => ":wiring",
        Action::TuneStep(_) => ":tune-step",
        Action::TuneStallguard(_) => ":tune-stallguard",
        _ => return None,
    };
    Some(format!("{tool} {TOOL_IN_RUN_ONLY}"))
}

/// What the batch needs done next.
#[derive(Debug, Clone, PartialEq)]
pub enum BatchStep {
    /// Send this line; call [`Batch::on_reply`] with its answer.
    Send(String),
    /// Call [`Batch::on_wake`] after this long.
    Wake(Duration),
    /// Show this text.
    Echo(String),
    /// A step failed: show this, the batch is over.
    Failed(String),
    /// Every step done.
    Done,
}

/// A checked batch being run.
#[derive(Debug)]
pub struct Batch {
    /// "FILE" or the typed directive, for messages.
    name: String,
    steps: Vec<Step>,
    next: usize,
    /// The `:wait-until` in progress gives up at this instant.
    deadline: Option<Instant>,
    /// Reads the `:wait-until` in progress has made.
    reads: u32,
    /// The lines the family wants confirmed, as `NAME:LINE: `line`: why`.
    confirm: Vec<String>,
    /// Each step's line as prepared, for a second read.
    prepared: Vec<Option<PreparedLine>>,
    console: Console,
    /// The first of two reads of an `:expect` or `:wait-until` whose
    /// value needs a second that agrees ([`confirms_reads`]).
    first_read: Option<ReplyValue>,
    /// What the end of the batch checks of the axes, once it completed.
    at_the_end: AtTheEnd,
}

/// The family's console, for judging a second read.
struct Console(&'static dyn FamilyConsole);

impl std::fmt::Debug for Console {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Console")
    }
}

impl Batch {
    /// Parse and check a file's text: every console line is validated for
    /// `family` at `address` first, every problem listed as `NAME:LINE:
    /// message`. Nothing is sent when anything is wrong.
    pub fn check(
        name: &str,
        text: &str,
        family: &Family,
        address: u8,
    ) -> Result<Batch, Vec<String>> {
        let checked = check_script(name, text, family, address)?;
        // Refused with the file, before anything is sent.
        let only_in_run: Vec<String> = checked
            .iter()
            .filter_map(|c| {
                run_only(&c.step.action).map(|why| format!("{name}:{}: {why}", c.step.line_number))
            })
            .collect();
        if !only_in_run.is_empty() {
            return Err(only_in_run);
        }
        let confirm = checked
            .iter()
            .filter_map(|c| {
                let line = c.line.as_ref()?;
                let why = family.console.confirmation(line)?;
                Some(format!(
                    "{name}:{}: `{}`: {why}",
                    c.step.line_number, line.canonical
                ))
            })
            .collect();
        let at_the_end = AtTheEnd::of_script(&checked);
        let (steps, prepared) = checked
            .into_iter()
            .map(|checked| (checked.step, checked.line))
            .unzip();
        Ok(Batch {
            name: name.to_string(),
            steps,
            next: 0,
            deadline: None,
            reads: 0,
            confirm,
            prepared,
            console: Console(family.console),
            first_read: None,
            at_the_end,
        })
    }

    /// What the end of the batch checks of the axes once every step is
    /// done: whether an axis may be left moving, and whether the file
    /// means it ([`crate::script::LEAVE_MOVING`]).
    pub fn at_the_end(&self) -> AtTheEnd {
        self.at_the_end
    }

    /// The file's name, or the directive typed.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The lines the family wants confirmed before they are sent, as
    /// `NAME:LINE: `line`: why`.
    pub fn confirmations(&self) -> &[String] {
        &self.confirm
    }

    /// How many steps the batch has.
    pub fn len(&self) -> usize {
        self.steps.len()
    }

    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }

    fn at(&self) -> String {
        match self.steps.get(self.next) {
            Some(step) if self.steps.len() > 1 || self.name.contains('.') => {
                format!("{}:{}: ", self.name, step.line_number)
            }
            _ => String::new(),
        }
    }

    /// Start the current step (the first, or the one after the last
    /// answered), running echoes straight through.
    pub fn advance(&mut self) -> Vec<BatchStep> {
        let mut out = Vec::new();
        loop {
            let Some(step) = self.steps.get(self.next) else {
                out.push(BatchStep::Done);
                return out;
            };
            match &step.action {
                Action::Echo(text) => {
                    out.push(BatchStep::Echo(text.clone()));
                    self.next += 1;
                }
                // Said of the file as a whole: nothing to do where it stands.
                Action::LeaveMoving => self.next += 1,
                // Refused by `Batch::check`.
                Action::ApplyParams { .. }
                | Action::Wiring(_)
                | Action::TuneStep(_)
                | Action::TuneStallguard(_) => {
                    let why = run_only(&step.action).unwrap_or_default();
                    out.push(BatchStep::Failed(format!("{}{why}", self.at())));
                    return out;
                }
                Action::Line(line) | Action::Expect { line, .. } => {
                    out.push(BatchStep::Send(line.clone()));
                    return out;
                }
                Action::WaitUntil { line, timeout, .. } => {
                    self.deadline = Some(Instant::now() + *timeout);
                    self.reads = 0;
                    out.push(BatchStep::Send(line.clone()));
                    return out;
                }
                Action::Sleep(duration) => {
                    out.push(BatchStep::Wake(*duration));
                    return out;
                }
            }
        }
    }

    /// While a `:wait-until` reads: one line saying how it stands, which
    /// replaces the one of its previous read (its reads come every 20 ms;
    /// a line each would bury everything else). `None` for other steps and
    /// for a read that failed, which is shown in full. Call it with each
    /// answer before [`Batch::on_reply`].
    pub fn wait_progress(&mut self, result: &Result<LineResult, SessionError>) -> Option<String> {
        let Some(Action::WaitUntil { line, value, .. }) =
            self.steps.get(self.next).map(|s| &s.action)
        else {
            return None;
        };
        let got = result.as_ref().ok()?.value.to_string();
        self.reads = self.reads.saturating_add(1);
        let reads = match self.reads {
            1 => "1 read".to_string(),
            n => format!("{n} reads"),
        };
        Some(format!(":wait-until {line} == {value}: {got} ({reads})"))
    }

    /// The answer to the line of the current step.
    pub fn on_reply(&mut self, result: &Result<LineResult, SessionError>) -> Vec<BatchStep> {
        let at = self.at();
        let Some(step) = self.steps.get(self.next) else {
            return vec![BatchStep::Done];
        };
        let result = match result {
            Ok(result) => result,
            Err(e) => return vec![BatchStep::Failed(format!("{at}{e}"))],
        };
        let mut got = result.value.to_string();
        let judged = matches!(
            step.action,
            Action::Expect { .. } | Action::WaitUntil { .. }
        );
        let prepared = self.prepared.get(self.next).and_then(Option::as_ref);
        if judged && let Some(prepared) = prepared.filter(|l| confirms_reads(self.console.0, l)) {
            // No check over the answer: a value that looks good is read
            // once more, and good only if the second read is good too.
            match self.first_read.take() {
                Some(first) => {
                    got = (self.console.0)
                        .as_if_unread(prepared, &first, &result.value)
                        .to_string();
                }
                None => {
                    if let Action::Expect { line, value } | Action::WaitUntil { line, value, .. } =
                        &step.action
                        && result_matches(&got, value)
                    {
                        self.first_read = Some(result.value.clone());
                        return vec![BatchStep::Send(line.clone())];
                    }
                }
            }
        }
        match &step.action {
            Action::Expect { value, .. } if !result_matches(&got, value) => {
                return vec![BatchStep::Failed(format!(
                    "{at}expected {} == {value}, got {got}",
                    result.line
                ))];
            }
            Action::WaitUntil { value, timeout, .. } if !result_matches(&got, value) => {
                let over = self.deadline.is_none_or(|d| Instant::now() >= d);
                if over {
                    return vec![BatchStep::Failed(format!(
                        "{at}{} did not become {value} within {} ms (last {got})",
                        result.line,
                        timeout.as_millis()
                    ))];
                }
                return vec![BatchStep::Wake(WAIT_INTERVAL)];
            }
            _ => {}
        }
        self.deadline = None;
        self.next += 1;
        self.advance()
    }

    /// A wake-up asked for by the current step.
    pub fn on_wake(&mut self) -> Vec<BatchStep> {
        match self.steps.get(self.next).map(|s| &s.action) {
            Some(Action::Sleep(_)) => {
                self.next += 1;
                self.advance()
            }
            // Read again.
            Some(Action::WaitUntil { line, .. }) => vec![BatchStep::Send(line.clone())],
            _ => Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::find_family;
    use crate::protocol::console::ReplyValue;

    fn tmcl() -> &'static Family {
        find_family("tmcl").expect("tmcl")
    }

    fn reply(value: ReplyValue) -> Result<LineResult, SessionError> {
        Ok(LineResult {
            line: "GAP 8, 0".into(),
            request: Vec::new(),
            reply: Vec::new(),
            status: Some(100),
            value,
            elapsed: Duration::ZERO,
            attempts: 1,
        })
    }

    /// Issue 19: the console's `:expect` and `:wait-until` call a value
    /// read from a family without a checksum good only when a second read
    /// agrees; TMCL's checksum vouches for one.
    #[test]
    fn an_unchecked_value_is_read_twice_before_it_is_good() {
        let cmd4cr = find_family("cmd4cr").expect("cmd4cr");
        let mut batch = Batch::check("f.txt", ":expect PX == 5\n", cmd4cr, 1).expect("valid");
        assert_eq!(batch.advance(), [BatchStep::Send("PX".into())]);
        let again = batch.on_reply(&reply(ReplyValue::Number(5)));
        assert_eq!(again, [BatchStep::Send("PX".into())], "read once more");
        let after = batch.on_reply(&reply(ReplyValue::Number(-2080262363)));
        assert!(
            matches!(after.as_slice(), [BatchStep::Failed(_)]),
            "{after:?}"
        );

        let mut batch = Batch::check("f.txt", ":expect PX == 5\n", cmd4cr, 1).expect("valid");
        batch.advance();
        batch.on_reply(&reply(ReplyValue::Number(5)));
        assert_eq!(
            batch.on_reply(&reply(ReplyValue::Number(5))),
            [BatchStep::Done]
        );

        let mut batch = Batch::check("f.txt", ":expect GAP 8, 0 == 5\n", tmcl(), 1).expect("valid");
        batch.advance();
        assert_eq!(
            batch.on_reply(&reply(ReplyValue::Number(5))),
            [BatchStep::Done]
        );
    }

    #[test]
    fn run_options_take_the_no_stop_flag_before_the_file() {
        assert_eq!(run_options(" f.txt "), (StopOnFailure::Stop, "f.txt"));
        assert_eq!(
            run_options("--no-stop-on-failure  my file.txt"),
            (StopOnFailure::Leave, "my file.txt")
        );
        assert_eq!(
            run_options("--no-stop-on-failure"),
            (StopOnFailure::Leave, "")
        );
        // A file whose name only starts like it.
        assert_eq!(
            run_options("--no-stop-on-failure.txt"),
            (StopOnFailure::Stop, "--no-stop-on-failure.txt")
        );
    }

    #[test]
    fn a_file_that_applies_a_parameter_file_is_refused_before_anything_is_sent() {
        let problems =
            Batch::check("f.txt", "GAP 4, 0\n:params axis.toml\n", tmcl(), 1).expect_err("refused");
        assert_eq!(problems, [format!("f.txt:2: {PARAMS_IN_RUN_ONLY}")]);
    }

    #[test]
    fn the_tool_directives_are_refused_in_the_console_before_anything_is_sent() {
        let text = "GAP 4, 0\n:wiring --speed 2047\n:tune-stallguard --from 200 --to 1000\n";
        let problems = Batch::check("f.txt", text, tmcl(), 1).expect_err("refused");
        assert_eq!(
            problems,
            [
                format!("f.txt:2: :wiring {TOOL_IN_RUN_ONLY}"),
                format!("f.txt:3: :tune-stallguard {TOOL_IN_RUN_ONLY}"),
            ]
        );
    }

    #[test]
    fn a_file_with_no_line_is_refused_as_axterm_run_refuses_it() {
        for text in ["", "# nothing yet\n\n// still nothing\n"] {
            let problems = Batch::check("empty.txt", text, tmcl(), 1).expect_err("empty");
            assert_eq!(
                problems,
                [
                    "empty.txt: no line to run (the file is empty, or holds only comments and \
                  blank lines)"
                ]
            );
        }
    }

    #[test]
    fn a_file_with_bad_lines_lists_them_all_and_sends_nothing() {
        let problems = Batch::check("f.txt", "GAP 1, 0\nSAP 6, 0, 100000\n:bogus\n", tmcl(), 1)
            .expect_err("bad");
        assert_eq!(problems.len(), 2, "{problems:?}");
        assert!(problems[0].starts_with("f.txt:2: "));
        assert!(problems[1].starts_with("f.txt:3: unknown directive"));
        let problems = Batch::check("f.txt", ":wait-until MVP ABS, 0, 1 == ok\n", tmcl(), 1)
            .expect_err("acts");
        assert!(problems[0].contains("only reads"));
    }

    #[test]
    fn steps_run_in_order_and_an_expect_that_fails_ends_the_batch() {
        let text = ":echo go\nSAP 4, 0, 5\n:sleep 1s\n:expect GAP 4, 0 == 5\nMST 0\n";
        let mut batch = Batch::check("f.txt", text, tmcl(), 1).expect("valid");
        assert_eq!(batch.len(), 5);
        assert_eq!(
            batch.advance(),
            [
                BatchStep::Echo("go".into()),
                BatchStep::Send("SAP 4, 0, 5".into())
            ]
        );
        assert_eq!(
            batch.on_reply(&reply(ReplyValue::None)),
            [BatchStep::Wake(Duration::from_secs(1))]
        );
        assert_eq!(batch.on_wake(), [BatchStep::Send("GAP 4, 0".into())]);
        let failed = batch.on_reply(&reply(ReplyValue::Number(6)));
        assert_eq!(
            failed,
            [BatchStep::Failed(
                "f.txt:4: expected GAP 8, 0 == 5, got 6".into()
            )]
        );
    }

    #[tokio::test(start_paused = true)]
    async fn a_wait_until_tells_how_it_stands_in_one_line_per_read() {
        let mut batch = Batch::check(
            "f.txt",
            "GAP 8, 0\n:wait-until GAP 8, 0 == 1 timeout 1s\n",
            tmcl(),
            1,
        )
        .expect("valid");
        batch.advance();
        // Not a wait: shown as any line is.
        assert_eq!(batch.wait_progress(&reply(ReplyValue::Number(0))), None);
        batch.on_reply(&reply(ReplyValue::Number(0)));
        assert_eq!(
            batch
                .wait_progress(&reply(ReplyValue::Number(0)))
                .as_deref(),
            Some(":wait-until GAP 8, 0 == 1: 0 (1 read)")
        );
        batch.on_reply(&reply(ReplyValue::Number(0)));
        batch.on_wake();
        assert_eq!(
            batch
                .wait_progress(&reply(ReplyValue::Number(1)))
                .as_deref(),
            Some(":wait-until GAP 8, 0 == 1: 1 (2 reads)")
        );
        let failed: Result<LineResult, SessionError> = Err(SessionError::Refused {
            line: "GAP 8, 0".into(),
            message: "no".into(),
        });
        assert_eq!(
            batch.wait_progress(&failed),
            None,
            "an error is shown in full"
        );
    }

    #[tokio::test(start_paused = true)]
    async fn wait_until_reads_again_until_the_value_comes_or_time_is_up() {
        let mut batch = Batch::check(
            ":wait-until",
            ":wait-until GAP 8, 0 == 1 timeout 1s",
            tmcl(),
            1,
        )
        .expect("valid");
        assert_eq!(batch.advance(), [BatchStep::Send("GAP 8, 0".into())]);
        assert_eq!(
            batch.on_reply(&reply(ReplyValue::Number(0))),
            [BatchStep::Wake(WAIT_INTERVAL)]
        );
        assert_eq!(batch.on_wake(), [BatchStep::Send("GAP 8, 0".into())]);
        assert_eq!(
            batch.on_reply(&reply(ReplyValue::Number(1))),
            [BatchStep::Done]
        );

        let mut batch = Batch::check(
            ":wait-until",
            ":wait-until GAP 8, 0 == 1 timeout 1s",
            tmcl(),
            1,
        )
        .expect("valid");
        batch.advance();
        tokio::time::advance(Duration::from_secs(1)).await;
        let steps = batch.on_reply(&reply(ReplyValue::Number(0)));
        assert!(
            matches!(&steps[..], [BatchStep::Failed(m)] if m.contains("did not become 1 within 1000 ms")),
            "{steps:?}"
        );
    }
}
