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
use crate::session::run_end::{LinkAtStop, RunAftermath, RunEnding, RunStop};
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

/// One module of one link as the loop watches it.
pub(super) struct Connection {
    pub(super) controller: Arc<dyn Controller>,
    /// The link it is on (numbered from 0 in the order links were opened):
    /// the modules of one link share its traffic, events and busy line,
    /// which only the link's first module watches.
    pub(super) link: usize,
    /// Its channels are closed: nothing more comes of it.
    gone: bool,
    status: watch::Receiver<Vec<AxisStatus>>,
    link_state: watch::Receiver<LinkState>,
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
    /// The first (or only) module of link `link`: it watches the link's
    /// traffic, events and busy line too.
    fn new(controller: Arc<dyn Controller>, poll: Option<PollCadence>) -> Connection {
        Connection::on_link(controller, poll, 0, true)
    }

    fn on_link(
        controller: Arc<dyn Controller>,
        poll: Option<PollCadence>,
        link: usize,
        watches_link: bool,
    ) -> Connection {
        controller.set_polling(poll);
        Connection {
            status: controller.status(),
            link_state: controller.link_state(),
            identity: controller.identity(),
            settings: controller.settings(),
            traffic: controller.traffic().filter(|_| watches_link),
            traffic_after: None,
            traffic_pause: TRAFFIC_BATCH,
            traffic_taken: tokio::time::Instant::now(),
            events: controller.events().filter(|_| watches_link),
            busy: controller.busy().filter(|_| watches_link),
            controller,
            link,
            gone: false,
            poll,
        }
    }

    /// The next thing that happens on this module.
    async fn wait(&mut self, traffic_shown: bool) -> ModuleWakeup {
        if self.gone {
            return std::future::pending().await;
        }
        // The traffic monitor brought to the front waits no longer than
        // its refresh for the frames that gathered behind its tab.
        let traffic_after = self.traffic_after.map(|at| {
            if traffic_shown {
                at.min(self.traffic_taken + TRAFFIC_BATCH)
            } else {
                at
            }
        });
        let traffic = async {
            match (self.traffic.as_mut(), traffic_after) {
                (Some(_), Some(at)) => {
                    tokio::time::sleep_until(at).await;
                    ModuleWakeup::TrafficDue
                }
                (Some(rx), None) => ModuleWakeup::Traffic(rx.recv().await),
                (None, _) => std::future::pending().await,
            }
        };
        let events = async {
            match self.events.as_mut() {
                Some(rx) => rx.recv().await,
                None => std::future::pending().await,
            }
        };
        let settings = async {
            match self.settings.as_mut() {
                Some(rx) => rx.changed().await,
                None => std::future::pending().await,
            }
        };
        let gone = |changed: Result<(), watch::error::RecvError>| match changed {
            Ok(()) => ModuleWakeup::Changed,
            Err(_) => ModuleWakeup::ChannelGone,
        };
        let busy = async {
            match self.busy.as_mut() {
                Some(rx) => match rx.changed().await {
                    Ok(()) => ModuleWakeup::Busy,
                    Err(_) => std::future::pending().await,
                },
                None => std::future::pending().await,
            }
        };
        tokio::select! {
            changed = self.status.changed() => gone(changed),
            changed = self.link_state.changed() => gone(changed),
            changed = self.identity.changed() => gone(changed),
            changed = settings => gone(changed),
            wakeup = traffic => wakeup,
            event = events => ModuleWakeup::Device(event),
            wakeup = busy => wakeup,
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
            link: self.link_state.borrow_and_update().clone(),
            identity: self.identity.borrow_and_update().clone(),
            poll: self.poll,
            settings: Arc::new(
                self.settings
                    .as_mut()
                    .map(|s| s.borrow_and_update().clone())
                    .unwrap_or_default(),
            ),
            mechanics: Arc::new(c.mechanics()),
        }
    }
}

