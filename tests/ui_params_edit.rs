//! The parameter table's edit, confirmed unchanged, on every family: on
//! every editable row of every table, Enter opens the field with the value
//! shown and Enter again writes exactly the value the console was given
//! when it read the row (or, where nothing is known or the family writes
//! no such line, sends nothing and says so). Through the real console and
//! a session on each family's in-process simulator, on tokio's paused
//! clock.

mod ui_support;

use std::collections::HashMap;
use std::sync::Arc;

use axterm::cli::ConnectionArgs;
use axterm::cli::connection::Target;
use axterm::device::LinkState;
use axterm::families::FAMILIES;
use axterm::protocol::parameters::{ParamOp, ParamRow, ParameterSet, Scope};
use axterm::session::params::{ModuleValue, reading};
use axterm::session::{AxisStatus, LineResult, Session, SessionError};
use axterm::ui::app::{App, AppEvent, Effect};
use axterm::ui::pane::Snapshot;
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use ui_support::{console, key, key_with, screen};

async fn open(sim: &str) -> Session {
    let target = Target::resolve(&ConnectionArgs {
        sim: Some(sim.into()),
        ..ConnectionArgs::default()
    })
    .expect("a simulator connection");
    target.open().await.expect("the simulator opens")
}

/// What the console is shown of `session`, `axis` (an index) selected.
fn snapshot(session: &Session, sim: &str, axis: usize) -> Snapshot {
    let axes = session.axes().to_vec();
    Snapshot {
        family: session.family(),
        address: session.address(),
        link_name: format!("sim {sim}"),
        status: vec![AxisStatus::default(); axes.len()],
        axes,
        link: LinkState::Connected {
            link: format!("sim {sim}"),
        },
        identity: None,
        poll: None,
        settings: Arc::new(session.settings().borrow().clone()),
        mechanics: Default::default(),
        axis,
    }
}

/// Every answer the console was given, by line: the last one for each.
type Answers = HashMap<String, Result<LineResult, SessionError>>;

/// Send every line the console asks for through the session, answering
/// it, until it asks for no more; the lines sent, in order. The answers
/// go into `answers`.
async fn serve(
    app: &mut App,
    session: &Session,
    answers: &mut Answers,
    effects: Vec<Effect>,
) -> Vec<String> {
    let mut sent = Vec::new();
    let mut queue = effects;
    while !queue.is_empty() {
        assert!(sent.len() < 100_000, "the console never stops sending");
        let mut next = Vec::new();
        for effect in queue {
            if let Some((pane, tag, lines)) = effect.sends() {
                for line in lines {
                    sent.push(line.clone());
                    let result = session.execute_line(&line).await;
                    answers.insert(line.clone(), result.clone());
                    next.extend(app.handle(AppEvent::Reply {
                        pane,
                        tag,
                        line,
                        result,
                    }));
                }
            }
        }
        queue = next;
    }
    sent
}

/// The value the console was given for `row`: the answer to its read
/// line, or for a row the module cannot read back, what the session
/// wrote.
fn shown(
    session: &Session,
    parameters: &dyn ParameterSet,
    answers: &Answers,
    row: &ParamRow,
) -> Option<i64> {
    if !row.access.read {
        return session.settings().borrow().value(row.scope, row.number);
    }
    let line = parameters.line(row, ParamOp::Read).ok()?;
    match reading(parameters, row, answers.get(&line)?, &|_| None) {
        ModuleValue::Value(v) => Some(v),
        _ => None,
    }
}

