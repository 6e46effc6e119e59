//! The axis status pane: per axis, live from the session's snapshots,
//! position against target, speed against the maximum speed, the ramp
//! state (as the module reports it, else read from the speed) and what
//! the axis does (moving, at its target, stopped short of it:
//! [`AxisStatus::motion`]), the switch lamps, the load gauge or the family's lamps
//! (CMD-4CR: the MST inputs and waits) and the latched error flags
//! (cleared with F8, or `:clear`). The title and the status bar show the
//! poll rate asked for and the full refreshes a second the link gives.
//!
//! Positions and speeds show as the module counts them, or (the units key,
//! where the family converts them) in real-world units: the parameters a
//! conversion needs (TMCL: the microstep resolution and the pulse divisor,
//! §6.1) are read from the module each time the key switches to them, so a
//! setting changed meanwhile is taken into account.
//!
//! Each axis gets a card of three rows; cards sit side by side when the
//! pane is wide. When the pane is too low for the cards (6 axes at
//! 80×24), each axis gets one row.

use std::collections::{BTreeMap, HashMap};

use ratatui::Frame;
use ratatui::crossterm::event::KeyCode;
use ratatui::layout::Rect;
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use super::keymap::{Action, Context};
use super::pane::{
    Input, ModuleEntry, Outcome, Pane, PaneEvent, Region, Request, Snapshot, View, key_label,
};
use super::readable::{Offer, PaneClock, ReadableRate, status_difference};
use super::theme::{Role, Theme};
use crate::device::LinkState;
use crate::protocol::console::{AxisFlag, LoadScale, MotionPhase, ReplyValue};
use crate::protocol::parameters::{ParamOp, ParameterSet, Scope, SpeedUnit, StatusQuantity};
use crate::protocol::units::{InUnits, Quantity as UnitQuantity, to_units};
use crate::session::{AxisInfo, AxisMotion, AxisStatus};

mod ramp;
mod widgets;
pub use ramp::Ramp;
use widgets::*;
pub use widgets::{SUSPENDED, poll_text};

/// Rows of one axis card.
const CARD_ROWS: u16 = 3;

/// Characters a position column of the one-row-per-axis layout holds
/// however the value changes (`-999999`): a wider value widens every
/// row's column alike. Kept short so that five MCCL axes' rows keep their
/// lamps and errors at 80 columns.
const POSITION_COLUMN: usize = 7;

/// Characters a speed column holds (`-99999`).
const SPEED_COLUMN: usize = 6;

/// Characters a maximum speed column holds (`99999`: a maximum is never
/// negative, and changes only when someone sets it).
const MAX_SPEED_COLUMN: usize = 5;

/// Characters a following-error column holds (`-9999`: a servo trips at
/// its maximum following error long before more).
const FERR_COLUMN: usize = 5;

/// Whether the module's family reads a following error: its column is
/// kept from the first row on, not only once a value came.
fn reads_following_error(view: &View) -> bool {
    view.session.is_some_and(|s| {
        s.family
            .console
            .status_values()
            .contains(&crate::protocol::console::StatusValue::FollowingError)
    })
}
/// A card is at least this wide; wider panes put cards side by side.
const CARD_MIN_WIDTH: u16 = 84;
/// Columns between cards side by side.
const CARD_GAP: u16 = 2;
/// Snapshots with the same speed (below the maximum) before the axis
/// counts as moving at a constant speed rather than still ramping: every
/// reading makes a snapshot, and the speed is read about as often as the
/// position.
const STEADY_SNAPSHOTS: u32 = 4;

/// What the pane remembers of one axis between snapshots.
#[derive(Debug, Clone, Default)]
struct AxisMemory {
    speed: Option<i64>,
    ramp: Option<Ramp>,
    /// Snapshots since the speed last changed.
    unchanged: u32,
    /// The span of positions and targets drawn: the position gauge's
    /// range.
    low: i64,
    high: i64,
}

/// How the pane shows positions and speeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Units {
    /// As the module counts them.
    #[default]
    Raw,
    /// In real-world units: speeds in pps (positions in the module's
    /// steps) or in rpm (positions in revolutions).
    Real(SpeedUnit),
    /// In each axis's own unit from the mechanics in force (`mm`, `deg`),
    /// beside the raw value, by the family's unit law.
    Axis,
}

impl Units {
    /// For the pane's title.
    pub fn label(self) -> &'static str {
        match self {
            Units::Raw => "raw",
            Units::Real(SpeedUnit::Pps) => "pps",
            Units::Real(SpeedUnit::Rpm) => "rpm",
            Units::Axis => "axis units",
        }
    }

    /// What the units key switches to: raw, pps, rpm (where the family
    /// converts to them), the axes' own units (where mechanics are in
    /// force), raw…
    fn next(self, real: bool, axis: bool) -> Units {
        let order = [
            Units::Raw,
            Units::Real(SpeedUnit::Pps),
            Units::Real(SpeedUnit::Rpm),
            Units::Axis,
        ];
        let offered = |u: &Units| match u {
            Units::Raw => true,
            Units::Real(_) => real,
            Units::Axis => axis,
        };
        let at = order.iter().position(|u| *u == self).unwrap_or(0);
        order
            .iter()
            .cycle()
            .skip(at + 1)
            .take(order.len())
            .find(|u| offered(u))
            .copied()
            .unwrap_or(Units::Raw)
    }
}

