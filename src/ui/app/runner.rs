//! The loop that drives an [`App`]: it waits for keys, the session's channels,
//! traffic, replies and timers, and carries out the effects the app asks for.

use std::sync::Arc;
use std::time::Duration;

use ratatui::crossterm::event::Event as TermEvent;
use tokio::sync::{broadcast, mpsc, watch};
use tokio::task::JoinHandle;

use super::traffic_log::TrafficLog;
use super::{App, AppEvent, Connector, Controller, Effect, Pending};
use crate::device::{Busy, DeviceEvent, LinkState, TrafficRecord};
use crate::protocol::program::{Progress, TransferFailure};
use crate::protocol::settings::SettingsCache;
use crate::session::Cancel;
use crate::session::{AxisStatus, PollCadence};
use crate::ui::pane::{Notice, Snapshot};

/// How long the loop lets traffic gather before it hands it to the panes:
/// status polling alone sends a hundred or more frames a second, and
/// waking the loop for each cost more than everything else an idle
/// console does. The first frame after a quiet spell is handed on at once;
/// the traffic monitor redraws no more often than this anyway
/// ([`crate::ui::traffic::REFRESH`]).
pub const TRAFFIC_BATCH: Duration = crate::ui::traffic::REFRESH;

/// How long traffic may gather while the traffic monitor is not on screen
/// (it keeps recording behind its tab): the pause doubles from
/// [`TRAFFIC_BATCH`] up to this while frames keep coming.
pub const TRAFFIC_BATCH_HIDDEN: Duration = Duration::from_secs(1);

/// Records a pause may let gather at the rate last seen: a quarter of the
/// device's traffic stream ([`crate::device::TRAFFIC_CAPACITY`]), so that
/// a fast transfer shortens the pause before the stream overflows.
pub const TRAFFIC_HEADROOM: usize = crate::device::TRAFFIC_CAPACITY / 4;

/// The pane that shows traffic (see [`App::is_on_screen`]).
const TRAFFIC_PANE: &str = "traffic";

/// The pause after a batch of `taken` records gathered over `seen`:
/// [`TRAFFIC_BATCH`] after a quiet spell (`fresh`), else twice the last
/// one, at most `longest`, and never so long that [`TRAFFIC_HEADROOM`]
/// records would come at the rate just seen.
pub fn traffic_pause(
    fresh: bool,
    last: Duration,
    longest: Duration,
    taken: usize,
    seen: Duration,
) -> Duration {
    let pause = if fresh {
        TRAFFIC_BATCH
    } else {
        last.saturating_mul(2)
    }
    .min(longest);
    let Ok(taken) = u32::try_from(taken) else {
        return Duration::from_millis(1);
    };
    if taken == 0 {
        return pause;
    }
    let headroom = u32::try_from(TRAFFIC_HEADROOM).unwrap_or(u32::MAX);
    let safe = seen.saturating_mul(headroom) / taken;
    pause.min(safe).max(Duration::from_millis(1))
}

/// One connected controller as the loop watches it.
pub(super) struct Connection {
    pub(super) controller: Arc<dyn Controller>,
    status: watch::Receiver<Vec<AxisStatus>>,
    link: watch::Receiver<LinkState>,
    identity: watch::Receiver<Option<String>>,
    settings: Option<watch::Receiver<SettingsCache>>,
    traffic: Option<broadcast::Receiver<TrafficRecord>>,
    /// Traffic is taken in batches: after a batch, none is taken before
    /// this (see [`TRAFFIC_BATCH`]); `None`: the next record wakes the
    /// loop.
    traffic_after: Option<tokio::time::Instant>,
    /// The last pause, and when traffic was last taken.
    traffic_pause: Duration,
    traffic_taken: tokio::time::Instant,
    events: Option<broadcast::Receiver<DeviceEvent>>,
    poll: Option<PollCadence>,
    /// The line the controller is busy with, where it can be.
    busy: Option<watch::Receiver<Option<Busy>>>,
}

