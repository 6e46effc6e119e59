//! The connect screen: what `axterm` alone opens on. It lists the recent
//! connections, every built-in simulator, the serial ports found (the
//! link layer's listing, as `axterm ports` shows them) and a TCP bridge,
//! with the protocol, baud rate and module address to use; choosing one
//! connects ([`Request::Connect`] with the same options as the command
//! line) and, once it is open, hands the keyboard to the command line.
//! Connections that open are remembered ([`recent`]). While connected,
//! `+` adds the chosen connection as one more link beside those open
//! ([`Request::AddLink`]): its module joins the axes pane's list.
//!
//! The form takes typed text (baud, address, host), so its keys are the
//! command line's ([`Context::Command`]): Up/Down choose, Enter connects,
//! Tab moves between the fields, Esc goes back to the list.

pub mod recent;

use std::io;
use std::path::Path;

use ratatui::Frame;
use ratatui::crossterm::event::{KeyCode, KeyEvent};
use ratatui::layout::{Position, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use super::field::Field;
use super::keymap::{Action, Context};
use super::pane::{Input, NoticeLevel, Outcome, Pane, PaneEvent, Region, Request, View, key_label};
use super::text::fit;
use super::theme::Role;
use crate::families::{FAMILIES, find_family};
use crate::families::{find_kind, kinds};
use crate::link::ports::ListedPort;
use crate::protocol::{Family, LinkChoice, LinkOption};
use recent::Recents;

/// Lists the serial ports of the machine with their stable names: the
/// link layer's listing, or a test's.
pub type PortLister = fn() -> io::Result<Vec<ListedPort>>;

/// A listed port's line on the connect screen: its device path, and what
/// is behind it with its stable name (`by-id usb-FTDI_…`).
fn port_line(listed: &ListedPort) -> (String, String) {
    let device = listed.port.path.clone();
    let info = listed.port.to_string();
    let mut note = info
        .strip_prefix(device.as_str())
        .unwrap_or("")
        .trim()
        .to_string();
    if let Some(stable) = listed.by_id.first() {
        let file = std::path::Path::new(stable)
            .file_name()
            .map_or_else(|| stable.clone(), |f| f.to_string_lossy().into_owned());
        if !note.is_empty() {
            note.push_str(" · ");
        }
        note.push_str("by-id ");
        note.push_str(&file);
    }
    (device, note)
}

/// The baud rate offered first: the TMCM-1110's default (§5.1 GP65 = 0).
pub const DEFAULT_BAUD: &str = "9600";

/// The bridge offered first: `axterm sim --tcp` on this machine.
pub const DEFAULT_TCP: &str = "127.0.0.1:4001";

/// One line of the list one can choose.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Choice {
    Recent(Vec<String>),
    Sim {
        name: &'static str,
        description: &'static str,
    },
    Port(String),
    /// Look for serial ports again.
    Rescan,
    Tcp,
}

/// What the keys type into.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Focus {
    List,
    Protocol,
    Baud,
    Address,
    Tcp,
    /// The chosen family's link option, if it has one.
    Link,
}

impl Focus {
    /// The next field; the link option's only when there is one.
    fn next(self, has_link_option: bool) -> Focus {
        match self {
            Focus::List => Focus::Protocol,
            Focus::Protocol => Focus::Baud,
            Focus::Baud => Focus::Address,
            Focus::Address => Focus::Tcp,
            Focus::Tcp if has_link_option => Focus::Link,
            Focus::Tcp | Focus::Link => Focus::List,
        }
    }
}

/// The connect screen.
pub struct ConnectPane {
    recents: Recents,
    list_ports: PortLister,
    ports: Vec<ListedPort>,
    port_problem: Option<String>,
    scanned: bool,
    selected: usize,
    focus: Focus,
    /// Index into [`FAMILIES`].
    protocol: usize,
    baud: Field,
    address: Field,
    tcp: Field,
    /// The choice of the chosen family's link option (the first it has:
    /// no family has more), index into its choices; 0 is its default.
    link: usize,
    /// The options of the connection being opened.
    connecting: Option<Vec<String>>,
    /// A link asked to be added from here, not opened yet.
    adding: bool,
    message: Option<(Role, String)>,
    /// The family of the choice last told to the other panes
    /// ([`Request::ChooseFamily`]).
    announced: Option<&'static str>,
}