/// Which module values were read from: another one needs them read again.
#[derive(Debug, Clone, PartialEq, Eq)]
struct ModuleKey {
    family: &'static str,
    link: String,
    address: u8,
}

impl ModuleKey {
    fn of(session: &Snapshot) -> ModuleKey {
        ModuleKey {
            family: session.family.name,
            link: session.link_name.clone(),
            address: session.address,
        }
    }

    fn is(&self, session: &Snapshot) -> bool {
        self.family == session.family.name
            && self.link == session.link_name
            && self.address == session.address
    }
}

/// The position, target, speed and maximum speed of an axis as shown.
struct ShownValues {
    position: String,
    target: String,
    speed: String,
    max_speed: String,
}

/// Axis gauges and lamps.
#[derive(Debug, Default)]
pub struct AxesPane {
    memory: Vec<AxisMemory>,
    units: Units,
    /// Per axis (index into the snapshot's axes), the parameters the
    /// family's status conversions need, as read from the module.
    inputs: Vec<BTreeMap<u16, i64>>,
    /// The module `inputs` were read from.
    inputs_of: Option<ModuleKey>,
    /// Reads in flight: tag → axis index and parameter number.
    reading: HashMap<u64, (usize, u16)>,
    next_tag: u64,
    /// Said in the title instead of the units key's hint: a family with
    /// no conversions, a read that failed. Until the next key.
    note: Option<String>,
    /// The controller runs a line that holds it busy: nothing is polled.
    busy: bool,
    /// The status as drawn: numbers change at a readable rate
    /// ([`super::readable`]), lamps and flags at once.
    drawn: ReadableRate<Vec<AxisStatus>>,
    /// The module `drawn` shows.
    drawn_of: Option<ModuleKey>,
    /// The status drawn of each module of several but the selected one
    /// (by index into [`View::modules`]), at the same readable rate.
    others_drawn: BTreeMap<usize, (ModuleKey, ReadableRate<Vec<AxisStatus>>)>,
    /// The wake-up asked for to draw numbers held back, if any.
    waking: Option<u64>,
    clock: PaneClock,
}

impl AxesPane {
    pub fn new() -> AxesPane {
        AxesPane::default()
    }

    /// The same, with "now" from `clock` (tests).
    pub fn with_clock(clock: PaneClock) -> AxesPane {
        AxesPane {
            clock,
            ..AxesPane::default()
        }
    }

    /// Take the snapshot's status for drawing, numbers at a readable
    /// rate; a wake-up to draw numbers held back, if one is needed.
    fn offer_status(&mut self, session: &Snapshot) -> Option<Request> {
        if !self.drawn_of.as_ref().is_some_and(|k| k.is(session)) {
            self.drawn.reset();
            self.drawn_of = Some(ModuleKey::of(session));
        }
        let now = self.clock.now();
        let offer = self.drawn.offer(&session.status, now, |shown, live| {
            status_difference(shown, live)
        });
        if offer == Offer::Shown {
            self.widen_spans();
        }
        match offer {
            Offer::Later(after) if self.waking.is_none() => {
                self.next_tag += 1;
                self.waking = Some(self.next_tag);
                Some(Request::WakeAfter {
                    after,
                    tag: self.next_tag,
                })
            }
            _ => None,
        }
    }

    /// Take module `index`'s status (not the selected module's) for
    /// drawing, as [`AxesPane::offer_status`]: whether to draw now, and a
    /// wake-up to draw numbers held back.
    fn offer_module(&mut self, index: usize, module: &Snapshot) -> (bool, Option<Request>) {
        let now = self.clock.now();
        let (key, drawn) = self
            .others_drawn
            .entry(index)
            .or_insert_with(|| (ModuleKey::of(module), ReadableRate::default()));
        if !key.is(module) {
            *key = ModuleKey::of(module);
            drawn.reset();
        }
        let offer = drawn.offer(&module.status, now, |shown, live| {
            status_difference(shown, live)
        });
        match offer {
            Offer::Shown => (true, None),
            Offer::Later(after) if self.waking.is_none() => {
                self.next_tag += 1;
                self.waking = Some(self.next_tag);
                let wake = Request::WakeAfter {
                    after,
                    tag: self.next_tag,
                };
                (false, Some(wake))
            }
            _ => (false, None),
        }
    }

    /// The status to draw of module `index` (not the selected one).
    fn module_status<'a>(&'a self, index: usize, module: &'a Snapshot) -> &'a [AxisStatus] {
        self.others_drawn
            .get(&index)
            .filter(|(key, _)| key.is(module))
            .and_then(|(_, drawn)| drawn.shown())
            .map_or(&module.status, |shown| shown.as_slice())
    }

    /// The status to draw of axis `index`.
    fn drawn_status(&self, index: usize, session: &Snapshot) -> AxisStatus {
        let drawn = self
            .drawn
            .shown()
            .filter(|_| self.drawn_of.as_ref().is_some_and(|k| k.is(session)))
            .unwrap_or(&session.status);
        drawn.get(index).cloned().unwrap_or_default()
    }

    /// How positions and speeds are shown now.
    pub fn units(&self) -> Units {
        self.units
    }

