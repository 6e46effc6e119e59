//! The editor's safety copy survives killing the process: the real binary
//! in tmux, text typed in the editor, `kill -9` once the copy on disk
//! holds it, the console started again, and the text offered on screen.
//!
//! Synchronisation is by polling (the screen, the copy's file) until what
//! is expected is there, with one overall deadline so that a broken build
//! fails instead of hanging; nothing here measures how fast anything is.

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use axterm::ui::editor::autosave::read_autosave;

/// Give up on the whole test after this long.
const DEADLINE: Duration = Duration::from_secs(60);
/// Between two looks.
const LOOK_AGAIN: Duration = Duration::from_millis(50);

/// A tmux server of our own, killed when dropped.
struct Tmux {
    socket: String,
    started: Instant,
}

impl Tmux {
    fn start(command: &str, dir: &Path) -> Tmux {
        let version = Command::new("tmux").arg("-V").output();
        assert!(
            version.is_ok_and(|o| o.status.success()),
            "this test needs tmux (apt-get install tmux; .ci/run installs it)"
        );
        let tmux = Tmux {
            socket: format!("axterm-e2e-editor-{}", std::process::id()),
            started: Instant::now(),
        };
        let status = Command::new("tmux")
            .args(["-L", &tmux.socket, "-f", "/dev/null"])
            .args(["new-session", "-d", "-x", "100", "-y", "30", "-c"])
            .arg(dir)
            .arg(command)
            .env_remove("TMUX")
            .status()
            .expect("tmux runs");
        assert!(status.success(), "tmux new-session failed");
        tmux
    }

    fn keys(&self, keys: &[&str]) {
        let status = Command::new("tmux")
            .args(["-L", &self.socket, "send-keys"])
            .args(keys)
            .status()
            .expect("tmux send-keys");
        assert!(status.success());
    }

    fn screen(&self) -> String {
        let out = Command::new("tmux")
            .args(["-L", &self.socket, "capture-pane", "-p", "-J"])
            .output()
            .expect("tmux capture-pane");
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    /// Ask `ready` until it says yes; what it said yes to.
    fn until<T>(&self, what: &str, ready: impl Fn() -> Option<T>) -> T {
        loop {
            if let Some(found) = ready() {
                return found;
            }
            assert!(
                self.started.elapsed() < DEADLINE,
                "gave up waiting for {what}; the screen:\n{}",
                self.screen()
            );
            std::thread::sleep(LOOK_AGAIN);
        }
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = Command::new("tmux")
            .args(["-L", &self.socket, "kill-server"])
            .status();
    }
}

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
    let tmux = Tmux::start(&command, dir.path());
    tmux.until("the console", || {
        tmux.screen().contains("poll 20 Hz").then_some(())
    });
    tmux.keys(&["M-7"]);
    tmux.until("the editor", || {
        tmux.screen().contains("Program — untitled").then_some(())
    });
    let typed = ["Start: MVP ABS, 0, 51200", "WAIT POS, 0, 0", "JA Start"];
    for line in typed {
        tmux.keys(&["-l", line]);
        tmux.keys(&["Enter"]);
    }
    let wanted = format!("{}\n", typed.join("\n"));
    tmux.until("the safety copy to hold the text", || {
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
    tmux.until("the second console", || {
        let s = tmux.screen();
        (dir.path().join("second").exists() && s.contains("poll 20 Hz") && !s.contains("Start:"))
            .then_some(())
    });
    tmux.keys(&["M-7"]);
    let screen = tmux.until("the recovered text", || {
        let s = tmux.screen();
        s.contains("recovered unsaved text of untitled")
            .then_some(s)
    });
    for line in typed {
        assert!(screen.contains(line), "{line} missing:\n{screen}");
    }
}
