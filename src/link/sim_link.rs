//! A simulated controller in this process as a [`Link`]: a task owns the
//! line, advances the simulator on tokio's clock (paused in tests, so
//! everything is deterministic) and passes bytes both ways through a
//! [`SimLine`] (wire time, faults).

use std::time::Duration;

use tokio::sync::mpsc;
use tokio::time::Instant;

use super::sim_line::SimLine;
use super::{Inbox, Link, SharedSim, byte_time};
use crate::sim::faults::FaultPlan;

/// How often the simulator is advanced when nothing is due on the line:
/// it may speak on its own (TMCL 138's second reply when a move ends), and
/// this is how late such news can be.
pub const TICK: Duration = Duration::from_millis(1);

pub(super) fn open(sim: SharedSim, baud: Option<u32>, faults: FaultPlan, name: String) -> Link {
    let (inbox, incoming) = Inbox::new();
    let (outgoing, from_host) = mpsc::unbounded_channel::<Vec<u8>>();
    tokio::spawn(run(sim, SimLine::new(baud, &faults), inbox, from_host));
    Link {
        name,
        incoming,
        outgoing: Box::new(outgoing),
        byte_time: baud.map(byte_time),
    }
}

/// The line's task. The simulated module's clock stands still while no
/// link to it is open (its state is kept for the next opening). Two links
/// open on one simulator at once would each advance it; the device task
/// opens one at a time, and a lost link's task has let go of the simulator
/// before its loss notice is sent.
async fn run(
    sim: SharedSim,
    mut line: SimLine,
    inbox: Inbox,
    mut from_host: mpsc::UnboundedReceiver<Vec<u8>>,
) {
    let epoch = Instant::now();
    let mut next_tick = epoch + TICK;
    let wake = tokio::time::sleep_until(next_tick);
    tokio::pin!(wake);
    loop {
        tokio::select! {
            biased;
            _ = inbox.closed() => return,
            bytes = from_host.recv() => match bytes {
                Some(bytes) => line.host_wrote(Instant::now() - epoch, &bytes),
                // The writer is gone: the link was dropped.
                None => return,
            },
            _ = &mut wake => {}
        }
        let now = Instant::now();
        if now >= next_tick {
            next_tick = now + TICK;
        }
        let out = {
            // A panic elsewhere while holding the lock leaves a usable
            // simulator; carry on with it.
            let mut guard = sim.lock().unwrap_or_else(|e| e.into_inner());
            line.run(guard.as_mut(), now - epoch)
        };
        if !inbox.bytes(&out.to_host) {
            return;
        }
        if let Some(reason) = out.cut {
            drop(sim);
            return inbox.lost(reason);
        }
        let due = line.next_due().map(|d| epoch + d);
        wake.as_mut()
            .reset(due.map_or(next_tick, |due| due.min(next_tick)));
    }
}