impl Connection {
    fn new(controller: Arc<dyn Controller>, poll: Option<PollCadence>) -> Connection {
        controller.set_polling(poll);
        Connection {
            status: controller.status(),
            link: controller.link_state(),
            identity: controller.identity(),
            settings: controller.settings(),
            traffic: controller.traffic(),
            traffic_after: None,
            traffic_pause: TRAFFIC_BATCH,
            traffic_taken: tokio::time::Instant::now(),
            events: controller.events(),
            busy: controller.busy(),
            controller,
            poll,
        }
    }

    fn snapshot(&mut self, axis: usize) -> Snapshot {
        let c = &self.controller;
        let axes = c.axes();
        Snapshot {
            family: c.family(),
            address: c.address(),
            link_name: c.link_name(),
            axis: axis.min(axes.len().saturating_sub(1)),
            axes,
            status: self.status.borrow_and_update().clone(),
            link: self.link.borrow_and_update().clone(),
            identity: self.identity.borrow_and_update().clone(),
            poll: self.poll,
            settings: Arc::new(
                self.settings
                    .as_mut()
                    .map(|s| s.borrow_and_update().clone())
                    .unwrap_or_default(),
            ),
        }
    }
}

/// Something the loop waits for, besides the app's own messages.
enum Wakeup {
    Input(Option<TermEvent>),
    Changed,
    ChannelGone,
    Traffic(Result<TrafficRecord, broadcast::error::RecvError>),
    /// The busy line changed.
    Busy,
    /// The pause after a batch of traffic is over.
    TrafficDue,
    Device(Result<DeviceEvent, broadcast::error::RecvError>),
    Internal(Option<AppEvent>),
    Connected(Result<Arc<dyn Controller>, String>),
}

/// The loop's side of the console: the connection and everything in
/// flight for the app.
struct Runner {
    connection: Option<Connection>,
    internal: mpsc::UnboundedSender<AppEvent>,
    /// Tasks sending lines, which the emergency stop aborts.
    sending: Vec<JoinHandle<()>>,
    connecting: Option<Pending<Result<Arc<dyn Controller>, String>>>,
    connector: Connector,
    log: Option<TrafficLog>,
    /// The cancel handle of the last transfer started (one at a time:
    /// the session refuses a second). Not aborted by the emergency stop:
    /// the session cancels it, and its end is still reported.
    transfer: Option<Cancel>,
}

/// Drives an [`App`] until it quits: `input` carries terminal events,
/// `extra` anything else (signals, start-up notices), `draw` paints the
/// app (it is called only when something changed). The session's watch
/// channels and event stream, the replies and the timers wake the loop,
/// and traffic at most once per [`TRAFFIC_BATCH`]; nothing else does.
pub async fn run(
    app: &mut App,
    controller: Option<Arc<dyn Controller>>,
    connector: Connector,
    mut input: mpsc::UnboundedReceiver<TermEvent>,
    extra: Option<mpsc::UnboundedReceiver<AppEvent>>,
    draw: &mut (dyn FnMut(&mut App) -> std::io::Result<()> + Send),
) -> std::io::Result<()> {
    let (internal, mut internal_rx) = mpsc::unbounded_channel::<AppEvent>();
    if let Some(mut extra) = extra {
        let tx = internal.clone();
        tokio::spawn(async move {
            while let Some(event) = extra.recv().await {
                if tx.send(event).is_err() {
                    break;
                }
            }
        });
    }
    let mut runner = Runner {
        connection: controller.map(|c| Connection::new(c, Some(PollCadence::default()))),
        internal,
        sending: Vec::new(),
        connecting: None,
        connector,
        log: None,
        transfer: None,
    };
    if let Some(c) = runner.connection.as_mut() {
        let snapshot = c.snapshot(0);
        runner.handle(app, AppEvent::Connected(snapshot));
    }
    loop {
        if app.should_quit() {
            break;
        }
        if app.needs_redraw() {
            draw(app)?;
        }
        let traffic_shown = app.is_on_screen(TRAFFIC_PANE);
        let wakeup = runner
            .wait(&mut input, &mut internal_rx, traffic_shown)
            .await;
        let traffic = matches!(wakeup, Wakeup::Traffic(Ok(_)) | Wakeup::TrafficDue);
        if let Some(event) = runner.event(app, wakeup) {
            runner.handle(app, event);
        }
        if traffic {
            runner.take_traffic(app, traffic_shown);
        }
    }
    if let Some(log) = runner.log.take() {
        log.stop();
    }
    if let Some(c) = runner.connection {
        c.controller.set_polling(None);
    }
    for job in runner.sending {
        job.abort();
    }
    // A download leaves download mode before it ends.
    if let Some(cancel) = runner.transfer {
        cancel.cancel();
    }
    Ok(())
}

