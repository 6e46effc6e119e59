//! Shared by the parameter, traffic, plot and connect pane tests: a module
//! behind the console made of the TMCM-1110 simulator and the family's own
//! line preparation and reply reading (what a session does, without the
//! device task), and a driver that answers every line the console sends.
#![allow(dead_code)]

use std::time::Duration;

use axterm::families::find_family;
use axterm::families::find_kind;
use axterm::protocol::Family;
use axterm::session::{LineResult, SessionError};
use axterm::sim::{SimOptions, SimulatedController};
use axterm::ui::app::{App, AppEvent, Effect};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::buffer::Buffer;
use ratatui::style::Style;

/// A simulated TMCM-1110 answering console lines.
pub struct SimModule {
    pub family: &'static Family,
    pub sim: Box<dyn SimulatedController>,
    /// Every line sent to it, in order.
    pub lines: Vec<String>,
    /// Lines answered with an error status instead (`GAP 204, 0`).
    pub refuse: Vec<String>,
}

impl SimModule {
    pub fn new() -> SimModule {
        let kind = find_kind("tmcm1110").expect("tmcm1110 simulator");
        SimModule {
            family: find_family("tmcl").expect("tmcl"),
            sim: (kind.build)(&SimOptions::default()),
            lines: Vec::new(),
            refuse: Vec::new(),
        }
    }

    /// Send one line and read the answer, as a session would.
    pub fn answer(&mut self, line: &str) -> Result<LineResult, SessionError> {
        let prepared =
            self.family
                .console
                .prepare(line, 1)
                .map_err(|error| SessionError::Refused {
                    line: line.to_string(),
                    message: error.to_string(),
                })?;
        self.lines.push(prepared.canonical.clone());
        let mut request = prepared.bytes.clone();
        if self.refuse.contains(&prepared.canonical) {
            // An invalid type: the module answers status 3.
            request[1] = 0xEE;
            request[8] = request[..8].iter().fold(0u8, |s, b| s.wrapping_add(*b));
        }
        self.sim.feed(&request);
        let mut reply = self.sim.take_output();
        let mut waited = 0;
        while reply.len() < 9 && waited < 1000 {
            self.sim.advance(Duration::from_millis(1));
            reply.extend(self.sim.take_output());
            waited += 1;
        }
        let frames: Vec<Vec<u8>> = reply.chunks(9).map(<[u8]>::to_vec).collect();
        let reading = self
            .family
            .console
            .interpret(&prepared, &frames)
            .map_err(|error| SessionError::Reply {
                error: Box::new(error),
                request: prepared.bytes.clone(),
                reply: reply.clone(),
                elapsed: Duration::ZERO,
            })?;
        Ok(LineResult {
            line: prepared.canonical,
            request: prepared.bytes,
            reply,
            status: reading.status,
            value: reading.value,
            elapsed: Duration::from_millis(2),
            attempts: 1,
        })
    }
}

/// Carry out the console's effects against `module` until it asks for no
/// more lines: every line is answered, and what the answer makes the
/// console send next is answered too. Returns the lines sent, in order.
/// Effects other than sends are returned in `others`.
pub fn serve(app: &mut App, module: &mut SimModule, effects: Vec<Effect>) -> Served {
    let mut served = Served::default();
    let mut queue = effects;
    let mut guard = 0;
    while !queue.is_empty() {
        guard += 1;
        assert!(guard < 100_000, "the console never stops sending");
        let mut next = Vec::new();
        let sends = queue.iter().filter(|e| e.sends().is_some()).count();
        served.most_at_once = served.most_at_once.max(sends);
        for effect in queue {
            match effect.sends() {
                Some((pane, tag, lines)) => {
                    for line in lines {
                        served.lines.push(line.clone());
                        let result = module.answer(&line);
                        let failed = result.is_err();
                        next.extend(app.handle(AppEvent::Reply {
                            pane,
                            tag,
                            line,
                            result,
                        }));
                        if failed {
                            break;
                        }
                    }
                }
                None => served.others.push(effect),
            }
        }
        queue = next;
    }
    served
}

#[derive(Debug, Default)]
pub struct Served {
    pub lines: Vec<String>,
    pub others: Vec<Effect>,
    /// The most lines asked for in one go (1: a row at a time).
    pub most_at_once: usize,
}

/// Draw and return the buffer as well as the lines of text.
pub fn draw(app: &mut App, width: u16, height: u16) -> (Vec<String>, Buffer) {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("test backend");
    terminal.draw(|f| app.render(f)).expect("draw");
    let buffer = terminal.backend().buffer().clone();
    let lines = (0..height)
        .map(|y| {
            (0..width)
                .map(|x| buffer[(x, y)].symbol().to_string())
                .collect::<String>()
        })
        .collect();
    (lines, buffer)
}

/// The style of the first cell of `needle` on the line that contains
/// `row_text`.
pub fn style_of(lines: &[String], buffer: &Buffer, row_text: &str, needle: &str) -> Option<Style> {
    let (y, line) = lines
        .iter()
        .enumerate()
        .find(|(_, l)| l.contains(row_text))?;
    let start = line.find(row_text)?;
    let at = line[start..].find(needle)? + start;
    let x = line[..at].chars().count();
    let cell = &buffer[(x as u16, y as u16)];
    Some(cell.style())
}
