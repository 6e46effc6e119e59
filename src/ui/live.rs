//! The console on a real terminal and a real session: [`Controller`] for
//! [`Session`], and [`run_terminal`], which holds the terminal, watches
//! for SIGTERM/SIGHUP and runs the loop.

use std::io::{self, Write};
use std::path::PathBuf;
use std::sync::Arc;

use super::diff_backend::DiffBackend;
use ratatui::Terminal;
use tokio::sync::{broadcast, mpsc, watch};

use super::app::{self, App, AppEvent, Connector, Controller, Pending};
use super::keymap::choose_keymap;
use super::pane::Notice;
use super::terminal::{TerminalGuard, spawn_reader};
use super::theme::{choose_theme, no_color_in_env};
use super::{PaneSetup, panes};
use crate::device::{Busy, DeviceEvent, LinkState, TrafficRecord};
use crate::link::SharedSim;
use crate::protocol::Family;
use crate::protocol::program::{Progress, TransferFailure, TransferJob, TransferReport};
use crate::protocol::settings::SettingsCache;
use crate::protocol::units::{MechanicsTable, SharedMechanics};
use crate::session::Cancel;
use crate::session::run_end::{AtTheEnd, EndCheck, RunAftermath, RunEnding, StopOnFailure};
use crate::session::{
    AxisFlag, AxisInfo, AxisStatus, LineResult, PollCadence, Session, SessionError, SessionOptions,
};

/// A session as the console drives it.
pub struct SessionController {
    session: Session,
    /// The link as the user named it.
    link_name: String,
    options: SessionOptions,
    /// The simulator behind the link, when it runs in this process.
    simulator: Option<SharedSim>,
    /// The other module addresses on the link opened with this one
    /// ([`Controller::other_modules`]).
    others: Vec<u8>,
    /// The mechanics in force, shared with every controller of the console.
    mechanics: SharedMechanics,
}

impl SessionController {
    pub fn new(session: Session, link_name: String, options: SessionOptions) -> SessionController {
        SessionController {
            session,
            link_name,
            options,
            simulator: None,
            others: Vec::new(),
            mechanics: SharedMechanics::default(),
        }
    }

    /// The same, converting with the console's shared mechanics.
    pub fn with_mechanics(mut self, mechanics: SharedMechanics) -> SessionController {
        self.mechanics = mechanics;
        self
    }

    /// The same, with more modules on its link at `addresses` (a bus):
    /// the console lists each ([`Controller::other_modules`]).
    pub fn with_other_modules(mut self, addresses: Vec<u8>) -> SessionController {
        self.others = addresses;
        self
    }

    /// The same, with the in-process simulator the link reaches: programs
    /// can be loaded into it ([`Controller::load_program`]).
    pub fn with_simulator(mut self, simulator: SharedSim) -> SessionController {
        self.simulator = Some(simulator);
        self
    }
}

