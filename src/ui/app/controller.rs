//! The controller as the console drives it, and how `:connect` opens one.

use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;

use tokio::sync::{broadcast, watch};

use crate::device::{Busy, DeviceEvent, LinkState, TrafficRecord};
use crate::protocol::Family;
use crate::protocol::program::{Progress, TransferFailure, TransferJob, TransferReport};
use crate::protocol::settings::SettingsCache;
use crate::session::Cancel;
use crate::session::run_end::{
    AtTheEnd, EndCheck, LinkAtStop, RunAftermath, RunEnding, RunStop, StopOnFailure,
};
use crate::session::{AxisFlag, AxisInfo, AxisStatus, LineResult, PollCadence, SessionError};

/// A future the loop can spawn.
/// What the wiring check found: its lines, and whether each switch fired
/// for its own direction and stopped the axis.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WiringFindings {
    pub lines: Vec<String>,
    pub wired_right: bool,
    /// The lines of each faulty leg ([`crate::session::wiring::faults`]):
    /// what a commissioning sheet's verdict names.
    pub faults: Vec<String>,
}

pub type Pending<T> = Pin<Box<dyn Future<Output = T> + Send>>;

/// What the tuning pane asks the controller to do
/// ([`crate::session::tuning`]), on one axis.
#[derive(Debug, Clone, PartialEq)]
pub enum TuneJob {
    /// Read the axis's gains ([`crate::session::Session::read_gains`]).
    Gains { axis: usize },
    /// A step-response test ([`crate::session::Session::step_response`]).
    Step {
        axis: usize,
        ask: crate::protocol::tuning::StepAsk,
        /// The settling band, counts either side of the target.
        band: f64,
    },
    /// A load sweep ([`crate::session::Session::stall_sweep`]).
    Sweep {
        axis: usize,
        ask: crate::protocol::tuning::SweepAsk,
    },
    /// The start of a live current watch
    /// ([`crate::session::Session::begin_current_watch`]): write `set`,
    /// read the form, and with `run` (a direction and a speed) start the
    /// motor, which is left turning. Without either it only reads the
    /// form.
    CurrentStart {
        axis: usize,
        set: Vec<(String, i64)>,
        run: Option<(crate::protocol::jog::Direction, i64)>,
    },
    /// One reading of a live current watch, `wait` after the job starts
    /// ([`crate::session::Session::read_current`]), timed from `began`
    /// and taken to the full current `full`.
    CurrentRead {
        axis: usize,
        full: Option<i64>,
        began: tokio::time::Instant,
        wait: std::time::Duration,
    },
}

