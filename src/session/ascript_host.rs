//! Driving an A-Script program run from the host (its I/O-free part is
//! [`crate::protocol::cmd4cr::host`]).

pub use crate::protocol::cmd4cr::host::*;

use tokio::time::Instant;

use super::Session;

impl Session {
    /// Run `program` from the host until every program has ended (or
    /// failed), telling `on_event` what happens. Drop the future to stop
    /// it: the line in flight is answered, nothing more is sent.
    pub async fn run_ascript(
        &self,
        program: &HostProgram,
        on_event: &mut (dyn FnMut(&HostEvent) + Send),
    ) -> HostEnd {
        let mut run = HostRun::new(program);
        let mut step = run.start(Instant::now());
        loop {
            for event in run.take_events() {
                on_event(&event);
            }
            step = match step {
                HostStep::Send(line) => {
                    let result = self.execute_line(&line).await;
                    run.on_reply(&result, Instant::now())
                }
                HostStep::Wake(after) => {
                    tokio::time::sleep(after).await;
                    run.on_wake(Instant::now())
                }
                HostStep::Finished(end) => return end,
            };
        }
    }
}
