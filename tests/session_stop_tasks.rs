//! The emergency stop ends the background programs the session knows run,
//! and all of them only when it cannot know (MCCL tasks: `ID7` lists them,
//! `ETn` ends one, `GT` starts one whose ID only the accumulator holds),
//! over the in-process MultiFlex simulator on tokio's paused clock. The
//! stop is still queued whole at emergency-stop priority.

use axterm::cli::ConnectionArgs;
use axterm::cli::connection::Target;
use axterm::families::FAMILIES;
use axterm::protocol::console::RunningPrograms;
use axterm::session::Session;

async fn session(kind: &str) -> Session {
    let target = Target::resolve(&ConnectionArgs {
        sim: Some(kind.into()),
        baud: Some(115_200),
        ..ConnectionArgs::default()
    })
    .expect("resolves");
    target.open().await.expect("the simulator link opens")
}

/// The stop's lines as sent, each answered with success.
async fn stop(session: &Session) -> Vec<String> {
    session
        .emergency_stop_lines()
        .await
        .into_iter()
        .map(|result| match result {
            Ok(r) => r.line,
            Err(e) => panic!("a stop line failed: {e}"),
        })
        .collect()
}

async fn say(session: &Session, line: &str) -> String {
    match session.execute_line(line).await {
        Ok(r) => r.value.to_string(),
        Err(e) => panic!("{line}: {e}"),
    }
}

fn every_task() -> Vec<String> {
    std::iter::once("0AB".to_string())
        .chain((1..=21).map(|id| format!("ET{id}")))
        .collect()
}

#[tokio::test(start_paused = true)]
async fn the_mccl_stop_ends_the_tasks_that_run_and_all_only_when_it_cannot_know() {
    let session = session("mccl").await;
    // Just connected: whatever the controller was left running.
    assert_eq!(session.running_programs(), RunningPrograms::Unknown);
    assert_eq!(stop(&session).await, every_task());
    // Every task ended, and nothing started since.
    assert_eq!(stop(&session).await, ["0AB"]);

    // A task started: its ID is in the accumulator only.
    say(&session, "MD100,WA1,JP0").await;
    say(&session, "GT100").await;
    assert_eq!(session.running_programs(), RunningPrograms::Unknown);
    // `:tasks` reads them.
    let listing = say(&session, "ID7").await;
    let RunningPrograms::Known(ids) = session.running_programs() else {
        panic!("ID7 answered {listing} and the tasks are still unknown");
    };
    assert_eq!(ids.len(), 1, "{listing}");
    let ended: Vec<String> = ids.iter().map(|id| format!("ET{id}")).collect();
    let expected: Vec<String> = std::iter::once("0AB".to_string()).chain(ended).collect();
    assert_eq!(stop(&session).await, expected);
    assert!(
        say(&session, "ID7").await.contains("TASKS: 0"),
        "the task still runs"
    );

    // A task ended by hand is no longer ended by the stop.
    say(&session, "GT100").await;
    let listing = say(&session, "ID7").await;
    let RunningPrograms::Known(ids) = session.running_programs() else {
        panic!("{listing}");
    };
    for id in ids {
        say(&session, &format!("ET{id}")).await;
    }
    assert_eq!(
        session.running_programs(),
        RunningPrograms::Known(Vec::new())
    );
    assert_eq!(stop(&session).await, ["0AB"]);
}

/// Every family's stop, knowing nothing of what runs, is its whole stop.
#[test]
fn knowing_nothing_every_family_stops_everything() {
    for family in FAMILIES {
        let address = family.console.default_address();
        let whole: Vec<String> = family
            .console
            .emergency_stop(address)
            .into_iter()
            .map(|l| l.canonical)
            .collect();
        let knowing: Vec<String> = family
            .console
            .emergency_stop_knowing(address, &RunningPrograms::Unknown)
            .into_iter()
            .map(|l| l.canonical)
            .collect();
        assert_eq!(knowing, whole, "{}", family.name);
        assert!(!whole.is_empty(), "{}", family.name);
    }
}
