//! The real binary in a real pseudo-terminal: a tmux server of the test's
//! own, keys sent to it, the screen read back (`capture-pane`).
//!
//! Synchronisation is by polling the screen until the expected text
//! appears, with one overall deadline so that a broken build fails
//! instead of hanging; nothing here measures how fast anything is.
#![allow(dead_code)]

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

/// Give up on the whole test after this long (a debug build on a loaded
/// machine is slow; a working one needs a few seconds).
pub const DEADLINE: Duration = Duration::from_secs(60);
/// Between two looks at the screen.
const LOOK_AGAIN: Duration = Duration::from_millis(50);

/// A tmux server of our own, killed when dropped.
pub struct Tmux {
    socket: String,
    started: Instant,
}

impl Tmux {
    /// Run `command` in `dir` on a 100×30 terminal; `name` keeps the
    /// servers of tests running side by side apart.
    pub fn start(name: &str, command: &str, dir: &Path) -> Tmux {
        let version = Command::new("tmux").arg("-V").output();
        assert!(
            version.is_ok_and(|o| o.status.success()),
            "this test needs tmux (apt-get install tmux; .ci/run installs it)"
        );
        let socket = format!("axterm-e2e-{name}-{}", std::process::id());
        let tmux = Tmux {
            socket,
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

    pub fn keys(&self, keys: &[&str]) {
        let status = Command::new("tmux")
            .args(["-L", &self.socket, "send-keys"])
            .args(keys)
            .status()
            .expect("tmux send-keys");
        assert!(status.success());
    }

    pub fn resize(&self, width: u16, height: u16) {
        let status = Command::new("tmux")
            .args(["-L", &self.socket, "resize-window", "-x"])
            .arg(width.to_string())
            .arg("-y")
            .arg(height.to_string())
            .status()
            .expect("tmux resize-window");
        assert!(status.success());
    }

    /// Type text literally.
    pub fn type_text(&self, text: &str) {
        self.keys(&["-l", text]);
    }

    pub fn screen(&self) -> String {
        let out = Command::new("tmux")
            .args(["-L", &self.socket, "capture-pane", "-p", "-J"])
            .output()
            .expect("tmux capture-pane");
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    /// Look at the screen until `ready` says yes; the screen it said yes
    /// to.
    pub fn until(&self, what: &str, ready: impl Fn(&str) -> bool) -> String {
        self.until_found(what, || {
            let screen = self.screen();
            ready(&screen).then_some(screen)
        })
    }

    /// Ask `found` (the screen, a file the console writes…) until it gives
    /// something; what it gave.
    pub fn until_found<T>(&self, what: &str, found: impl Fn() -> Option<T>) -> T {
        loop {
            if let Some(found) = found() {
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

/// The shell command that runs `axterm ARGS` with its data directory in
/// `dir`, then prints its exit code (`AXTERM-EXIT-n`), the terminal's
/// settings and an end marker, and waits so that the screen can be read.
pub fn console_command(dir: &Path, args: &str) -> String {
    format!(
        "AXTERM_DATA_DIR={data} {binary} {args}; echo AXTERM-EXIT-$?; stty -a; echo MARKER-END; sleep 600",
        data = dir.display(),
        binary = env!("CARGO_BIN_EXE_axterm"),
    )
}

/// After [`console_command`]'s marker: the terminal is in cooked mode
/// again (canonical input, echo, signals, CR/NL and output processing),
/// as the `stty -a` printed after `AXTERM-EXIT-{code}` shows.
pub fn assert_terminal_restored(after: &str, code: i32) {
    let marker = format!("AXTERM-EXIT-{code}");
    assert!(after.contains(&marker), "{after}");
    let stty = after.split(&marker).nth(1).unwrap_or_default();
    let words: Vec<&str> = stty.split_whitespace().collect();
    for setting in ["icanon", "echo", "isig", "icrnl", "opost"] {
        assert!(
            words.contains(&setting),
            "{setting} is not set again:\n{stty}"
        );
    }
}
