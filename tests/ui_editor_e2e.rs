//! The editor's safety copy survives killing the process: the real binary
//! in tmux, text typed in the editor, `kill -9` once the copy on disk
//! holds it, the console started again, and the text offered on screen.
//!
//! Synchronisation is by polling (the screen, the copy's file) until what
//! is expected is there, with one overall deadline so that a broken build
//! fails instead of hanging; nothing here measures how fast anything is.

mod tmux_support;

use axterm::ui::editor::autosave::read_autosave;
use tmux_support::Tmux;

#[test]
fn text_typed_in_the_editor_survives_kill_9() {
    let dir = tempfile::tempdir().expect("temp dir");
    let data = dir.path().join("data");
    let binary = env!("CARGO_BIN_EXE_axterm");
    // The first console is killed; the shell then starts a second one with
    // the same data directory.
    let command = format!(
        "export AXTERM_DATA_DIR={data}; {binary} --sim tmcm1110 & echo $! > pid; wait; \
         echo > second; {binary} --sim tmcm1110; sleep 600",
        data = data.display(),
    );
    let tmux = Tmux::start("editor", &command, dir.path());
    tmux.until("the console", |s| s.contains("poll 20 Hz"));
    tmux.keys(&["M-7"]);
    tmux.until("the editor", |s| s.contains("Program — untitled"));
    let typed = ["Start: MVP ABS, 0, 51200", "WAIT POS, 0, 0", "JA Start"];
    for line in typed {
        tmux.keys(&["-l", line]);
        tmux.keys(&["Enter"]);
    }
    let wanted = format!("{}\n", typed.join("\n"));
    tmux.until_found("the safety copy to hold the text", || {
        read_autosave(&data).filter(|copy| copy.text == wanted)
    });
    let pid: i32 = std::fs::read_to_string(dir.path().join("pid"))
        .expect("pid file")
        .trim()
        .parse()
        .expect("a pid");
    // SAFETY: kill(2) with a pid this test started and a valid signal.
    let sent = unsafe { libc::kill(pid, libc::SIGKILL) };
    assert_eq!(sent, 0, "SIGKILL could not be sent");

    // The second console (it starts with the command pane in front, so
    // the killed one's editor is gone from the screen): the editor offers
    // the text.
    tmux.until("the second console", |s| {
        dir.path().join("second").exists() && s.contains("poll 20 Hz") && !s.contains("Start:")
    });
    tmux.keys(&["M-7"]);
    // The notice may be drawn a frame before the text it offers.
    let screen = tmux.until("the recovered text", |s| {
        s.contains("recovered unsaved text of untitled") && typed.iter().all(|l| s.contains(l))
    });
    for line in typed {
        assert!(screen.contains(line), "{line} missing:\n{screen}");
    }
}
