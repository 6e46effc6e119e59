//! The same work on several modules of one bus, in turn: `--addresses
//! 1-4` (a list as `axterm scan` takes it) or `--all` (a scan first, then
//! every module that answered), for `params diff|apply`, `exec` and `run`.
//! Every module asked for gets a row of the table at the end, one that
//! does not answer too; a failure on one does not stop the others unless
//! `--stop-on-failure`, and then the modules not tried are rows saying so.
//!
//! The work is written over a list of sessions on one link, each at its
//! module's address ([`Session::at_address`]): one device task, one
//! request in flight, as a multi-drop bus wants.
//!
//! Several links (`--sim mccl --sim mccl`, `--port A --port B`, cut by
//! [`super::links`]) make one fleet too: every module of every link,
//! worked link by link, module by module ([`Walk`]). A link is opened
//! when its turn comes; one that cannot be opened is a failed row, and
//! the others are still worked. This is how a line of MultiFlex boards
//! (one board per link, no module address) is a fleet.

use std::collections::VecDeque;
use std::fmt::Write as _;

use clap::Args;
use serde_json::{Value, json};

use super::ConnectionArgs;
use super::connection::Target;
use super::links::{all_links, describe_link};
use super::output::Format;
use super::scan::{find_modules, parse_addresses, probe_timeout};
use crate::device::DeviceError;
use crate::link::LinkError;
use crate::protocol::Family;
use crate::session::{Session, SessionError};

/// Which modules of the bus to work on.
#[derive(Debug, Clone, Default, Args)]
pub struct FleetArgs {
    /// Do the same on each of these modules in turn: a list of addresses
    /// and ranges, e.g. 1-4 or 1,3,7 (the connection's --address is then
    /// not used); a table at the end. With several links (--port A --port
    /// B), on each link's bus.
    #[arg(long, conflicts_with = "all")]
    pub addresses: Option<String>,
    /// Scan the bus first (as `axterm scan`), then do the same on every
    /// module that answered (with several links, each link's bus).
    #[arg(long)]
    pub all: bool,
    /// With several modules or links: stop at the first module that fails
    /// (those not tried are listed as such). By default every module of
    /// every link is tried.
    #[arg(long)]
    pub stop_on_failure: bool,
}

/// A link of several, as the table and the lines name it: `L2` and its
/// connection (`--port /dev/ttyUSB1`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct LinkName {
    pub label: String,
    pub connection: String,
}

/// One link of the fleet, resolved, not opened yet.
pub struct FleetLink {
    /// `None` when there is one link: then nothing names it.
    pub name: Option<LinkName>,
    pub target: Target,
    pub modules: Modules,
}

impl FleetLink {
    /// Every link the options give, each resolved with its modules
    /// (`--addresses`/`--all` apply to each). One link resolves as a
    /// single-link command always did ([`Target::resolve`]); with several,
    /// each link's `--address` list is its modules (its first or default
    /// address without one). A usage error names the link.
    pub fn resolve_all(
        connection: &ConnectionArgs,
        args: &FleetArgs,
    ) -> Result<Vec<FleetLink>, String> {
        if connection.more_links.is_empty() {
            let target = Target::resolve(connection)?;
            let modules = Modules::from_args(args, target.family)?;
            return Ok(vec![FleetLink {
                name: None,
                target,
                modules,
            }]);
        }
        all_links(connection)
            .into_iter()
            .enumerate()
            .map(|(index, link)| {
                let name = LinkName {
                    label: format!("L{}", index + 1),
                    connection: describe_link(link),
                };
                let at =
                    |message: String| format!("{} ({}): {message}", name.label, name.connection);
                let target = Target::resolve_modules(link).map_err(at)?;
                let mut modules = Modules::from_args(args, target.family).map_err(at)?;
                if modules == Modules::One && target.addresses.len() > 1 {
                    modules = Modules::List(target.addresses.clone());
                }
                Ok(FleetLink {
                    name: Some(name),
                    target,
                    modules,
                })
            })
            .collect()
    }

    /// Whether the work on `links` is a fleet's (a table at the end):
    /// several links, or several modules of one.
    pub fn several(links: &[FleetLink]) -> bool {
        links.len() > 1 || links.iter().any(|l| l.modules.several())
    }