    /// The units key: raw, pps, rpm, raw… where the family converts;
    /// otherwise it says so.
    fn toggle_units(&mut self, session: &Snapshot) -> Outcome {
        let params = session.family.console.parameters();
        let real = params.is_some_and(|p| !p.status_inputs().is_empty());
        let axis = session.family.console.units().is_some() && !session.mechanics.is_empty();
        let Some(params) = params.filter(|_| real || axis) else {
            self.units = Units::Raw;
            // Axis units need mechanics: `:mechanics FILE` gives them.
            self.note = Some(format!(
                "{} has no real-world units: raw only{}",
                session.family.name,
                if session.family.console.units().is_some() {
                    " (:mechanics FILE)"
                } else {
                    ""
                }
            ));
            return Outcome::redraw();
        };
        self.units = self.units.next(real, axis);
        if self.units == Units::Raw {
            return Outcome::redraw();
        }
        Outcome::Handled(self.read_inputs(session, params))
    }

    /// The axis parameters of `axis` the units shown now convert with:
    /// the family's status inputs, or its unit law's (those the module
    /// can be asked for; the others come from what this session wrote).
    fn inputs_wanted(&self, session: &Snapshot, params: &dyn ParameterSet, axis: u8) -> Vec<u16> {
        match self.units {
            Units::Axis => {
                let Some(law) = session.family.console.units() else {
                    return Vec::new();
                };
                let readable: Vec<(Scope, u16)> = params
                    .tables(axis)
                    .iter()
                    .flat_map(|t| t.rows.iter())
                    .filter(|r| r.access.read)
                    .map(|r| (r.scope, r.number))
                    .collect();
                law.inputs(axis)
                    .into_iter()
                    .filter(|input| input.0 == Scope::Axis(axis) && readable.contains(input))
                    .map(|(_, number)| number)
                    .collect()
            }
            _ => params.status_inputs().to_vec(),
        }
    }

    /// Ask the module for what the conversions need, for every axis.
    fn read_inputs(&mut self, session: &Snapshot, params: &dyn ParameterSet) -> Vec<Request> {
        self.inputs = vec![BTreeMap::new(); session.axes.len()];
        self.inputs_of = Some(ModuleKey::of(session));
        self.reading.clear();
        let mut requests = Vec::new();
        for (index, axis) in session.axes.iter().enumerate() {
            let tables = params.tables(axis.number);
            for number in self.inputs_wanted(session, params, axis.number) {
                let row = tables
                    .iter()
                    .flat_map(|t| t.rows.iter())
                    .find(|r| r.scope == Scope::Axis(axis.number) && r.number == number);
                let line = match row {
                    Some(row) => params
                        .line(row, ParamOp::Read)
                        .map_err(|e| format!("cannot read {} of {}: {e}", row.name, axis.name)),
                    None => Err(format!(
                        "{} has no axis parameter {number} for {}",
                        session.family.name, axis.name
                    )),
                };
                match line {
                    Ok(line) => {
                        self.next_tag += 1;
                        self.reading.insert(self.next_tag, (index, number));
                        requests.push(Request::Send {
                            lines: vec![line],
                            tag: self.next_tag,
                        });
                    }
                    Err(message) => self.note = Some(message),
                }
            }
        }
        requests
    }

    /// A status value as the units say; a value that cannot be converted
    /// (what it needs not read yet, or unreadable) is marked raw.
    fn show(
        &self,
        index: usize,
        quantity: StatusQuantity,
        value: Option<i64>,
        view: &View,
    ) -> String {
        let Some(value) = value else {
            return number(None);
        };
        if self.units == Units::Axis {
            return self.in_axis_units(index, quantity, value, view);
        }
        let Units::Real(unit) = self.units else {
            return value.to_string();
        };
        let inputs = self.inputs.get(index);
        let axis_value = |n: u16| inputs.and_then(|m| m.get(&n)).copied();
        view.session
            .and_then(|s| s.family.console.parameters())
            .and_then(|p| p.status_physical(quantity, value, unit, &axis_value))
            .map_or_else(|| format!("{value} raw"), |p| p.to_string())
    }

    /// `value` beside itself in the axis's own unit (`102400 = 20.00 mm`);
    /// raw alone, marked, where the axis has no mechanics or a setting the
    /// law needs is not known.
    fn in_axis_units(
        &self,
        index: usize,
        quantity: StatusQuantity,
        value: i64,
        view: &View,
    ) -> String {
        let Some(session) = view.session else {
            return value.to_string();
        };
        let Some(axis) = session.axes.get(index) else {
            return value.to_string();
        };
        let (Some(law), Some(mechanics)) = (
            session.family.console.units(),
            session.mechanics.get(axis.number),
        ) else {
            return format!("{value} raw");
        };
        let quantity = match quantity {
            StatusQuantity::Position => UnitQuantity::Position,
            StatusQuantity::Speed => UnitQuantity::Speed,
        };
        let inputs = self.inputs.get(index);
        let value_of = |scope: Scope, number: u16| {
            let read = match scope {
                Scope::Axis(a) if a == axis.number => inputs.and_then(|m| m.get(&number)).copied(),
                _ => None,
            };
            read.or_else(|| session.settings.value(scope, number))
        };
        match to_units(
            law,
            mechanics,
            axis.number,
            quantity,
            value as f64,
            &value_of,
        ) {
            Ok(converted) => format!(
                "{value} = {}",
                InUnits {
                    value: converted,
                    quantity,
                    unit: &mechanics.unit
                }
            ),
            Err(_) => format!("{value} raw"),
        }
    }