impl Controller for SessionController {
    fn family(&self) -> &'static Family {
        self.session.family()
    }

    fn address(&self) -> u8 {
        self.session.address()
    }

    fn axes(&self) -> Vec<AxisInfo> {
        self.session.axes().to_vec()
    }

    fn link_name(&self) -> String {
        self.link_name.clone()
    }

    fn status(&self) -> watch::Receiver<Vec<AxisStatus>> {
        self.session.status()
    }

    fn link_state(&self) -> watch::Receiver<LinkState> {
        self.session.link_state()
    }

    fn identity(&self) -> watch::Receiver<Option<String>> {
        self.session.identity()
    }

    fn settings(&self) -> Option<watch::Receiver<SettingsCache>> {
        Some(self.session.settings())
    }

    fn traffic(&self) -> Option<broadcast::Receiver<TrafficRecord>> {
        Some(self.session.device().traffic())
    }

    fn events(&self) -> Option<broadcast::Receiver<DeviceEvent>> {
        Some(self.session.device().events())
    }

    fn execute(&self, line: String) -> Pending<Result<LineResult, SessionError>> {
        let session = self.session.clone();
        let law = session.family().console.units();
        if !crate::protocol::units::has_units(law, &line) {
            return Box::pin(async move { session.execute_line(&line).await });
        }
        // Values in an axis's unit: converted with the module's settings,
        // read now; one that does not convert sends nothing.
        let mechanics = self
            .mechanics
            .read()
            .map(|m| m.clone())
            .unwrap_or_else(|e| e.into_inner().clone());
        Box::pin(async move {
            let known = session.settings().borrow().clone();
            let converted = session
                .convert_units(&line, &mechanics, &known)
                .await
                .map_err(|message| SessionError::Refused {
                    line: line.trim().to_string(),
                    message,
                })?;
            session
                .execute_line(&converted.line)
                .await
                .map_err(|e| match e {
                    SessionError::Refused { line, message } => SessionError::Refused {
                        line,
                        message: format!(
                            "{}, which the line does not take: {message}",
                            converted.notes.join(", ")
                        ),
                    },
                    other => other,
                })
        })
    }

    fn mechanics(&self) -> MechanicsTable {
        self.mechanics
            .read()
            .map(|m| m.clone())
            .unwrap_or_else(|e| e.into_inner().clone())
    }

    fn set_mechanics(&self, table: MechanicsTable) -> Result<(), String> {
        let axes = self.session.axes();
        if let Some(axis) = table
            .axes
            .keys()
            .find(|a| !axes.iter().any(|i| i.number == **a))
        {
            return Err(format!(
                "the mechanics give axis {axis}, which {} does not have",
                self.session.family().name
            ));
        }
        match self.mechanics.write() {
            Ok(mut m) => *m = table,
            Err(e) => *e.into_inner() = table,
        }
        Ok(())
    }

    fn read_agreed(&self, line: String) -> Pending<Result<LineResult, SessionError>> {
        let session = self.session.clone();
        Box::pin(async move {
            let prepared = session.prepare(&line)?;
            session.read_agreed(&prepared).await
        })
    }

    fn execute_stop(&self, line: String) -> Pending<Result<LineResult, SessionError>> {
        let session = self.session.clone();
        Box::pin(async move { session.execute_stop_line(&line).await })
    }

    fn emergency_stop(&self) -> Pending<Vec<Result<LineResult, SessionError>>> {
        let session = self.session.clone();
        Box::pin(async move { session.emergency_stop_lines().await })
    }

    fn end_run(&self, ending: RunEnding, policy: StopOnFailure) -> Pending<RunAftermath> {
        let session = self.session.clone();
        Box::pin(async move { session.end_run(ending, policy).await })
    }

    fn check_run_end(&self, check: AtTheEnd) -> Pending<EndCheck> {
        let session = self.session.clone();
        Box::pin(async move { session.check_run_end(check).await })
    }

    fn check_wiring(
        &self,
        axis: usize,
        speed: i64,
        give_up: std::time::Duration,
    ) -> Pending<Result<app::WiringFindings, String>> {
        let session = self.session.clone();
        Box::pin(async move {
            let plan = session
                .family()
                .console
                .jog()
                .ok_or_else(|| format!("the {} family has no jog", session.family().name))?;
            let name = session
                .axes()
                .get(axis)
                .map_or_else(|| format!("axis {axis}"), |a| a.name.to_string());
            match session.check_wiring(plan, axis, speed, give_up).await {
                Ok(legs) => Ok(app::WiringFindings {
                    lines: crate::session::wiring::findings(&name, &legs),
                    wired_right: crate::session::wiring::wired_right(&legs),
                    faults: crate::session::wiring::faults(&name, &legs),
                }),
                Err(error) => {
                    // The axis may still move: stop everything, as the
                    // command line's check does.
                    let _ = session.emergency_stop_lines().await;
                    Err(error.to_string())
                }
            }
        })
    }

    fn tune(&self, job: app::TuneJob) -> Pending<Result<app::TuneOutcome, String>> {
        let session = self.session.clone();
        Box::pin(async move {
            let family = session.family();
            let none = |tool: &str| format!("the {} family has no {tool}", family.name);
            let result = match job {
                app::TuneJob::Gains { axis } => {
                    let plan = family
                        .console
                        .step_response()
                        .ok_or_else(|| none("step test"))?;
                    session
                        .read_gains(plan, axis)
                        .await
                        .map(app::TuneOutcome::Gains)
                }
                app::TuneJob::Step { axis, ask, band } => {
                    let plan = family
                        .console
                        .step_response()
                        .ok_or_else(|| none("step test"))?;
                    session
                        .step_response(
                            plan,
                            axis,
                            &ask,
                            &crate::protocol::tuning::StepSpec {
                                band,
                                ..crate::protocol::tuning::StepSpec::default()
                            },
                        )
                        .await
                        .map(app::TuneOutcome::Step)
                }
                app::TuneJob::Sweep { axis, ask } => {
                    let plan = family
                        .console
                        .stall_sweep()
                        .ok_or_else(|| none("load sweep"))?;
                    session
                        .stall_sweep(plan, axis, &ask)
                        .await
                        .map(app::TuneOutcome::Sweep)
                }
                app::TuneJob::CurrentStart { axis, set, run } => {
                    let plan = family
                        .console
                        .current_control()
                        .ok_or_else(|| none("current control"))?;
                    let run = match run {
                        Some((direction, speed)) => Some(crate::session::tuning::WatchRun {
                            jog: family.console.jog().ok_or_else(|| none("jog"))?,
                            direction,
                            speed,
                        }),
                        None => None,
                    };
                    session
                        .begin_current_watch(plan, axis, &set, run)
                        .await
                        .map(app::TuneOutcome::CurrentStarted)
                }
                app::TuneJob::CurrentRead {
                    axis,
                    full,
                    began,
                    wait,
                } => {
                    let plan = family
                        .console
                        .current_control()
                        .ok_or_else(|| none("current control"))?;
                    tokio::time::sleep(wait).await;
                    session
                        .read_current(plan, axis, full, began)
                        .await
                        .map(app::TuneOutcome::CurrentRead)
                }
            };
            result.map_err(|error| error.to_string())
        })
    }

    fn read_settings(&self, sent: Vec<String>) -> Pending<Result<crate::report::Settings, String>> {
        let session = self.session.clone();
        Box::pin(async move { Ok(crate::session::sheet::read_settings(&session, &sent).await) })
    }

    fn set_polling(&self, cadence: Option<PollCadence>) {
        match cadence {
            Some(cadence) => self.session.start_polling(cadence),
            None => self.session.stop_polling(),
        }
    }

    fn busy(&self) -> Option<watch::Receiver<Option<Busy>>> {
        Some(self.session.busy())
    }

    fn abort_line(&self) -> Pending<bool> {
        let session = self.session.clone();
        Box::pin(async move { session.abort_line().await })
    }

    fn pause_line(&self) -> Pending<Option<bool>> {
        let session = self.session.clone();
        Box::pin(async move { session.pause_line().await })
    }

    fn acknowledge_errors(&self, axis: usize, seen: &[AxisFlag]) {
        self.session.acknowledge_errors(axis, seen);
    }

    fn watch(&self, axis: usize, line: &str, on: bool, fast: bool) -> Result<(), String> {
        if on {
            self.session
                .watch_at(axis, line, fast)
                .map_err(|e| e.to_string())
        } else {
            self.session.unwatch(axis, line);
            Ok(())
        }
    }

    fn clear_errors(
        &self,
        axis: usize,
        seen: Vec<AxisFlag>,
    ) -> Pending<Result<Option<LineResult>, SessionError>> {
        let session = self.session.clone();
        Box::pin(async move { session.clear_errors(axis, &seen).await })
    }

    fn with_address(&self, address: u8) -> Arc<dyn Controller> {
        let options = SessionOptions {
            address: Some(address),
            ..self.options.clone()
        };
        let session = self.session.at_address(address);
        identify_later(&session);
        Arc::new(SessionController {
            session,
            link_name: self.link_name.clone(),
            options,
            simulator: self.simulator.clone(),
            others: Vec::new(),
            mechanics: self.mechanics.clone(),
        })
    }

    fn other_modules(&self) -> Vec<Arc<dyn Controller>> {
        self.others
            .iter()
            .map(|&address| self.with_address(address))
            .collect()
    }

    fn load_program(&self, source: &str) -> Result<String, String> {
        let Some(simulator) = &self.simulator else {
            return Err(format!(
                "{} is no simulator in this process: there is no program memory to load into",
                self.link_name
            ));
        };
        // A panic elsewhere while holding the lock leaves a usable
        // simulator; carry on with it.
        let mut sim = simulator.lock().unwrap_or_else(|e| e.into_inner());
        sim.load_program(source)
            .map(|()| format!("loaded into the simulator ({})", self.link_name))
            .map_err(|problems| problems.join("; "))
    }

    fn drive_sim_input(&self, setting: &str) -> Result<String, String> {
        let Some(simulator) = &self.simulator else {
            return Err(app::no_simulator_to_drive(&self.link_name));
        };
        // As for load_program: a lock poisoned elsewhere still holds a
        // usable simulator.
        let mut sim = simulator.lock().unwrap_or_else(|e| e.into_inner());
        sim.drive_input(setting)
    }

    fn transfer(
        &self,
        job: TransferJob,
        cancel: Cancel,
        mut progress: Box<dyn FnMut(Progress) + Send>,
    ) -> Pending<Result<TransferReport, TransferFailure>> {
        let session = self.session.clone();
        Box::pin(async move { session.run_job(&job, &cancel, &mut *progress).await })
    }
}