impl ConnectPane {
    /// Recent connections kept in `data_dir`; ports listed by `list_ports`.
    pub fn new(data_dir: Option<&Path>, list_ports: PortLister) -> ConnectPane {
        let recents = Recents::load(data_dir);
        let message = recents.problem().map(|p| (Role::Warning, p.to_string()));
        ConnectPane {
            recents,
            list_ports,
            ports: Vec::new(),
            port_problem: None,
            scanned: false,
            selected: 0,
            focus: Focus::List,
            protocol: 0,
            baud: Field::new(DEFAULT_BAUD),
            address: Field::new(""),
            tcp: Field::new(DEFAULT_TCP),
            link: 0,
            connecting: None,
            adding: false,
            message,
            announced: None,
        }
    }

    /// The protocol family the highlighted choice would connect with.
    pub fn chosen_family(&self) -> Option<&'static Family> {
        match self.choices().get(self.selected)? {
            Choice::Recent(args) => family_of_args(args),
            Choice::Sim { name, .. } => crate::families::family_of(find_kind(name)?),
            Choice::Port(_) | Choice::Rescan | Choice::Tcp => find_family(self.protocol_name()),
        }
    }

    /// Tell the other panes when a key changed the family of the choice.
    fn announce(&mut self, outcome: Outcome) -> Outcome {
        let Outcome::Handled(mut requests) = outcome else {
            return outcome;
        };
        let family = self.chosen_family().map(|f| f.name);
        if let Some(name) = family.filter(|name| self.announced != Some(*name)) {
            self.announced = Some(name);
            requests.push(Request::ChooseFamily(name));
        }
        Outcome::Handled(requests)
    }

    /// The recent connections, newest first.
    pub fn recents(&self) -> &[Vec<String>] {
        self.recents.entries()
    }

    fn scan(&mut self) {
        self.scanned = true;
        match (self.list_ports)() {
            Ok(ports) => {
                self.ports = ports;
                self.port_problem = None;
            }
            Err(e) => {
                self.ports.clear();
                self.port_problem = Some(format!("cannot list serial ports: {e}"));
            }
        }
    }

    fn choices(&self) -> Vec<Choice> {
        let mut choices: Vec<Choice> = self
            .recents
            .entries()
            .iter()
            .cloned()
            .map(Choice::Recent)
            .collect();
        choices.extend(kinds().map(|kind| Choice::Sim {
            name: kind.name,
            description: kind.description,
        }));
        // A port with a /dev/serial/by-id name is opened (and kept in the
        // recent connections) by it: the name stays when the adapter is
        // plugged in again and comes back as another ttyUSB.
        choices.extend(
            self.ports
                .iter()
                .map(|p| Choice::Port(p.by_id.first().unwrap_or(&p.port.path).clone())),
        );
        choices.push(Choice::Rescan);
        choices.push(Choice::Tcp);
        choices
    }

    /// The link option of the chosen family and the choice made, if it
    /// has one.
    fn link_option(&self) -> Option<(&'static LinkOption, &'static LinkChoice)> {
        // A recent connection is opened with the options it had.
        if let Some(Choice::Recent(_)) = self.choices().get(self.selected) {
            return None;
        }
        let option = self.chosen_family()?.console.link_options().first()?;
        let choice = option
            .choices
            .get(self.link % option.choices.len().max(1))?;
        Some((option, choice))
    }

    /// `--link-option NAME=VALUE` for a choice other than the default.
    fn link_args(&self) -> Vec<String> {
        match self.link_option() {
            Some((option, choice))
                if option
                    .choices
                    .first()
                    .is_some_and(|c| c.value != choice.value) =>
            {
                vec![
                    "--link-option".into(),
                    format!("{}={}", option.name, choice.value),
                ]
            }
            _ => Vec::new(),
        }
    }

    fn protocol_name(&self) -> &'static str {
        FAMILIES
            .get(self.protocol)
            .or_else(|| FAMILIES.first())
            .map_or("", |f| f.name)
    }

    /// The address typed, checked; `None` when left empty (the family's
    /// default).
    fn address(&self) -> Result<Option<String>, String> {
        let text = self.address.text().trim();
        if text.is_empty() {
            return Ok(None);
        }
        text.parse::<u8>()
            .map(|a| Some(a.to_string()))
            .map_err(|_| format!("address {text}: give a number from 0 to 255"))
    }

    fn baud(&self) -> Result<String, String> {
        let text = self.baud.text().trim();
        match text.parse::<u32>() {
            Ok(b) if b > 0 => Ok(b.to_string()),
            _ => Err(format!("baud {text}: give a rate such as 9600 or 115200")),
        }
    }

    /// The connection options of a choice, as on the command line.
    fn args(&self, choice: &Choice) -> Result<Vec<String>, String> {
        let mut args: Vec<String> = match choice {
            Choice::Recent(args) => return Ok(args.clone()),
            Choice::Rescan => return Ok(Vec::new()),
            Choice::Sim { name, .. } => vec!["--sim".into(), (*name).into()],
            Choice::Port(path) => vec![
                "--port".into(),
                path.clone(),
                "--protocol".into(),
                self.protocol_name().into(),
                "--baud".into(),
                self.baud()?,
            ],
            Choice::Tcp => {
                let host = self.tcp.text().trim();
                if !host.contains(':') || host.ends_with(':') {
                    return Err(format!("tcp {host}: give HOST:PORT, e.g. {DEFAULT_TCP}"));
                }
                vec![
                    "--tcp".into(),
                    host.into(),
                    "--protocol".into(),
                    self.protocol_name().into(),
                    // The serial side of the bridge: the session keeps
                    // its slow polls to a share of that line.
                    "--baud".into(),
                    self.baud()?,
                ]
            }
        };
        if let Some(address) = self.address()? {
            args.push("--address".into());
            args.push(address);
        }
        args.extend(self.link_args());
        Ok(args)
    }

    /// Connect to the chosen one, instead of what is open or (`add`)
    /// beside it.
    fn connect(&mut self) -> Outcome {
        self.open_choice(false)
    }

    fn open_choice(&mut self, add: bool) -> Outcome {
        let choices = self.choices();
        let Some(choice) = choices.get(self.selected) else {
            return Outcome::redraw();
        };
        if *choice == Choice::Rescan {
            self.scan();
            self.message = Some((
                Role::Accent,
                format!("{} serial port(s) found", self.ports.len()),
            ));
            return Outcome::redraw();
        }
        match self.args(choice) {
            Ok(args) if add => {
                self.message = Some((
                    Role::Accent,
                    format!(
                        "adding a link: {}… (it joins the axes pane's list)",
                        args.join(" ")
                    ),
                ));
                self.adding = true;
                Outcome::request(Request::AddLink(args))
            }
            Ok(args) => {
                self.message = Some((Role::Accent, format!("connecting: {}…", args.join(" "))));
                self.connecting = Some(args.clone());
                Outcome::request(Request::Connect(args))
            }
            Err(why) => {
                self.message = Some((Role::Error, format!("{why}; nothing opened")));
                Outcome::redraw()
            }
        }
    }

    fn key(&mut self, key: &KeyEvent, view: &View) -> Outcome {
        if !self.scanned {
            self.scan();
        }
        let action = view.keymap.action_for(Context::Command, key);
        let count = self.choices().len();
        match action {
            Some(Action::HistoryPrevious) => self.selected = self.selected.saturating_sub(1),
            Some(Action::HistoryNext) => {
                self.selected = (self.selected + 1).min(count.saturating_sub(1));
            }
            Some(Action::Submit) => return self.connect(),
            Some(Action::Complete) => {
                self.focus = self.focus.next(self.link_option().is_some());
            }
            Some(Action::Cancel) => {
                self.focus = Focus::List;
                self.message = None;
            }
            Some(_) => return Outcome::Ignored,
            None => return self.type_key(key, view),
        }
        Outcome::redraw()
    }

    fn type_key(&mut self, key: &KeyEvent, view: &View) -> Outcome {
        let field = match self.focus {
            // `+`: one more link beside those open.
            Focus::List if key.code == KeyCode::Char('+') => {
                return self.open_choice(view.session.is_some());
            }
            Focus::List => return Outcome::Ignored,
            Focus::Protocol => {
                let step = match key.code {
                    KeyCode::Left => FAMILIES.len().saturating_sub(1),
                    KeyCode::Right | KeyCode::Char(' ') => 1,
                    _ => return Outcome::Ignored,
                };
                let before = FAMILIES
                    .get(self.protocol)
                    .map(|f| f.console.default_baud());
                self.protocol = (self.protocol + step) % FAMILIES.len().max(1);
                // The baud rate follows the family's factory rate unless
                // the user typed another (SIXpack 2: 19200 Bd, §6.1.1).
                let after = FAMILIES
                    .get(self.protocol)
                    .map(|f| f.console.default_baud());
                if let (Some(before), Some(after)) = (before, after)
                    && self.baud.text().trim() == before.to_string()
                {
                    self.baud = Field::new(after.to_string());
                }
                self.link = 0;
                return Outcome::redraw();
            }
            Focus::Link => {
                let count = self
                    .link_option()
                    .map_or(1, |(option, _)| option.choices.len().max(1));
                let step = match key.code {
                    KeyCode::Left => count - 1,
                    KeyCode::Right | KeyCode::Char(' ') => 1,
                    _ => return Outcome::Ignored,
                };
                self.link = (self.link % count + step) % count;
                return Outcome::redraw();
            }
            Focus::Baud => &mut self.baud,
            Focus::Address => &mut self.address,
            Focus::Tcp => &mut self.tcp,
        };
        if field.edit(key) {
            Outcome::redraw()
        } else {
            Outcome::Ignored
        }
    }

    fn choice_line(
        &self,
        choice: &Choice,
        selected: bool,
        view: &View,
        width: usize,
    ) -> Line<'static> {
        let theme = view.theme;
        let (text, note) = match choice {
            Choice::Recent(args) => (args.join(" "), String::new()),
            Choice::Sim { name, description } => (format!("sim {name}"), description.to_string()),
            Choice::Port(name) => self
                .ports
                .iter()
                .find(|p| p.port.path == *name || p.by_id.first() == Some(name))
                .map_or_else(|| (name.clone(), String::new()), port_line),
            Choice::Rescan => ("↻ look for serial ports again".into(), String::new()),
            Choice::Tcp => (
                format!("tcp {}", self.tcp.text().trim()),
                "serial-over-TCP bridge (ser2net, axterm sim --tcp); baud = its serial side".into(),
            ),
        };
        let marker = if selected { "▶ " } else { "  " };
        let line = fit(&format!("{marker}{text:<24} {note}"), width);
        let style = if selected {
            theme.style(if view.focused && self.focus == Focus::List {
                Role::Selection
            } else {
                Role::Accent
            })
        } else {
            theme.style(Role::Normal)
        };
        Line::styled(line, style)
    }

    /// The protocol and baud rate the highlighted choice connects with
    /// where they are not the form's (a simulator, a recent connection):
    /// the form shows what will be used, not values that do not apply.
    fn choice_protocol_and_baud(&self) -> Option<(String, String)> {
        let args = match self.choices().get(self.selected)? {
            Choice::Sim { name, .. } => vec!["--sim".to_string(), (*name).to_string()],
            Choice::Recent(args) => args.clone(),
            Choice::Port(_) | Choice::Rescan | Choice::Tcp => return None,
        };
        let family = family_of_args(&args)?;
        let baud = option_value(&args, "--baud").map(str::to_string);
        let baud = match (baud, option_value(&args, "--sim")) {
            (Some(baud), _) => baud,
            // A simulator without --baud has no wire time to emulate.
            (None, Some(_)) => "none".to_string(),
            (None, None) => family.console.default_baud().to_string(),
        };
        Some((family.name.to_string(), baud))
    }

    fn form_line(&self, view: &View) -> (Line<'static>, Option<usize>) {
        let theme = view.theme;
        let mut spans = Vec::new();
        let mut cursor = None;
        let mut column = 0;
        let on_form = matches!(self.focus, Focus::Protocol | Focus::Baud);
        let (protocol, baud) = match self.choice_protocol_and_baud() {
            Some(applied) if !on_form => applied,
            _ => (
                self.protocol_name().to_string(),
                self.baud.text().to_string(),
            ),
        };
        let fields = [
            (Focus::Protocol, "protocol ", protocol, None),
            (Focus::Baud, "baud ", baud, Some(&self.baud)),
            (
                Focus::Address,
                "address ",
                self.address.text().to_string(),
                Some(&self.address),
            ),
            (
                Focus::Tcp,
                "tcp ",
                self.tcp.text().to_string(),
                Some(&self.tcp),
            ),
        ];
        for (focus, label, value, field) in fields {
            let shown = if value.is_empty() && focus == Focus::Address {
                "default".to_string()
            } else {
                value
            };
            let active = self.focus == focus && view.focused;
            spans.push(Span::styled(label, theme.style(Role::Muted)));
            column += label.chars().count();
            spans.push(Span::styled("[", theme.style(Role::Muted)));
            column += 1;
            if active && let Some(field) = field {
                cursor = Some(column + field.cursor_column());
            }
            let style = theme.style(if active {
                Role::Selection
            } else {
                Role::Normal
            });
            column += shown.chars().count();
            spans.push(Span::styled(shown, style));
            spans.push(Span::styled("]  ", theme.style(Role::Muted)));
            column += 3;
        }
        (Line::from(spans), cursor)
    }
}

