//! `axterm sim` as a background job of an interactive shell, in a real
//! terminal (tmux): reading settings from standard input must not get it
//! stopped by SIGTTIN (it serves from the background), and once brought to
//! the foreground it takes a setting typed at the terminal.

mod tmux_support;

use tmux_support::Tmux;

#[test]
fn a_background_sim_serves_and_takes_settings_once_in_the_foreground() {
    let dir = tempfile::tempdir().expect("temp dir");
    let tmux = Tmux::start("simbg", "bash --norc --noprofile -i", dir.path());
    let axterm = env!("CARGO_BIN_EXE_axterm");
    // The pty path is the first line of `out`; the loop waits for it. The
    // markers are computed, so that the typed line does not show them.
    tmux.type_text(&format!(
        "{axterm} sim cmd4cr --pty > out & until [ -s out ]; do sleep 0.05; done; \
         {axterm} exec --port \"$(head -1 out)\" --protocol cmd4cr IO5; echo BG$((1+1))EXIT-$?"
    ));
    tmux.keys(&["Enter"]);
    let screen = tmux.until("the exec from the foreground", |s| s.contains("BG2EXIT-"));
    assert!(screen.contains("BG2EXIT-0"), "{screen}");
    assert!(!screen.contains("Stopped"), "{screen}");

    tmux.type_text("fg");
    tmux.keys(&["Enter"]);
    // bash names the job it brings back: a line ending in `--pty > out`.
    tmux.until("the job in the foreground", |s| {
        s.lines().any(|l| l.trim_end().ends_with("--pty > out"))
    });
    tmux.type_text("IO5=1");
    tmux.keys(&["Enter"]);
    tmux.until("the answer to IO5=1", |s| s.contains("axterm sim: IO5 on"));
    tmux.keys(&["C-c"]);
    tmux.type_text("echo AFTER$((1+1))");
    tmux.keys(&["Enter"]);
    tmux.until("the shell again", |s| s.contains("AFTER2"));
}
