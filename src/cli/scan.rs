//! `axterm scan CONNECTION [--addresses 1-255]`: ask every address on the
//! bus who it is (TMCL: firmware version, 136 type 0; CMD-4CR: VER) with a
//! short timeout, and list the modules that answer. Without
//! `--addresses`, every address the family has (TMCL 1-255, CMD-4CR
//! 0-99).

use std::time::Duration;

use clap::Args;

use super::connection::{Target, run_to_exit};
use super::{ConnectionArgs, EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::device::DeviceError;
use crate::protocol::Family;
use crate::session::SessionError;

/// How long to wait for an answer at each address, on top of the wire
/// time of the exchange: modules answer within a few milliseconds (TMCL
/// GP75 telegram pause aside), so an empty bus of 255 addresses takes
/// about 13 s, not minutes.
pub const PROBE_TIMEOUT: Duration = Duration::from_millis(50);

/// Bytes on the wire per probe, request and reply, with room to spare.
pub const PROBE_BYTES: u32 = 40;

#[derive(Debug, Clone, Args)]
pub struct ScanArgs {
    /// Addresses to try: a list of numbers and ranges, e.g. 1-255 or
    /// 1,5,10-20 (default: every address of the protocol family).
    #[arg(long)]
    pub addresses: Option<String>,
}

/// `1-255`, `7`, `1,3,10-20` → the addresses in order, each once.
pub fn parse_addresses(text: &str) -> Result<Vec<u8>, String> {
    let mut addresses = Vec::new();
    for part in text.split(',').map(str::trim) {
        let number = |s: &str| {
            s.trim()
                .parse::<u8>()
                .map_err(|_| format!("`{s}` is not an address 0..255 (in --addresses {text})"))
        };
        let (first, last) = match part.split_once('-') {
            Some((a, b)) => (number(a)?, number(b)?),
            None => {
                let n = number(part)?;
                (n, n)
            }
        };
        if first > last {
            return Err(format!(
                "range {part} runs backwards (in --addresses {text})"
            ));
        }
        for address in first..=last {
            if !addresses.contains(&address) {
                addresses.push(address);
            }
        }
    }
    Ok(addresses)
}

/// The addresses to try: those given, each one the family can have, or
/// every address of the family. A frame for an address outside the
/// family's would reach another module (CMD-4CR `@100VER` is read by
/// controller 10 as `0VER`) and report it where it is not.
fn family_addresses(family: &Family, given: Option<&str>) -> Result<Vec<u8>, String> {
    let range = family.console.addresses();
    let Some(text) = given else {
        return Ok(range.collect());
    };
    let addresses = parse_addresses(text)?;
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
    let target = match Target::resolve(connection) {
        Ok(target) => target,
        Err(message) => {
            eprintln!("axterm scan: {message}");
            return EXIT_USAGE;
        }
    };
    let family = target.family;
    let addresses = match family_addresses(family, args.addresses.as_deref()) {
        Ok(addresses) => addresses,
        Err(message) => {
            eprintln!("axterm scan: {message}");
            return EXIT_USAGE;
        }
    };
    let timeout = match target.options.device.timeout {
        Some(timeout) => timeout,
        None => PROBE_TIMEOUT + target.spec.byte_time().unwrap_or_default() * PROBE_BYTES,
    };
    run_to_exit("scan", async move {
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm scan: {e}");
                return EXIT_CONNECTION;
            }
        };
        let mut found = 0;
        for &address in &addresses {
            match session.probe(address, timeout).await {
                Ok(identity) => {
                    found += 1;
                    println!("address {address}: {identity}");
                }
                Err(SessionError::Device {
                    error: DeviceError::Timeout { .. },
                    ..
                }) => {}
                // Something answered, if not as asked: a module is there.
                Err(error @ SessionError::Reply { .. }) => {
                    found += 1;
                    println!("address {address}: (answers, but: {error})");
                }
                Err(error) => {
                    eprintln!("axterm scan: {error}");
                    return EXIT_DEVICE;
                }
            }
        }
        eprintln!(
            "axterm scan: {found} module{} found at {} address{} tried on {}",
            if found == 1 { "" } else { "s" },
            addresses.len(),
            if addresses.len() == 1 { "" } else { "es" },
            target.spec.describe()
        );
        if found > 0 { EXIT_OK } else { EXIT_DEVICE }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn address_lists_and_ranges() {
        assert_eq!(parse_addresses("1-255").unwrap().len(), 255);
        assert_eq!(parse_addresses("7").unwrap(), [7]);
        assert_eq!(parse_addresses("1, 3,2-4").unwrap(), [1, 3, 2, 4]);
        assert!(parse_addresses("5-1").unwrap_err().contains("backwards"));
        assert!(parse_addresses("1-256").unwrap_err().contains("`256`"));
        assert!(parse_addresses("").is_err());
        assert!(parse_addresses("a").is_err());
    }

    #[test]
    fn the_family_decides_the_default_and_the_limits() {
        let tmcl = crate::protocol::find_family("tmcl").expect("tmcl");
        let cmd4cr = crate::protocol::find_family("cmd4cr").expect("cmd4cr");
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
