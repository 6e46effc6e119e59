//! STAND-IN until the theme loader lands (branch `uiconf`): the same
//! [`Role`] names and `Theme::style(role)`, with fixed dark colours, so
//! that panes written against it need no change when the real one
//! replaces this file.

use ratatui::style::{Color, Modifier, Style};

/// What a piece of the screen is, for colouring.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Role {
    Normal,
    Muted,
    Accent,
    Title,
    Border,
    BorderFocused,
    StatusBar,
    StatusKey,
    Emergency,
    Ok,
    Warning,
    Error,
    Selection,
    Changed,
    Matched,
    Prompt,
    Sent,
    Received,
    Poll,
    GaugeFill,
    GaugeEmpty,
    LampOn,
    LampOff,
    LampAlarm,
    PlotAxes,
    Plot1,
    Plot2,
    Plot3,
    Plot4,
}

/// Colours of the console.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Theme {
    name: String,
}

impl Default for Theme {
    fn default() -> Theme {
        Theme {
            name: "dark".into(),
        }
    }
}

impl Theme {
    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn builtin(name: &str) -> Option<Theme> {
        (name == "dark").then(Theme::default)
    }

    pub fn style(&self, role: Role) -> Style {
        let plain = Style::default();
        match role {
            Role::Normal => plain,
            Role::Muted => plain.fg(Color::DarkGray),
            Role::Accent => plain.fg(Color::Cyan),
            Role::Title => plain.add_modifier(Modifier::BOLD),
            Role::Border => plain.fg(Color::DarkGray),
            Role::BorderFocused => plain.fg(Color::Cyan),
            Role::StatusBar => plain.bg(Color::Blue).fg(Color::White),
            Role::StatusKey => plain.bg(Color::Blue).fg(Color::Yellow),
            Role::Emergency => plain
                .bg(Color::Red)
                .fg(Color::White)
                .add_modifier(Modifier::BOLD),
            Role::Ok => plain.fg(Color::Green),
            Role::Warning => plain.fg(Color::Yellow),
            Role::Error => plain.fg(Color::LightRed),
            Role::Selection => plain.add_modifier(Modifier::REVERSED),
            Role::Changed => plain.fg(Color::LightYellow),
            Role::Matched => plain.add_modifier(Modifier::UNDERLINED),
            Role::Prompt => plain.fg(Color::Cyan).add_modifier(Modifier::BOLD),
            Role::Sent => plain.fg(Color::LightBlue),
            Role::Received => plain.fg(Color::LightGreen),
            Role::Poll => plain.fg(Color::DarkGray),
            Role::GaugeFill => plain.fg(Color::Cyan).bg(Color::Black),
            Role::GaugeEmpty => plain.fg(Color::DarkGray),
            Role::LampOn => plain.fg(Color::LightGreen).add_modifier(Modifier::BOLD),
            Role::LampOff => plain.fg(Color::DarkGray),
            Role::LampAlarm => plain.fg(Color::LightRed).add_modifier(Modifier::BOLD),
            Role::PlotAxes => plain.fg(Color::Gray),
            Role::Plot1 => plain.fg(Color::Cyan),
            Role::Plot2 => plain.fg(Color::Yellow),
            Role::Plot3 => plain.fg(Color::Magenta),
            Role::Plot4 => plain.fg(Color::Green),
        }
    }
}