    fn shown_values(&self, index: usize, status: &AxisStatus, view: &View) -> ShownValues {
        use StatusQuantity::{Position, Speed};
        ShownValues {
            position: self.show(index, Position, status.position, view),
            target: self.show(index, Position, status.target, view),
            speed: self.show(index, Speed, status.speed, view),
            max_speed: self.show(index, Speed, status.max_speed, view),
        }
    }

    /// Follow a new snapshot: speed trends.
    fn remember(&mut self, session: &Snapshot) {
        self.memory
            .resize(session.status.len(), AxisMemory::default());
        for (memory, status) in self.memory.iter_mut().zip(&session.status) {
            if status.speed != memory.speed {
                memory.ramp = Some(Ramp::from_speeds(
                    memory.speed,
                    status.speed,
                    status.max_speed,
                ));
                memory.speed = status.speed;
                memory.unchanged = 0;
            } else {
                // Snapshots change for other readings too: the speed is
                // steady only once it has been the same for a while.
                memory.unchanged = memory.unchanged.saturating_add(1);
                let steady = Ramp::from_speeds(status.speed, status.speed, status.max_speed);
                if memory.ramp.is_none()
                    || matches!(steady, Ramp::Standing | Ramp::Cruising | Ramp::Unknown)
                    || memory.unchanged >= STEADY_SNAPSHOTS
                {
                    memory.ramp = Some(steady);
                }
            }
        }
    }

    /// Widen the position gauges' ranges to the positions and targets
    /// drawn: a range that grew with every poll while the position drawn
    /// waits for its turn would move the gauge's fill back and forth.
    fn widen_spans(&mut self) {
        let Some(drawn) = self.drawn.shown() else {
            return;
        };
        self.memory.resize(drawn.len(), AxisMemory::default());
        for (memory, status) in self.memory.iter_mut().zip(drawn) {
            for value in [status.position, status.target].into_iter().flatten() {
                memory.low = memory.low.min(value);
                memory.high = memory.high.max(value);
            }
        }
    }

    /// What the axis is doing: as the module says where it does (CMD-4CR
    /// MST), else read from how its speed changes.
    fn ramp(&self, index: usize, status: &AxisStatus) -> Ramp {
        if let Some(phase) = status.phase {
            return Ramp::from_phase(phase, status.speed, status.max_speed);
        }
        self.memory
            .get(index)
            .and_then(|m| m.ramp)
            .unwrap_or_else(|| Ramp::from_speeds(None, status.speed, status.max_speed))
    }

    /// The position gauge's range for an axis: every position and target
    /// seen, and 0.
    fn span(&self, index: usize, status: &AxisStatus) -> (i64, i64) {
        let (mut low, mut high) = self.memory.get(index).map_or((0, 0), |m| (m.low, m.high));
        for value in [status.position, status.target].into_iter().flatten() {
            low = low.min(value);
            high = high.max(value);
        }
        (low, high)
    }

    fn card(
        &self,
        index: usize,
        axis: &AxisInfo,
        status: &AxisStatus,
        selected: bool,
        width: u16,
        view: &View,
    ) -> Vec<Line<'static>> {
        let theme = view.theme;
        let scale: Option<LoadScale> = view.session.and_then(|s| s.family.console.load_scale());
        let width = usize::from(width);
        let label_width = 10;
        let name = format!(
            "{}{:<w$}",
            if selected { "▶" } else { " " },
            short_name(axis.name, label_width - 1),
            w = label_width - 1
        );
        let name_style = if selected {
            theme.style(Role::Accent)
        } else {
            theme.style(Role::Title)
        };
        // Row 1: position, gauge, target, reached.
        let ShownValues {
            position,
            target,
            speed,
            max_speed: max,
        } = self.shown_values(index, status, view);
        // Numbers in real-world units carry their unit and may be wider.
        let w = [&position, &target, &speed, &max]
            .iter()
            .map(|t| t.chars().count())
            .max()
            .unwrap_or(0)
            .max(11);
        // What the axis does: a stop before the target is no move.
        let reached = match status.motion() {
            AxisMotion::AtTarget => lamp(theme, true, false, "reached"),
            AxisMotion::Moving => lamp(theme, false, false, "moving"),
            AxisMotion::StoppedShort => lamp(theme, false, false, "stopped short"),
            AxisMotion::Stopped => lamp(theme, false, false, "stopped"),
            AxisMotion::Unknown => lamp(theme, false, false, "reached?"),
        };
        // The widest fixed parts: label, "pos "/"spd ", number, " tgt "/
        // " max ", number, then the longest lamp (`○ stopped short`) or
        // ramp label (`constant speed`).
        let fixed = label_width + 4 + (w + 1) + 5 + (w + 1) + 15;
        // A closed loop's following error after the ramp: ` ferr -12345`,
        // as wide as any, so that the gauges keep their width.
        let fixed = fixed
            + if reads_following_error(view) || status.following_error.is_some() {
                6 + FERR_COLUMN
            } else {
                0
            };
        let gauge_width = width.saturating_sub(fixed).max(4);
        let (low, high) = self.span(index, status);
        let position_gauge = gauge(
            theme,
            status.position.map(|p| fraction(p, low, high)),
            status.target.map(|t| fraction(t, low, high)),
            gauge_width,
        );
        let mut row1 = vec![
            Span::styled(name, name_style),
            Span::styled("pos ", theme.style(Role::Muted)),
            Span::styled(format!("{position:>w$} "), theme.style(Role::Normal)),
        ];
        row1.extend(position_gauge);
        row1.push(Span::styled(" tgt ", theme.style(Role::Muted)));
        row1.push(Span::styled(
            format!("{target:>w$} "),
            theme.style(Role::Normal),
        ));
        row1.extend(reached);

