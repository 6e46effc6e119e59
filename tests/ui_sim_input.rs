//! `:sim-input` in the console, through the real loop and a session on the
//! in-process CMD-4CR simulator, on tokio's paused clock: a setting closes
//! an input of the simulator (read back over the link), a bad one says
//! why, and on a link without a simulator in this process it says there
//! is nothing to drive.

mod ui_support;

use std::sync::Arc;

use axterm::cli::ConnectionArgs;
use axterm::cli::connection::Target;
use axterm::link::LinkSpec;
use axterm::ui::app::Controller;
use axterm::ui::live::SessionController;
use ui_support::looped::{Rig, enter, run_command_console};

/// The console's controller on the in-process simulator, as `axterm --sim
/// cmd4cr` builds it; without the simulator handed over when `reach_sim`
/// is false (as for a real port).
async fn controller(reach_sim: bool) -> Arc<dyn Controller> {
    let target = Target::resolve(&ConnectionArgs {
        sim: Some("cmd4cr".into()),
        ..ConnectionArgs::default()
    })
    .expect("resolves");
    let session = target.open().await.expect("the simulator link opens");
    let controller =
        SessionController::new(session, target.spec.describe(), target.options.clone());
    match (&target.spec, reach_sim) {
        (LinkSpec::Sim { sim, .. }, true) => Arc::new(controller.with_simulator(Arc::clone(sim))),
        _ => Arc::new(controller),
    }
}

#[tokio::test(start_paused = true)]
async fn a_setting_closes_an_input_of_the_in_process_simulator() {
    run_command_console(controller(true).await, (120, 40), async |rig: &mut Rig| {
        enter(rig, "IO5");
        rig.screens.until("sent @01IO5\\r  got 0").await;
        enter(rig, ":sim-input IO5=1");
        rig.screens.until("simulator input: IO5 on").await;
        enter(rig, "IO");
        // IO5 is bit 4 of the IO word.
        rig.screens.until("sent @01IO\\r  got 16").await;
        enter(rig, ":sim-input IO5=2");
        rig.screens
            .until(":sim-input IO5=2: IO5 takes 1 (on) or 0 (off), not `2`")
            .await;
        enter(rig, ":sim-input");
        rig.screens
            .until(":sim-input needs a setting NAME=VALUE, e.g. IO5=1")
            .await;
        enter(rig, ":help :sim-input");
        rig.screens.until("ALMX|ALMY|ALMZ|ALMU=0|1: ALM").await;
    })
    .await;
}

#[tokio::test(start_paused = true)]
async fn without_a_simulator_in_this_process_there_is_nothing_to_drive() {
    run_command_console(controller(false).await, (120, 40), async |rig: &mut Rig| {
        enter(rig, ":sim-input IO5=1");
        rig.screens
            .until("is no simulator in this process: there is no input to drive")
            .await;
    })
    .await;
}
