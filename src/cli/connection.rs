//! The connection options (`--sim`, `--port`, `--tcp` with `--protocol`,
//! `--baud`, `--address`, `--timeout`) turned into a link, a protocol
//! family and session options.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use super::{AddressList, ConnectionArgs, EXIT_DEVICE};
use crate::device::DeviceOptions;
use crate::link::{LinkError, LinkSpec, RFC2217_SCHEME, ports};
use crate::protocol::{self, Family};
use crate::session::{Session, SessionOptions};
use crate::sim::bus::{BusFaults, SimBus};
use crate::sim::{self, SimOptions};

/// A connection as the options describe it, not opened yet.
pub struct Target {
    pub spec: LinkSpec,
    pub family: &'static Family,
    /// The module single-module work goes to: the first of `addresses`.
    pub address: u8,
    /// Every module `--address` names, in order (with --sim, the modules
    /// of the simulated bus); the family's default address alone without
    /// `--address`.
    pub addresses: Vec<u8>,
    pub options: SessionOptions,
}

/// Whether the options name a connection at all (`--sim`, `--port` or
/// `--tcp`): a dry run without one checks its file against the family
/// alone, one with one checks the connection's options too.
pub fn names_a_connection(args: &ConnectionArgs) -> bool {
    args.sim.is_some() || args.port.is_some() || args.tcp.is_some()
}

/// The modules `list` names for `family`, checked: each an address the
/// family has, and several only where the family's link carries a module
/// address (MCCL's does not: one MultiFlex board per link).
pub fn family_modules(family: &Family, list: Option<&AddressList>) -> Result<Vec<u8>, String> {
    let Some(list) = list else {
        return Ok(vec![family.console.default_address()]);
    };
    let range = family.console.addresses();
    if list.is_several() && range.start() == range.end() {
        let board = family
            .description
            .split(['(', ','])
            .next()
            .unwrap_or(family.name)
            .trim();
        return Err(format!(
            "--address {list}: a {board} board has no module address on its link (the {} \
             family: one board per link), so several boards are several links, not one bus",
            family.name
        ));
    }
    if let Some(outside) = list.as_slice().iter().find(|a| !range.contains(a)) {
        let at = if list.is_several() {
            format!("{outside} (in --address {list})")
        } else {
            outside.to_string()
        };
        return Err(format!(
            "--address {at} is outside {}..{}, the addresses of the {} family",
            range.start(),
            range.end(),
            family.name
        ));
    }
    Ok(list.as_slice().to_vec())
}

/// The simulated controller behind a `--sim` line or `axterm sim`: one
/// module, or a bus of one `kind` simulator at each address of `list`
/// ([`SimBus`]) with the faults of each module; `memory_file` keeps the
/// non-volatile memory (one file per module on a bus,
/// [`crate::sim::bus::module_file`]).
pub fn simulated_line(
    kind: &sim::SimKind,
    list: Option<&AddressList>,
    memory_file: Option<&std::path::Path>,
    faults: &BusFaults,
) -> Result<Box<dyn sim::SimulatedController>, String> {
    let family = crate::families::family_of(kind)
        .ok_or_else(|| format!("the {} simulator speaks no known family", kind.name))?;
    let addresses = family_modules(family, list)?;
    let several = list.is_some_and(AddressList::is_several);
    if !several && faults.no_module_faults() {
        return Ok((kind.build)(&SimOptions {
            address: list.map(AddressList::first),
            eeprom_file: memory_file.map(std::path::Path::to_path_buf),
        }));
    }
    let mut bus = if several {
        SimBus::of_kind(kind, &addresses, memory_file)?
    } else {
        // One module with faults of its own: a bus of one, its file as given.
        let address = addresses.first().copied().unwrap_or_default();
        let controller = (kind.build)(&SimOptions {
            address: Some(address),
            eeprom_file: memory_file.map(std::path::Path::to_path_buf),
        });
        SimBus::new(vec![(address, controller)])?
    };
    faults.apply(&mut bus)?;
    Ok(Box::new(bus))
}

impl Target {
    /// Resolve the options for a command that works on one module. An
    /// error is a usage error (exit 2): no or conflicting connection,
    /// unknown simulator or protocol, an address list on a real line.
    pub fn resolve(args: &ConnectionArgs) -> Result<Target, String> {
        Target::resolve_with(args, false)
    }

    /// Resolve the options for a command that works on several modules
    /// ([`Target::addresses`]): an address list is taken on any line.
    pub fn resolve_modules(args: &ConnectionArgs) -> Result<Target, String> {
        Target::resolve_with(args, true)
    }