    /// The addresses asked for before the link is open: `None` for a
    /// scan's (not known until it ran).
    fn asked(&self) -> Vec<Option<u8>> {
        match &self.modules {
            Modules::One => vec![Some(self.target.address)],
            Modules::List(addresses) => addresses.iter().copied().map(Some).collect(),
            Modules::Scan => vec![None],
        }
    }

    /// A row for each module asked for on this link, not worked, saying
    /// `note` (`failed`: counted as a failure).
    fn rows_unworked(&self, firmware: &str, note: &str, failed: bool) -> Vec<ModuleRow> {
        self.asked()
            .into_iter()
            .map(|address| ModuleRow {
                address: address.unwrap_or_default(),
                whole_link: address.is_none(),
                link: self.name.clone(),
                firmware: firmware.into(),
                failed: usize::from(failed),
                note: note.into(),
                ..ModuleRow::default()
            })
            .collect()
    }
}

/// A module of the fleet, its turn come: its session and its link.
pub struct FleetModule {
    pub session: Session,
    pub link: Option<LinkName>,
    /// Which of the fleet's links (0 the first).
    pub link_index: usize,
}

impl FleetModule {
    pub fn address(&self) -> u8 {
        self.session.address()
    }

    /// How lines name the module: `module 3`, or `L2 module 3` with
    /// several links.
    pub fn who(&self) -> String {
        match &self.link {
            Some(link) => format!("{} module {}", link.label, self.address()),
            None => format!("module {}", self.address()),
        }
    }

    /// Its row, firmware known, nothing done yet.
    pub fn row(&self, firmware: String) -> ModuleRow {
        ModuleRow {
            address: self.address(),
            link: self.link.clone(),
            firmware,
            ..ModuleRow::default()
        }
    }

    /// Put the module (and its link) into a line's JSON object.
    pub fn mark(&self, object: &mut Value) {
        object["module"] = json!(self.address());
        if let Some(link) = &self.link {
            object["link"] = json!(link.label);
            object["connection"] = json!(link.connection);
        }
    }
}

/// The fleet's modules in turn, link by link, module by module: each link
/// opened (and scanned with `--all`) when its turn comes, the rows of
/// modules not worked (a link that cannot be opened, those after a
/// failure with `--stop-on-failure`) kept as they are met.
pub struct Walk<'a> {
    links: &'a [FleetLink],
    command: &'a str,
    stop_on_failure: bool,
    next_link: usize,
    /// The open link's modules still to work, and its index.
    waiting: VecDeque<Session>,
    open_link: usize,
    /// Why the modules not worked yet will not be.
    ended: Option<String>,
    rows: Vec<ModuleRow>,
}

impl<'a> Walk<'a> {
    pub fn new(links: &'a [FleetLink], command: &'a str, stop_on_failure: bool) -> Walk<'a> {
        Walk {
            links,
            command,
            stop_on_failure,
            next_link: 0,
            waiting: VecDeque::new(),
            open_link: 0,
            ended: None,
            rows: Vec::new(),
        }
    }

    /// The next module to work, or `None` when there is none left. An
    /// error only when the fleet's one link cannot be opened (the command
    /// then fails as a single-link one does).
    pub async fn next(&mut self) -> Result<Option<FleetModule>, LinkError> {
        loop {
            if let Some(why) = self.ended.clone() {
                let note = format!("not tried: {why}");
                let name = self.links.get(self.open_link).and_then(|l| l.name.clone());
                for session in self.waiting.drain(..) {
                    self.rows.push(ModuleRow {
                        address: session.address(),
                        link: name.clone(),
                        firmware: "-".into(),
                        note: note.clone(),
                        ..ModuleRow::default()
                    });
                }
                for link in &self.links[self.next_link.min(self.links.len())..] {
                    self.rows.extend(link.rows_unworked("-", &note, false));
                }
                self.next_link = self.links.len();
                return Ok(None);
            }
            if let Some(session) = self.waiting.pop_front() {
                let link = &self.links[self.open_link];
                return Ok(Some(FleetModule {
                    session,
                    link: link.name.clone(),
                    link_index: self.open_link,
                }));
            }
            let Some(link) = self.links.get(self.next_link) else {
                return Ok(None);
            };
            self.open_link = self.next_link;
            self.next_link += 1;
            match link.target.open().await {
                Ok(session) => {
                    let modules = sessions(
                        &session,
                        &link.modules,
                        &link.target,
                        self.command,
                        link.name.as_ref(),
                    )
                    .await;
                    self.waiting = modules.into();
                }
                Err(error) if self.links.len() == 1 => return Err(error),
                Err(error) => {
                    let label = link.name.as_ref().map_or("the link", |n| n.label.as_str());
                    let connection = link.name.as_ref().map_or("", |n| n.connection.as_str());
                    eprintln!("axterm {}: {label} ({connection}): {error}", self.command);
                    // A table cell has one line: the reason without its advice
                    // (printed whole just above).
                    let note = format!("{label} cannot be opened: {}", error.headline());
                    self.rows
                        .extend(link.rows_unworked("(no link)", &note, true));
                    if self.stop_on_failure {
                        self.ended = Some(format!(
                            "--stop-on-failure after {label} could not be opened"
                        ));
                    }
                }
            }
        }
    }

    /// The row of the module [`Walk::next`] gave; with
    /// `--stop-on-failure` a failed one ends the walk.
    pub fn record(&mut self, module: &FleetModule, row: ModuleRow) {
        if !row.ok && self.stop_on_failure && self.ended.is_none() {
            self.ended = Some(format!("--stop-on-failure after {} failed", module.who()));
        }
        self.rows.push(row);
    }

    /// End the walk: the modules not worked yet are rows saying `why`.
    pub fn end_all(&mut self, why: String) {
        self.ended.get_or_insert(why);
    }

    /// Every row, in the order met.
    pub fn rows(self) -> Vec<ModuleRow> {
        self.rows
    }
}