        // Row 2: speed against max, ramp.
        let speed_fraction = match (status.speed, status.max_speed) {
            (Some(s), Some(m)) if m != 0 => {
                Some((s.unsigned_abs() as f64 / m.unsigned_abs() as f64).min(1.0))
            }
            (Some(0), _) => Some(0.0),
            _ => None,
        };
        let mut row2 = vec![
            Span::raw(" ".repeat(label_width)),
            Span::styled("spd ", theme.style(Role::Muted)),
            Span::styled(format!("{speed:>w$} "), theme.style(Role::Normal)),
        ];
        row2.extend(gauge(theme, speed_fraction, None, gauge_width));
        row2.push(Span::styled(" max ", theme.style(Role::Muted)));
        row2.push(Span::styled(
            format!("{max:>w$} "),
            theme.style(Role::Normal),
        ));
        let ramp = self.ramp(index, status).label();
        match status.following_error {
            // A closed loop's following error (MCCL TF) after the ramp.
            Some(error) => {
                row2.push(Span::styled(
                    format!("{ramp:<15}"),
                    theme.style(Role::Normal),
                ));
                row2.push(Span::styled(" ferr ", theme.style(Role::Muted)));
                row2.push(Span::styled(error.to_string(), theme.style(Role::Normal)));
            }
            None => row2.push(Span::styled(ramp, theme.style(Role::Normal))),
        }

        // Row 3: switches, load (or the family's lamps), errors.
        let mut row3 = vec![Span::raw(" ".repeat(label_width))];
        for (on, name) in [
            (status.left_switch, "L"),
            (status.right_switch, "R"),
            (status.home_switch, "H"),
        ] {
            row3.extend(switch_lamp(theme, on, name));
            row3.push(Span::raw(" "));
        }
        let lamps = family_lamps(view);
        if scale.is_some() || lamps.is_empty() {
            row3.push(Span::styled(" load ", theme.style(Role::Muted)));
            let load_fraction = match (status.load, scale) {
                (Some(v), Some(s)) if s.full_scale > 0 => {
                    let f = (v as f64 / s.full_scale as f64).clamp(0.0, 1.0);
                    Some(if s.zero_is_highest { 1.0 - f } else { f })
                }
                _ => None,
            };
            row3.extend(gauge(theme, load_fraction, None, 10));
            row3.push(Span::styled(
                format!(" {:>5}  ", number(status.load)),
                theme.style(Role::Normal),
            ));
        } else {
            row3.push(Span::raw(" "));
        }
        for flag in lamps {
            let on = status.driver_flags.as_ref().map(|lit| lit.contains(flag));
            row3.extend(switch_lamp_styled(theme, on, flag.name, Role::LampOn));
            row3.push(Span::raw(" "));
        }
        if !lamps.is_empty() {
            row3.push(Span::raw(" "));
        }
        row3.extend(error_spans(view, status));
        vec![Line::from(row1), Line::from(row2), Line::from(row3)]
    }

    /// One row per axis, for a low pane; `widths` are the widest position,
    /// target, speed and maximum of all axes, so columns line up.
    fn row(
        &self,
        index: usize,
        axis: &AxisInfo,
        status: &AxisStatus,
        selected: bool,
        widths: [usize; 4],
        view: &View,
    ) -> Line<'static> {
        let theme = view.theme;
        // Columns as wide as the values a poll brings in practice, so that
        // no column moves when a number gains a digit; only a longer one
        // widens them (every row alike).
        let [wp, wt, ws, wm] = widths;
        let (wp, wt) = (wp.max(POSITION_COLUMN), wt.max(POSITION_COLUMN));
        let (ws, wm) = (ws.max(SPEED_COLUMN), wm.max(MAX_SPEED_COLUMN));
        let shown = self.shown_values(index, status, view);
        // Names as long as the module's longest, 4 to 8 characters: `X`,
        // `servo 1` and `step 5` all read.
        let name_width = view
            .session
            .and_then(|s| s.axes.iter().map(|a| a.name.chars().count()).max())
            .unwrap_or(4)
            .clamp(4, 8);
        let mut spans = vec![
            Span::styled(
                format!(
                    "{}{:<name_width$} ",
                    if selected { "▶" } else { " " },
                    short_name(axis.name, name_width)
                ),
                if selected {
                    theme.style(Role::Accent)
                } else {
                    theme.style(Role::Title)
                },
            ),
            Span::styled(
                format!("{:>wp$}→{:<wt$} ", shown.position, shown.target),
                theme.style(Role::Normal),
            ),
        ];
        spans.extend(lamp(
            theme,
            status.motion() == AxisMotion::AtTarget,
            false,
            "",
        ));
        // `v500` right-aligned as one word (scripts read it so).
        let speed = format!("v{}", shown.speed);
        let ws = ws + 1;
        spans.push(Span::styled(
            format!(
                " {speed:>ws$}/{:<wm$} {:<6} ",
                shown.max_speed,
                self.ramp(index, status).short_label()
            ),
            theme.style(Role::Normal),
        ));
        if reads_following_error(view) {
            spans.push(Span::styled(
                format!("fe{:<FERR_COLUMN$} ", number(status.following_error)),
                theme.style(Role::Normal),
            ));
        }
        for (on, name) in [
            (status.left_switch, "L"),
            (status.right_switch, "R"),
            (status.home_switch, "H"),
        ] {
            spans.extend(switch_lamp(theme, on, name));
        }
        let lamps = family_lamps(view);
        let has_load = view
            .session
            .is_some_and(|s| s.family.console.load_scale().is_some());
        if has_load || lamps.is_empty() {
            spans.push(Span::styled(
                format!(" ld {} ", number(status.load)),
                theme.style(Role::Normal),
            ));
        } else {
            spans.push(Span::raw(" "));
            // No room for every lamp on one row: the lit ones.
            for flag in status.driver_flags.iter().flatten() {
                spans.extend(switch_lamp_styled(
                    theme,
                    Some(true),
                    flag.name,
                    Role::LampOn,
                ));
                spans.push(Span::raw(" "));
            }
        }
        spans.extend(error_spans(view, status));
        Line::from(spans)
    }
}

