//! `axterm CONNECTION` with no subcommand: the terminal console on that
//! link (or, with no connection, the console waiting for `:connect`).

use std::path::PathBuf;
use std::sync::Arc;

use super::connection::{Target, runtime};
use super::links::{all_links, parse_from};
use super::{ConnectionArgs, EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::link::LinkSpec;
use crate::protocol::units::SharedMechanics;
use crate::ui::PaneSetup;
use crate::ui::app::{Connector, Controller};
use crate::ui::live::{Appearance, SessionController, identify_later, run_terminal};

/// Environment variable naming the directory for the console's history
/// (default: the platform data directory, e.g. ~/.local/share/axterm).
pub const DATA_DIR_VAR: &str = "AXTERM_DATA_DIR";

/// Where the console keeps its history.
pub fn data_dir() -> Option<PathBuf> {
    match std::env::var_os(DATA_DIR_VAR) {
        Some(dir) if !dir.is_empty() => Some(PathBuf::from(dir)),
        _ => directories::ProjectDirs::from("", "", "axterm").map(|d| d.data_dir().to_path_buf()),
    }
}

fn has_connection(args: &ConnectionArgs) -> bool {
    args.sim.is_some() || args.port.is_some() || args.tcp.is_some()
}

/// Open the connection the options describe and start polling its status:
/// its first module's controller, which brings the others of an address
/// list (`--address 1-4`, [`Controller::other_modules`]).
async fn open(
    args: &ConnectionArgs,
    mechanics: &SharedMechanics,
) -> Result<Arc<dyn Controller>, (i32, String)> {
    let target = Target::resolve_modules(args).map_err(|m| (EXIT_USAGE, m))?;
    let session = target
        .open()
        .await
        .map_err(|e| (EXIT_CONNECTION, e.to_string()))?;
    identify_later(&session);
    let others = target.addresses.iter().skip(1).copied().collect();
    let controller =
        SessionController::new(session, target.spec.describe(), target.options.clone())
            .with_other_modules(others)
            .with_mechanics(mechanics.clone());
    Ok(Arc::new(match &target.spec {
        LinkSpec::Sim { sim, .. } => controller.with_simulator(Arc::clone(sim)),
        _ => controller,
    }))
}

/// Test only: with this variable set (to anything), `:connect` (or a
/// connection chosen on the connect screen) panics inside the console loop
/// instead of connecting, so that an end-to-end test can crash the real
/// binary with its terminal in the console's mode and see it given back
/// (`tests/e2e_console.rs`). Nothing else reads it; unset, it costs one
/// look at the environment when the console starts.
pub const TEST_PANIC_VAR: &str = "AXTERM_TEST_PANIC";

/// The message of the deliberate panic.
pub const TEST_PANIC_MESSAGE: &str =
    "AXTERM_TEST_PANIC is set: a deliberate panic inside the console (test only)";

/// `:connect ARGS`: the same options as on the command line.
fn connector(mechanics: SharedMechanics) -> Connector {
    let crash = std::env::var_os(TEST_PANIC_VAR).is_some();
    Box::new(move |args: Vec<String>| {
        let mechanics = mechanics.clone();
        // The connector is called from the console loop itself (not from
        // a task of its own): a panic here unwinds through the loop with
        // the terminal in raw mode and on the alternate screen.
        if crash {
            panic!("{TEST_PANIC_MESSAGE}");
        }
        Box::pin(async move {
            let argv = std::iter::once("axterm".to_string()).chain(args.iter().cloned());
            let cli = parse_from(argv).map_err(|e| {
                let text = e.to_string();
                let first = text.lines().next().unwrap_or("bad connection options");
                format!(":connect: {}", first.trim_start_matches("error: "))
            })?;
            if !has_connection(&cli.connection) {
                return Err(":connect needs --sim KIND, --port PATH or --tcp HOST:PORT".into());
            }
            if !cli.connection.more_links.is_empty() {
                return Err(format!(
                    ":connect opens one link ({} given): add the others with :link-add",
                    super::links::describe_links(&cli.connection)
                ));
            }
            open(&cli.connection, &mechanics)
                .await
                .map_err(|(_, message)| format!(":connect: {message}"))
        })
    })
}

/// `mechanics`: the file `--mechanics` names; its mechanics are those in
/// force from the start (`:mechanics FILE` changes them).
pub fn run(
    args: &ConnectionArgs,
    appearance: Appearance,
    mechanics: Option<&std::path::Path>,
) -> i32 {
    let mechanics: SharedMechanics = match super::mechanics::load(mechanics) {
        Ok(m) => Arc::new(std::sync::RwLock::new(
            m.map(|m| m.table).unwrap_or_default(),
        )),
        Err(message) => {
            eprintln!("axterm: {message}");
            return EXIT_USAGE;
        }
    };
    // Usage errors are reported before the terminal is touched.
    if has_connection(args) {
        for link in all_links(args) {
            if let Err(message) = Target::resolve_modules(link) {
                eprintln!("axterm: {message}");
                return EXIT_USAGE;
            }
        }
    }
    let runtime = match runtime() {
        Ok(runtime) => runtime,
        Err(message) => {
            eprintln!("axterm: {message}");
            return EXIT_DEVICE;
        }
    };
    let setup = PaneSetup {
        history_dir: data_dir(),
    };
    runtime.block_on(async {
        let mut links = Vec::new();
        if has_connection(args) {
            for link in all_links(args) {
                match open(link, &mechanics).await {
                    Ok(controller) => {
                        let others = controller.other_modules();
                        links.push(std::iter::once(controller).chain(others).collect());
                    }
                    Err((code, message)) => {
                        eprintln!("axterm: {message}");
                        return code;
                    }
                }
            }
        }
        match run_terminal(links, connector(mechanics), &setup, &appearance).await {
            Ok(()) => EXIT_OK,
            Err(e) => {
                eprintln!("axterm: the terminal failed: {e}");
                EXIT_DEVICE
            }
        }
    })
}
