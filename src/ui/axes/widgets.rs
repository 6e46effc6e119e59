//! The small drawing pieces of an axis card: gauges, lamps, numbers.

use super::*;

/// The lamps of the connected family (none for TMCL, whose driver flags
/// are listed as text).
pub(super) fn family_lamps(view: &View) -> &'static [AxisFlag] {
    view.session.map_or(&[], |s| s.family.console.lamps())
}

pub(super) fn error_spans(view: &View, status: &AxisStatus) -> Vec<Span<'static>> {
    let theme = view.theme;
    let clear = key_label(view.keymap, Context::Axis, Action::ClearErrors);
    let mut spans = Vec::new();
    if status.errors.is_empty() {
        spans.push(Span::styled("no errors", theme.style(Role::Muted)));
    } else {
        let names: Vec<&str> = status.errors.iter().map(|f| f.name).collect();
        spans.push(Span::styled(
            format!("ERR {}", names.join(", ")),
            theme.style(Role::LampAlarm),
        ));
        spans.push(Span::styled(
            format!(" ({clear} clears)"),
            theme.style(Role::Muted),
        ));
    }
    let listed = family_lamps(view).is_empty();
    if let Some(flags) = status
        .driver_flags
        .as_ref()
        .filter(|f| listed && !f.is_empty())
    {
        let names: Vec<&str> = flags.iter().map(|f| f.name).collect();
        spans.push(Span::styled(
            format!("  drv {}", names.join(", ")),
            theme.style(Role::Warning),
        ));
    }
    spans
}

/// The most of a module's identity the title shows.
pub(super) const IDENTITY_WIDTH: usize = 36;

/// What the title and the status bar say of polling while the controller
/// runs a line that holds it busy (MCCL `RP`, `WS`, `MC`: it takes nothing
/// else until the line's answer).
pub const SUSPENDED: &str = "poll suspended: controller busy";

/// The poll rate asked for and, once measured, the full status
/// refreshes a second the link really gives (`poll 20 Hz → 7.3/s`): on a
/// slow line the second is what the gauges show.
pub fn poll_text(session: &Snapshot) -> String {
    let asked = match session.poll {
        Some(c) if !c.fast.is_zero() => format!("poll {} Hz", crate::ui::app::rate_of(c.fast)),
        Some(_) => "poll max".into(),
        None => return "poll off".into(),
    };
    let refresh = session
        .status
        .get(session.axis)
        .or(session.status.first())
        .and_then(|s| s.refresh);
    match refresh {
        Some(rate) => format!("{asked} → {rate}"),
        None => asked,
    }
}

pub(super) fn number(value: Option<i64>) -> String {
    value.map_or_else(|| "—".to_string(), |v| v.to_string())
}

pub(super) fn truncate(text: &str, max: usize) -> String {
    text.chars().take(max).collect()
}

/// An axis name in at most `max` characters: a name of two forms
/// (`m0/Motor1`: the protocol's number, the manual's name) gives its first
/// when the whole does not fit, rather than a piece of both.
pub(super) fn short_name(name: &str, max: usize) -> String {
    match name.split_once('/') {
        Some((first, _)) if name.chars().count() > max => truncate(first, max),
        _ => truncate(name, max),
    }
}

/// Where `value` lies between `low` and `high`, 0..1.
pub(super) fn fraction(value: i64, low: i64, high: i64) -> f64 {
    if high <= low {
        // Nothing to show a distance on yet (everything at 0).
        return 0.0;
    }
    let (value, low, high) = (i128::from(value), i128::from(low), i128::from(high));
    ((value - low) as f64 / (high - low) as f64).clamp(0.0, 1.0)
}

/// A bar `width` cells wide filled to `fill`, with a mark at `mark`.
pub(super) fn gauge(
    theme: &Theme,
    fill: Option<f64>,
    mark: Option<f64>,
    width: usize,
) -> Vec<Span<'static>> {
    let Some(fill) = fill else {
        return vec![Span::styled(
            "·".repeat(width),
            theme.style(Role::GaugeEmpty),
        )];
    };
    let filled = ((fill * width as f64).round() as usize).min(width);
    let mark = mark.map(|m| ((m * width as f64).round() as usize).min(width.saturating_sub(1)));
    let mut spans = Vec::new();
    let cell = |i: usize| -> (char, Role) {
        if Some(i) == mark {
            ('┃', Role::Accent)
        } else if i < filled {
            ('█', Role::GaugeFill)
        } else {
            ('░', Role::GaugeEmpty)
        }
    };
    let mut run = String::new();
    let mut run_role = None;
    for i in 0..width {
        let (c, role) = cell(i);
        if let Some(r) = run_role.filter(|r| *r != role) {
            spans.push(Span::styled(std::mem::take(&mut run), theme.style(r)));
        }
        run_role = Some(role);
        run.push(c);
    }
    if let Some(r) = run_role {
        spans.push(Span::styled(run, theme.style(r)));
    }
    spans
}

pub(super) fn lamp(theme: &Theme, on: bool, alarm: bool, label: &str) -> Vec<Span<'static>> {
    let (symbol, role) = match (on, alarm) {
        (true, true) => ("●", Role::LampAlarm),
        (true, false) => ("●", Role::LampOn),
        (false, _) => ("○", Role::LampOff),
    };
    let mut spans = vec![Span::styled(symbol, theme.style(role))];
    if !label.is_empty() {
        spans.push(Span::styled(format!(" {label}"), theme.style(Role::Normal)));
    }
    spans
}

/// A switch lamp: its letter, lit when the switch is active.
pub(super) fn switch_lamp(theme: &Theme, on: Option<bool>, name: &str) -> Vec<Span<'static>> {
    switch_lamp_styled(theme, on, name, Role::LampAlarm)
}

/// A named lamp, lit in `lit` when on; `None`: not read yet.
pub(super) fn switch_lamp_styled(
    theme: &Theme,
    on: Option<bool>,
    name: &str,
    lit: Role,
) -> Vec<Span<'static>> {
    let (symbol, role) = match on {
        Some(true) => ("●", lit),
        Some(false) => ("○", Role::LampOff),
        None => ("·", Role::Muted),
    };
    vec![
        Span::styled(name.to_string(), theme.style(Role::Muted)),
        Span::styled(symbol, theme.style(role)),
    ]
}

/// How many cards go side by side at this width: as many as fit, then
/// spread evenly over the rows they need (4 axes in 3 columns would leave
/// one alone; 2 by 2 reads better).
pub(super) fn columns(width: u16, axes: usize) -> usize {
    let axes = axes.max(1);
    let fit = usize::from((width + CARD_GAP) / (CARD_MIN_WIDTH + CARD_GAP)).clamp(1, axes);
    let rows = axes.div_ceil(fit);
    axes.div_ceil(rows)
}