/// The modules asked for, before the link is opened.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Modules {
    /// The connection's own module (no --addresses, no --all): output as
    /// for one module, no table.
    One,
    List(Vec<u8>),
    /// Every module a scan finds.
    Scan,
}

impl Modules {
    /// From the options, checked against the family's addresses. A family
    /// with one module per link (MCCL) takes neither option.
    pub fn from_args(args: &FleetArgs, family: &Family) -> Result<Modules, String> {
        let range = family.console.addresses();
        let asked = if args.all {
            "--all".to_string()
        } else {
            match &args.addresses {
                Some(text) => format!("--addresses {text}"),
                None => return Ok(Modules::One),
            }
        };
        if range.start() == range.end() {
            return Err(format!(
                "{asked}: the {} family has no module address on its link (one controller per \
                 link): give one link per controller instead",
                family.name
            ));
        }
        let Some(text) = &args.addresses else {
            return Ok(Modules::Scan);
        };
        let addresses = parse_addresses(text)?;
        if let Some(outside) = addresses.iter().find(|a| !range.contains(a)) {
            return Err(format!(
                "address {outside} is outside {}..{}, the addresses of the {} family (in \
                 --addresses {text})",
                range.start(),
                range.end(),
                family.name
            ));
        }
        Ok(Modules::List(addresses))
    }

    pub fn several(&self) -> bool {
        *self != Modules::One
    }
}

/// The sessions to work on, in order: the connection's own module, the
/// listed ones, or those a scan found (said on stderr as found).
pub async fn sessions(
    session: &Session,
    modules: &Modules,
    target: &Target,
    command: &str,
    link: Option<&LinkName>,
) -> Vec<Session> {
    match modules {
        Modules::One => vec![session.clone()],
        Modules::List(addresses) => addresses.iter().map(|&a| session.at_address(a)).collect(),
        Modules::Scan => {
            let timeout = probe_timeout(target);
            let on = link.map_or(String::new(), |l| format!("{}: ", l.label));
            let every: Vec<u8> = session.family().console.addresses().collect();
            let found: Vec<u8> = match find_modules(session, &every, timeout).await {
                Ok(found) => found.iter().map(|module| module.address).collect(),
                Err(error) => {
                    eprintln!("axterm {command}: {on}the scan stopped: {error}");
                    Vec::new()
                }
            };
            let list: Vec<String> = found.iter().map(u8::to_string).collect();
            eprintln!(
                "axterm {command}: {on}scan found {} module(s){}{}",
                found.len(),
                if found.is_empty() { "" } else { ": " },
                list.join(", ")
            );
            found.iter().map(|&a| session.at_address(a)).collect()
        }
    }
}

