//! Several links on one command line: `--sim tmcm1110 --sim cmd4cr`,
//! `--port A --port B --baud 19200`, mixed.
//!
//! The rule: each `--sim`, `--port` or `--tcp` starts a link; the link
//! options that follow it (`--protocol`, `--baud`, `--address`,
//! `--timeout`, `--link-option`, `--input`, `--fault`, `--program`), up to the next
//! link flag, are that link's. Link options given before the first link
//! flag are every link's, unless a link gives the same option itself.
//! With one link this is what the options always meant, in any order.
//!
//! Clap sees every link flag and option as repeatable; the links are cut
//! out of the matches by the positions of their values and each is parsed
//! again on its own, so each link's options have the types and checks of
//! a single connection ([`ConnectionArgs`]).

use clap::{ArgMatches, CommandFactory, FromArgMatches, Parser};

use super::{Cli, ConnectionArgs};

/// The flags that start a link.
const LINK_FLAGS: &[(&str, &str)] = &[("sim", "--sim"), ("port", "--port"), ("tcp", "--tcp")];

/// The options that belong to the link before them.
const LINK_OPTIONS: &[(&str, &str)] = &[
    ("protocol", "--protocol"),
    ("baud", "--baud"),
    ("address", "--address"),
    ("timeout", "--timeout"),
    ("link_option", "--link-option"),
    ("input", "--input"),
    ("fault", "--fault"),
    ("program", "--program"),
];

/// The link options one link may give several times (each adds one).
const REPEATABLE: &[&str] = &["link_option", "input", "fault"];

/// One link's options as given, for parsing on their own.
#[derive(Debug, Parser)]
#[command(name = "axterm")]
struct OneLink {
    #[command(flatten)]
    connection: ConnectionArgs,
}

/// Parse a whole command line (`argv[0]` first) with the link rule above:
/// `cli.connection` is the first link, `cli.connection.more_links` the
/// others, in the order given.
pub fn parse_from<I, T>(argv: I) -> Result<Cli, clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let matches = Cli::command().try_get_matches_from(argv)?;
    let mut cli = Cli::from_arg_matches(&matches)?;
    let mut links = split_links(&matches)?;
    if !links.is_empty() {
        cli.connection = links.remove(0);
        cli.connection.more_links = links;
    }
    Ok(cli)
}

/// One value of a link flag or option, where it stood on the line.
struct Given {
    at: usize,
    flag: &'static str,
    id: &'static str,
    value: std::ffi::OsString,
}

/// Every link, each parsed alone; empty when no link flag was given.
fn split_links(matches: &ArgMatches) -> Result<Vec<ConnectionArgs>, clap::Error> {
    let mut given = Vec::new();
    for &(id, flag) in LINK_FLAGS.iter().chain(LINK_OPTIONS) {
        let (Some(at), Some(values)) = (matches.indices_of(id), matches.get_raw(id)) else {
            continue;
        };
        for (at, value) in at.zip(values) {
            given.push(Given {
                at,
                flag,
                id,
                value: value.to_os_string(),
            });
        }
    }
    given.sort_by_key(|g| g.at);
    let starts_link = |g: &Given| LINK_FLAGS.iter().any(|&(id, _)| id == g.id);
    let Some(first) = given.iter().position(starts_link) else {
        once_each(given.iter(), "")?;
        return Ok(Vec::new());
    };
    let shared = &given[..first];
    once_each(shared.iter(), " before the first link")?;
    let mut groups: Vec<Vec<&Given>> = Vec::new();
    for g in &given[first..] {
        if starts_link(g) {
            groups.push(vec![g]);
        } else if let Some(group) = groups.last_mut() {
            group.push(g);
        }
    }
    groups
        .into_iter()
        .map(|own| {
            once_each(own.iter().copied(), " for one link")?;
            let defaults = shared.iter().filter(|s| !own.iter().any(|o| o.id == s.id));
            let mut argv: Vec<std::ffi::OsString> = vec!["axterm".into()];
            for g in defaults.chain(own.iter().copied()) {
                argv.push(g.flag.into());
                argv.push(g.value.clone());
            }
            OneLink::try_parse_from(argv).map(|one| one.connection)
        })
        .collect()
}

/// A usage error for an option that takes one value given twice where
/// it counts once (`where`: for one link, before the first link).
fn once_each<'a>(given: impl Iterator<Item = &'a Given>, place: &str) -> Result<(), clap::Error> {
    let mut seen: Vec<&str> = Vec::new();
    for g in given {
        if REPEATABLE.contains(&g.id) {
            continue;
        }
        if seen.contains(&g.id) {
            return Err(clap::Error::raw(
                clap::error::ErrorKind::ArgumentConflict,
                format!(
                    "{} given twice{place}: each --sim, --port or --tcp starts a link, and \
                     the options after it are that link's\n",
                    g.flag
                ),
            ));
        }
        seen.push(g.id);
    }
    Ok(())
}

/// Every link the options name, the first one first.
pub fn all_links(args: &ConnectionArgs) -> Vec<&ConnectionArgs> {
    std::iter::once(args).chain(&args.more_links).collect()
}