/// Something the loop waits for, besides the app's own messages.
enum Wakeup {
    Input(Option<TermEvent>),
    /// Something happened on module `.0` of the list.
    Module(usize, ModuleWakeup),
    Internal(Option<AppEvent>),
    Connected(Result<Arc<dyn Controller>, String>),
    /// A link added beside the others opened (or not).
    Added(Result<Arc<dyn Controller>, String>),
}

/// Something that happened on one module (or its link).
enum ModuleWakeup {
    Changed,
    ChannelGone,
    Traffic(Result<TrafficRecord, broadcast::error::RecvError>),
    /// The busy line changed.
    Busy,
    /// The pause after a batch of traffic is over.
    TrafficDue,
    Device(Result<DeviceEvent, broadcast::error::RecvError>),
}

/// A future that may borrow.
type Borrowing<'a, T> = std::pin::Pin<Box<dyn Future<Output = T> + Send + 'a>>;

/// The first of `futures` to finish; pending while there are none.
async fn first_of<T>(mut futures: Vec<Borrowing<'_, T>>) -> T {
    std::future::poll_fn(|cx| {
        for future in futures.iter_mut() {
            if let std::task::Poll::Ready(value) = future.as_mut().poll(cx) {
                return std::task::Poll::Ready(value);
            }
        }
        std::task::Poll::Pending
    })
    .await
}

/// Every one of `futures`, polled together (each one's first poll comes
/// before any of them is waited for), their outputs in order.
pub async fn join_all<T>(futures: Vec<Pending<T>>) -> Vec<T> {
    let mut futures: Vec<(Pending<T>, Option<T>)> =
        futures.into_iter().map(|f| (f, None)).collect();
    std::future::poll_fn(|cx| {
        let mut waiting = false;
        for (future, output) in futures.iter_mut() {
            if output.is_none() {
                match future.as_mut().poll(cx) {
                    std::task::Poll::Ready(value) => *output = Some(value),
                    std::task::Poll::Pending => waiting = true,
                }
            }
        }
        if waiting {
            std::task::Poll::Pending
        } else {
            std::task::Poll::Ready(())
        }
    })
    .await;
    futures
        .into_iter()
        .filter_map(|(_, output)| output)
        .collect()
}

/// How long the console's wiring check jogs in one direction without a
/// limit switch before it gives up (as `axterm wiring`'s default).
const WIRING_GIVE_UP: Duration = Duration::from_secs(30);

/// The loop's side of the console: the connection and everything in
/// flight for the app.
struct Runner {
    /// Every module of every link, in the app's order
    /// ([`App::modules`]); lines go to the selected one.
    connections: Vec<Connection>,
    internal: mpsc::UnboundedSender<AppEvent>,
    /// Tasks sending lines, which the emergency stop aborts.
    sending: Vec<JoinHandle<()>>,
    connecting: Option<Pending<Result<Arc<dyn Controller>, String>>>,
    /// A link being added beside the others.
    adding: Option<Pending<Result<Arc<dyn Controller>, String>>>,
    connector: Connector,
    log: Option<TrafficLog>,
    /// The cancel handle of the last transfer started (one at a time:
    /// the session refuses a second). Not aborted by the emergency stop:
    /// the session cancels it, and its end is still reported.
    transfer: Option<Cancel>,
    /// The running wiring check, which [`Effect::CancelWiring`] ends (its
    /// task is in `sending` too, so the emergency stop ends it as well).
    wiring: Option<tokio::task::AbortHandle>,
    /// The running tuning job, which [`Effect::CancelTune`] ends (in
    /// `sending` too, so the emergency stop ends it as well).
    tune: Option<tokio::task::AbortHandle>,
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
    input: mpsc::UnboundedReceiver<TermEvent>,
    extra: Option<mpsc::UnboundedReceiver<AppEvent>>,
    draw: &mut (dyn FnMut(&mut App) -> std::io::Result<()> + Send),
) -> std::io::Result<()> {
    let links = controller.map(|c| vec![vec![c]]).unwrap_or_default();
    run_links(app, links, connector, input, extra, draw).await
}

