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

use std::fmt::Write as _;

use clap::Args;
use serde_json::{Value, json};

use super::output::Format;
use super::scan::{PROBE_BYTES, PROBE_TIMEOUT, parse_addresses};
use crate::device::DeviceError;
use crate::link::LinkSpec;
use crate::protocol::Family;
use crate::session::{Session, SessionError};

/// Which modules of the bus to work on.
#[derive(Debug, Clone, Default, Args)]
pub struct FleetArgs {
    /// Do the same on each of these modules in turn: a list of addresses
    /// and ranges, e.g. 1-4 or 1,3,7 (the connection's --address is then
    /// not used); a table at the end.
    #[arg(long, conflicts_with = "all")]
    pub addresses: Option<String>,
    /// Scan the bus first (as `axterm scan`), then do the same on every
    /// module that answered.
    #[arg(long)]
    pub all: bool,
    /// With several modules: stop at the first module that fails (those
    /// not tried are listed as such). By default every module is tried.
    #[arg(long)]
    pub stop_on_failure: bool,
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
    spec: &LinkSpec,
    command: &str,
) -> Vec<Session> {
    match modules {
        Modules::One => vec![session.clone()],
        Modules::List(addresses) => addresses.iter().map(|&a| session.at_address(a)).collect(),
        Modules::Scan => {
            let timeout = PROBE_TIMEOUT + spec.byte_time().unwrap_or_default() * PROBE_BYTES;
            let mut found = Vec::new();
            for address in session.family().console.addresses() {
                match session.probe(address, timeout).await {
                    Ok(_) | Err(SessionError::Reply { .. }) => found.push(address),
                    Err(_) => {}
                }
            }
            let list: Vec<String> = found.iter().map(u8::to_string).collect();
            eprintln!(
                "axterm {command}: scan found {} module(s){}{}",
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

    pub fn json(&self) -> Value {
        json!({
            "module": self.address,
            "firmware": self.firmware,
            "written": self.written,
            "verified": self.verified,
            "differs": self.differs,
            "failed": self.failed,
            "ok": self.ok,
            "note": self.note,
        })
    }
}

/// Work on each session in turn (`work` gives a module's row); with
/// `stop_on_failure` the modules after the first that fails are rows
/// saying they were not tried.
pub async fn each_module<W, F>(
    sessions: &[Session],
    stop_on_failure: bool,
    mut work: W,
) -> Vec<ModuleRow>
where
    W: FnMut(Session) -> F,
    F: Future<Output = ModuleRow>,
{
    let mut rows: Vec<ModuleRow> = Vec::new();
    let mut failed_at = None;
    for session in sessions {
        if let Some(after) = failed_at {
            rows.push(ModuleRow::not_tried(session.address(), after));
            continue;
        }
        let row = work(session.clone()).await;
        if !row.ok && stop_on_failure {
            failed_at = Some(row.address);
        }
        rows.push(row);
    }
    rows
}

/// The table at the end: one row a module, in the order worked on.
pub fn table(rows: &[ModuleRow], columns: &[&str]) -> String {
    let firmware = rows
        .iter()
        .map(|r| r.firmware.chars().count())
        .max()
        .unwrap_or(0)
        .max("firmware".len());
    let mut out = String::new();
    let _ = write!(out, "{:>6}  {:<firmware$}", "module", "firmware");
    for column in columns {
        let _ = write!(out, "  {column:>8}");
    }
    out.push_str("  result\n");
    for row in rows {
        let _ = write!(out, "{:>6}  {:<firmware$}", row.address, row.firmware);
        for column in columns {
            let n = match *column {
                "written" | "lines" => row.written,
                "verified" => row.verified,
                "differs" => row.differs,
                _ => row.failed,
            };
            let _ = write!(out, "  {n:>8}");
        }
        let result = if row.ok { "ok" } else { "FAILED" };
        let _ = write!(out, "  {result}");
        if !row.note.is_empty() {
            let _ = write!(out, "  {}", row.note);
        }
        out.push('\n');
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
            let modules: Vec<Value> = rows.iter().map(ModuleRow::json).collect();
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
    use crate::protocol::find_family;

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
