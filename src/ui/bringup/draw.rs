//! What the pane draws besides the jog: the lamp lines of the inputs and
//! outputs.

use super::*;

impl BringUpPane {
    /// The inputs and outputs: the axis's switches, the module's, the
    /// outputs (the chosen one marked), the general inputs, the analog
    /// values.
    pub(super) fn io_lines(
        &self,
        lines: &mut Vec<Line<'static>>,
        plan: &dyn IoPlan,
        session: &Snapshot,
        width: usize,
        view: &View,
    ) {
        let theme = view.theme;
        let points = plan.points();
        let state = |index: usize| self.point_state(plan, index, session);
        let shown = |p: &IoPoint| p.axis.is_none_or(|a| a == session.axis);
        let axis_name = session.selected_axis().map_or("axis", |a| a.name);
        // A switch lit is trouble; an input or output lit is just on.
        let lamps_of = |wanted: fn(&IoPoint) -> bool, lit: Role| -> Vec<LampRow> {
            points
                .iter()
                .enumerate()
                .filter(|(_, p)| shown(p) && wanted(p))
                .map(|(i, p)| {
                    let (mark, role) = match state(i).map(|v| v != 0) {
                        Some(true) => ("●", lit),
                        other => lamp(other),
                    };
                    (p.name.to_string(), mark, role)
                })
                .collect()
        };
        let axis_switches = lamps_of(
            |p| p.kind == IoKind::Switch && p.axis.is_some(),
            Role::LampAlarm,
        );
        let module_switches = lamps_of(
            |p| p.kind == IoKind::Switch && p.axis.is_none(),
            Role::LampAlarm,
        );
        let mut outputs = lamps_of(IoPoint::is_output, Role::LampOn);
        let chosen = self.output.min(outputs.len().saturating_sub(1));
        if let Some(row) = outputs.get_mut(chosen) {
            row.0 = format!("›{}", row.0);
        }
        let inputs = lamps_of(|p| p.kind == IoKind::DigitalInput, Role::LampOn);
        for (title, items) in [
            (format!("{axis_name} "), axis_switches),
            ("module ".to_string(), module_switches),
            ("outputs ".to_string(), outputs),
        ] {
            if !items.is_empty() {
                flow(lines, &title, &items, width, theme);
            }
        }
        let keys = |action| key_label(view.keymap, Context::BringUp, action);
        lines.push(Line::styled(
            fit(
                &format!(
                    "{}/{} choose an output · {} switch it (asks y/n)",
                    keys(Action::OutputNext),
                    keys(Action::OutputPrevious),
                    keys(Action::OutputToggle),
                ),
                width,
            ),
            theme.style(Role::Muted),
        ));
        let analog = points
            .iter()
            .enumerate()
            .filter(|(_, p)| shown(p))
            .filter_map(|(i, p)| match p.kind {
                IoKind::AnalogInput { volts } => {
                    let value = match (state(i), volts) {
                        (Some(count), Some(scale)) => format!("{:.2} V", scale.volts(count)),
                        (Some(count), None) => format!("{count}"),
                        (None, _) => "—".into(),
                    };
                    Some(format!("{} {value}", p.name))
                }
                _ => None,
            })
            .collect::<Vec<_>>();
        if !analog.is_empty() {
            lines.push(Line::from(vec![
                Span::styled("analog ", theme.style(Role::Muted)),
                Span::styled(
                    fit(&analog.join(" · "), width.saturating_sub(7)),
                    theme.style(Role::Normal),
                ),
            ]));
        }
        // The general inputs last: on a small screen a long list (32 on
        // a MultiFlex) runs past the pane's foot, not the outputs.
        if !inputs.is_empty() {
            flow(lines, "inputs ", &inputs, width, theme);
        }
    }
}

/// A point's name, its lamp and the lamp's colour.
type LampRow = (String, &'static str, Role);

/// `items` (name, lamp) after `title`, as many to a line as fit.
pub(super) fn flow(
    lines: &mut Vec<Line<'static>>,
    title: &str,
    items: &[LampRow],
    width: usize,
    theme: &crate::ui::theme::Theme,
) {
    let indent = title.chars().count();
    let mut spans = vec![Span::styled(title.to_string(), theme.style(Role::Muted))];
    let mut used = indent;
    for (name, mark, role) in items {
        let wide = name.chars().count() + 3;
        if used + wide > width && used > indent {
            lines.push(Line::from(std::mem::take(&mut spans)));
            spans.push(Span::raw(" ".repeat(indent)));
            used = indent;
        }
        spans.push(Span::styled(name.clone(), theme.style(Role::Normal)));
        spans.push(Span::styled(format!("{mark}  "), theme.style(*role)));
        used += wide;
    }
    lines.push(Line::from(spans));
}

/// A lamp: `●` lit, `○` dark, `·` unknown.
pub(super) fn lamp(value: Option<bool>) -> (&'static str, Role) {
    match value {
        Some(true) => ("●", Role::LampAlarm),
        Some(false) => ("○", Role::LampOff),
        None => ("·", Role::Muted),
    }
}

pub(super) fn number(value: Option<i64>) -> String {
    value.map_or_else(|| "—".to_string(), |v| v.to_string())
}