/// The family of the choice the connect screen highlights when it opens:
/// the most recent connection's (kept in `data_dir`), else the first
/// simulator's.
pub fn initial_family(data_dir: Option<&Path>) -> Option<&'static Family> {
    match Recents::load(data_dir).entries().first() {
        Some(args) => family_of_args(args),
        None => crate::families::family_of(kinds().next()?),
    }
}

/// The value `option` has in connection options (`--baud 9600` or
/// `--baud=9600`), if given.
fn option_value<'a>(args: &'a [String], option: &str) -> Option<&'a str> {
    let prefix = format!("{option}=");
    args.iter().enumerate().find_map(|(i, arg)| {
        if arg == option {
            args.get(i + 1).map(String::as_str)
        } else {
            arg.strip_prefix(&prefix)
        }
    })
}

/// The protocol family connection options name: `--protocol`, else the
/// simulator's, else TMCL (as on the command line).
pub fn family_of_args(args: &[String]) -> Option<&'static Family> {
    let value = |option: &str| option_value(args, option);
    match (value("--protocol"), value("--sim")) {
        (Some(protocol), _) => find_family(protocol),
        (None, Some(sim)) => crate::families::family_of(find_kind(sim)?),
        // As the command line: the first family when nothing says.
        (None, None) => FAMILIES.first().map(|f| f.family),
    }
}

