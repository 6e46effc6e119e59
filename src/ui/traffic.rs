//! The traffic monitor: every frame sent and received, with its time,
//! direction, bytes, meaning (the family's decoder: a request as its
//! console line, a reply as its status and value) and, for an answer, the
//! round trip since its request.
//!
//! Frames are kept as bytes and put into words only when a row is drawn
//! or saved, once each: status polling alone brings a hundred or more a
//! second, nearly all of which nobody ever looks at, and decoding each on
//! arrival was the larger part of an idle console's work.
//!
//! Memory is bounded: a ring of the last [`TRAFFIC_LIMIT`] frames. Pausing
//! freezes the view while frames go on being kept; the console's own
//! status polls (and their answers) can be hidden; what is shown can be
//! saved to a text file.
//!
//! On a console with several links each frame carries its link (`L2`),
//! and the monitor shows one link's frames or every link's.

use std::cell::OnceCell;
use std::collections::VecDeque;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ratatui::Frame;
use ratatui::crossterm::event::{KeyEvent, MouseEventKind};
use ratatui::layout::{Position, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use super::field::Field;
use super::keymap::{Action, Context};
use super::pane::{Input, Outcome, Pane, PaneEvent, Region, Request, View, key_label};
use super::text::fit;
use super::theme::Role;
use crate::device::{Direction, Priority, TrafficKind, TrafficRecord};
use crate::protocol::Family;

/// Frames kept: at a 20 Hz poll of eleven values (TMCL), about two
/// minutes of traffic; ten thousand short lines are a few megabytes.
pub const TRAFFIC_LIMIT: usize = 10_000;

/// The file name offered when saving.
pub const DEFAULT_FILE: &str = "axterm-traffic.txt";

/// The monitor is redrawn at most this often while frames pour in: status
/// polling alone makes a hundred or more a second, and the screen need
/// not follow each one.
pub const REFRESH: Duration = Duration::from_millis(100);

/// One frame as the monitor keeps it.
struct Entry {
    /// Numbers frames in arrival order, across evictions.
    seq: u64,
    /// The link it passed on ([`crate::ui::pane::ModuleEntry::link`]).
    link: usize,
    at: Instant,
    direction: Direction,
    kind: TrafficKind,
    poll: bool,
    bytes: Vec<u8>,
    /// For a received frame: the last request sent before it, in whose
    /// light it reads.
    request: Option<Arc<[u8]>>,
    /// The family connected when it came, which puts it into words.
    family: Option<&'static Family>,
    /// For an answer: since its request went out.
    rtt: Option<Duration>,
    /// The bytes and the meaning as shown, made the first time they are.
    words: OnceCell<Words>,
}

/// A frame put into words.
#[derive(Debug, Clone)]
struct Words {
    /// The bytes as the family writes them.
    hex: String,
    meaning: String,
}

impl Entry {
    fn words(&self) -> &Words {
        self.words.get_or_init(|| self.describe())
    }

    fn describe(&self) -> Words {
        let family = self.family;
        let described = match self.direction {
            Direction::Sent => family.and_then(|f| f.console.describe_request(&self.bytes)),
            Direction::Received => family.and_then(|f| {
                f.console
                    .describe_reply(&self.bytes, self.request.as_deref())
            }),
        };
        let meaning = match self.kind {
            TrafficKind::Garbage => format!(
                "garbage: {} byte(s) that never made a frame",
                self.bytes.len()
            ),
            TrafficKind::Stale => format!("late, nobody waited: {}", described.unwrap_or_default()),
            TrafficKind::Unsolicited => format!("unsolicited: {}", described.unwrap_or_default()),
            TrafficKind::Request | TrafficKind::Answer => described.unwrap_or_default(),
        };
        let hex = family.map_or_else(
            || {
                self.bytes
                    .iter()
                    .map(|b| format!("{b:02X}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            },
            |f| (f.show_bytes)(&self.bytes),
        );
        Words { hex, meaning }
    }
}

/// The traffic monitor pane.
pub struct TrafficPane {
    entries: VecDeque<Entry>,
    limit: usize,
    next_seq: u64,
    /// Times are shown from the first frame seen.
    start: Option<Instant>,
    /// The last request sent on each link: replies are read in its
    /// light, and timed from it.
    last_request: Vec<(usize, Instant, Arc<[u8]>)>,
    /// Show only this link's frames.
    link_filter: Option<usize>,
    /// The highest link number seen: with more than one, rows name theirs.
    last_link: usize,
    /// Frames numbered from this one on are not shown while paused.
    paused: Option<u64>,
    hide_polls: bool,
    /// Rows scrolled back from the newest; 0 follows new frames.
    scroll: usize,
    page: usize,
    saving: Option<Field>,
    message: Option<(Role, String)>,
    /// Frames dropped off the ring since the last clear.
    evicted: u64,
    /// A wake-up to redraw is asked for; frames shown meanwhile wait for
    /// it ([`REFRESH`]).
    waking: bool,
    /// Frames came in to show since the last redraw.
    unseen: bool,
    next_tag: u64,
}

impl Default for TrafficPane {
    fn default() -> Self {
        TrafficPane::new()
    }
}

impl TrafficPane {
    pub fn new() -> TrafficPane {
        TrafficPane::with_limit(TRAFFIC_LIMIT)
    }

    /// A monitor keeping at most `limit` frames.
    pub fn with_limit(limit: usize) -> TrafficPane {
        TrafficPane {
            entries: VecDeque::new(),
            limit: limit.max(1),
            next_seq: 0,
            start: None,
            last_request: Vec::new(),
            link_filter: None,
            last_link: 0,
            paused: None,
            hide_polls: false,
            scroll: 0,
            page: 10,
            saving: None,
            message: None,
            evicted: 0,
            waking: false,
            unseen: false,
            next_tag: 1,
        }
    }

    /// Frames kept.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    pub fn is_paused(&self) -> bool {
        self.paused.is_some()
    }

    /// Take in one frame; true if it shows (not paused, not a hidden poll).
    /// It is put into words only when shown (see the module docs).
    fn record(
        &mut self,
        link: usize,
        record: &TrafficRecord,
        family: Option<&'static Family>,
    ) -> bool {
        self.start.get_or_insert(record.at);
        self.last_link = self.last_link.max(link);
        let poll = record.priority == Some(Priority::Poll);
        let mut rtt = None;
        let mut request = None;
        let last = self.last_request.iter().position(|(l, _, _)| *l == link);
        match record.direction {
            Direction::Sent => {
                let sent = (link, record.at, Arc::from(record.bytes.as_slice()));
                match last.and_then(|at| self.last_request.get_mut(at)) {
                    Some(slot) => *slot = sent,
                    None => self.last_request.push(sent),
                }
            }
            Direction::Received => {
                if let Some((_, at, bytes)) = last.and_then(|at| self.last_request.get(at)) {
                    if record.kind == TrafficKind::Answer {
                        rtt = Some(record.at.saturating_duration_since(*at));
                    }
                    request = Some(Arc::clone(bytes));
                }
            }
        }
        let entry = Entry {
            seq: self.next_seq,
            link,
            at: record.at,
            direction: record.direction,
            kind: record.kind,
            poll,
            bytes: record.bytes.clone(),
            request,
            family,
            rtt,
            words: OnceCell::new(),
        };
        self.next_seq += 1;
        let shows = self.paused.is_none()
            && !(poll && self.hide_polls)
            && self.link_filter.is_none_or(|only| only == link);
        if shows && self.scroll > 0 {
            // Keep the rows being read where they are.
            self.scroll += 1;
        }
        self.entries.push_back(entry);
        while self.entries.len() > self.limit {
            self.entries.pop_front();
            self.evicted += 1;
        }
        shows
    }

    /// The frames the view shows, oldest first.
    fn shown(&self) -> impl Iterator<Item = &Entry> {
        let until = self.paused.unwrap_or(u64::MAX);
        self.entries.iter().filter(move |e| {
            e.seq < until
                && !(self.hide_polls && e.poll)
                && self.link_filter.is_none_or(|only| only == e.link)
        })
    }

    fn line_text(&self, entry: &Entry) -> String {
        let start = self.start.unwrap_or(entry.at);
        let at = entry.at.saturating_duration_since(start).as_secs_f64();
        let direction = match entry.direction {
            Direction::Sent => "→",
            Direction::Received => "←",
        };
        let rtt = entry.rtt.map_or_else(String::new, |d| {
            format!("{:.1}ms", d.as_secs_f64() * 1000.0)
        });
        let words = entry.words();
        let link = if self.last_link > 0 {
            format!("L{} ", entry.link + 1)
        } else {
            String::new()
        };
        format!(
            "{at:>9.3} {link}{direction} {rtt:>7} {} {}",
            words.hex, words.meaning
        )
    }

    fn role_of(entry: &Entry) -> Role {
        match (entry.kind, entry.direction) {
            (TrafficKind::Garbage | TrafficKind::Stale, _) => Role::Warning,
            _ if entry.poll => Role::Poll,
            (_, Direction::Sent) => Role::Sent,
            (_, Direction::Received) => Role::Received,
        }
    }

    /// The shown frames as a text file.
    /// An existing file is replaced only with `--force` before its name.
    fn save(&mut self, path: PathBuf, existing: crate::files::Existing) {
        let mut text = String::new();
        let _ = writeln!(
            text,
            "# axterm traffic: seconds since the first frame, direction, round trip, bytes, meaning"
        );
        let mut count = 0;
        for entry in self.shown() {
            let _ = writeln!(text, "{}", self.line_text(entry));
            count += 1;
        }
        self.message = Some(match crate::files::save(&path, text.as_bytes(), existing) {
            Ok(()) => (
                Role::Ok,
                format!("saved {count} frame(s) to {}", path.display()),
            ),
            Err(e) => (Role::Error, format!("cannot write {}: {e}", path.display())),
        });
    }

    fn save_key(&mut self, mut field: Field, key: &KeyEvent, view: &View) -> Outcome {
        match view.keymap.action_for(Context::Command, key) {
            Some(Action::Cancel) => {}
            Some(Action::Submit) => {
                let text = field.text().trim().to_string();
                let (existing, name) = crate::files::force_option(&text);
                if name.is_empty() {
                    self.message = Some((Role::Error, "no file name given".into()));
                    self.saving = Some(field);
                } else {
                    self.save(PathBuf::from(name), existing);
                }
            }
            _ => {
                let edited = field.edit(key);
                self.saving = Some(field);
                if !edited {
                    return Outcome::Ignored;
                }
            }
        }
        Outcome::redraw()
    }

    fn key(&mut self, key: &KeyEvent, view: &View) -> Outcome {
        if let Some(field) = self.saving.take() {
            return self.save_key(field, key, view);
        }
        let Some(action) = view.keymap.action_for(Context::Traffic, key) else {
            return Outcome::Ignored;
        };
        let shown = self.shown().count();
        let most = shown.saturating_sub(self.page);
        match action {
            Action::PauseTraffic => {
                self.paused = match self.paused {
                    Some(_) => {
                        self.scroll = 0;
                        None
                    }
                    None => Some(self.next_seq),
                };
            }
            Action::ToggleHidePolls => {
                self.hide_polls = !self.hide_polls;
                self.scroll = 0;
            }
            // Every link, link 1, link 2, … every link again.
            Action::TrafficLink => {
                self.link_filter = match self.link_filter {
                    None if self.last_link > 0 => Some(0),
                    Some(link) if link < self.last_link => Some(link + 1),
                    _ => None,
                };
                self.scroll = 0;
            }
            Action::ClearTraffic => {
                self.entries.clear();
                self.scroll = 0;
                self.evicted = 0;
                self.message = None;
            }
            Action::SaveTraffic => {
                self.message = None;
                self.saving = Some(Field::new(DEFAULT_FILE));
            }
            Action::ScrollUp => self.scroll = (self.scroll + 1).min(most),
            Action::ScrollDown => self.scroll = self.scroll.saturating_sub(1),
            Action::ScrollPageUp => self.scroll = (self.scroll + self.page).min(most),
            Action::ScrollPageDown => self.scroll = self.scroll.saturating_sub(self.page),
            Action::ScrollTop => self.scroll = most,
            Action::ScrollBottom => self.scroll = 0,
            Action::Cancel => self.message = None,
            _ => return Outcome::Ignored,
        }
        Outcome::redraw()
    }

    /// Redraw now and ask to be woken after [`REFRESH`].
    fn wake(&mut self) -> Outcome {
        self.waking = true;
        let tag = self.next_tag;
        self.next_tag += 1;
        Outcome::request(Request::WakeAfter {
            after: REFRESH,
            tag,
        })
    }

    fn status_text(&self, view: &View) -> String {
        let shown = self.shown().count();
        let mut parts = vec![format!("{shown} frames")];
        if self.evicted > 0 {
            parts.push(format!("last {} kept", self.limit));
        }
        if self.hide_polls {
            parts.push("polls hidden".into());
        }
        if let Some(link) = self.link_filter {
            parts.push(format!("link {} only", link + 1));
        }
        if let Some(at) = self.paused {
            let newer = self.next_seq.saturating_sub(at);
            parts.push(format!("PAUSED (+{newer} new)"));
        } else if self.scroll > 0 {
            parts.push(format!("{} rows back", self.scroll));
        }
        let key = |action| key_label(view.keymap, Context::Traffic, action);
        parts.push(format!(
            "{} pause · {} polls · {} save",
            key(Action::PauseTraffic),
            key(Action::ToggleHidePolls),
            key(Action::SaveTraffic)
        ));
        if self.last_link > 0 {
            parts.push(format!("{} link", key(Action::TrafficLink)));
        }
        parts.join(" · ")
    }
}

impl Pane for TrafficPane {
    fn name(&self) -> &'static str {
        "traffic"
    }

    /// While a file name is typed, letters are text.
    fn context(&self) -> Context {
        if self.saving.is_some() {
            Context::Command
        } else {
            Context::Traffic
        }
    }

    fn title(&self, _view: &View) -> String {
        if self.paused.is_some() {
            "Traffic (paused)".into()
        } else {
            "Traffic".into()
        }
    }

    fn region(&self) -> Region {
        Region::Side
    }

    fn render(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        if area.height == 0 || area.width == 0 {
            return;
        }
        let theme = view.theme;
        let width = usize::from(area.width);
        let height = usize::from(area.height);
        let mut footer: Vec<Line> = Vec::new();
        let mut cursor = None;
        if let Some(field) = &self.saving {
            let label = "save to: ";
            cursor = Some(label.chars().count() + field.cursor_column());
            footer.push(Line::from(vec![
                Span::styled(label, theme.style(Role::Prompt)),
                Span::styled(field.text().to_string(), theme.style(Role::Normal)),
            ]));
        } else if let Some((role, text)) = &self.message {
            footer.push(Line::styled(fit(text, width), theme.style(*role)));
        }
        let body = height.saturating_sub(2 + footer.len());
        self.page = body.max(1);
        let mut lines = vec![
            Line::styled(
                fit(&self.status_text(view), width),
                theme.style(Role::Muted),
            ),
            Line::styled(
                fit("   time s   rtt     bytes / meaning", width),
                theme.style(Role::Title),
            ),
        ];
        let count = self.shown().count();
        self.scroll = self.scroll.min(count.saturating_sub(body));
        let shown: Vec<&Entry> = self.shown().collect();
        let end = shown.len() - self.scroll;
        let begin = end.saturating_sub(body);
        for entry in shown.get(begin..end).unwrap_or_default() {
            lines.push(Line::styled(
                fit(&self.line_text(entry), width),
                theme.style(Self::role_of(entry)),
            ));
        }
        if shown.is_empty() {
            lines.push(Line::styled(
                if view.session.is_some() {
                    "no frames yet"
                } else {
                    "not connected"
                },
                theme.style(Role::Muted),
            ));
        }
        while lines.len() < 2 + body {
            lines.push(Line::raw(""));
        }
        let footer_row = lines.len();
        lines.extend(footer);
        frame.render_widget(Paragraph::new(lines), area);
        if view.focused
            && let Some(column) = cursor
        {
            let x = area.x + column.min(width.saturating_sub(1)) as u16;
            let y = area.y + (footer_row as u16).min(area.height - 1);
            frame.set_cursor_position(Position::new(x, y));
        }
    }

    fn handle_input(&mut self, input: &Input, view: &View) -> Outcome {
        match input {
            Input::Key(key) => self.key(key, view),
            Input::Paste(text) => match self.saving.as_mut() {
                Some(field) => {
                    field.insert_str(text.lines().next().unwrap_or(""));
                    Outcome::redraw()
                }
                None => Outcome::Ignored,
            },
            Input::Mouse(mouse) => {
                let most = self.shown().count().saturating_sub(self.page);
                match mouse.kind {
                    MouseEventKind::ScrollUp => self.scroll = (self.scroll + 3).min(most),
                    MouseEventKind::ScrollDown => self.scroll = self.scroll.saturating_sub(3),
                    _ => return Outcome::Ignored,
                }
                Outcome::redraw()
            }
        }
    }

    fn on_event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
        match event {
            PaneEvent::TrafficLink(link) => {
                self.link_filter = *link;
                self.scroll = 0;
                Outcome::redraw()
            }
            PaneEvent::Traffic(_) | PaneEvent::LinkTraffic { .. } => {
                let (link, record) = match event {
                    PaneEvent::LinkTraffic { link, record } => (*link, record),
                    PaneEvent::Traffic(record) => (0, record),
                    _ => return Outcome::Ignored,
                };
                // Put into words by the family of its own link.
                let family = view
                    .modules
                    .iter()
                    .find(|m| m.link == link)
                    .map(|m| m.snapshot.family)
                    .or(view.session.map(|s| s.family));
                if !self.record(link, record, family) {
                    Outcome::Ignored
                } else if !view.shown {
                    // Behind a tab: kept, drawn when it comes to the front,
                    // no refresh wake-ups meanwhile.
                    self.unseen = true;
                    Outcome::Ignored
                } else if self.waking {
                    self.unseen = true;
                    Outcome::Ignored
                } else {
                    // Shown now; what follows within REFRESH waits for
                    // the wake-up.
                    self.wake()
                }
            }
            PaneEvent::Wake { .. } => {
                self.waking = false;
                if std::mem::take(&mut self.unseen) {
                    self.wake()
                } else {
                    Outcome::Ignored
                }
            }
            _ => Outcome::Ignored,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ui::keymap::Keymap;
    use crate::ui::theme::Theme;
    use ratatui::Terminal;
    use ratatui::backend::TestBackend;

    fn frame(direction: Direction, bytes: [u8; 9], ms: u64, t0: Instant) -> TrafficRecord {
        TrafficRecord {
            at: t0 + Duration::from_millis(ms),
            direction,
            kind: match direction {
                Direction::Sent => TrafficKind::Request,
                Direction::Received => TrafficKind::Answer,
            },
            bytes: bytes.to_vec(),
            priority: Some(Priority::Poll),
        }
    }

    fn in_words(pane: &TrafficPane) -> usize {
        pane.entries
            .iter()
            .filter(|e| e.words.get().is_some())
            .count()
    }

    #[test]
    fn frames_are_put_into_words_only_when_a_row_shows_them() {
        let theme = Theme::builtin("dark").expect("theme");
        let keymap = Keymap::builtin("default").expect("keymap");
        // Not connected: the bytes in hex, no meaning, which is enough to
        // see what was put into words.
        let mut view = View {
            theme: &theme,
            keymap: &keymap,
            session: None,
            modules: &[],
            module: 0,
            focused: false,
            shown: false,
        };
        let mut pane = TrafficPane::new();
        let t0 = Instant::now();
        // GAP 1, 0 and its answer (-500), two hundred times.
        let gap = [1, 6, 1, 0, 0, 0, 0, 0, 8];
        let reply = crate::protocol::tmcl::Reply {
            host_address: 2,
            module_address: 1,
            status: crate::protocol::tmcl::Status::OK,
            command: 6,
            value: -500,
        }
        .to_bytes();
        for n in 0..200 {
            pane.on_event(
                &PaneEvent::Traffic(frame(Direction::Sent, gap, n, t0)),
                &view,
            );
            pane.on_event(
                &PaneEvent::Traffic(frame(Direction::Received, reply, n, t0)),
                &view,
            );
        }
        assert_eq!(pane.len(), 400);
        assert_eq!(in_words(&pane), 0, "nothing drawn, nothing decoded");

        view.shown = true;
        let mut terminal = Terminal::new(TestBackend::new(100, 12)).expect("backend");
        terminal
            .draw(|f| pane.render(f, f.area(), &view))
            .expect("draw");
        // Twelve rows: a status line, a header and ten frames.
        assert_eq!(in_words(&pane), 10);
        let screen = format!("{:?}", terminal.backend().buffer());
        assert!(
            screen.contains("02 01 64 06 FF FF FE 0C"),
            "the last answer, -500: {screen}"
        );
        // Drawn again, the same rows are not decoded again.
        terminal
            .draw(|f| pane.render(f, f.area(), &view))
            .expect("draw");
        assert_eq!(in_words(&pane), 10);
    }
}
