//! `:programs` and `:tasks`: what the controller keeps besides the program
//! in the editor and what it runs in the background, through the family's
//! [`ProgramStore`] (MCCL: macros listed with `TM-1`, one deleted by `RM`
//! and the others defined again, background tasks listed with `ID7` and
//! ended with `ET`). The pane sends the store's lines and hands their
//! answers back here; this keeps where a job stands and what to say.

use crate::protocol::Family;
use crate::protocol::program::{ProgramStore, StoredProgram};
use crate::session::{LineResult, SessionError};
use crate::ui::theme::Role;

/// A job of the store under way.
#[derive(Debug, Clone)]
pub(super) enum StoreJob {
    /// The listing asked for, to show.
    List,
    /// The listing asked for, to delete program `number` from.
    ListToDelete(i64),
    /// The deleting lines sent: `left` answers to come, then the listing
    /// must hold `kept`.
    Deleting {
        number: i64,
        kept: Vec<StoredProgram>,
        left: usize,
    },
    /// The listing asked for after a deletion.
    Check {
        number: i64,
        kept: Vec<StoredProgram>,
    },
    /// The running programs asked for.
    Running,
    /// A running program being stopped.
    Stopping(i64),
}

/// What the pane does next for a job.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum StoreStep {
    /// Say this.
    Say(Role, String),
    /// Send these lines, the answers back under the job.
    Send(Vec<String>),
}

/// The family's store, if it has one.
pub(super) fn store_of(
    family: Option<&'static Family>,
) -> Result<&'static dyn ProgramStore, String> {
    let family = family.ok_or("not connected: give :connect first")?;
    family
        .console
        .program()
        .and_then(|tool| tool.store())
        .ok_or_else(|| format!("{} controllers store no programs to list here", family.name))
}

/// Start `:programs …` or `:tasks …` (`command` is the name): the job and
/// the lines to send first.
pub(super) fn start(
    store: &dyn ProgramStore,
    command: &str,
    rest: &str,
) -> Result<(StoreJob, Vec<String>), String> {
    let mut words = rest.split_whitespace();
    let number = |word: Option<&str>, what: &str| -> Result<i64, String> {
        word.and_then(|w| w.parse().ok())
            .ok_or_else(|| format!(":{command} {what} needs a number"))
    };
    match (command, words.next()) {
        ("programs", None) => Ok((StoreJob::List, vec![store.list_line()])),
        ("programs", Some("delete")) => {
            let n = number(words.next(), "delete")?;
            Ok((StoreJob::ListToDelete(n), vec![store.list_line()]))
        }
        ("tasks", None) => match store.running_line() {
            Some(line) => Ok((StoreJob::Running, vec![line])),
            None => Err(format!("the controller lists no {}s", store.running_noun())),
        },
        ("tasks", Some("stop")) => {
            let id = number(words.next(), "stop")?;
            Ok((StoreJob::Stopping(id), vec![store.stop_line(id)]))
        }
        (_, Some(word)) => Err(format!(
            "`:{command} {word}`: give :{command}{} (`:help` lists them)",
            if command == "programs" {
                " or :programs delete N"
            } else {
                " or :tasks stop ID"
            }
        )),
        (_, None) => Err(format!("unknown console command `:{command}`")),
    }
}

/// One answer to the job's lines: the steps it leads to, and the job that
/// goes on (`None`: it is over).
pub(super) fn on_reply(
    store: &dyn ProgramStore,
    job: StoreJob,
    result: &Result<LineResult, SessionError>,
) -> (Vec<StoreStep>, Option<StoreJob>) {
    let noun = store.stored_noun();
    let failed = |what: &str, e: &SessionError| {
        (
            vec![StoreStep::Say(Role::Error, format!("{what}: {e}"))],
            None,
        )
    };
    match job {
        StoreJob::List => match result {
            Ok(r) => {
                let list = store.stored(&r.value);
                let mut steps = vec![StoreStep::Say(
                    Role::Accent,
                    format!("{} {noun}(s) stored", list.len()),
                )];
                steps.extend(list.into_iter().map(|p| {
                    StoreStep::Say(Role::Normal, format!("  {noun} {}: {}", p.number, p.text))
                }));
                (steps, None)
            }
            Err(e) => failed("listing failed", e),
        },
        StoreJob::ListToDelete(number) => match result {
            Ok(r) => match store.delete(&store.stored(&r.value), number) {
                Ok(deletion) => {
                    let left = deletion.lines.len();
                    (
                        vec![
                            StoreStep::Say(Role::Warning, deletion.warning),
                            StoreStep::Send(deletion.lines),
                        ],
                        Some(StoreJob::Deleting {
                            number,
                            kept: deletion.kept,
                            left,
                        }),
                    )
                }
                Err(why) => (vec![StoreStep::Say(Role::Error, why.to_string())], None),
            },
            Err(e) => failed("listing failed, nothing was deleted", e),
        },
        StoreJob::Deleting { number, kept, left } => match result {
            Err(e) => failed(
                &format!("deleting {noun} {number} stopped at `{}`", e.line()),
                e,
            ),
            Ok(_) if left > 1 => (
                Vec::new(),
                Some(StoreJob::Deleting {
                    number,
                    kept,
                    left: left - 1,
                }),
            ),
            Ok(_) => (
                vec![StoreStep::Send(vec![store.list_line()])],
                Some(StoreJob::Check { number, kept }),
            ),
        },
        StoreJob::Check { number, kept } => match result {
            Ok(r) => match store.compare(&kept, &store.stored(&r.value)) {
                Ok(()) => {
                    let numbers: Vec<String> = kept.iter().map(|p| p.number.to_string()).collect();
                    (
                        vec![StoreStep::Say(
                            Role::Ok,
                            format!(
                                "{noun} {number} deleted; the listing holds the others as they \
                                 were ({})",
                                if numbers.is_empty() {
                                    "none".to_string()
                                } else {
                                    numbers.join(", ")
                                }
                            ),
                        )],
                        None,
                    )
                }
                Err(why) => (
                    vec![StoreStep::Say(
                        Role::Error,
                        format!("after deleting {noun} {number}: {why}"),
                    )],
                    None,
                ),
            },
            Err(e) => failed("the listing after the deletion failed", e),
        },
        StoreJob::Running => match result {
            Ok(r) => {
                let ids = store.running(&r.value);
                let text = if ids.is_empty() {
                    format!("no {} running", store.running_noun())
                } else {
                    let ids: Vec<String> = ids.iter().map(i64::to_string).collect();
                    format!(
                        "{} IDs: {} (:tasks stop ID stops one)",
                        store.running_noun(),
                        ids.join(", ")
                    )
                };
                (vec![StoreStep::Say(Role::Accent, text)], None)
            }
            Err(e) => failed("listing failed", e),
        },
        StoreJob::Stopping(id) => match result {
            Ok(r) => (
                vec![StoreStep::Say(
                    Role::Ok,
                    format!("{} {id}: {} → {}", store.running_noun(), r.line, r.value),
                )],
                None,
            ),
            Err(e) => failed(&format!("stopping {} {id}", store.running_noun()), e),
        },
    }
}
