//! The real binary on a MultiFlex simulator in tmux: the parameter table
//! shows the velocity in its unit, and an edit of it confirmed unchanged
//! (Enter, Enter) writes that same velocity, which reads back unchanged
//! (it once wrote the thousandths the table showed as units: 1000× the
//! velocity).

mod tmux_support;

use tmux_support::{Tmux, assert_terminal_restored, console_command};

/// The value and unit the table shows for `SV velocity`, once read.
fn velocity(screen: &str) -> Option<(String, String)> {
    let line = screen.lines().find(|l| l.contains("SV velocity"))?;
    let after = line.split("SV velocity").nth(1)?;
    let mut words = after.split_whitespace();
    let value = words.next()?;
    let unit = words.next()?;
    value
        .parse::<f64>()
        .ok()
        .map(|_| (value.to_string(), unit.to_string()))
}

#[test]
fn an_unchanged_velocity_edit_writes_and_reads_back_the_same_velocity() {
    let dir = tempfile::tempdir().expect("temp dir");
    let command = console_command(dir.path(), "--sim mccl");
    let tmux = Tmux::start("mccl-params", &command, dir.path());
    tmux.until("the console", |s| s.contains("F12 STOP"));

    tmux.keys(&["M-3"]);
    let (shown, unit) = tmux.until_found("the velocity read", || velocity(&tmux.screen()));
    assert_eq!(unit, "counts/s", "{}", tmux.screen());
    assert!(
        shown.ends_with(".000") && shown.len() < 11,
        "in counts/s with its 3 decimals, not in thousandths: {shown}"
    );

    // SV is the first row, selected: Enter opens it with the value shown.
    tmux.keys(&["Enter"]);
    tmux.until("the field with the value shown", |s| {
        s.contains(&format!("SV velocity = {shown}"))
    });
    tmux.keys(&["Enter"]);
    // The write names the velocity shown; once read back, the table shows
    // the same velocity.
    let written = format!("1SV{shown}");
    let after = tmux.until("the write and its read-back", |s| {
        s.contains(&format!("{written}:"))
            && !s.contains("busy")
            && velocity(s).is_some_and(|(v, _)| v == shown)
    });
    assert!(!after.contains("nothing sent"), "{after}");

    tmux.keys(&["F10"]);
    let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
    assert_terminal_restored(&after, 0);
}