    fn resolve_with(args: &ConnectionArgs, several_modules: bool) -> Result<Target, String> {
        let family = family_of(args)?;
        let addresses = family_modules(family, args.address.as_ref())?;
        let address = addresses
            .first()
            .copied()
            .unwrap_or_else(|| family.console.default_address());
        if let Some(list) = &args.address
            && list.is_several()
            && args.sim.is_none()
            && !several_modules
        {
            return Err(format!(
                "--address {list} names several modules; on a real line this command works on \
                 one: give one address (a list builds a simulated bus with --sim KIND)"
            ));
        }
        if args.sim.is_none() && !args.fault.is_empty() {
            return Err(format!(
                "--fault {} injects faults into a simulated line (with --sim KIND, or \
                 `axterm sim`); a real line brings its own",
                args.fault.first().map_or("", String::as_str)
            ));
        }
        let spec = match (&args.sim, &args.port, &args.tcp) {
            (Some(kind), None, None) => {
                let kind = crate::families::find_kind(kind).ok_or_else(|| unknown_sim(kind))?;
                let faults = BusFaults::parse(&args.fault)?;
                let mut controller = simulated_line(kind, args.address.as_ref(), None, &faults)?;
                if let Some(path) = args.program.as_deref() {
                    super::sim_program::load_program_file(
                        controller.as_mut(),
                        crate::families::family_of(kind),
                        path,
                    )
                    .map_err(|problems| problems.join("\n"))?;
                }
                drive_inputs(controller.as_mut(), &args.input)?;
                LinkSpec::Sim {
                    kind: kind.name.to_string(),
                    sim: Arc::new(Mutex::new(controller)),
                    // Wire time is only emulated when asked for.
                    baud: args.baud,
                    faults: faults.line,
                }
            }
            (None, Some(_), None) | (None, None, Some(_)) if args.program.is_some() => {
                return Err(
                    "--program loads a simulator's program memory (with --sim cmd4cr); \
                     the CMD-4CR manual documents no way to load a program into the controller \
                     over the wire: `axterm run-ascript` runs one from the host instead"
                        .into(),
                );
            }
            (None, Some(_), None) | (None, None, Some(_)) if !args.input.is_empty() => {
                return Err(format!(
                    "--input {} drives an input of a simulator (with --sim KIND, or `axterm sim`); \
                     a real controller's inputs are wired",
                    args.input.first().map_or("", String::as_str)
                ));
            }
            // The family's factory rate when none is given (TMCL 9600 Bd,
            // SIXpack 2 19200 Bd).
            (None, Some(path), None) => LinkSpec::Serial {
                // A by-id file name alone is looked up where udev puts them.
                path: ports::resolve_port(path, std::path::Path::new(ports::BY_ID_DIR)),
                baud: args.baud.unwrap_or(family.console.default_baud()),
            },
            // RFC 2217 sets the bridge's port, so it needs a rate: the
            // family's factory rate when none is given, as on a port.
            (None, None, Some(address)) => match address.strip_prefix(RFC2217_SCHEME) {
                Some(address) => LinkSpec::Rfc2217 {
                    address: address.to_string(),
                    baud: args.baud.unwrap_or(family.console.default_baud()),
                },
                None => LinkSpec::Tcp {
                    address: address.clone(),
                    // The bridge's serial side, when the user says it.
                    baud: args.baud,
                },
            },
            (None, None, None) => {
                return Err(
                    "give a connection: --sim KIND (e.g. --sim tmcm1110), --port PATH or --tcp HOST:PORT"
                        .into(),
                );
            }
            _ => return Err("give only one of --sim, --port and --tcp".into()),
        };
        if args.baud == Some(0) {
            return Err("--baud must be above 0".into());
        }
        let timeout = match args.timeout {
            Some(0) => return Err("--timeout must be at least 1 ms".into()),
            Some(ms) => Some(Duration::from_millis(ms)),
            None => None,
        };
        Ok(Target {
            spec,
            family,
            address,
            addresses,
            options: SessionOptions {
                address: Some(address),
                device: DeviceOptions {
                    timeout,
                    ..DeviceOptions::default()
                },
                ..SessionOptions::default()
            },
        })
    }

    /// Open the link and start the session (exit 3 when this fails).
    pub async fn open(&self) -> Result<Session, LinkError> {
        Session::connect(self.spec.clone(), self.family, self.options.clone()).await
    }
}

