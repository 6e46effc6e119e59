//! The acceptance test of issue 6 for A-Script: one of the manual's
//! example programs (§5.4, as corrected in the digest) runs in the
//! simulator — loaded by the simulator-side option (`--program`), started
//! with `SACTRL` over the wire — and from the host through the same path
//! as `:run-ascript` / `axterm run-ascript` against a fresh simulator; the
//! resulting axis positions agree.
//!
//! On tokio's paused clock: the in-process simulator advances on it, and
//! the waits are conditions (`SASTAT` back to idle; the host run's end),
//! read through the session, never time.

mod ascript_support;

use std::time::Duration;

use ascript_support::example;
use axterm::cli::ConnectionArgs;
use axterm::cli::connection::Target;
use axterm::protocol::cmd4cr::host::start_host_run;
use axterm::protocol::program::HostNews;
use axterm::session::Session;

async fn connect(program: Option<&std::path::Path>) -> Session {
    let target = Target::resolve(&ConnectionArgs {
        sim: Some("cmd4cr".into()),
        program: program.map(std::path::Path::to_path_buf),
        ..ConnectionArgs::default()
    })
    .expect("the connection options resolve");
    target.open().await.expect("the simulator link opens")
}

async fn read(session: &Session, line: &str) -> String {
    session
        .execute_line(line)
        .await
        .unwrap_or_else(|e| panic!("{line}: {e}"))
        .value
        .to_string()
}

/// Positions after the program ran in the simulator: loaded with
/// `--program`, started with `SACTRLn=1`, until `SASTATn` reads idle.
async fn in_the_simulator(path: &std::path::Path, prg: u8) -> String {
    let session = connect(Some(path)).await;
    assert_eq!(
        read(&session, &format!("SASTAT{prg}")).await,
        "0",
        "loaded, idle"
    );
    read(&session, &format!("SACTRL{prg}=1")).await;
    let mut reads = 0;
    while read(&session, &format!("SASTAT{prg}")).await != "0" {
        reads += 1;
        assert!(reads < 100_000, "PRG {prg} never ended");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    read(&session, "PP").await
}

/// Positions after the program ran from the host against a fresh
/// simulator (nothing loaded into it).
async fn from_the_host(name: &str, source: &str) -> (String, Vec<String>) {
    let session = connect(None).await;
    let program = start_host_run(name, source, None).expect("checks for the host");
    let mut events = Vec::new();
    let end = session
        .run_from_host(program.run, &mut |n: &HostNews| events.push(n.text.clone()))
        .await;
    assert!(end.ok, "{end}\n{}", events.join("\n"));
    (read(&session, "PP").await, events)
}

async fn agree(section: &str, prg: u8, expected: &str) {
    let source = example(section);
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join(format!("example-{section}.asc"));
    std::fs::write(&path, &source).expect("write the program");
    let simulated = in_the_simulator(&path, prg).await;
    let (hosted, events) = from_the_host(&path.display().to_string(), &source).await;
    assert_eq!(
        simulated,
        hosted,
        "{section}: simulator vs host\n{}",
        events.join("\n")
    );
    assert_eq!(
        hosted, expected,
        "{section}: where the manual's program ends"
    );
    assert!(
        events
            .first()
            .is_some_and(|e| e == &format!("PRG {prg} started from the host")),
        "{events:?}"
    );
}

#[tokio::test(start_paused = true)]
async fn example_4_ends_at_1000_in_the_simulator_and_from_the_host() {
    // Ten trips X 0 → 1000 (§5.4.4, `FO=1` read as `EO=1`).
    agree("5.4.4", 1, "1000:0:0:0").await;
}

#[tokio::test(start_paused = true)]
async fn example_2_buffered_contour_ends_alike_in_the_simulator_and_from_the_host() {
    // Seven buffered XYZ moves at changing speeds (§5.4.2), sent from the
    // host as I[X]:[Y]:[Z]:[speed] with the HSPD read back.
    agree("5.4.2", 1, "0:100:100:0").await;
}