impl Runner {
    async fn wait(
        &mut self,
        input: &mut mpsc::UnboundedReceiver<TermEvent>,
        internal: &mut mpsc::UnboundedReceiver<AppEvent>,
        traffic_shown: bool,
    ) -> Wakeup {
        let connecting = &mut self.connecting;
        let connect = async {
            match connecting.as_mut() {
                Some(pending) => pending.await,
                None => std::future::pending().await,
            }
        };
        let Some(c) = self.connection.as_mut() else {
            return tokio::select! {
                event = input.recv() => Wakeup::Input(event),
                event = internal.recv() => Wakeup::Internal(event),
                result = connect => Wakeup::Connected(result),
            };
        };
        // The traffic monitor brought to the front waits no longer than
        // its refresh for the frames that gathered behind its tab.
        let traffic_after = c.traffic_after.map(|at| {
            if traffic_shown {
                at.min(c.traffic_taken + TRAFFIC_BATCH)
            } else {
                at
            }
        });
        let traffic = async {
            match (c.traffic.as_mut(), traffic_after) {
                (Some(_), Some(at)) => {
                    tokio::time::sleep_until(at).await;
                    Wakeup::TrafficDue
                }
                (Some(rx), None) => Wakeup::Traffic(rx.recv().await),
                (None, _) => std::future::pending().await,
            }
        };
        let events = async {
            match c.events.as_mut() {
                Some(rx) => rx.recv().await,
                None => std::future::pending().await,
            }
        };
        let settings = async {
            match c.settings.as_mut() {
                Some(rx) => rx.changed().await,
                None => std::future::pending().await,
            }
        };
        let gone = |changed: Result<(), watch::error::RecvError>| match changed {
            Ok(()) => Wakeup::Changed,
            Err(_) => Wakeup::ChannelGone,
        };
        let busy = async {
            match c.busy.as_mut() {
                Some(rx) => match rx.changed().await {
                    Ok(()) => Wakeup::Busy,
                    Err(_) => std::future::pending().await,
                },
                None => std::future::pending().await,
            }
        };
        tokio::select! {
            event = input.recv() => Wakeup::Input(event),
            event = internal.recv() => Wakeup::Internal(event),
            result = connect => Wakeup::Connected(result),
            changed = c.status.changed() => gone(changed),
            changed = c.link.changed() => gone(changed),
            changed = c.identity.changed() => gone(changed),
            changed = settings => gone(changed),
            wakeup = traffic => wakeup,
            event = events => Wakeup::Device(event),
            wakeup = busy => wakeup,
        }
    }