/// Read the module's identity in the background: the status bar shows it
/// when it comes, and a module that does not answer is no reason to wait.
pub fn identify_later(session: &Session) {
    let session = session.clone();
    tokio::spawn(async move {
        let _ = session.identify().await;
    });
}

/// The console's colours and keys as asked for.
#[derive(Debug, Clone, Default)]
pub struct Appearance {
    /// `--theme`; `None`: `dark`, or `mono` under `NO_COLOR`.
    pub theme: Option<String>,
    /// `--keymap`; `None`: `default`.
    pub keymap: Option<String>,
    /// Where the user's themes/ and keymaps/ are.
    pub config_dir: Option<PathBuf>,
    /// Take the mouse (clicks focus panes, the wheel scrolls).
    pub mouse: bool,
}

/// Run the console on this process's terminal until the user quits or a
/// SIGTERM/SIGHUP comes. Must be called inside a tokio runtime. The
/// terminal is restored whatever happens.
pub async fn run_terminal(
    links: Vec<Vec<Arc<dyn Controller>>>,
    connector: Connector,
    setup: &PaneSetup,
    appearance: &Appearance,
) -> io::Result<()> {
    let config_dir = appearance.config_dir.as_deref();
    let theme = choose_theme(appearance.theme.as_deref(), no_color_in_env(), config_dir);
    let keymap = choose_keymap(appearance.keymap.as_deref(), config_dir);
    let (tx, signals) = mpsc::unbounded_channel();
    // A theme or keymap file with a mistake: said in the console, which
    // goes on with the built-in.
    for problem in [&theme.problem, &keymap.problem].into_iter().flatten() {
        let _ = tx.send(AppEvent::Notice(Notice::error(problem.to_string())));
    }
    let mut terminating = termination_signals()?;
    tokio::spawn(async move {
        while let Some(event) = terminating.recv().await {
            if tx.send(event).is_err() {
                break;
            }
        }
    });
    let guard = TerminalGuard::enter(appearance.mouse)?;
    let input = spawn_reader();
    // Not `Terminal::clear`: it asks the terminal where the cursor is, and
    // the answer would race the input thread (and never come over a dumb
    // pipe). The alternate screen starts blank; this makes sure.
    ratatui::crossterm::execute!(
        io::stdout(),
        ratatui::crossterm::terminal::Clear(ratatui::crossterm::terminal::ClearType::All)
    )?;
    let mut terminal = Terminal::new(DiffBackend::new(io::stdout()))?;
    let mut app = App::new(panes(setup), theme.value, keymap.value);
    app.set_config_dir(appearance.config_dir.clone());
    if links.is_empty() {
        // `axterm` alone: choose a connection first.
        app.focus("connect");
    }
    // The loop runs as a task of its own, not as the runtime's main
    // future: waking the main future from a task goes through the
    // runtime's wake-up file descriptor (a write and another epoll round)
    // every time, where waking a task costs no system call at all.
    let looping = tokio::spawn(async move {
        let result = app::run_links(
            &mut app,
            links,
            connector,
            input,
            Some(signals),
            &mut |app: &mut App| terminal.draw(|frame| app.render(frame)).map(|_| ()),
        )
        .await;
        (result, app.parting_report().to_vec())
    });
    let (result, parting) = match looping.await {
        Ok(done) => done,
        // A bug in the loop: the panic hook has given the terminal back
        // and printed the message; it goes on as the panic it is (exit
        // code 101), as it did before the loop became a task.
        Err(e) if e.is_panic() => std::panic::resume_unwind(e.into_panic()),
        Err(e) => (
            Err(io::Error::other(format!("the console loop failed: {e}"))),
            Vec::new(),
        ),
    };
    drop(guard);
    // After a SIGHUP the terminal may be gone: a report that cannot be
    // written is no reason to fail (`eprintln!` would panic).
    let mut stderr = io::stderr().lock();
    for line in parting {
        let _ = writeln!(stderr, "{line}");
    }
    result
}

/// SIGTERM, SIGHUP (the SSH session dropped) and SIGINT from outside, as
/// [`AppEvent::Terminate`]. Registered before the terminal is touched.
fn termination_signals() -> io::Result<mpsc::UnboundedReceiver<AppEvent>> {
    let (tx, rx) = mpsc::unbounded_channel();
    #[cfg(unix)]
    {
        use tokio::signal::unix::{SignalKind, signal};
        let mut terminate = signal(SignalKind::terminate())?;
        let mut hangup = signal(SignalKind::hangup())?;
        let mut interrupt = signal(SignalKind::interrupt())?;
        tokio::spawn(async move {
            tokio::select! {
                _ = terminate.recv() => {}
                _ = hangup.recv() => {}
                _ = interrupt.recv() => {}
            }
            let _ = tx.send(AppEvent::Terminate);
        });
    }
    #[cfg(not(unix))]
    {
        tokio::spawn(async move {
            let _ = tokio::signal::ctrl_c().await;
            let _ = tx.send(AppEvent::Terminate);
        });
    }
    Ok(rx)
}