/// The protocol family: `--protocol`, else the simulator's, else TMCL.
/// Needs no connection, so that files can be checked without one.
pub fn family_of(args: &ConnectionArgs) -> Result<&'static Family, String> {
    let sim_family = match &args.sim {
        Some(kind) => Some(
            crate::families::find_kind(kind)
                .ok_or_else(|| unknown_sim(kind))
                .map(crate::families::family_of)?
                .map(|f| f.name)
                .unwrap_or_default(),
        ),
        None => None,
    };
    let name = args.protocol.as_deref().or(sim_family).unwrap_or("tmcl");
    let family = crate::families::find_family(name).ok_or_else(|| {
        format!(
            "unknown protocol family '{name}' (known: {})",
            crate::families::family_names()
        )
    })?;
    if let (Some(kind), Some(speaks)) = (&args.sim, sim_family)
        && !family.name.eq_ignore_ascii_case(speaks)
    {
        return Err(format!(
            "the {kind} simulator speaks {speaks}, not {}",
            family.name
        ));
    }
    protocol::with_link_options(family, &args.link_option).map_err(String::from)
}

/// Apply every `--input` setting to `sim`, in order: what each made hold,
/// or the first that is wrong (a usage error), naming it.
pub fn drive_inputs(
    sim: &mut dyn sim::SimulatedController,
    settings: &[String],
) -> Result<Vec<String>, String> {
    settings
        .iter()
        .map(|setting| {
            sim.drive_input(setting)
                .map_err(|message| format!("--input {setting}: {message}"))
        })
        .collect()
}

fn unknown_sim(kind: &str) -> String {
    format!(
        "unknown simulator '{kind}' (known: {})",
        crate::families::kind_names()
    )
}

/// A single-threaded runtime for the console.
pub fn runtime() -> Result<tokio::runtime::Runtime, String> {
    tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .map_err(|e| format!("cannot start: {e}"))
}

