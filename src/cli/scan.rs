//! `axterm scan CONNECTION [--addresses 1-255] [--format json]`: ask every
//! address on the bus who it is (TMCL: firmware version, 136 type 0;
//! CMD-4CR: VER) with a short timeout, and list the modules that answer.
//! Without `--addresses`, the list `--address` gives (`--address 1-4`), or
//! every address the family has (TMCL 1-255, CMD-4CR 0-99). The modules
//! found are also [`find_modules`], for commands that work on every
//! module of a bus.

use std::time::Duration;

use clap::Args;
use serde_json::json;

use super::connection::{Target, run_to_exit};
use super::output::Format;
use super::{ConnectionArgs, EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::device::DeviceError;
use crate::protocol::Family;
use crate::session::{Session, SessionError};

/// How long to wait for an answer at each address, on top of the wire
/// time of the exchange: modules answer within a few milliseconds (TMCL
/// GP75 telegram pause aside), so an empty bus of 255 addresses takes
/// about 13 s, not minutes.
pub const PROBE_TIMEOUT: Duration = Duration::from_millis(50);

/// Bytes on the wire per probe, request and reply, with room to spare.
const PROBE_BYTES: u32 = 40;

#[derive(Debug, Clone, Args)]
pub struct ScanArgs {
    /// Addresses to try: a list of numbers and ranges, e.g. 1-255 or
    /// 1,5,10-20 (default: the list --address gives, else every address
    /// of the protocol family).
    #[arg(long)]
    pub addresses: Option<String>,
    /// Output: text (a line per module) or json (one object: the
    /// connection, the family, how many addresses were tried, and the
    /// modules found with address and identity).
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub format: Format,
}

/// A module that answered a scan.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FoundModule {
    pub address: u8,
    /// Who it said it is (its firmware version), or why its answer was
    /// not one: something answered, so a module is there.
    pub identity: Result<String, String>,
}

/// Ask each of `addresses` in turn who it is, waiting at most `timeout`
/// for each: the modules that answered, in the order asked. Silence is no
/// module; a failure of the link itself ends the scan with its error.
pub async fn find_modules(
    session: &Session,
    addresses: &[u8],
    timeout: Duration,
) -> Result<Vec<FoundModule>, SessionError> {
    let mut found = Vec::new();
    for &address in addresses {
        match session.probe(address, timeout).await {
            Ok(identity) => found.push(FoundModule {
                address,
                identity: Ok(identity),
            }),
            Err(SessionError::Device {
                error: DeviceError::Timeout { .. },
                ..
            }) => {}
            // Something answered, if not as asked: a module is there.
            Err(error @ SessionError::Reply { .. }) => found.push(FoundModule {
                address,
                identity: Err(error.to_string()),
            }),
            Err(error) => return Err(error),
        }
    }
    Ok(found)
}

/// How long a probe waits at most on `target`'s line: `--timeout`, else
/// [`PROBE_TIMEOUT`] and the wire time of a probe.
pub fn probe_timeout(target: &Target) -> Duration {
    match target.options.device.timeout {
        Some(timeout) => timeout,
        None => PROBE_TIMEOUT + target.spec.byte_time().unwrap_or_default() * PROBE_BYTES,
    }
}

/// The address-list parser, shared by every front end (moved to
/// [`crate::protocol::addresses`]; the old path stays).
pub use crate::protocol::addresses::parse_addresses;

/// The addresses to try: those given, each one the family can have, or
/// every address of the family. A frame for an address outside the
/// family's would reach another module (CMD-4CR `@100VER` is read by
/// controller 10 as `0VER`) and report it where it is not.
fn family_addresses(family: &Family, given: Option<&str>) -> Result<Vec<u8>, String> {
    let range = family.console.addresses();
    let Some(text) = given else {
        return Ok(range.collect());
    };
    let addresses = parse_addresses(text).map_err(|e| format!("--addresses {text}: {e}"))?;
    match addresses.iter().find(|a| !range.contains(a)) {
        Some(outside) => Err(format!(
            "address {outside} is outside {}..{}, the addresses of the {} family (in --addresses {text})",
            range.start(),
            range.end(),
            family.name
        )),
        None => Ok(addresses),
    }
}