/// Who a module is, or why it does not say.
pub enum Identity {
    Firmware(String),
    /// Something answered, but not as asked.
    Odd(String),
    /// No answer at all: the module is not there or is deaf.
    Silent(String),
}

impl Identity {
    pub async fn ask(session: &Session) -> Identity {
        match session.identify().await {
            Ok(firmware) => Identity::Firmware(firmware),
            Err(error @ SessionError::Reply { .. }) => Identity::Odd(error.to_string()),
            Err(SessionError::Device {
                error: DeviceError::Timeout { .. },
                address,
                ..
            }) => Identity::Silent(format!("module {address} does not answer")),
            Err(error) => Identity::Silent(error.to_string()),
        }
    }

    /// The table's firmware column.
    pub fn shown(&self) -> String {
        match self {
            Identity::Firmware(f) => f.clone(),
            Identity::Odd(_) => "(odd answer)".into(),
            Identity::Silent(_) => "(no answer)".into(),
        }
    }

    pub fn answers(&self) -> bool {
        !matches!(self, Identity::Silent(_))
    }
}

/// One module's row of the table.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ModuleRow {
    pub address: u8,
    /// The row stands for a whole link whose modules are not known (a
    /// scan on a link not opened): no address.
    pub whole_link: bool,
    /// Its link, when there are several.
    pub link: Option<LinkName>,
    pub firmware: String,
    pub written: usize,
    pub verified: usize,
    pub differs: usize,
    pub failed: usize,
    /// Whether the module did what was asked.
    pub ok: bool,
    /// What the numbers do not say (no answer, not tried, cannot be read
    /// back).
    pub note: String,
}

impl ModuleRow {
    /// A module not tried because an earlier one failed.
    pub fn not_tried(address: u8, after: u8) -> ModuleRow {
        ModuleRow {
            address,
            firmware: "-".into(),
            note: format!("not tried: --stop-on-failure after module {after} failed"),
            ..ModuleRow::default()
        }
    }

    /// The row as `params diff|apply` report it: every count.
    pub fn json(&self) -> Value {
        self.json_with(&["written", "verified", "differs", "failed"])
    }

    /// The row with the counts of `columns`, under the names the text
    /// table gives them: `exec` and `run` count lines (a read is not a
    /// write), `params` what was written, verified, differs.
    pub fn json_with(&self, columns: &[&str]) -> Value {
        let mut object = json!({
            "module": self.address,
            "firmware": self.firmware,
            "ok": self.ok,
            "note": self.note,
        });
        for column in columns {
            object[*column] = json!(self.count(column));
        }
        if self.whole_link {
            object["module"] = Value::Null;
        }
        if let Some(link) = &self.link {
            object["link"] = json!(link.label);
            object["connection"] = json!(link.connection);
        }
        object
    }

    /// The count a column of the table shows (`lines` counts the lines
    /// done, kept in `written`).
    fn count(&self, column: &str) -> usize {
        match column {
            "written" | "lines" => self.written,
            "verified" => self.verified,
            "differs" => self.differs,
            _ => self.failed,
        }
    }

    /// The result column: `FAILED` only for a module that failed (did not
    /// answer, refused, was not tried); one that answered every question
    /// and only differs from the file says so.
    pub fn result(&self) -> &'static str {
        if self.ok {
            "ok"
        } else if self.failed == 0 && self.differs > 0 {
            "differs"
        } else {
            "FAILED"
        }
    }

    /// The module column: its address, `-` for a whole link's row.
    fn module_shown(&self) -> String {
        if self.whole_link {
            "-".into()
        } else {
            self.address.to_string()
        }
    }
}

/// The table at the end: one row a module, in the order worked on.
/// The firmware column holds at most this many characters: a MultiFlex
/// answers its `VE` with a paragraph, which would push the counts off the
/// screen. The JSON form keeps the whole answer.
pub const FIRMWARE_COLUMN: usize = 40;

/// `firmware` as the table shows it: its first line, cut to
/// [`FIRMWARE_COLUMN`] characters with an ellipsis.
fn firmware_shown(firmware: &str) -> String {
    let first = firmware.lines().next().unwrap_or("").trim();
    if first.chars().count() <= FIRMWARE_COLUMN && first.len() == firmware.trim().len() {
        return first.to_string();
    }
    let cut: String = first.chars().take(FIRMWARE_COLUMN - 1).collect();
    format!("{}…", cut.trim_end())
}