/// What a [`TuneJob`] gave.
#[derive(Debug, Clone, PartialEq)]
pub enum TuneOutcome {
    Gains(Vec<(&'static str, Option<f64>)>),
    Step(crate::session::tuning::StepRun),
    Sweep(crate::session::tuning::SweepRun),
    /// The form and the full current as read; no samples.
    CurrentStarted(crate::session::tuning::CurrentRun),
    CurrentRead(crate::session::tuning::CurrentSample),
}

/// The controller as the console drives it: a [`crate::session::Session`],
/// or a fake in tests.
pub trait Controller: Send + Sync {
    fn family(&self) -> &'static Family;
    fn address(&self) -> u8;
    fn axes(&self) -> Vec<AxisInfo>;
    /// The link as the user named it.
    fn link_name(&self) -> String;
    fn status(&self) -> watch::Receiver<Vec<AxisStatus>>;
    fn link_state(&self) -> watch::Receiver<LinkState>;
    fn identity(&self) -> watch::Receiver<Option<String>>;
    /// The settings written this session, for a module that cannot be
    /// asked for them ([`crate::session::Session::settings`]); `None`
    /// (the default) when the controller keeps none.
    fn settings(&self) -> Option<watch::Receiver<SettingsCache>> {
        None
    }
    fn traffic(&self) -> Option<broadcast::Receiver<TrafficRecord>>;
    fn events(&self) -> Option<broadcast::Receiver<DeviceEvent>>;
    /// Send one line at user priority (values in an axis's unit
    /// converted with the mechanics in force and the module's settings
    /// first, where the controller converts).
    fn execute(&self, line: String) -> Pending<Result<LineResult, SessionError>>;
    /// Send one line that stops motion ahead of everything queued
    /// ([`crate::session::Session::execute_stop_line`]). By default: as
    /// [`Controller::execute`].
    fn execute_stop(&self, line: String) -> Pending<Result<LineResult, SessionError>> {
        self.execute(line)
    }
    /// The axes' mechanics in force (none by default).
    fn mechanics(&self) -> crate::protocol::units::MechanicsTable {
        crate::protocol::units::MechanicsTable::default()
    }
    /// Take `table` as the mechanics in force, for every module of the
    /// console; refused by default (a controller that converts nothing).
    fn set_mechanics(&self, table: crate::protocol::units::MechanicsTable) -> Result<(), String> {
        let _ = table;
        Err(format!("{} converts no units", self.link_name()))
    }
    /// Read `line` at user priority until two answers agree where the
    /// family's answers carry no check
    /// ([`crate::session::Session::read_agreed`]). By default: once.
    fn read_agreed(&self, line: String) -> Pending<Result<LineResult, SessionError>> {
        self.execute(line)
    }
    /// Every stop line, ahead of everything queued; what came back for each.
    fn emergency_stop(&self) -> Pending<Vec<Result<LineResult, SessionError>>>;
    /// End a run that ended so under `policy`
    /// ([`crate::session::Session::end_run`]). By default: the stop lines
    /// of [`Controller::emergency_stop`] when the policy says so, without
    /// waiting for a lost link.
    fn end_run(&self, ending: RunEnding, policy: StopOnFailure) -> Pending<RunAftermath> {
        let stop = policy.stops_after(ending).then(|| self.emergency_stop());
        Box::pin(RunAftermath::of(ending, policy, move || async move {
            RunStop {
                ending,
                lines: match stop {
                    Some(stop) => stop.await,
                    None => Vec::new(),
                },
                link: LinkAtStop::Up,
            }
        }))
    }
    /// Check the axes at the end of a run that completed
    /// ([`crate::session::Session::check_run_end`]). By default nothing is
    /// known to move.
    fn check_run_end(&self, check: AtTheEnd) -> Pending<EndCheck> {
        let _ = check;
        Box::pin(async { EndCheck::completed() })
    }
    /// The wiring check of axis `axis` ([`crate::session::Session::check_wiring`]
    /// with the family's jog plan at `speed`): its findings, a plain line
    /// each, and whether they found the axis wired right. By default the
    /// connection cannot.
    fn check_wiring(
        &self,
        axis: usize,
        speed: i64,
        give_up: std::time::Duration,
    ) -> Pending<Result<WiringFindings, String>> {
        let _ = (axis, speed, give_up);
        Box::pin(async { Err("this connection cannot run the wiring check".to_string()) })
    }
    /// A tuning job with the family's tuning plan: what it gave, or why
    /// not. By default the connection cannot.
    fn tune(&self, job: TuneJob) -> Pending<Result<TuneOutcome, String>> {
        let _ = job;
        Box::pin(async { Err("this connection cannot run the tuning tools".to_string()) })
    }
    /// The module's settings that have a factory default, read now
    /// ([`crate::session::sheet::read_settings`]; `sent`: the canonical
    /// lines sent that succeeded). By default the connection cannot.
    fn read_settings(&self, sent: Vec<String>) -> Pending<Result<crate::report::Settings, String>> {
        let _ = sent;
        Box::pin(async { Err("this connection cannot read settings".to_string()) })
    }
    fn set_polling(&self, cadence: Option<PollCadence>);
    /// The line the controller is busy with, if any: a line that runs until
    /// its answer ([`crate::session::Session::busy`]). `None` when the
    /// controller never is.
    fn busy(&self) -> Option<watch::Receiver<Option<Busy>>> {
        None
    }
    /// Abort the line the controller is busy with: whether there was one.
    fn abort_line(&self) -> Pending<bool> {
        Box::pin(async { false })
    }
    /// Pause or resume the line the controller is busy with: whether it is
    /// paused now; `None` when no line that can pause is running.
    fn pause_line(&self) -> Pending<Option<bool>> {
        Box::pin(async { None })
    }
    fn acknowledge_errors(&self, axis: usize, seen: &[AxisFlag]);
    /// Poll `line` (a read of `axis`) with the status (`on`) or no longer
    /// ([`crate::session::Session::watch_at`]), with the fast status
    /// items when `fast`. By default it cannot.
    fn watch(&self, axis: usize, line: &str, on: bool, fast: bool) -> Result<(), String> {
        let _ = (axis, on, fast);
        Err(format!(
            "this connection cannot poll {line} with the status"
        ))
    }
    /// Clear the error flags of `axis` in the module where its family
    /// needs a line for that (CMD-4CR `CLRX`), then forget those the user
    /// has seen; what the clear line brought back, if one was sent. By
    /// default only forgets them.
    fn clear_errors(
        &self,
        axis: usize,
        seen: Vec<AxisFlag>,
    ) -> Pending<Result<Option<LineResult>, SessionError>> {
        self.acknowledge_errors(axis, &seen);
        Box::pin(async { Ok(None) })
    }
    /// The same link, sending to another module address.
    fn with_address(&self, address: u8) -> Arc<dyn Controller>;
    /// The other modules on the same link that were opened with this one
    /// (`--address 1-4`: modules 2, 3 and 4), each its own controller,
    /// for the console's module list. None by default.
    fn other_modules(&self) -> Vec<Arc<dyn Controller>> {
        Vec::new()
    }
    /// Run a program transfer, telling `progress` how far it came;
    /// `cancel` stops it between two words (so does the emergency stop).
    /// Controllers without program memory refuse.
    fn transfer(
        &self,
        job: TransferJob,
        cancel: Cancel,
        progress: Box<dyn FnMut(Progress) + Send>,
    ) -> Pending<Result<TransferReport, TransferFailure>> {
        let _ = (job, cancel, progress);
        let family = self.family().name;
        Box::pin(async move {
            Err(TransferFailure::refused(format!(
                "{family} modules keep no program that axterm can transfer"
            )))
        })
    }
    /// Load program source into the simulator behind the link, as its
    /// vendor's tool would write it into the controller: what it holds
    /// now, or why not. Only a simulator in this process can; a real
    /// controller (or a served simulator) refuses.
    fn load_program(&self, source: &str) -> Result<String, String> {
        let _ = source;
        Err(format!(
            "{} is no simulator in this process: there is no program memory to load into",
            self.link_name()
        ))
    }
    /// Drive an input of the simulator behind the link by a setting
    /// (`IO5=1`, [`crate::sim::SimulatedController::drive_input`]): what
    /// now holds, or why not. Only a simulator in this process can; a
    /// real controller (or a served simulator) refuses.
    fn drive_sim_input(&self, setting: &str) -> Result<String, String> {
        let _ = setting;
        Err(no_simulator_to_drive(&self.link_name()))
    }
}

/// Why `:sim-input` does nothing on `link`.
pub fn no_simulator_to_drive(link: &str) -> String {
    format!(
        "{link} is no simulator in this process: there is no input to drive \
         (a real controller's inputs are wired; a served `axterm sim` reads settings on its standard input)"
    )
}

/// Opens a connection for `:connect` (and the connect screen).
pub type Connector =
    Box<dyn Fn(Vec<String>) -> Pending<Result<Arc<dyn Controller>, String>> + Send>;