pub fn run(connection: &ConnectionArgs, args: &ScanArgs) -> i32 {
    let target = match Target::resolve_modules(connection) {
        Ok(target) => target,
        Err(message) => {
            eprintln!("axterm scan: {message}");
            return EXIT_USAGE;
        }
    };
    let family = target.family;
    let addresses = match (&args.addresses, &connection.address) {
        (None, Some(list)) if list.is_several() => Ok(target.addresses.clone()),
        (given, _) => family_addresses(family, given.as_deref()),
    };
    let addresses = match addresses {
        Ok(addresses) => addresses,
        Err(message) => {
            eprintln!("axterm scan: {message}");
            return EXIT_USAGE;
        }
    };
    let timeout = probe_timeout(&target);
    let format = args.format;
    run_to_exit("scan", async move {
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm scan: {e}");
                return EXIT_CONNECTION;
            }
        };
        let found = match find_modules(&session, &addresses, timeout).await {
            Ok(found) => found,
            Err(error) => {
                eprintln!("axterm scan: {error}");
                return EXIT_DEVICE;
            }
        };
        match format {
            Format::Text => {
                for module in &found {
                    match &module.identity {
                        Ok(identity) => println!("address {}: {identity}", module.address),
                        Err(error) => {
                            println!("address {}: (answers, but: {error})", module.address)
                        }
                    }
                }
            }
            Format::Json => println!(
                "{}",
                scan_json(&target.spec.describe(), family, addresses.len(), &found)
            ),
        }
        eprintln!(
            "axterm scan: {} module{} found at {} address{} tried on {}",
            found.len(),
            if found.len() == 1 { "" } else { "s" },
            addresses.len(),
            if addresses.len() == 1 { "" } else { "es" },
            target.spec.describe()
        );
        if found.is_empty() {
            EXIT_DEVICE
        } else {
            EXIT_OK
        }
    })
}

/// The scan as one JSON object: `connection`, `family`, `tried` (how many
/// addresses), and `modules`, each `{"address", "identity"}` with
/// `identity` null and an `error` when the answer was no identity.
pub fn scan_json(
    connection: &str,
    family: &Family,
    tried: usize,
    found: &[FoundModule],
) -> serde_json::Value {
    let modules: Vec<_> = found
        .iter()
        .map(|module| match &module.identity {
            Ok(identity) => json!({ "address": module.address, "identity": identity }),
            Err(error) => json!({
                "address": module.address,
                "identity": serde_json::Value::Null,
                "error": error,
            }),
        })
        .collect();
    json!({
        "connection": connection,
        "family": family.name,
        "tried": tried,
        "modules": modules,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_json_form_lists_address_and_identity() {
        let tmcl = crate::families::find_family("tmcl").expect("tmcl");
        let found = [
            FoundModule {
                address: 1,
                identity: Ok("1110V112".into()),
            },
            FoundModule {
                address: 4,
                identity: Err("bad reply".into()),
            },
        ];
        let json = scan_json("simulator tmcm1110", tmcl, 6, &found);
        assert_eq!(
            json,
            serde_json::json!({
                "connection": "simulator tmcm1110",
                "family": "tmcl",
                "tried": 6,
                "modules": [
                    {"address": 1, "identity": "1110V112"},
                    {"address": 4, "identity": null, "error": "bad reply"},
                ],
            })
        );
    }

    #[test]
    fn the_family_decides_the_default_and_the_limits() {
        let tmcl = crate::families::find_family("tmcl").expect("tmcl");
        let cmd4cr = crate::families::find_family("cmd4cr").expect("cmd4cr");
        assert_eq!(family_addresses(tmcl, None).unwrap().len(), 255);
        assert_eq!(
            family_addresses(cmd4cr, None).unwrap(),
            (0..=99).collect::<Vec<u8>>()
        );
        assert_eq!(family_addresses(cmd4cr, Some("0,99")).unwrap(), [0, 99]);
        let error = family_addresses(cmd4cr, Some("1-255")).unwrap_err();
        assert!(error.contains("address 100 is outside 0..99"), "{error}");
        assert!(
            family_addresses(tmcl, Some("0"))
                .unwrap_err()
                .contains("1..255")
        );
    }
}