/// Rows the grouped list of several modules takes: a heading per link, a
/// line per module, a row per axis.
fn module_list_rows(modules: &[ModuleEntry]) -> usize {
    let links = modules
        .iter()
        .enumerate()
        .filter(|(i, m)| *i == 0 || modules.get(i - 1).is_none_or(|p| p.link != m.link))
        .count();
    links
        + modules
            .iter()
            .map(|m| 1 + m.snapshot.axes.len())
            .sum::<usize>()
}

impl AxesPane {
    /// Every module of every link, grouped by link, one row per axis
    /// (the rows of a low pane), scrolled to keep the selected module's
    /// selected axis in view. The selected module's rows are this pane's
    /// (units, speed trends); the others' are raw, as polled.
    fn render_modules(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        if let Some(session) = view.session
            && self.memory.len() != session.status.len()
        {
            self.remember(session);
        }
        let theme = view.theme;
        let plain = AxesPane::default();
        let mut lines: Vec<Line> = Vec::new();
        let mut selected_row = 0;
        let mut last_link = None;
        for (index, entry) in view.modules.iter().enumerate() {
            let chosen = index == view.module;
            // The selected module as the panes see it (its axis choice).
            let module = match view.session {
                Some(session) if chosen => session,
                _ => &entry.snapshot,
            };
            if last_link != Some(entry.link) {
                last_link = Some(entry.link);
                let state = match &module.link {
                    LinkState::Connected { .. } => "connected".to_string(),
                    LinkState::Disconnected { reason, .. } => format!("link lost: {reason}"),
                    LinkState::Closed => "closed".into(),
                };
                lines.push(Line::from(vec![
                    Span::styled(
                        format!("link {} {}", entry.link + 1, module.link_name),
                        theme.style(Role::Title),
                    ),
                    Span::styled(
                        format!(" · {state} · {}", poll_text(module)),
                        theme.style(Role::Muted),
                    ),
                ]));
            }
            let identity = module
                .identity
                .as_ref()
                .map(|i| format!(" {}", super::text::fit(i, IDENTITY_WIDTH)))
                .unwrap_or_default();
            lines.push(Line::from(vec![
                Span::styled(
                    format!("{}module {} ", if chosen { "▶" } else { " " }, index + 1),
                    theme.style(if chosen { Role::Accent } else { Role::Title }),
                ),
                Span::styled(
                    format!("{} #{}{identity}", module.family.name, module.address),
                    theme.style(Role::Muted),
                ),
            ]));
            let module_view = View {
                session: Some(module),
                modules: &[],
                module: 0,
                ..*view
            };
            let pane = if chosen { &*self } else { &plain };
            // As drawn: numbers at a readable rate.
            let statuses: Vec<AxisStatus> = if chosen {
                (0..module.axes.len())
                    .map(|i| self.drawn_status(i, module))
                    .collect()
            } else {
                self.module_status(index, module).to_vec()
            };
            let status_of = |i: usize| statuses.get(i).cloned().unwrap_or_default();
            let shown: Vec<ShownValues> = module
                .axes
                .iter()
                .enumerate()
                .map(|(i, _)| pane.shown_values(i, &status_of(i), &module_view))
                .collect();
            let width_of = |field: fn(&ShownValues) -> &String| {
                shown
                    .iter()
                    .map(|v| field(v).chars().count())
                    .max()
                    .unwrap_or(1)
            };
            let widths = [
                width_of(|v| &v.position),
                width_of(|v| &v.target),
                width_of(|v| &v.speed),
                width_of(|v| &v.max_speed),
            ];
            for (i, axis) in module.axes.iter().enumerate() {
                let status = status_of(i);
                let here = chosen && i == module.axis;
                if here {
                    selected_row = lines.len();
                }
                let mut row = pane.row(i, axis, &status, here, widths, &module_view);
                row.spans.insert(0, Span::raw(" "));
                lines.push(row);
            }
        }
        let skip = (selected_row + 1).saturating_sub(usize::from(area.height));
        let skip = u16::try_from(skip).unwrap_or(u16::MAX);
        frame.render_widget(Paragraph::new(lines).scroll((skip, 0)), area);
    }
}