/// A family whose module cannot be asked for its settings knows only what
/// was written: write each row's factory value first (each line with the
/// others' factory values), so that its rows have values to edit.
async fn write_defaults(session: &Session, parameters: &dyn ParameterSet) {
    if !parameters.remembers_writes() {
        return;
    }
    for info in session.axes() {
        let tables = parameters.tables(info.number);
        let rows: Vec<&ParamRow> = tables.iter().flat_map(|t| t.rows.iter()).collect();
        let default = |scope: Scope, number: u16| {
            rows.iter()
                .find(|r| r.scope == scope && r.number == number)
                .and_then(|r| r.default)
        };
        for row in &rows {
            let Some(value) = row.default.filter(|_| row.access.write) else {
                continue;
            };
            if let Ok(line) = parameters.line_with(row, ParamOp::Write(value), &default) {
                session
                    .execute_line(&line)
                    .await
                    .unwrap_or_else(|e| panic!("{line}: {e}"));
            }
        }
    }
}

/// Every editable row of every table of every axis of `sim`: Enter, Enter.
async fn unchanged_edits_write_what_was_read(sim: &str) {
    let session = open(sim).await;
    let parameters = session
        .family()
        .console
        .parameters()
        .expect("parameter tables");
    write_defaults(&session, parameters).await;
    let mut app = console();
    app.handle(AppEvent::Snapshot(snapshot(&session, sim, 0)));
    let effects = app.handle(key_with(KeyCode::Char('3'), KeyModifiers::ALT));
    assert_eq!(app.focused(), Some("params"));
    let mut answers = Answers::new();
    serve(&mut app, &session, &mut answers, effects).await;
    let mut edited = 0;
    for (index, info) in session.axes().iter().enumerate() {
        // Another axis: its tables, read afresh.
        app.handle(AppEvent::Snapshot(snapshot(&session, sim, index)));
        let effects = app.handle(key(KeyCode::F(5)));
        serve(&mut app, &session, &mut answers, effects).await;
        let rows: Vec<ParamRow> = parameters
            .tables(info.number)
            .into_iter()
            .flat_map(|t| t.rows)
            .collect();
        for (at, row) in rows.iter().enumerate() {
            if at > 0 {
                app.handle(key(KeyCode::Down));
            }
            if !row.access.write {
                continue;
            }
            let what = format!("{sim} {:?} #{} {}", row.scope, row.number, row.name);
            let before = shown(&session, parameters, &answers, row);
            app.handle(AppEvent::Snapshot(snapshot(&session, sim, index)));
            app.handle(key(KeyCode::Enter));
            let effects = app.handle(key(KeyCode::Enter));
            let sent = serve(&mut app, &session, &mut answers, effects).await;
            let Some(value) = before else {
                // Nothing known: nothing to confirm, nothing sent, and
                // the screen says so.
                assert!(sent.is_empty(), "{what}: nothing known, yet {sent:?}");
                let shown = screen(&mut app, 160, 40).join("\n");
                assert!(shown.contains("nothing sent"), "{what}:\n{shown}");
                app.handle(key(KeyCode::Esc));
                continue;
            };
            let known = session.settings().borrow().clone();
            let known = |scope: Scope, number: u16| known.value(scope, number);
            let expected = match parameters.line_with(row, ParamOp::Write(value), &known) {
                Ok(line) => line,
                Err(why) => {
                    // The family writes no such line (SIXpack 2: an odd
                    // motor's peak is set on the even one): nothing sent,
                    // and the screen says why.
                    assert!(sent.is_empty(), "{what}: {why}, yet {sent:?}");
                    let shown = screen(&mut app, 200, 40).join("\n");
                    let start: String = why.message.chars().take(40).collect();
                    assert!(
                        shown.contains("nothing sent") && shown.contains(&start),
                        "{what}:\n{shown}"
                    );
                    app.handle(key(KeyCode::Esc));
                    continue;
                }
            };
            assert_eq!(
                sent.first(),
                Some(&expected),
                "{what}: {value} read; the unchanged field sent {sent:?}"
            );
            edited += 1;
        }
    }
    assert!(edited > 0, "{sim}: no row had a value to edit");
}

#[tokio::test(start_paused = true)]
async fn an_edit_confirmed_unchanged_writes_the_value_read_on_every_family() {
    for family in FAMILIES {
        for sim in family.simulators {
            unchanged_edits_write_what_was_read(sim.name).await;
        }
    }
}
