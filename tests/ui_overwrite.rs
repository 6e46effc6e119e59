//! Files of the user's, in the console: `:plot csv`, `:log`, `:record` and
//! `:record-macro` refuse a file that exists, leave it as it is and say
//! `--force` replaces it; `--force` before the name does. Driven by keys
//! through the real loop on tokio's paused clock, on a SIXpack 2 (its
//! program tool records macros, so every such command is there).

mod ui_support;

use std::path::Path;

use ui_support::looped::{Rig, enter, run_command_console};
use ui_support::sim_controller;

const KEPT: &str = "the technician's own file\n";

fn kept(path: &Path) -> bool {
    std::fs::read_to_string(path).expect("the file") == KEPT
}

#[tokio::test(start_paused = true)]
async fn console_commands_refuse_an_existing_file_unless_forced() {
    let dir = tempfile::tempdir().expect("temp dir");
    let name = |file: &str| dir.path().join(file);
    // The command, the file it writes, what it says once it does.
    let commands = [
        (":plot csv", name("plot.csv"), "series written to"),
        (":log", name("wire.log"), "logging every frame to"),
        (":record", name("session.txt"), "recording the session to"),
        (
            ":record-macro",
            name("macro.sqm"),
            "recording every line sent from here to",
        ),
    ];
    for (_, path, _) in &commands {
        std::fs::write(path, KEPT).expect("write");
    }
    let controller = sim_controller("sixpack2", 115_200).await;
    run_command_console(controller, (220, 40), async |rig: &mut Rig| {
        for (command, path, _) in &commands {
            let shown = path.display();
            enter(rig, &format!("{command} {shown}"));
            rig.screens
                .until_frame(&format!("{command} refused"), |frame| {
                    frame.contains(&format!("{shown}: it exists: give --force to replace it"))
                        && frame.contains(command.split_whitespace().next().unwrap_or(""))
                })
                .await;
            assert!(kept(path), "{command} left {shown} as it was");
        }
        for (command, path, done) in &commands {
            let shown = path.display();
            enter(rig, &format!("{command} --force {shown}"));
            rig.screens.until(&format!("{done} {shown}")).await;
        }
        for off in [":log off", ":record off", ":record-macro off"] {
            enter(rig, off);
        }
        rig.screens.until("recording ended").await;
    })
    .await;
    for (command, path, _) in &commands {
        assert!(!kept(path), "{command} --force replaced {}", path.display());
    }
}