pub fn table(rows: &[ModuleRow], columns: &[&str]) -> String {
    let firmware = rows
        .iter()
        .map(|r| firmware_shown(&r.firmware).chars().count())
        .max()
        .unwrap_or(0)
        .max("firmware".len());
    // The link column only with several links: one link's table is as it
    // always was.
    let links: Vec<&LinkName> = rows.iter().filter_map(|r| r.link.as_ref()).collect();
    let mut out = String::new();
    if !links.is_empty() {
        out.push_str("link  ");
    }
    let _ = write!(out, "{:>6}  {:<firmware$}", "module", "firmware");
    for column in columns {
        let _ = write!(out, "  {column:>8}");
    }
    out.push_str("  result\n");
    for row in rows {
        if !links.is_empty() {
            let label = row.link.as_ref().map_or("", |l| l.label.as_str());
            let _ = write!(out, "{label:<4}  ");
        }
        let _ = write!(
            out,
            "{:>6}  {:<firmware$}",
            row.module_shown(),
            firmware_shown(&row.firmware)
        );
        for column in columns {
            let _ = write!(out, "  {:>8}", row.count(column));
        }
        let result = row.result();
        let _ = write!(out, "  {result}");
        if !row.note.is_empty() {
            let _ = write!(out, "  {}", row.note);
        }
        out.push('\n');
    }
    let mut named: Vec<&LinkName> = Vec::new();
    for link in links {
        if !named.contains(&link) {
            named.push(link);
            let _ = writeln!(out, "{}: {}", link.label, link.connection);
        }
    }
    let good = rows.iter().filter(|r| r.ok).count();
    let _ = writeln!(out, "{good} of {} module(s) ok", rows.len());
    out
}

