//! Driving a program run from the host (A-Script's, for one): the
//! family's [`HostRun`] state
//! machine says what to send and how long to wait; each line goes through
//! the session like a typed one (parsed, validated, at user priority, so
//! the emergency stop goes first).

use std::time::Duration;

use tokio::time::Instant;

use super::Session;
use super::transfer::answer_of;
use crate::protocol::program::{HostEnd, HostNews, HostRun, HostStep};

impl Session {
    /// Run `run` from the host until every program has ended (or failed),
    /// telling `on_news` what happens. Drop the future to stop it: the
    /// line in flight is answered, nothing more is sent.
    pub async fn run_from_host(
        &self,
        mut run: Box<dyn HostRun>,
        on_news: &mut (dyn FnMut(&HostNews) + Send),
    ) -> HostEnd {
        let began = Instant::now();
        let mut step = run.start(Duration::ZERO);
        loop {
            for news in run.take_news() {
                on_news(&news);
            }
            step = match step {
                HostStep::Send(line) => {
                    let result = self.execute_line(&line).await;
                    run.on_answer(&answer_of(&line, &result), began.elapsed())
                }
                HostStep::Wake(after) => {
                    tokio::time::sleep(after).await;
                    run.on_wake(began.elapsed())
                }
                HostStep::Finished(end) => return end,
            };
        }
    }
}