    /// What a wake-up means for the app, if anything.
    fn event(&mut self, app: &App, wakeup: Wakeup) -> Option<AppEvent> {
        Some(match wakeup {
            Wakeup::Input(Some(event)) => AppEvent::Terminal(event),
            Wakeup::Input(None) => AppEvent::Terminate,
            Wakeup::Changed => {
                let axis = app.snapshot().map_or(0, |s| s.axis);
                AppEvent::Snapshot(self.connection.as_mut()?.snapshot(axis))
            }
            Wakeup::ChannelGone => {
                self.disconnect();
                AppEvent::Disconnected
            }
            Wakeup::Busy => {
                let busy = self.connection.as_mut()?.busy.as_mut()?;
                AppEvent::Busy(busy.borrow_and_update().clone())
            }
            Wakeup::Traffic(Ok(record)) => AppEvent::Traffic(record),
            Wakeup::TrafficDue => return None,
            Wakeup::Device(Ok(event)) => AppEvent::Device(event),
            Wakeup::Traffic(Err(broadcast::error::RecvError::Closed))
            | Wakeup::Device(Err(broadcast::error::RecvError::Closed)) => {
                if let Some(c) = self.connection.as_mut() {
                    c.traffic = None;
                    c.events = None;
                }
                return None;
            }
            // A pane that could not keep up misses some traffic; the next
            // record comes.
            Wakeup::Traffic(Err(_)) | Wakeup::Device(Err(_)) => return None,
            Wakeup::Internal(event) => event?,
            Wakeup::Connected(result) => {
                self.connecting = None;
                match result {
                    Ok(controller) => {
                        let poll = self
                            .connection
                            .as_ref()
                            .map_or(Some(PollCadence::default()), |c| c.poll);
                        self.disconnect();
                        let mut c = Connection::new(controller, poll);
                        let snapshot = c.snapshot(0);
                        self.connection = Some(c);
                        AppEvent::Connected(snapshot)
                    }
                    Err(message) => AppEvent::Notice(Notice::error(message)),
                }
            }
        })
    }

    /// Hand the panes every traffic record waiting, and pause before
    /// taking more if there were any ([`traffic_pause`]; otherwise the
    /// next record wakes the loop at once).
    fn take_traffic(&mut self, app: &mut App, traffic_shown: bool) {
        let Some(c) = self.connection.as_mut() else {
            return;
        };
        let woken_by_a_record = c.traffic_after.is_none();
        let mut records = Vec::new();
        let mut closed = false;
        if let Some(rx) = c.traffic.as_mut() {
            loop {
                match rx.try_recv() {
                    Ok(record) => records.push(record),
                    // Missed by a pane that could not keep up; read on.
                    Err(broadcast::error::TryRecvError::Lagged(_)) => {}
                    Err(broadcast::error::TryRecvError::Empty) => break,
                    Err(broadcast::error::TryRecvError::Closed) => {
                        closed = true;
                        break;
                    }
                }
            }
        }
        let now = tokio::time::Instant::now();
        c.traffic_after = if woken_by_a_record || !records.is_empty() {
            let longest = if traffic_shown {
                TRAFFIC_BATCH
            } else {
                TRAFFIC_BATCH_HIDDEN
            };
            c.traffic_pause = traffic_pause(
                woken_by_a_record,
                c.traffic_pause,
                longest,
                records.len(),
                now.saturating_duration_since(c.traffic_taken),
            );
            Some(now + c.traffic_pause)
        } else {
            None
        };
        c.traffic_taken = now;
        if closed {
            c.traffic = None;
            c.traffic_after = None;
        }
        for record in records {
            self.handle(app, AppEvent::Traffic(record));
        }
    }

    /// Let go of the connection: no polling, no log.
    fn disconnect(&mut self) {
        if let Some(log) = self.log.take() {
            log.stop();
        }
        if let Some(old) = self.connection.take() {
            old.controller.set_polling(None);
        }
    }

    /// Hand an event to the app and carry out what it asks for; events
    /// that come of it are handled in turn.
    fn handle(&mut self, app: &mut App, event: AppEvent) {
        self.sending.retain(|job| !job.is_finished());
        let mut queue = vec![event];
        while let Some(event) = queue.pop() {
            for effect in app.handle(event) {
                self.carry_out(effect, app, &mut queue);
            }
        }
    }