/// Print the table (text, on stdout) or its JSON form (one object, the
/// rows under "modules"); the exit code: 0 when every module did what
/// was asked (and there was one), 1 otherwise.
pub fn finish(rows: &[ModuleRow], columns: &[&str], format: Format) -> i32 {
    match format {
        Format::Text => print!("{}", table(rows, columns)),
        Format::Json => {
            let modules: Vec<Value> = rows.iter().map(|row| row.json_with(columns)).collect();
            let ok = !rows.is_empty() && rows.iter().all(|r| r.ok);
            println!("{}", json!({ "modules": modules, "ok": ok }));
        }
    }
    if !rows.is_empty() && rows.iter().all(|r| r.ok) {
        super::EXIT_OK
    } else {
        super::EXIT_DEVICE
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::find_family;

    #[test]
    fn a_paragraph_of_firmware_is_cut_in_the_table_and_kept_whole_in_json() {
        let long = format!("MultiFlex ETH {}\nsecond line", "x".repeat(80));
        let row = ModuleRow {
            address: 0,
            firmware: long.clone(),
            ok: true,
            ..ModuleRow::default()
        };
        let said = table(std::slice::from_ref(&row), &["written"]);
        let line = said.lines().nth(1).expect("the row");
        let shown = line
            .split_whitespace()
            .nth(1)
            .expect("the firmware column")
            .to_string();
        assert!(line.contains("MultiFlex ETH xxx"), "{said}");
        assert!(!said.contains("second line"), "{said}");
        assert!(
            line.contains('…') && !line.contains(&"x".repeat(FIRMWARE_COLUMN)),
            "{said} ({shown})"
        );
        assert_eq!(row.json()["firmware"], long);
        assert_eq!(firmware_shown("TMCM-1110 v1.42"), "TMCM-1110 v1.42");
    }

    fn fleet(addresses: Option<&str>, all: bool) -> FleetArgs {
        FleetArgs {
            addresses: addresses.map(String::from),
            all,
            stop_on_failure: false,
        }
    }

    #[test]
    fn addresses_are_lists_within_the_family() {
        let tmcl = find_family("tmcl").unwrap();
        assert_eq!(
            Modules::from_args(&fleet(None, false), tmcl),
            Ok(Modules::One)
        );
        assert_eq!(
            Modules::from_args(&fleet(Some("1-3,7"), false), tmcl),
            Ok(Modules::List(vec![1, 2, 3, 7]))
        );
        assert_eq!(
            Modules::from_args(&fleet(None, true), tmcl),
            Ok(Modules::Scan)
        );
        let cmd4cr = find_family("cmd4cr").unwrap();
        let error = Modules::from_args(&fleet(Some("98-100"), false), cmd4cr).unwrap_err();
        assert!(error.contains("address 100 is outside 0..99"), "{error}");
    }

    #[test]
    fn mccl_has_no_module_address_to_list() {
        let mccl = find_family("mccl").unwrap();
        for args in [fleet(Some("1-4"), false), fleet(None, true)] {
            let error = Modules::from_args(&args, mccl).unwrap_err();
            assert!(
                error.contains("the mccl family has no module address"),
                "{error}"
            );
        }
    }

    /// `params diff` on a module that answers and only differs: not
    /// `FAILED`, which stays for one that does not answer (issue 19,
    /// point 8). The table is every family's, so one test covers them.
    #[test]
    fn a_module_that_only_differs_is_not_called_failed() {
        let rows = [
            ModuleRow {
                address: 1,
                firmware: "TMCM-1110".into(),
                differs: 2,
                ..ModuleRow::default()
            },
            ModuleRow {
                address: 2,
                firmware: "-".into(),
                failed: 1,
                note: "module 2 does not answer".into(),
                ..ModuleRow::default()
            },
        ];
        let text = table(&rows, &["written", "verified", "differs", "failed"]);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[1].ends_with("  differs"), "{text}");
        assert!(!lines[1].contains("FAILED"), "{text}");
        assert!(
            lines[2].ends_with("FAILED  module 2 does not answer"),
            "{text}"
        );
        assert_eq!(lines[3], "0 of 2 module(s) ok", "{text}");
    }

    #[test]
    fn with_several_links_the_table_names_each_rows_link_and_each_link() {
        let link = |n: usize, connection: &str| {
            Some(LinkName {
                label: format!("L{n}"),
                connection: connection.into(),
            })
        };
        let rows = [
            ModuleRow {
                link: link(1, "--sim mccl"),
                firmware: "MFX".into(),
                written: 1,
                verified: 1,
                ok: true,
                ..ModuleRow::default()
            },
            ModuleRow {
                link: link(2, "--port /dev/ttyUSB1"),
                whole_link: true,
                firmware: "(no link)".into(),
                failed: 1,
                note: "L2 cannot be opened: gone".into(),
                ..ModuleRow::default()
            },
        ];
        let text = table(&rows, &["written", "verified", "differs", "failed"]);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].starts_with("link  module  firmware"), "{text}");
        assert!(lines[1].starts_with("L1         0  MFX"), "{text}");
        assert!(
            lines[2].starts_with("L2         -  (no link)")
                && lines[2].ends_with("FAILED  L2 cannot be opened: gone"),
            "{text}"
        );
        assert_eq!(
            lines[3..],
            [
                "L1: --sim mccl",
                "L2: --port /dev/ttyUSB1",
                "1 of 2 module(s) ok"
            ]
        );
        assert_eq!(rows[1].json()["module"], Value::Null);
        assert_eq!(rows[1].json()["link"], "L2");
        assert_eq!(rows[1].json()["connection"], "--port /dev/ttyUSB1");
    }

    #[test]
    fn the_table_has_a_row_for_every_module_and_says_which_failed() {
        let rows = [
            ModuleRow {
                address: 1,
                firmware: "1110V112".into(),
                written: 3,
                verified: 3,
                ok: true,
                ..ModuleRow::default()
            },
            ModuleRow {
                address: 3,
                firmware: "(no answer)".into(),
                failed: 1,
                note: "module 3 does not answer".into(),
                ..ModuleRow::default()
            },
            ModuleRow::not_tried(4, 3),
        ];
        let text = table(&rows, &["written", "verified", "differs", "failed"]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 5, "{text}");
        assert!(lines[0].starts_with("module  firmware"), "{text}");
        assert!(
            lines[1].contains("1110V112") && lines[1].ends_with("ok"),
            "{text}"
        );
        assert!(
            lines[2].contains("FAILED  module 3 does not answer"),
            "{text}"
        );
        assert!(
            lines[3].contains("not tried: --stop-on-failure after module 3"),
            "{text}"
        );
        assert_eq!(lines[4], "1 of 3 module(s) ok");
    }
}
