//! Shared by the tests of a session on tokio's paused clock: waiting for
//! the status snapshots to get somewhere.
#![allow(dead_code)]

use std::time::Duration;

use axterm::session::{AxisStatus, Session};

/// Virtual time: only guards against a hung test.
pub const GIVE_UP_AFTER: Duration = Duration::from_secs(600);

/// Wait (in virtual time) until the snapshot of all axes satisfies `done`.
pub async fn wait_for(session: &Session, done: impl Fn(&[AxisStatus]) -> bool) -> Vec<AxisStatus> {
    let mut status = session.status();
    let wait = async {
        loop {
            let axes = status.borrow_and_update().clone();
            if done(&axes) {
                return axes;
            }
            status.changed().await.expect("the session is alive");
        }
    };
    tokio::time::timeout(GIVE_UP_AFTER, wait)
        .await
        .expect("the status got there")
}