    fn carry_out(&mut self, effect: Effect, app: &App, queue: &mut Vec<AppEvent>) {
        let not_connected = || {
            AppEvent::Notice(Notice::error(
                "not connected: give :connect --sim tmcm1110 (or --port PATH, --tcp HOST:PORT)",
            ))
        };
        match effect {
            Effect::Send { pane, tag, lines } => {
                let Some(c) = self.connection.as_ref() else {
                    queue.push(not_connected());
                    return;
                };
                let controller = Arc::clone(&c.controller);
                let tx = self.internal.clone();
                self.sending.push(tokio::spawn(async move {
                    for line in lines {
                        let result = controller.execute(line.clone()).await;
                        let failed = result.is_err();
                        let reply = AppEvent::Reply {
                            pane,
                            tag,
                            line,
                            result,
                        };
                        if tx.send(reply).is_err() || failed {
                            break;
                        }
                    }
                }));
            }
            Effect::EmergencyStop => {
                // Lines still waiting to be sent must not go after the stop.
                for job in self.sending.drain(..) {
                    job.abort();
                }
                let Some(c) = self.connection.as_ref() else {
                    queue.push(AppEvent::Stopped(Vec::new()));
                    return;
                };
                let stop = c.controller.emergency_stop();
                let tx = self.internal.clone();
                tokio::spawn(async move {
                    let results = stop.await;
                    let _ = tx.send(AppEvent::Stopped(results));
                });
            }
            Effect::AbortLine | Effect::PauseLine => {
                let Some(c) = self.connection.as_ref() else {
                    queue.push(not_connected());
                    return;
                };
                let controller = Arc::clone(&c.controller);
                // What it did shows as the busy line changing (or ending).
                tokio::spawn(async move {
                    match effect {
                        Effect::AbortLine => drop(controller.abort_line().await),
                        _ => drop(controller.pause_line().await),
                    }
                });
            }
            Effect::EndRun {
                pane,
                ending,
                policy,
            } => {
                // Unlike the stop key, lines already queued are kept: they
                // are other panes' and answered after the stop, which goes
                // first at emergency-stop priority.
                let Some(c) = self.connection.as_ref() else {
                    queue.push(not_connected());
                    return;
                };
                let end = c.controller.end_run(ending, policy);
                let tx = self.internal.clone();
                tokio::spawn(async move {
                    let aftermath = end.await;
                    let _ = tx.send(AppEvent::RunEnded { pane, aftermath });
                });
            }
            Effect::Poll(cadence) => {
                if let Some(c) = self.connection.as_mut() {
                    c.poll = cadence;
                    c.controller.set_polling(cadence);
                    let axis = app.snapshot().map_or(0, |s| s.axis);
                    queue.push(AppEvent::Snapshot(c.snapshot(axis)));
                } else {
                    queue.push(not_connected());
                }
            }
            Effect::SetAddress(address) => {
                let Some(c) = self.connection.as_ref() else {
                    queue.push(not_connected());
                    return;
                };
                let poll = c.poll;
                let controller = c.controller.with_address(address);
                self.disconnect();
                let mut fresh = Connection::new(controller, poll);
                let axis = app.snapshot().map_or(0, |s| s.axis);
                queue.push(AppEvent::Snapshot(fresh.snapshot(axis)));
                self.connection = Some(fresh);
            }
            Effect::ClearErrors { axis, seen } => {
                let Some(c) = self.connection.as_ref() else {
                    return;
                };
                let name = app
                    .snapshot()
                    .and_then(|s| s.axes.get(axis))
                    .map_or_else(|| format!("axis {axis}"), |a| a.name.to_string());
                let clearing = c.controller.clear_errors(axis, seen);
                let tx = self.internal.clone();
                // Among the lines the emergency stop drops if still waiting.
                self.sending.push(tokio::spawn(async move {
                    let notice = match clearing.await {
                        Ok(None) => return,
                        Ok(Some(result)) => Notice::info(format!(
                            "{}: {}, the error flags of {name} are cleared in the controller",
                            result.line, result.value
                        )),
                        Err(e) => Notice::error(format!(
                            "the error flags of {name} stay: clearing them failed: {e}"
                        )),
                    };
                    let _ = tx.send(AppEvent::Notice(notice));
                }));
            }
            Effect::Log(path) => {
                if let Some(log) = self.log.take() {
                    log.stop();
                }
                let Some(path) = path else {
                    return;
                };
                let Some(c) = self.connection.as_ref() else {
                    queue.push(not_connected());
                    return;
                };
                match TrafficLog::start(&path, c, &self.internal) {
                    Ok(log) => {
                        self.log = Some(log);
                        queue.push(AppEvent::Notice(Notice::info(format!(
                            "logging every frame to {}",
                            path.display()
                        ))));
                    }
                    Err(message) => queue.push(AppEvent::Notice(Notice::error(message))),
                }
            }
            Effect::Connect(args) => {
                self.connecting = Some((self.connector)(args));
            }
            Effect::Wake { pane, tag, after } => {
                let tx = self.internal.clone();
                tokio::spawn(async move {
                    tokio::time::sleep(after).await;
                    let _ = tx.send(AppEvent::Wake { pane, tag });
                });
            }
            Effect::Transfer { pane, tag, job } => {
                let Some(c) = self.connection.as_ref() else {
                    queue.push(AppEvent::Transferred {
                        pane,
                        tag,
                        result: Err(not_connected_transfer()),
                    });
                    return;
                };
                let cancel = Cancel::new();
                self.transfer = Some(cancel.clone());
                let tx = self.internal.clone();
                let mut last: Option<Progress> = None;
                let progress = Box::new(move |progress: Progress| {
                    if worth_showing(last.as_ref(), &progress) {
                        last = Some(progress);
                        let _ = tx.send(AppEvent::TransferProgress {
                            pane,
                            tag,
                            progress,
                        });
                    }
                });
                let running = c.controller.transfer(job, cancel, progress);
                let tx = self.internal.clone();
                tokio::spawn(async move {
                    let result = running.await;
                    let _ = tx.send(AppEvent::Transferred { pane, tag, result });
                });
            }
            Effect::CancelTransfer => {
                if let Some(cancel) = self.transfer.as_ref() {
                    cancel.cancel();
                }
            }
            Effect::LoadProgram { pane, tag, source } => {
                let result = match self.connection.as_ref() {
                    Some(c) => c.controller.load_program(&source),
                    None => Err("not connected: nothing to load into".to_string()),
                };
                queue.push(AppEvent::ProgramLoaded { pane, tag, result });
            }
            Effect::DriveSimInput(setting) => {
                let Some(c) = self.connection.as_ref() else {
                    queue.push(not_connected());
                    return;
                };
                let notice = match c.controller.drive_sim_input(&setting) {
                    Ok(said) => Notice::info(format!("simulator input: {said}")),
                    Err(message) => Notice::error(format!(":sim-input {setting}: {message}")),
                };
                queue.push(AppEvent::Notice(notice));
            }
            Effect::Watch { axis, line, on } => {
                let Some(c) = self.connection.as_ref() else {
                    queue.push(not_connected());
                    return;
                };
                if let Err(message) = c.controller.watch(axis, &line, on) {
                    queue.push(AppEvent::Notice(Notice::error(format!(
                        "cannot plot {line}: {message}"
                    ))));
                }
            }
            Effect::Expire { id, after } => {
                let tx = self.internal.clone();
                tokio::spawn(async move {
                    tokio::time::sleep(after).await;
                    let _ = tx.send(AppEvent::Expired(id));
                });
            }
            Effect::Quit => {}
        }
    }
}

/// A transfer asked for with no controller connected.
fn not_connected_transfer() -> TransferFailure {
    TransferFailure::refused(
        "cannot start the transfer: not connected: give :connect --sim tmcm1110 (or --port \
         PATH, --tcp HOST:PORT)",
    )
}

/// Whether a transfer's progress is worth a redraw: the start of each
/// phase, every whole percent, the last word (a download of 2048 words
/// on a fast link would otherwise redraw 4096 times). Without a total
/// (an upload until the first blank word), every 16th word.
pub fn worth_showing(last: Option<&Progress>, next: &Progress) -> bool {
    let Some(last) = last else {
        return true;
    };
    if last.phase != next.phase || next.done == 0 {
        return true;
    }
    match next.total {
        Some(total) if total > 0 => {
            next.done >= total || last.done * 100 / total != next.done * 100 / total
        }
        _ => next.done.is_multiple_of(16),
    }
}