/// Run a front end's session work to its exit code on a single-threaded
/// runtime. The work runs as a task of its own, not as the runtime's main
/// future: tokio polls that one only between batches of other tasks, which
/// would hold every answer back while the device task keeps polling.
pub fn run_to_exit<F>(command: &str, work: F) -> i32
where
    F: Future<Output = i32> + Send + 'static,
{
    let runtime = match tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
    {
        Ok(runtime) => runtime,
        Err(e) => {
            eprintln!("axterm {command}: cannot start: {e}");
            return EXIT_DEVICE;
        }
    };
    runtime.block_on(async move {
        tokio::spawn(work).await.unwrap_or_else(|_| {
            eprintln!("axterm {command}: stopped unexpectedly");
            EXIT_DEVICE
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args() -> ConnectionArgs {
        ConnectionArgs::default()
    }

    #[test]
    fn a_simulator_brings_its_family_and_the_address() {
        let target = Target::resolve(&ConnectionArgs {
            sim: Some("TMCM1110".into()),
            address: Some(7.into()),
            ..args()
        })
        .unwrap();
        assert_eq!(target.family.name, "tmcl");
        assert_eq!(target.address, 7);
        assert!(matches!(target.spec, LinkSpec::Sim { baud: None, .. }));
    }

    #[test]
    fn serial_ports_default_to_9600_baud_and_address_1() {
        let target = Target::resolve(&ConnectionArgs {
            port: Some("/dev/ttyUSB0".into()),
            timeout: Some(250),
            ..args()
        })
        .unwrap();
        assert!(matches!(target.spec, LinkSpec::Serial { baud: 9600, .. }));
        assert_eq!(target.address, 1);
        assert_eq!(
            target.options.device.timeout,
            Some(Duration::from_millis(250))
        );
    }

    #[test]
    fn a_serial_port_defaults_to_the_familys_factory_rate() {
        let target = Target::resolve(&ConnectionArgs {
            port: Some("/dev/ttyUSB0".into()),
            protocol: Some("sixpack2".into()),
            ..args()
        })
        .unwrap();
        // SIXpack 2: 19200 Bd with no jumpers fitted, address 0 (§5.2).
        assert!(matches!(target.spec, LinkSpec::Serial { baud: 19200, .. }));
        assert_eq!(target.address, 0);
    }

    #[test]
    fn a_tcp_bridge_learns_the_baud_rate_of_its_serial_side_only_when_told() {
        let bridge = |baud| {
            Target::resolve(&ConnectionArgs {
                tcp: Some("localhost:4001".into()),
                protocol: Some("cmd4cr".into()),
                baud,
                ..args()
            })
            .unwrap()
            .spec
        };
        let told = bridge(Some(9600));
        assert_eq!(told.byte_time(), Some(crate::link::byte_time(9600)));
        assert_eq!(told.describe(), "tcp localhost:4001 (line at 9600 Bd)");
        let untold = bridge(None);
        assert_eq!(untold.byte_time(), None);
        assert_eq!(untold.describe(), "tcp localhost:4001");
    }

    #[test]
    fn an_rfc2217_bridge_is_set_to_the_given_or_the_family_rate() {
        let bridge = |baud| {
            Target::resolve(&ConnectionArgs {
                tcp: Some("rfc2217://localhost:4001".into()),
                protocol: Some("tmcl".into()),
                baud,
                ..args()
            })
            .unwrap()
            .spec
        };
        let told = bridge(Some(57600));
        assert!(
            matches!(&told, LinkSpec::Rfc2217 { address, baud: 57600 } if address == "localhost:4001")
        );
        assert_eq!(told.describe(), "rfc2217://localhost:4001 at 57600 Bd");
        // TMCL's factory rate, as on a serial port.
        assert!(matches!(bridge(None), LinkSpec::Rfc2217 { baud: 9600, .. }));
    }

    #[test]
    fn usage_errors_name_the_problem() {
        let cases = [
            (args(), "give a connection"),
            (
                ConnectionArgs {
                    sim: Some("nosuch".into()),
                    ..args()
                },
                "unknown simulator 'nosuch' (known: tmcm1110, cmd4cr, sixpack2, mccl, mccl-eth)",
            ),
            (
                ConnectionArgs {
                    tcp: Some("localhost:1".into()),
                    protocol: Some("klingon".into()),
                    ..args()
                },
                "unknown protocol family 'klingon'",
            ),
            (
                ConnectionArgs {
                    tcp: Some("localhost:1".into()),
                    timeout: Some(0),
                    ..args()
                },
                "--timeout",
            ),
            (
                ConnectionArgs {
                    port: Some("/dev/null".into()),
                    tcp: Some("localhost:1".into()),
                    ..args()
                },
                "only one of",
            ),
        ];
        for (args, needle) in cases {
            let Err(message) = Target::resolve(&args) else {
                panic!("{args:?} resolved")
            };
            assert!(message.contains(needle), "{message}");
        }
    }

    #[test]
    fn a_program_is_loaded_into_an_in_process_simulator_only() {
        let dir = tempfile::tempdir().expect("temp dir");
        let good = dir.path().join("good.asc");
        std::fs::write(&good, "PRG 1\n    V3=7\nEND\n").expect("write");
        let target = Target::resolve(&ConnectionArgs {
            sim: Some("cmd4cr".into()),
            program: Some(good.clone()),
            ..args()
        })
        .expect("loads");
        let LinkSpec::Sim { sim, .. } = &target.spec else {
            panic!("a simulator link");
        };
        let mut sim = sim.lock().expect("sim");
        sim.feed(b"@01SASTAT1\r");
        assert_eq!(sim.take_output(), b"0\r", "PRG 1 is there, idle");
        drop(sim);

        let bad = dir.path().join("bad.asc");
        std::fs::write(&bad, "PRG 0\n").expect("write");
        let Err(message) = Target::resolve(&ConnectionArgs {
            sim: Some("cmd4cr".into()),
            program: Some(bad.clone()),
            ..args()
        }) else {
            panic!("a program without END loaded");
        };
        assert!(
            message.starts_with(&format!("{}:1: Missing END", bad.display())),
            "{message}"
        );
        let Err(message) = Target::resolve(&ConnectionArgs {
            port: Some("/dev/ttyUSB0".into()),
            protocol: Some("cmd4cr".into()),
            program: Some(good),
            ..args()
        }) else {
            panic!("--program on a serial port");
        };
        assert!(message.contains("axterm run-ascript"), "{message}");
    }

    #[test]
    fn the_family_needs_no_connection() {
        assert_eq!(family_of(&args()).unwrap().name, "tmcl");
    }

    #[test]
    fn a_link_option_gives_the_family_as_it_reads_the_link() {
        let target = Target::resolve(&ConnectionArgs {
            sim: Some("sixpack2".into()),
            link_option: vec!["framing=cmd8".into()],
            ..args()
        })
        .unwrap();
        assert!(std::ptr::eq(
            target.family,
            &crate::protocol::sixpack2::FAMILY_CMD8
        ));
        let error = family_of(&ConnectionArgs {
            sim: Some("tmcm1110".into()),
            link_option: vec!["framing=cmd8".into()],
            ..args()
        })
        .err()
        .expect("refused");
        assert!(
            error.contains("the tmcl family has no link options"),
            "{error}"
        );
    }
}