impl Pane for AxesPane {
    fn name(&self) -> &'static str {
        "axes"
    }

    fn context(&self) -> Context {
        Context::Axis
    }

    fn title(&self, view: &View) -> String {
        let Some(s) = view.session else {
            return "Axes — not connected".into();
        };
        if view.modules.len() > 1 {
            let links = view
                .modules
                .iter()
                .map(|m| m.link)
                .collect::<std::collections::BTreeSet<_>>()
                .len();
            let units = self.note.clone().unwrap_or_else(|| {
                format!(
                    "{} units: {}",
                    key_label(view.keymap, Context::Axis, Action::ToggleUnits),
                    self.units.label()
                )
            });
            let links = match links {
                1 => "one link".to_string(),
                n => format!("{n} links"),
            };
            return format!(
                "Axes — {} modules on {links}, module {} selected · {units}",
                view.modules.len(),
                view.module + 1
            );
        }
        let state = match &s.link {
            LinkState::Connected { .. } => "connected".to_string(),
            LinkState::Disconnected { reason, .. } => format!("link lost: {reason}"),
            LinkState::Closed => "closed".into(),
        };
        let poll = if self.busy && s.poll.is_some() {
            SUSPENDED.to_string()
        } else {
            poll_text(s)
        };
        // A long identity (MCCL's VE text) leaves room for the state.
        let identity = s
            .identity
            .as_ref()
            .map(|i| format!(" ({})", super::text::fit(i, IDENTITY_WIDTH)))
            .unwrap_or_default();
        let units = self.note.clone().unwrap_or_else(|| {
            format!(
                "{} units: {}",
                key_label(view.keymap, Context::Axis, Action::ToggleUnits),
                self.units.label()
            )
        });
        format!(
            "Axes — {} #{}{identity} {state}, {poll} · {units}",
            s.link_name, s.address
        )
    }

    fn region(&self) -> Region {
        Region::Top
    }

    fn height_hint(&self, view: &View, width: u16, room: u16) -> Option<u16> {
        if view.modules.len() > 1 {
            return Some(u16::try_from(module_list_rows(view.modules)).unwrap_or(u16::MAX));
        }
        let axes = view.session.map_or(1, |s| s.axes.len().max(1));
        let cards = u16::try_from(axes.div_ceil(columns(width, axes)))
            .unwrap_or(u16::MAX)
            .saturating_mul(CARD_ROWS);
        let rows = u16::try_from(axes).unwrap_or(u16::MAX);
        Some(if cards <= room { cards } else { rows })
    }

    fn render(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        if view.modules.len() > 1 {
            self.render_modules(frame, area, view);
            return;
        }
        let Some(session) = view.session else {
            frame.render_widget(
                Paragraph::new("not connected: :connect --sim tmcm1110 in the command pane")
                    .style(view.theme.style(Role::Muted)),
                area,
            );
            return;
        };
        if self.memory.len() != session.status.len() {
            self.remember(session);
        }
        let axes: Vec<(usize, &AxisInfo, AxisStatus)> = session
            .axes
            .iter()
            .enumerate()
            .map(|(i, axis)| (i, axis, self.drawn_status(i, session)))
            .collect();
        let count = axes.len();
        let cols = columns(area.width, count);
        let card_rows = count.div_ceil(cols);
        if usize::from(area.height) < card_rows * usize::from(CARD_ROWS) {
            // Too low for cards: one row each, scrolled to keep the
            // selected axis in view.
            let shown: Vec<ShownValues> = axes
                .iter()
                .map(|(i, _, s)| self.shown_values(*i, s, view))
                .collect();
            let width_of = |field: fn(&ShownValues) -> &String| {
                shown
                    .iter()
                    .map(|v| field(v).chars().count())
                    .max()
                    .unwrap_or(1)
            };
            let widths = [
                width_of(|v| &v.position),
                width_of(|v| &v.target),
                width_of(|v| &v.speed),
                width_of(|v| &v.max_speed),
            ];
            let lines: Vec<Line> = axes
                .iter()
                .map(|(i, axis, status)| {
                    self.row(*i, axis, status, *i == session.axis, widths, view)
                })
                .collect();
            let skip = (session.axis + 1).saturating_sub(usize::from(area.height));
            frame.render_widget(Paragraph::new(lines).scroll((skip as u16, 0)), area);
            return;
        }
        let card_width = (area.width + CARD_GAP) / cols as u16 - CARD_GAP;
        for (n, (i, axis, status)) in axes.iter().enumerate() {
            let (row, col) = (n / cols, n % cols);
            let rect = Rect {
                x: area.x + col as u16 * (card_width + CARD_GAP),
                y: area.y + row as u16 * CARD_ROWS,
                width: card_width,
                height: CARD_ROWS,
            };
            let lines = self.card(*i, axis, status, *i == session.axis, card_width, view);
            frame.render_widget(Paragraph::new(lines).style(Style::default()), rect);
        }
    }

    fn handle_input(&mut self, input: &Input, view: &View) -> Outcome {
        let (Input::Key(key), Some(session)) = (input, view.session) else {
            return Outcome::Ignored;
        };
        let count = session.axes.len();
        let action = view.keymap.action_for(Context::Axis, key);
        if action.is_some() {
            self.note = None;
        }
        match action {
            Some(Action::ToggleUnits) => self.toggle_units(session),
            Some(Action::SelectPrevious) if session.axis > 0 => {
                Outcome::request(Request::SelectAxis(session.axis - 1))
            }
            Some(Action::SelectNext) if session.axis + 1 < count => {
                Outcome::request(Request::SelectAxis(session.axis + 1))
            }
            // Past the first or last axis: the module before or after in
            // the list (the picker of several modules).
            Some(Action::SelectPrevious) if view.module > 0 => {
                Outcome::request(Request::SelectModule(view.module - 1))
            }
            Some(Action::SelectNext) if view.module + 1 < view.modules.len() => {
                Outcome::request(Request::SelectModule(view.module + 1))
            }
            Some(Action::AxisStop) => {
                let line = session
                    .selected_axis()
                    .and_then(|axis| session.family.console.stop_axis_line(axis.number));
                match line {
                    Some(line) => Outcome::request(Request::Send {
                        lines: vec![line],
                        tag: 0,
                    }),
                    None => Outcome::Ignored,
                }
            }
            Some(_) => Outcome::Ignored,
            // 1…9 pick an axis.
            None => match key.code {
                KeyCode::Char(c @ '1'..='9') if key.modifiers.is_empty() => {
                    let index = usize::from(c as u8 - b'1');
                    if index < count {
                        Outcome::request(Request::SelectAxis(index))
                    } else {
                        Outcome::Ignored
                    }
                }
                _ => Outcome::Ignored,
            },
        }
    }

    fn on_event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
        match (event, view.session) {
            (PaneEvent::Reply { tag, line, result }, _) if self.reading.contains_key(tag) => {
                let Some((index, number)) = self.reading.remove(tag) else {
                    return Outcome::Ignored;
                };
                match result {
                    Ok(r) => match r.value {
                        ReplyValue::Number(value) => {
                            if let Some(inputs) = self.inputs.get_mut(index) {
                                inputs.insert(number, value);
                            }
                        }
                        ref other => {
                            self.note = Some(format!("{line} answered {other}, not a number"));
                        }
                    },
                    Err(e) => self.note = Some(format!("{line}: {e}")),
                }
                Outcome::redraw()
            }
            (PaneEvent::Wake { tag }, session) if self.waking == Some(*tag) => {
                self.waking = None;
                // The other modules' numbers held back come with it.
                let now = self.clock.now();
                let mut others = false;
                for (index, (key, drawn)) in &mut self.others_drawn {
                    if let Some(entry) = view.modules.get(*index)
                        && key.is(&entry.snapshot)
                        && index != &view.module
                    {
                        drawn.catch_up(&entry.snapshot.status, now);
                        others = true;
                    }
                }
                match session {
                    Some(session) if self.drawn_of.as_ref().is_some_and(|k| k.is(session)) => {
                        self.drawn.catch_up(&session.status, self.clock.now());
                        self.widen_spans();
                        Outcome::redraw()
                    }
                    _ if others => Outcome::redraw(),
                    _ => Outcome::Ignored,
                }
            }
            (PaneEvent::ModuleChanged(index), _) if *index != view.module => {
                let Some(entry) = view.modules.get(*index) else {
                    return Outcome::Ignored;
                };
                match self.offer_module(*index, &entry.snapshot) {
                    (true, _) => Outcome::redraw(),
                    (false, Some(wake)) => Outcome::request(wake),
                    (false, None) => Outcome::Ignored,
                }
            }
            (PaneEvent::Snapshot, Some(session)) => {
                self.remember(session);
                let mut requests: Vec<Request> = self.offer_status(session).into_iter().collect();
                // Another module (a new connection, another address):
                // what the conversions need is read from it afresh.
                if self.units != Units::Raw
                    && !self.inputs_of.as_ref().is_some_and(|k| k.is(session))
                {
                    let params = session.family.console.parameters();
                    let convertible = |p: &&dyn ParameterSet| match self.units {
                        Units::Axis => {
                            session.family.console.units().is_some()
                                && !session.mechanics.is_empty()
                        }
                        _ => !p.status_inputs().is_empty(),
                    };
                    match params.filter(convertible) {
                        Some(params) => requests.extend(self.read_inputs(session, params)),
                        None => self.units = Units::Raw,
                    }
                }
                Outcome::Handled(requests)
            }
            (PaneEvent::Snapshot, None) => {
                self.memory.clear();
                self.drawn.reset();
                Outcome::redraw()
            }
            (PaneEvent::Busy(busy), _) => {
                self.busy = busy.is_some();
                Outcome::redraw()
            }
            _ => Outcome::Ignored,
        }
    }
}

#[cfg(test)]
mod tests;