/// How the links of `args` are named in messages: `--sim tmcm1110, --port
/// /dev/ttyUSB0`.
pub fn describe_links(args: &ConnectionArgs) -> String {
    all_links(args)
        .iter()
        .map(|link| describe_link(link))
        .collect::<Vec<_>>()
        .join(", ")
}

/// How one link is named in messages: `--sim tmcm1110`, `--port
/// /dev/ttyUSB0`, `--tcp localhost:4001`.
pub fn describe_link(link: &ConnectionArgs) -> String {
    match (&link.sim, &link.port, &link.tcp) {
        (Some(kind), _, _) => format!("--sim {kind}"),
        (_, Some(path), _) => format!("--port {path}"),
        (_, _, Some(address)) => format!("--tcp {address}"),
        _ => "no link".to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(line: &str) -> Cli {
        parse_from(std::iter::once("axterm").chain(line.split_whitespace()))
            .unwrap_or_else(|e| panic!("{line}: {e}"))
    }

    #[test]
    fn one_link_means_what_it_always_meant_in_any_order() {
        for line in [
            "--sim tmcm1110 --baud 9600 --address 3",
            "--baud 9600 --address 3 --sim tmcm1110",
            "--address 3 --sim tmcm1110 --baud 9600",
        ] {
            let cli = parse(line);
            assert_eq!(cli.connection.sim.as_deref(), Some("tmcm1110"), "{line}");
            assert_eq!(cli.connection.baud, Some(9600), "{line}");
            assert_eq!(cli.connection.first_address(), Some(3), "{line}");
            assert!(cli.connection.more_links.is_empty(), "{line}");
        }
    }

    #[test]
    fn each_link_flag_starts_a_link_and_takes_the_options_after_it() {
        let cli = parse(
            "--timeout 300 --sim tmcm1110 --address 2 --sim cmd4cr --port /dev/ttyUSB0 \
             --protocol sixpack2 --baud 19200 --timeout 50 --tcp localhost:4001 --protocol mccl",
        );
        let links = all_links(&cli.connection);
        assert_eq!(links.len(), 4);
        assert_eq!(links[0].sim.as_deref(), Some("tmcm1110"));
        assert_eq!(links[0].addresses(), Some(&[2][..]));
        assert_eq!(links[0].timeout, Some(300), "the shared timeout");
        assert_eq!(links[1].sim.as_deref(), Some("cmd4cr"));
        assert!(
            links[1].address.is_none(),
            "the first link's address stays its own"
        );
        assert_eq!(links[2].port.as_deref(), Some("/dev/ttyUSB0"));
        assert_eq!(links[2].protocol.as_deref(), Some("sixpack2"));
        assert_eq!(links[2].baud, Some(19200));
        assert_eq!(links[2].timeout, Some(50), "its own timeout wins");
        assert_eq!(links[3].tcp.as_deref(), Some("localhost:4001"));
        assert_eq!(links[3].protocol.as_deref(), Some("mccl"));
        assert_eq!(links[3].timeout, Some(300));
        assert_eq!(
            describe_links(&cli.connection),
            "--sim tmcm1110, --sim cmd4cr, --port /dev/ttyUSB0, --tcp localhost:4001"
        );
    }

    #[test]
    fn links_after_a_subcommand_are_seen_too() {
        let cli = parse("exec --sim tmcm1110 --sim cmd4cr GAP");
        assert_eq!(cli.connection.more_links.len(), 1);
    }

    #[test]
    fn every_connection_option_is_a_link_flag_or_a_link_option() {
        use clap::Args;
        let command = ConnectionArgs::augment_args(clap::Command::new("axterm"));
        for arg in command.get_arguments() {
            let id = arg.get_id().as_str();
            assert!(
                LINK_FLAGS
                    .iter()
                    .chain(LINK_OPTIONS)
                    .any(|(known, _)| *known == id),
                "--{id} is neither a link flag nor a link option: say which it is"
            );
        }
    }

    #[test]
    fn an_option_twice_for_one_link_is_refused() {
        for line in [
            "--sim tmcm1110 --baud 9600 --baud 19200",
            "--baud 9600 --baud 19200 --sim tmcm1110",
            "--baud 9600 --baud 19200",
        ] {
            let argv = std::iter::once("axterm").chain(line.split_whitespace());
            let error = parse_from(argv).expect_err(line);
            assert!(error.to_string().contains("--baud given twice"), "{error}");
        }
        // Repeatable ones add up, and each link may give its own.
        let cli = parse(
            "--sim tmcm1110 --input IN1=1 --input IN2=1 --baud 9600 --sim cmd4cr --baud 9600",
        );
        assert_eq!(cli.connection.input, ["IN1=1", "IN2=1"]);
        assert_eq!(cli.connection.more_links[0].baud, Some(9600));
        let cli = parse("exec --sim cmd4cr --address 1-4 --fault 3:drop=1 --fault 4:drop=1 VER");
        assert_eq!(cli.connection.fault, ["3:drop=1", "4:drop=1"]);
    }

    #[test]
    fn a_bad_option_of_one_link_is_a_usage_error() {
        let error = parse_from([
            "axterm", "--sim", "tmcm1110", "--sim", "cmd4cr", "--baud", "x",
        ])
        .expect_err("refused");
        assert!(error.to_string().contains("--baud"), "{error}");
    }
}