impl Pane for ConnectPane {
    fn name(&self) -> &'static str {
        "connect"
    }

    fn context(&self) -> Context {
        Context::Command
    }

    fn title(&self, _view: &View) -> String {
        "Connect".into()
    }

    fn region(&self) -> Region {
        Region::Main
    }

    fn render(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        if area.height == 0 || area.width == 0 {
            return;
        }
        if !self.scanned {
            self.scan();
        }
        let theme = view.theme;
        let width = usize::from(area.width);
        let key = |action| key_label(view.keymap, Context::Command, action);
        let mut head = vec![Line::styled(
            fit(
                &match view.session {
                    Some(s) => format!(
                        "Connected to {} #{}: choose another connection to switch to it",
                        s.link_name, s.address
                    ),
                    None => "Connect to a controller".to_string(),
                },
                width,
            ),
            theme.style(Role::Title),
        )];
        let (form, form_cursor) = self.form_line(view);
        let mut footer = vec![form];
        if let Some((option, choice)) = self.link_option() {
            let active = self.focus == Focus::Link && view.focused;
            footer.push(Line::from(vec![
                Span::styled("link ", theme.style(Role::Muted)),
                Span::styled("[", theme.style(Role::Muted)),
                Span::styled(
                    format!("{}={}", option.name, choice.value),
                    theme.style(if active {
                        Role::Selection
                    } else {
                        Role::Normal
                    }),
                ),
                Span::styled("]  ", theme.style(Role::Muted)),
                Span::styled(
                    fit(
                        choice.help,
                        width.saturating_sub(option.name.len() + choice.value.len() + 10),
                    ),
                    theme.style(Role::Muted),
                ),
            ]));
        }
        footer.extend([Line::styled(
            fit(
                &format!(
                    "↑↓ choose · {} connect{} · {} next field · ←→ protocol · {} back to the list",
                    key(Action::Submit),
                    if view.session.is_some() {
                        " · + add a link"
                    } else {
                        ""
                    },
                    key(Action::Complete),
                    key(Action::Cancel)
                ),
                width,
            ),
            theme.style(Role::Muted),
        )]);
        if let Some((role, text)) = &self.message {
            // A port that would not open explains itself over several
            // lines (who owns it, who holds it, what to do): each its own.
            footer.extend(
                text.lines()
                    .map(|line| Line::styled(fit(line, width), theme.style(*role))),
            );
        }
        // The list, in sections, scrolled to keep the selection in view.
        let choices = self.choices();
        self.selected = self.selected.min(choices.len().saturating_sub(1));
        let mut list: Vec<(Option<usize>, Line)> = Vec::new();
        let mut section = "";
        for (i, choice) in choices.iter().enumerate() {
            let title = match choice {
                Choice::Recent(_) => "Recent",
                Choice::Sim { .. } => "Simulators (no hardware needed)",
                Choice::Port(_) | Choice::Rescan => "Serial ports",
                Choice::Tcp => "TCP",
            };
            if title != section {
                section = title;
                list.push((None, Line::styled(title, theme.style(Role::Accent))));
                if title == "Serial ports" {
                    if let Some(problem) = &self.port_problem {
                        list.push((
                            None,
                            Line::styled(format!("  {problem}"), theme.style(Role::Warning)),
                        ));
                    } else if self.ports.is_empty() {
                        list.push((None, Line::styled("  none found", theme.style(Role::Muted))));
                    }
                }
            }
            list.push((
                Some(i),
                self.choice_line(choice, i == self.selected, view, width),
            ));
        }
        let room = usize::from(area.height).saturating_sub(head.len() + footer.len());
        let at = list
            .iter()
            .position(|(i, _)| *i == Some(self.selected))
            .unwrap_or(0);
        let skip = (at + 1).saturating_sub(room);
        let mut lines: Vec<Line> = std::mem::take(&mut head);
        lines.extend(list.into_iter().skip(skip).take(room).map(|(_, l)| l));
        while lines.len() < usize::from(area.height).saturating_sub(footer.len()) {
            lines.push(Line::raw(""));
        }
        let form_row = lines.len();
        lines.append(&mut footer);
        frame.render_widget(Paragraph::new(lines), area);
        if view.focused
            && let Some(column) = form_cursor
        {
            let x = area.x + column.min(width.saturating_sub(1)) as u16;
            let y = area.y + (form_row as u16).min(area.height - 1);
            frame.set_cursor_position(Position::new(x, y));
        }
    }

    fn handle_input(&mut self, input: &Input, view: &View) -> Outcome {
        match input {
            Input::Key(key) => {
                let outcome = self.key(key, view);
                self.announce(outcome)
            }
            Input::Paste(text) => {
                let line = text.lines().next().unwrap_or("");
                match self.focus {
                    Focus::Baud => self.baud.insert_str(line),
                    Focus::Address => self.address.insert_str(line),
                    Focus::Tcp => self.tcp.insert_str(line),
                    Focus::List | Focus::Protocol | Focus::Link => return Outcome::Ignored,
                }
                Outcome::redraw()
            }
            Input::Mouse(_) => Outcome::Ignored,
        }
    }

    fn on_event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
        match event {
            PaneEvent::Focused => {
                self.scan();
                Outcome::redraw()
            }
            PaneEvent::Snapshot if self.adding && view.modules.len() > 1 => {
                self.adding = false;
                self.message = Some((
                    Role::Accent,
                    format!(
                        "link added: {} modules in the axes pane's list (:module N picks one)",
                        view.modules.len()
                    ),
                ));
                Outcome::redraw()
            }
            PaneEvent::Connected { args } => {
                let ours = self.connecting.take();
                if let Some(args) = args.clone().or(ours.clone())
                    && let Err(why) = self.recents.remember(args)
                {
                    self.message = Some((Role::Warning, why));
                    return Outcome::redraw();
                }
                if ours.is_some() {
                    self.message = None;
                    // Connected from here: on to the console.
                    return Outcome::request(Request::Focus("command"));
                }
                Outcome::redraw()
            }
            PaneEvent::Notice(notice)
                if notice.level == NoticeLevel::Error
                    && (self.connecting.is_some() || self.adding) =>
            {
                self.connecting = None;
                self.adding = false;
                self.message = Some((Role::Error, notice.text.clone()));
                Outcome::redraw()
            }
            _ => Outcome::Ignored,
        }
    }
}