/// [`run`] on several links at once, each with its modules (the first of
/// each watched for the link's traffic): the console's module list, the
/// first module selected.
pub async fn run_links(
    app: &mut App,
    links: Vec<Vec<Arc<dyn Controller>>>,
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
    let poll = Some(PollCadence::default());
    let connections = links
        .into_iter()
        .enumerate()
        .flat_map(|(link, modules)| {
            modules
                .into_iter()
                .enumerate()
                .map(move |(n, c)| Connection::on_link(c, poll, link, n == 0))
        })
        .collect();
    let mut runner = Runner {
        connections,
        internal,
        sending: Vec::new(),
        connecting: None,
        adding: None,
        connector,
        log: None,
        transfer: None,
        wiring: None,
        tune: None,
    };
    for index in 0..runner.connections.len() {
        let Some(c) = runner.connections.get_mut(index) else {
            break;
        };
        let (link, snapshot) = (c.link, c.snapshot(0));
        let event = match index {
            0 => AppEvent::Connected(snapshot),
            _ => AppEvent::Module {
                index,
                link,
                snapshot,
            },
        };
        runner.handle(app, event);
    }
    // A terminal that cannot be drawn on any more (the SSH session gone
    // before its SIGHUP came) ends the console as a signal does.
    let mut drawing_failed = None;
    loop {
        if app.should_quit() {
            break;
        }
        if app.needs_redraw()
            && let Err(e) = draw(app)
        {
            drawing_failed = Some(e);
            break;
        }
        let traffic_shown = app.is_on_screen(TRAFFIC_PANE);
        let wakeup = runner
            .wait(&mut input, &mut internal_rx, traffic_shown)
            .await;
        let traffic = match wakeup {
            Wakeup::Module(index, ModuleWakeup::Traffic(Ok(_)) | ModuleWakeup::TrafficDue) => {
                Some(index)
            }
            _ => None,
        };
        if let Some(event) = runner.event(app, wakeup) {
            runner.handle(app, event);
        }
        if let Some(index) = traffic {
            runner.take_traffic(app, index, traffic_shown);
        }
    }
    if let Some(log) = runner.log.take() {
        log.stop();
    }
    for c in &runner.connections {
        c.controller.set_polling(None);
    }
    for job in runner.sending {
        job.abort();
    }
    // A download leaves download mode before it ends.
    if let Some(cancel) = runner.transfer {
        cancel.cancel();
    }
    if app.terminated() || drawing_failed.is_some() {
        let report = stop_every_module(&runner.connections).await;
        app.set_parting_report(report);
    }
    match drawing_failed {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// The console ended from outside (SIGTERM, SIGHUP, SIGINT, its terminal
/// gone) must not leave a motor running that nobody can see any more: the
/// emergency stop of every module, as Ctrl-C gives a run in the command
/// line (`axterm run`), and what came back for each stop line.
async fn stop_every_module(connections: &[Connection]) -> Vec<String> {
    let mut report = Vec::new();
    for c in connections.iter().filter(|c| !c.gone) {
        let stop = RunStop {
            ending: RunEnding::Cancelled,
            lines: c.controller.emergency_stop().await,
            link: LinkAtStop::Up,
        };
        report.push(format!(
            "axterm: the console was ended from outside: stopping every axis of {} \
             (address {}):",
            c.controller.link_name(),
            c.controller.address()
        ));
        // The first line says why in a run's words; said above instead.
        report.extend(RunAftermath::Stopped(stop).report().into_iter().skip(1));
    }
    report
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
        let adding = &mut self.adding;
        let add = async {
            match adding.as_mut() {
                Some(pending) => pending.await,
                None => std::future::pending().await,
            }
        };
        let modules: Vec<Borrowing<'_, (usize, ModuleWakeup)>> = self
            .connections
            .iter_mut()
            .enumerate()
            .map(|(index, c)| -> Borrowing<'_, (usize, ModuleWakeup)> {
                Box::pin(async move { (index, c.wait(traffic_shown).await) })
            })
            .collect();
        tokio::select! {
            event = input.recv() => Wakeup::Input(event),
            event = internal.recv() => Wakeup::Internal(event),
            result = connect => Wakeup::Connected(result),
            result = add => Wakeup::Added(result),
            (index, wakeup) = first_of(modules) => Wakeup::Module(index, wakeup),
        }
    }

    /// What a wake-up means for the app, if anything.
    fn event(&mut self, app: &App, wakeup: Wakeup) -> Option<AppEvent> {
        Some(match wakeup {
            Wakeup::Input(Some(event)) => AppEvent::Terminal(event),
            Wakeup::Input(None) => AppEvent::Terminate,
            Wakeup::Module(index, wakeup) => return self.module_event(app, index, wakeup),
            Wakeup::Internal(event) => {
                let event = event?;
                if matches!(event, AppEvent::Tuned { .. }) {
                    // The job's last act is to say it is done: the next
                    // may start (a live watch asks for its next reading
                    // at once), though its task may not have ended yet.
                    self.tune = None;
                }
                event
            }
            Wakeup::Connected(result) => {
                self.connecting = None;
                match result {
                    Ok(controller) => {
                        let poll = self
                            .connections
                            .first()
                            .map_or(Some(PollCadence::default()), |c| c.poll);
                        self.disconnect();
                        let others = controller.other_modules();
                        let mut c = Connection::new(controller, poll);
                        let snapshot = c.snapshot(0);
                        self.connections = vec![c];
                        self.join_link(others, 0, poll);
                        AppEvent::Connected(snapshot)
                    }
                    Err(message) => AppEvent::Notice(Notice::error(message)),
                }
            }
            Wakeup::Added(result) => {
                self.adding = None;
                match result {
                    Ok(controller) => {
                        let poll = self
                            .connections
                            .first()
                            .map_or(Some(PollCadence::default()), |c| c.poll);
                        let link = self.connections.iter().map(|c| c.link + 1).max();
                        let link = link.unwrap_or(0);
                        let others = controller.other_modules();
                        let mut c = Connection::on_link(controller, poll, link, true);
                        let snapshot = c.snapshot(0);
                        let index = self.connections.len();
                        self.connections.push(c);
                        self.join_link(others, link, poll);
                        if index == 0 {
                            AppEvent::Connected(snapshot)
                        } else {
                            AppEvent::Module {
                                index,
                                link,
                                snapshot,
                            }
                        }
                    }
                    Err(message) => AppEvent::Notice(Notice::error(message)),
                }
            }
        })
    }

    /// What happened on module `index` means for the app, if anything.
    fn module_event(&mut self, app: &App, index: usize, wakeup: ModuleWakeup) -> Option<AppEvent> {
        let selected = index == app.selected_module();
        let alone = self.connections.len() == 1;
        let c = self.connections.get_mut(index)?;
        Some(match wakeup {
            ModuleWakeup::Changed => {
                let axis = match app.modules().get(index) {
                    Some(entry) => entry.snapshot.axis,
                    None => 0,
                };
                let axis = if selected {
                    app.snapshot().map_or(axis, |s| s.axis)
                } else {
                    axis
                };
                let snapshot = c.snapshot(axis);
                if selected && alone {
                    AppEvent::Snapshot(snapshot)
                } else {
                    AppEvent::Module {
                        index,
                        link: c.link,
                        snapshot,
                    }
                }
            }
            ModuleWakeup::ChannelGone => {
                if alone {
                    self.disconnect();
                    return Some(AppEvent::Disconnected);
                }
                // One of several: it stays listed as it was last seen.
                c.gone = true;
                c.controller.set_polling(None);
                return None;
            }
            ModuleWakeup::Busy => {
                let busy = c.busy.as_mut()?;
                AppEvent::Busy(busy.borrow_and_update().clone())
            }
            ModuleWakeup::Traffic(Ok(record)) => AppEvent::LinkTraffic {
                link: c.link,
                record,
            },
            ModuleWakeup::TrafficDue => return None,
            ModuleWakeup::Device(Ok(event)) => AppEvent::Device(event),
            ModuleWakeup::Traffic(Err(broadcast::error::RecvError::Closed))
            | ModuleWakeup::Device(Err(broadcast::error::RecvError::Closed)) => {
                c.traffic = None;
                c.events = None;
                return None;
            }
            // A pane that could not keep up misses some traffic; the next
            // record comes.
            ModuleWakeup::Traffic(Err(_)) | ModuleWakeup::Device(Err(_)) => return None,
        })
    }

    /// Hand the panes every traffic record waiting, and pause before
    /// taking more if there were any ([`traffic_pause`]; otherwise the
    /// next record wakes the loop at once).
    fn take_traffic(&mut self, app: &mut App, index: usize, traffic_shown: bool) {
        let Some(c) = self.connections.get_mut(index) else {
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
        let link = c.link;
        for record in records {
            self.handle(app, AppEvent::LinkTraffic { link, record });
        }
    }

    /// Let go of every connection: no polling, no log.
    fn disconnect(&mut self) {
        if let Some(log) = self.log.take() {
            log.stop();
        }
        for old in self.connections.drain(..) {
            old.controller.set_polling(None);
        }
    }

    /// More modules of link `link` join the list (a bus opened with an
    /// address list): each told to the app after the link's first.
    fn join_link(
        &mut self,
        modules: Vec<Arc<dyn Controller>>,
        link: usize,
        poll: Option<PollCadence>,
    ) {
        for controller in modules {
            let mut c = Connection::on_link(controller, poll, link, false);
            let snapshot = c.snapshot(0);
            let index = self.connections.len();
            self.connections.push(c);
            let _ = self.internal.send(AppEvent::Module {
                index,
                link,
                snapshot,
            });
        }
    }

    /// The selected module, where lines go.
    fn selected(&self, app: &App) -> Option<&Connection> {
        self.connections.get(app.selected_module())
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
        let stop = matches!(effect, Effect::SendStop { .. });
        let not_connected = || {
            AppEvent::Notice(Notice::error(
                "not connected: give :connect --sim tmcm1110 (or --port PATH, --tcp HOST:PORT)",
            ))
        };
        match effect {
            Effect::Send { pane, tag, lines } | Effect::SendStop { pane, tag, lines } => {
                let Some(c) = self.selected(app) else {
                    queue.push(not_connected());
                    return;
                };
                let controller = Arc::clone(&c.controller);
                let tx = self.internal.clone();
                self.sending.push(tokio::spawn(async move {
                    for line in lines {
                        let result = if stop {
                            controller.execute_stop(line.clone()).await
                        } else {
                            controller.execute(line.clone()).await
                        };
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
            Effect::ReadAgreed { pane, tag, line } => {
                let Some(c) = self.selected(app) else {
                    queue.push(not_connected());
                    return;
                };
                let controller = Arc::clone(&c.controller);
                let tx = self.internal.clone();
                // Kept with the other sends: the stop key aborts it too.
                self.sending.push(tokio::spawn(async move {
                    let result = controller.read_agreed(line.clone()).await;
                    let _ = tx.send(AppEvent::Reply {
                        pane,
                        tag,
                        line,
                        result,
                    });
                }));
            }
            Effect::EmergencyStop => {
                // Lines still waiting to be sent must not go after the stop.
                for job in self.sending.drain(..) {
                    job.abort();
                }
                // Every module of every link, at once: each stop is
                // queued on its link at emergency-stop priority before
                // any of them is waited for.
                let stops: Vec<_> = self
                    .connections
                    .iter()
                    .filter(|c| !c.gone)
                    .map(|c| c.controller.emergency_stop())
                    .collect();
                if stops.is_empty() {
                    queue.push(AppEvent::Stopped(Vec::new()));
                    return;
                }
                let tx = self.internal.clone();
                tokio::spawn(async move {
                    let results = join_all(stops).await;
                    let _ = tx.send(AppEvent::Stopped(results.concat()));
                });
            }
            Effect::AbortLine | Effect::PauseLine => {
                let Some(c) = self.selected(app) else {
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
                let Some(c) = self.selected(app) else {
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
            Effect::CheckRunEnd {
                pane,
                check,
                policy,
            } => {
                let Some(c) = self.selected(app) else {
                    queue.push(not_connected());
                    return;
                };
                let controller = Arc::clone(&c.controller);
                let tx = self.internal.clone();
                tokio::spawn(async move {
                    let found = controller.check_run_end(check).await;
                    if let Some(said) = found.said {
                        let notice = if found.alarming {
                            Notice::error(said)
                        } else {
                            Notice::warning(said)
                        };
                        let _ = tx.send(AppEvent::Notice(notice));
                    }
                    if found.ending != RunEnding::Completed {
                        let aftermath = controller.end_run(found.ending, policy).await;
                        let _ = tx.send(AppEvent::RunEnded { pane, aftermath });
                    }
                });
            }
            Effect::Poll(cadence) => {
                // The rate is the console's: every module polls at it.
                if self.connections.is_empty() {
                    queue.push(not_connected());
                }
                let selected = app.selected_module();
                let several = self.connections.len() > 1;
                for (index, c) in self.connections.iter_mut().enumerate() {
                    c.poll = cadence;
                    c.controller.set_polling(cadence);
                    if index == selected {
                        let axis = app.snapshot().map_or(0, |s| s.axis);
                        let snapshot = c.snapshot(axis);
                        queue.push(if several {
                            AppEvent::Module {
                                index,
                                link: c.link,
                                snapshot,
                            }
                        } else {
                            AppEvent::Snapshot(snapshot)
                        });
                    }
                }
            }
            Effect::SetAddress(address) => {
                let Some(c) = self.selected(app) else {
                    queue.push(not_connected());
                    return;
                };
                let (poll, link) = (c.poll, c.link);
                let controller = c.controller.with_address(address);
                let index = app.selected_module();
                if self.connections.len() == 1 {
                    self.disconnect();
                    let mut fresh = Connection::new(controller, poll);
                    let axis = app.snapshot().map_or(0, |s| s.axis);
                    queue.push(AppEvent::Snapshot(fresh.snapshot(axis)));
                    self.connections.push(fresh);
                    return;
                }
                // One module of several: only it changes address.
                let watches_link = self
                    .connections
                    .get(index)
                    .is_some_and(|c| c.traffic.is_some());
                if let Some(old) = self.connections.get_mut(index) {
                    old.controller.set_polling(None);
                    let mut fresh = Connection::on_link(controller, poll, link, watches_link);
                    let axis = app.snapshot().map_or(0, |s| s.axis);
                    queue.push(AppEvent::Module {
                        index,
                        link,
                        snapshot: fresh.snapshot(axis),
                    });
                    *old = fresh;
                }
            }
            Effect::ClearErrors { axis, seen } => {
                let Some(c) = self.selected(app) else {
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
                let Some((path, existing)) = path else {
                    return;
                };
                if self.selected(app).is_none() {
                    queue.push(not_connected());
                    return;
                }
                // One connection of each link: a bus's modules share it.
                let mut links: Vec<&Connection> = Vec::new();
                for c in self.connections.iter().filter(|c| !c.gone) {
                    if !links.iter().any(|l| l.link == c.link) {
                        links.push(c);
                    }
                }
                match TrafficLog::start(&path, existing, &links, &self.internal) {
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
            Effect::AddLink(args) => {
                self.adding = Some((self.connector)(args));
            }
            Effect::Wake { pane, tag, after } => {
                let tx = self.internal.clone();
                tokio::spawn(async move {
                    tokio::time::sleep(after).await;
                    let _ = tx.send(AppEvent::Wake { pane, tag });
                });
            }
            Effect::Transfer { pane, tag, job } => {
                let Some(c) = self.connections.get(app.selected_module()) else {
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
                let result = match self.selected(app) {
                    Some(c) => c.controller.load_program(&source),
                    None => Err("not connected: nothing to load into".to_string()),
                };
                queue.push(AppEvent::ProgramLoaded { pane, tag, result });
            }
            Effect::Mechanics(table) => {
                let Some(c) = self.selected(app) else {
                    queue.push(not_connected());
                    return;
                };
                let axes: Vec<String> = table.axes.keys().map(u8::to_string).collect();
                let notice = match c.controller.set_mechanics(table) {
                    Ok(()) if axes.is_empty() => {
                        Notice::info("no mechanics in force: raw values only")
                    }
                    Ok(()) => Notice::info(format!(
                        "mechanics of axis {} in force: values may be given and are shown in their units",
                        axes.join(", ")
                    )),
                    Err(message) => Notice::error(format!(":mechanics: {message}")),
                };
                queue.push(AppEvent::Notice(notice));
            }
            Effect::CheckWiring {
                pane,
                tag,
                axis,
                speed,
            } => {
                let Some(c) = self.selected(app) else {
                    queue.push(AppEvent::WiringChecked {
                        pane,
                        tag,
                        result: Err("not connected: nothing to check".into()),
                    });
                    return;
                };
                if self.wiring.as_ref().is_some_and(|w| !w.is_finished()) {
                    queue.push(AppEvent::WiringChecked {
                        pane,
                        tag,
                        result: Err("a wiring check is running already".into()),
                    });
                    return;
                }
                let check = c.controller.check_wiring(axis, speed, WIRING_GIVE_UP);
                let tx = self.internal.clone();
                let job = tokio::spawn(async move {
                    let result = check.await;
                    let _ = tx.send(AppEvent::WiringChecked { pane, tag, result });
                });
                self.wiring = Some(job.abort_handle());
                self.sending.push(job);
            }
            Effect::Tune { pane, tag, job } => {
                let Some(c) = self.selected(app) else {
                    queue.push(AppEvent::Tuned {
                        pane,
                        tag,
                        result: Err("not connected: nothing to tune".into()),
                    });
                    return;
                };
                if self.tune.as_ref().is_some_and(|t| !t.is_finished()) {
                    queue.push(AppEvent::Tuned {
                        pane,
                        tag,
                        result: Err("a tuning run is under way already".into()),
                    });
                    return;
                }
                let run = c.controller.tune(job);
                let tx = self.internal.clone();
                let task = tokio::spawn(async move {
                    let result = run.await;
                    let _ = tx.send(AppEvent::Tuned { pane, tag, result });
                });
                self.tune = Some(task.abort_handle());
                self.sending.push(task);
            }
            Effect::ReadSettings { pane, tag, sent } => {
                let Some(c) = self.selected(app) else {
                    queue.push(AppEvent::SettingsRead {
                        pane,
                        tag,
                        result: Err("not connected".into()),
                    });
                    return;
                };
                let read = c.controller.read_settings(sent);
                let tx = self.internal.clone();
                self.sending.push(tokio::spawn(async move {
                    let result = read.await;
                    let _ = tx.send(AppEvent::SettingsRead { pane, tag, result });
                }));
            }
            Effect::CancelTune => {
                if let Some(tune) = self.tune.take() {
                    tune.abort();
                }
            }
            Effect::CancelWiring => {
                if let Some(wiring) = self.wiring.take() {
                    wiring.abort();
                }
            }
            Effect::DriveSimInput(setting) => {
                let Some(c) = self.selected(app) else {
                    queue.push(not_connected());
                    return;
                };
                let notice = match c.controller.drive_sim_input(&setting) {
                    Ok(said) => Notice::info(format!("simulator input: {said}")),
                    Err(message) => Notice::error(format!(":sim-input {setting}: {message}")),
                };
                queue.push(AppEvent::Notice(notice));
            }
            Effect::Watch {
                axis,
                line,
                on,
                fast,
            } => {
                let Some(c) = self.selected(app) else {
                    queue.push(not_connected());
                    return;
                };
                if let Err(message) = c.controller.watch(axis, &line, on, fast) {
                    queue.push(AppEvent::Notice(Notice::error(format!(
                        "cannot poll {line}: {message}"
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
