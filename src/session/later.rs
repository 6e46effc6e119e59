//! Answers that come apart from their request ([`Answering::Later`]): the
//! request is written like one that is never answered, so that the line
//! stays free for other requests (polls, the user's lines, an emergency
//! stop), and the answer is picked out of the device task's news when it
//! comes (SIXpack 2 `$28` with a wait mask, §7.2, §6.2.1.7).

use std::sync::Arc;
use std::time::Duration;

use tokio::sync::broadcast;

use crate::device::{DeviceError, DeviceEvent, LinkState};
use crate::protocol::console::Answering;
use crate::protocol::wire::{Frame, ReplyRule, Verdict};

/// How a line's answer that comes later is waited for: subscribed to the
/// device's news before the line is sent, so that an answer that comes
/// at once is not missed.
pub(super) struct LaterAnswer {
    news: broadcast::Receiver<DeviceEvent>,
    rule: Arc<dyn ReplyRule>,
    within: Duration,
}

impl LaterAnswer {
    /// The wait for `answering`'s answer, if it comes later.
    pub(super) fn for_line(
        answering: &Answering,
        news: impl FnOnce() -> broadcast::Receiver<DeviceEvent>,
    ) -> Option<LaterAnswer> {
        match answering {
            Answering::Later { rule, within } => Some(LaterAnswer {
                news: news(),
                rule: Arc::clone(rule),
                within: *within,
            }),
            _ => None,
        }
    }

    /// The frame of the answer, once it has come as news; a timeout after
    /// `within`, or the link's loss.
    pub(super) async fn wait(mut self) -> Result<(Vec<Frame>, Duration), DeviceError> {
        let began = tokio::time::Instant::now();
        let within = self.within;
        let wait = async {
            loop {
                match self.news.recv().await {
                    Ok(DeviceEvent::Unsolicited { frame, .. })
                        if self.rule.examine(&[], &frame) == Verdict::Complete =>
                    {
                        return Ok(vec![frame]);
                    }
                    Ok(DeviceEvent::StateChanged(LinkState::Disconnected { reason, .. })) => {
                        return Err(DeviceError::LinkLost(reason));
                    }
                    Ok(DeviceEvent::StateChanged(LinkState::Closed)) => {
                        return Err(DeviceError::Closed);
                    }
                    Ok(_) | Err(broadcast::error::RecvError::Lagged(_)) => {}
                    Err(broadcast::error::RecvError::Closed) => return Err(DeviceError::Closed),
                }
            }
        };
        match tokio::time::timeout(within, wait).await {
            Ok(Ok(frames)) => Ok((frames, began.elapsed())),
            Ok(Err(error)) => Err(error),
            Err(_) => Err(DeviceError::Timeout {
                timeout: within,
                attempts: 1,
            }),
        }
    }
}
