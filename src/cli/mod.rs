//! Command-line front ends: argument parsing and the subcommands.

pub mod asm;
pub mod bench;
pub mod completions;
pub mod confirm;
pub mod connection;
pub mod console;
pub mod exec;
pub mod fleet;
pub mod links;
pub mod man_pages;
pub mod mechanics;
pub mod output;
pub mod params;
pub mod profiles;
pub mod run;
pub mod run_ascript;
pub mod run_end;
pub mod run_host;
pub mod run_macro;
pub mod run_sheet;
pub mod scan;
/// The batch file syntax, shared with the console's `:run` (moved to
/// [`crate::script`]; the old path stays for the front ends).
pub use crate::script;
pub mod sim_program;
pub mod sim_serve;
pub mod transfer;
pub mod tune;
pub mod wiring;

use std::io::Write;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use clap::{ArgAction, Args, Parser, Subcommand};

use crate::link::ports;
pub use crate::protocol::addresses::AddressList;
use crate::sim;
use crate::sim::bus::BusFaults;
use crate::ui::live::Appearance;

/// Exit code when everything went well.
pub const EXIT_OK: i32 = 0;
/// Exit code when a device replied with an error or timed out.
pub const EXIT_DEVICE: i32 = 1;
/// Exit code for bad usage or a line that does not parse (nothing was sent).
pub const EXIT_USAGE: i32 = 2;
/// Exit code when the connection could not be opened.
pub const EXIT_CONNECTION: i32 = 3;

/// The program's `--help` after its one-line description: how links are
/// given (the `links` and `fleet` modules). Plain text: clap prints it.
const LINKS_HELP: &str = "A terminal console for commissioning stepper and servo axes.

The console takes several links: each `--sim`, `--port` or `--tcp` starts one, and the link \
options after it (up to the next link flag) are its own; options before the first link flag are \
every link's. `exec`, `run` and `params diff|apply` take several too (every module of every \
link); the other subcommands take one link.";

#[derive(Debug, Parser)]
#[command(
    name = "axterm",
    version,
    about = "A terminal console for commissioning stepper and servo axes",
    long_about = LINKS_HELP
)]
pub struct Cli {
    #[command(flatten)]
    pub connection: ConnectionArgs,
    /// The console's colours: dark, light, high-contrast, mono, or a file
    /// of yours (default dark; mono when NO_COLOR is set).
    #[arg(long)]
    pub theme: Option<String>,
    /// The console's keys: default, vim, or a file of yours.
    #[arg(long)]
    pub keymap: Option<String>,
    /// Let the console take the mouse: click a pane to focus it, wheel to
    /// scroll (the terminal's own text selection then needs Shift).
    #[arg(long)]
    pub mouse: bool,
    /// The file of named connections that `@NAME` arguments are looked up
    /// in (default: profiles.toml in the config directory, or the file
    /// AXTERM_PROFILES names). `axterm @line3` opens what is saved under
    /// line3; `axterm profiles` lists them.
    #[arg(long, global = true, value_name = "FILE")]
    pub profiles: Option<std::path::PathBuf>,
    /// The axes' mechanics ([mechanics.N]: unit, full_steps_per_rev or
    /// counts_per_rev, microsteps, gear_ratio, travel_per_rev), read from
    /// a parameter file: values may then be given in the axis's unit
    /// (`MVP ABS, 0, 12.5mm`, `1MA90deg`, `HSPDX=20mm/s`) in encode, exec,
    /// run and the console, which show them in it too.
    #[arg(long, global = true, value_name = "FILE")]
    pub mechanics: Option<std::path::PathBuf>,
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The process's command line with its `@NAME` profile references
/// expanded ([`profiles`]); an error says what is wrong (exit code 2).
pub fn expanded_command_line() -> Result<Vec<std::ffi::OsString>, String> {
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    if !profiles::has_references(&args) {
        return Ok(args);
    }
    let file = profiles::locate(
        &args,
        std::env::var_os(profiles::PROFILES_ENV),
        crate::ui::config::platform_config_dir(),
    );
    let Some(file) = file else {
        return Err(format!(
            "no profile file: give --profiles FILE or {}=FILE",
            profiles::PROFILES_ENV
        ));
    };
    let name = file.display().to_string();
    let book = read_profiles(&file);
    profiles::expand_command_line(args, book.as_ref().map_err(String::clone), &name)
}

fn read_profiles(file: &std::path::Path) -> Result<profiles::ProfileBook, String> {
    let name = file.display();
    let text = crate::files::read_text(file).map_err(|e| format!("cannot read {name}: {e}"))?;
    profiles::ProfileBook::parse(&text).map_err(|e| format!("{name}: {e}"))
}

// Where the controller is: a serial port, a TCP bridge or a built-in
// simulator. Not a doc comment: clap would print it as the program's
// `--help` in place of what axterm is; [`LINKS_HELP`] says it there.
#[derive(Debug, Clone, Default, Args)]
pub struct ConnectionArgs {
    /// Serial port (e.g. /dev/ttyUSB0, COM3), or its stable name in
    /// /dev/serial/by-id as a full path or the file name alone (`axterm
    /// ports` lists them). Starts a link: the console, exec, run and
    /// params diff|apply take several (--port A --port B, mixed with --sim
    /// and --tcp); the options after it are its own.
    #[arg(long, global = true, action = ArgAction::Append)]
    pub port: Option<String>,
    /// Serial-over-TCP bridge, HOST:PORT (raw bytes), or rfc2217://HOST:PORT to
    /// set its port to --baud and 8N1 over RFC 2217. Starts a link, as --port.
    #[arg(long, global = true, action = ArgAction::Append)]
    pub tcp: Option<String>,
    /// Built-in simulator: tmcm1110, cmd4cr, sixpack2, mccl or mccl-eth.
    /// Starts a link, as --port: `axterm --sim tmcm1110 --sim cmd4cr`.
    #[arg(long, global = true, action = ArgAction::Append)]
    pub sim: Option<String>,
    /// Protocol family: tmcl, cmd4cr, sixpack2 or mccl (default: the
    /// simulator's, else tmcl).
    #[arg(long, global = true, action = ArgAction::Append)]
    pub protocol: Option<String>,
    /// Serial baud rate (default: the family's factory rate, 9600; sixpack2
    /// 19200); with --sim, emulate that wire time;
    /// with --tcp, the rate of the serial line behind the bridge (the slow
    /// status polls keep to a share of it).
    #[arg(long, global = true, action = ArgAction::Append)]
    pub baud: Option<u32>,
    /// Module address on the bus (default: the family's, 1; sixpack2 0);
    /// with --sim, also the simulator's. With --sim (and `axterm sim`) a
    /// list such as 1-4 or 1,3,7 puts that many modules on one simulated
    /// bus, each its own simulator; the work of a single-module command
    /// (exec, run, download…) goes to the first address of the list, the
    /// console lists every module of it; with several links, exec, run
    /// and params diff|apply work on every module of each link's list. Not for mccl: a MultiFlex board
    /// has no module address on its link (one board per link).
    #[arg(long, global = true, value_name = "ADDRESS|LIST", action = ArgAction::Append)]
    pub address: Option<AddressList>,
    /// Reply timeout in milliseconds (default: from the baud rate).
    #[arg(long, global = true, action = ArgAction::Append)]
    pub timeout: Option<u64>,
    /// With --sim cmd4cr (and `axterm sim cmd4cr`): A-Script source loaded
    /// into the simulator's program memory, checked first; its PRG blocks
    /// are programs 0-3, started with SACTRLn=1 (or SLOAD at power-on).
    #[arg(long, global = true, value_name = "FILE", action = ArgAction::Append)]
    pub program: Option<std::path::PathBuf>,
    /// With --sim (and `axterm sim`): drive a simulated input before
    /// anything is sent, e.g. --input IO5=1 (repeatable). cmd4cr:
    /// DI1..DI4, IO1..IO32, EMG, STA, ALMX..ALMU =0|1, AI1..AI2 =mV
    /// 0..3300, the switches L+X, L-X, HOMEX, SDX (and Y, Z, U) =0|1|stage;
    /// tmcm1110: IN1..IN6 =0|1|open, AIN0 =0..65535; mccl: IN1..IN32,
    /// LIM+1, LIM-1, HOME1, FAULT1, STALL1 (1..8) =0|1, AD1..AD8 =0..65535.
    #[arg(long = "input", global = true, value_name = "SETTING")]
    pub input: Vec<String>,
    /// With --sim (and `axterm sim`): faults to inject (repeatable). SPEC
    /// for the whole line, ADDRESS:SPEC for one module of a simulated bus
    /// (its answers only; disconnect-after=N takes it off the bus after N
    /// answers), e.g. --fault 3:drop=1. SPEC is NAME=VALUE items joined
    /// by commas (drop=0.1,seed=7), of drop=P, corrupt=P, garbage=P,
    /// delay=P:MS, disconnect-after=N, corrupt-store=N, seed=N.
    #[arg(long = "fault", global = true, value_name = "[ADDRESS:]SPEC")]
    pub fault: Vec<String>,
    /// A choice about reading the link that the family's manual leaves
    /// open (repeatable): sixpack2 framing=auto|cmd8|addr9, replies
    /// without (cmd8, §6.2.2.3) or with (addr9) the response address in
    /// front, or either (auto, the default).
    #[arg(long = "link-option", global = true, value_name = "NAME=VALUE")]
    pub link_option: Vec<String>,
    /// The links after the first (the console's `--sim A --sim B`), each
    /// with its own options; empty for one link.
    #[arg(skip)]
    pub more_links: Vec<ConnectionArgs>,
}

impl ConnectionArgs {
    /// The modules `--address` names, in the order written, each once;
    /// `None` without `--address` (then the family's default address is
    /// the one module). For commands that work on several modules.
    pub fn addresses(&self) -> Option<&[u8]> {
        self.address.as_ref().map(AddressList::as_slice)
    }

    /// The first module `--address` names: the one single-module work
    /// goes to.
    pub fn first_address(&self) -> Option<u8> {
        self.address.as_ref().map(AddressList::first)
    }
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Print the bytes a console line becomes.
    Encode {
        /// Protocol family: tmcl, cmd4cr, sixpack2 or mccl.
        family: String,
        /// The console line, e.g. 'MVP ABS, 0, 1000'.
        line: String,
    },
    /// Serve a simulated controller to other programs.
    ///
    /// On a new pseudo-terminal (--pty: its path is the first line printed)
    /// or a TCP socket (--tcp ADDR: loopback when only a port is given);
    /// --address sets the module address, or with a list (1-4, 1,3,7)
    /// serves a bus of that many modules on the one line, each its own
    /// simulator answering only its own address (an absent address gets
    /// no answer; --fault 3:drop=1 faults one module; an input setting
    /// 3:IO5=1 drives one module's input, IO5=1 every module's);
    /// --baud N makes every byte take
    /// its wire time at N baud (10 bits a byte, both ways). --input SETTING
    /// drives an input from the start (IO5=1); while it serves, each line
    /// on standard input is such a setting too, applied at once and
    /// answered on standard error (the end of standard input is no reason
    /// to stop). Runs until interrupted.
    Sim {
        /// Which controller: tmcm1110, cmd4cr, sixpack2, mccl (MultiFlex
        /// PCI) or mccl-eth (MultiFlex ETH: macros kept in --eeprom FILE).
        kind: String,
        /// Serve it on a new pseudo-terminal and print its path.
        #[arg(long)]
        pty: bool,
        /// File keeping the simulated EEPROM (CMD-4CR: flash) between runs:
        /// a new name, an empty file, or one this simulator wrote (any
        /// other file is refused and left as it is). On a bus (--address
        /// 1-4) each module keeps its own, named after it: line.json
        /// becomes line-1.json … line-4.json.
        #[arg(long)]
        eeprom: Option<std::path::PathBuf>,
    },
    /// Run console lines one by one and print one result line each.
    ///
    /// Every line is checked before anything is sent; the family's
    /// warnings go to stderr, and a line it wants confirmed (SIXpack 2:
    /// HardwareReset, StartReferenceSearch…) needs --yes. Exit codes: 0
    /// all good, 1 a device error or timeout, 2 a line that does not parse
    /// or validate or needs --yes (nothing sent), 3 the connection could
    /// not be opened. With --addresses/--all or several links (--sim mccl
    /// --sim mccl) the lines run on every module of every link in turn,
    /// each result prefixed with its module (and link), a table at the
    /// end; a link that cannot be opened is a failed row.
    Exec(exec::ExecArgs),
    /// Run a batch file of console lines (- for standard input).
    ///
    /// One console line per line; blank lines and lines starting with # or
    /// // are comments. Directives: `:expect LINE == VALUE`, `:wait-until
    /// LINE == VALUE [timeout DURATION]` (re-reads every 20 ms; default
    /// timeout 10s), `:sleep DURATION`, `:echo TEXT`, `:params FILE
    /// [--store]` (a parameter file applied); DURATION as 500ms, 2s,
    /// 1.5s, 1m. The whole file is checked before anything is sent. A run
    /// that fails, is cancelled with Ctrl-C or loses its link ends with
    /// the stop-everything sequence (the console's emergency stop), each
    /// stop line's answer printed, unless --no-stop-on-failure. A line the
    /// family wants confirmed needs --yes. With --addresses/--all or
    /// several links (--port A --port B) the file runs on every module of
    /// every link in turn, each run ended as a single one; a table at the
    /// end.
    Run(run::RunArgs),
    /// Run an A-Script program (CMD-4CR) from the host.
    ///
    /// For real hardware: the CMD-4CR manual documents no way to load a
    /// program into the controller over the wire. The whole file is checked
    /// first (compile errors, statements with no ASCII command, as
    /// FILE:LINE); then each statement that acts is sent as its ASCII
    /// command and printed with its answer, while variables, IF/WHILE,
    /// GOSUB, DELAY and SR run here and WAITx reads MSTx until the axis has
    /// stopped. Speaks cmd4cr unless told otherwise. A run that fails, is
    /// stopped with Ctrl-C or loses its link ends with the emergency stop,
    /// unless --no-stop-on-failure. Exit codes: 0 every program reached END, 1
    /// a program failed at run time (or no answer, or Ctrl-C), 2 a bad file
    /// (nothing sent), 3 the connection could not be opened.
    RunAscript(run_ascript::RunAscriptArgs),
    /// Play an SQPack macro file (SIXpack 2) from the host.
    ///
    /// The unit stores no program: a macro is sent frame by frame. The
    /// whole file is checked first (nine hex values a SendToPack line,
    /// values in range, as FILE:LINE:COLUMN); frames the family wants
    /// confirmed need --yes. Each frame is printed with its answer;
    /// unanswered frames are paced by their wire time, a query's answer
    /// is waited for. Speaks sixpack2 unless told otherwise. A playback
    /// that fails, is stopped with Ctrl-C or loses its link ends with the
    /// emergency stop, unless --no-stop-on-failure. Exit codes as
    /// run-ascript.
    RunMacro(run_macro::RunMacroArgs),
    /// List the named connections of the profile file (`axterm @NAME`).
    ///
    /// Each name with the options it stands for. The file is
    /// profiles.toml in the config directory, or the one --profiles or
    /// AXTERM_PROFILES names.
    Profiles,
    /// List serial ports, each with its stable names.
    ///
    /// One line a port (its path and what the system knows of the
    /// adapter), then each name udev gave it in /dev/serial/by-id,
    /// indented: --port takes such a name, as the full path or the file
    /// name alone, and it stays the same whatever order adapters are
    /// plugged in.
    Ports,
    /// Look for modules on a bus (firmware version request at each address).
    Scan(scan::ScanArgs),
    /// Check an axis's limit switches: jog toward + until one fires, then
    /// toward −, and say which fired for which direction.
    ///
    /// A line each: the switch that fired and where, whether the module
    /// stopped the axis at it, a switch that fires against the direction
    /// of travel (swapped wiring or inverted direction), where the home
    /// switch was seen. Exit 0 when each switch fired for its own direction
    /// and stopped the axis, 1 otherwise. Needs --yes: it moves the axis to
    /// both ends of its travel.
    Wiring(wiring::WiringArgs),
    /// Tune an axis: a servo step response the controller records
    /// (MCCL), or a StallGuard2 sweep with a suggested threshold (TMCL).
    Tune {
        #[command(subcommand)]
        command: tune::TuneCommand,
    },
    /// Assemble a program (TMCL): print its image, or its listing.
    Asm {
        /// The program source (- for standard input).
        file: String,
        /// Print address, bytes and source per instruction, and the labels.
        #[arg(long)]
        listing: bool,
        /// Write the image to this file (then nothing is printed but a listing).
        #[arg(long, short)]
        output: Option<std::path::PathBuf>,
        /// Replace the --output file if it exists (without it an existing
        /// file is refused, exit 2).
        #[arg(long, requires = "output")]
        force: bool,
    },
    /// Disassemble a program image file (- for standard input), or, with a
    /// connection and no file, the module's program.
    Disasm {
        file: Option<String>,
        #[command(flatten)]
        extent: transfer::ExtentArgs,
    },
    /// Assemble a program, download it to a module and verify every word.
    ///
    /// Stops and resets a running program first (131), stores every word
    /// (132/133), reads every word back (134) and fails at the first that
    /// differs. Exit codes: 0 verified, 1 a device error or a failed
    /// verification, 2 the program does not assemble (nothing sent), 3 the
    /// connection could not be opened. Ctrl-C cancels and leaves download
    /// mode.
    Download(transfer::DownloadArgs),
    /// Read a module's program back as source (or as an image).
    ///
    /// The module does not know its program's length: reading stops at the
    /// first blank word unless --words N or --all says otherwise.
    Upload(transfer::UploadArgs),
    /// Measure the link and the device task.
    Bench(bench::BenchArgs),
    /// A module's settings as a parameter file: export, diff, apply.
    ///
    /// The same TOML file as the console's parameter pane exports,
    /// compares and imports. `diff` and `apply` work on several modules of
    /// a bus with --addresses LIST or --all, and on several links (--port
    /// A --port B: every module of every link, e.g. a line of MultiFlex
    /// boards), a table at the end.
    Params {
        #[command(subcommand)]
        command: params::ParamsCommand,
    },
    /// Print a shell's completion script for axterm.
    ///
    /// bash, zsh, fish, elvish or powershell; made from the same
    /// definitions as --help. Where each shell looks for it:
    /// docs/install.md (e.g. `axterm completions bash >
    /// ~/.local/share/bash-completion/completions/axterm`).
    Completions(completions::CompletionsArgs),
    /// Print or write the manual pages (roff).
    ///
    /// One page per subcommand: axterm.1, axterm-run.1, axterm-params-diff.1
    /// and so on. Without --dir the program's page is printed (or the page
    /// of the subcommand named: `axterm man params diff`), e.g. for `man
    /// -l -`; --dir DIR writes every page into DIR, a path a line on
    /// standard output.
    Man(man_pages::ManArgs),
}

impl Command {
    /// Whether the subcommand works on several links (`--sim mccl --sim
    /// mccl`): those that work on a fleet of modules ([`fleet`]), every
    /// module of every link in turn.
    pub fn takes_several_links(&self) -> bool {
        matches!(
            self,
            Command::Exec(_)
                | Command::Run(_)
                | Command::Params {
                    command: params::ParamsCommand::Diff(_) | params::ParamsCommand::Apply(_)
                }
        )
    }

    /// The subcommand's name as typed.
    pub fn name(&self) -> &'static str {
        match self {
            Command::Encode { .. } => "encode",
            Command::Sim { .. } => "sim",
            Command::Exec(_) => "exec",
            Command::Run(_) => "run",
            Command::RunAscript(_) => "run-ascript",
            Command::RunMacro(_) => "run-macro",
            Command::Ports => "ports",
            Command::Profiles => "profiles",
            Command::Scan(_) => "scan",
            Command::Wiring(_) => "wiring",
            Command::Tune { .. } => "tune",
            Command::Asm { .. } => "asm",
            Command::Disasm { .. } => "disasm",
            Command::Download(_) => "download",
            Command::Upload(_) => "upload",
            Command::Bench(_) => "bench",
            Command::Params { .. } => "params",
            Command::Completions(_) => "completions",
            Command::Man(_) => "man",
        }
    }
}

/// Run a parsed command line; returns the process exit code.
pub fn run(cli: Cli) -> i32 {
    if let Some(command) = &cli.command
        && !cli.connection.more_links.is_empty()
        && !command.takes_several_links()
    {
        eprintln!(
            "axterm {}: one link at a time ({} given); only the console (axterm with no \
             subcommand), exec, run and params diff|apply take several",
            command.name(),
            links::describe_links(&cli.connection)
        );
        return EXIT_USAGE;
    }
    match cli.command {
        Some(Command::Sim { kind, pty, eeprom }) => run_sim(&cli.connection, &kind, pty, eeprom),
        Some(Command::Ports) => run_ports(),
        Some(Command::Profiles) => run_profiles(cli.profiles.as_deref()),
        Some(Command::Encode { family, line }) => run_encode(
            &family,
            &line,
            cli.connection.address.as_ref(),
            cli.mechanics.as_deref(),
        ),
        Some(Command::Exec(args)) => exec::run(&cli.connection, &args, cli.mechanics.as_deref()),
        Some(Command::Run(args)) => run::run(&cli.connection, &args, cli.mechanics.as_deref()),
        Some(Command::RunAscript(args)) => run_ascript::run(&cli.connection, &args),
        Some(Command::RunMacro(args)) => run_macro::run(&cli.connection, &args),
        Some(Command::Scan(args)) => scan::run(&cli.connection, &args),
        Some(Command::Wiring(args)) => wiring::run(&cli.connection, &args),
        Some(Command::Tune { command }) => tune::run(&cli.connection, &command),
        Some(Command::Bench(args)) => bench::run(&cli.connection, &args),
        Some(Command::Params { command }) => {
            params::run(&cli.connection, &command, cli.mechanics.as_deref())
        }
        Some(Command::Asm {
            file,
            listing,
            output,
            force,
        }) => asm::run_asm(
            &file,
            listing,
            output.as_deref(),
            crate::files::Existing::from_force(force),
            &cli.connection,
        ),
        Some(Command::Disasm { file, extent }) => {
            asm::run_disasm(file.as_deref(), &cli.connection, &extent)
        }
        Some(Command::Download(args)) => transfer::run_download(&cli.connection, &args),
        Some(Command::Completions(args)) => completions::run(&args),
        Some(Command::Man(args)) => man_pages::run(&args),
        Some(Command::Upload(args)) => transfer::run_upload(&cli.connection, &args),
        None => console::run(
            &cli.connection,
            Appearance {
                theme: cli.theme,
                keymap: cli.keymap,
                config_dir: crate::ui::config::platform_config_dir(),
                mouse: cli.mouse,
            },
            cli.mechanics.as_deref(),
        ),
    }
}

fn run_sim(
    connection: &ConnectionArgs,
    kind: &str,
    pty: bool,
    eeprom_file: Option<std::path::PathBuf>,
) -> i32 {
    let Some(sim_kind) = crate::families::find_kind(kind) else {
        eprintln!(
            "axterm sim: unknown simulator '{kind}' (known: {})",
            crate::families::kind_names()
        );
        return EXIT_USAGE;
    };
    let endpoint = match (pty, &connection.tcp) {
        (true, None) => sim_serve::Endpoint::Pty,
        (false, Some(addr)) => match sim_serve::parse_listen_address(addr) {
            Ok(addr) => sim_serve::Endpoint::Tcp(addr),
            Err(message) => {
                eprintln!("axterm sim: {message}");
                return EXIT_USAGE;
            }
        },
        _ => {
            eprintln!("axterm sim: give exactly one of --pty or --tcp ADDR");
            return EXIT_USAGE;
        }
    };
    let faults = match BusFaults::parse(&connection.fault) {
        Ok(faults) => faults,
        Err(e) => {
            eprintln!("axterm sim: {e}");
            return EXIT_USAGE;
        }
    };
    if connection.baud == Some(0) {
        eprintln!("axterm sim: --baud 0: give a baud rate above 0");
        return EXIT_USAGE;
    }
    let line = sim_serve::LineOptions {
        baud: connection.baud,
        faults: faults.line.clone(),
    };
    if let (Some(file), Some(why)) = (&eeprom_file, sim_kind.eeprom_refusal) {
        eprintln!(
            "axterm sim: --eeprom {}: the {} simulator keeps no memory file: {why}",
            file.display(),
            sim_kind.name
        );
        return EXIT_USAGE;
    }
    let mut sim = match connection::simulated_line(
        sim_kind,
        connection.address.as_ref(),
        eeprom_file.as_deref(),
        &faults,
    ) {
        Ok(sim) => sim,
        Err(message) => {
            eprintln!("axterm sim: {message}");
            return EXIT_USAGE;
        }
    };
    if let Some(problem) = sim.refused_memory_file() {
        eprintln!("axterm sim: {problem}");
        eprintln!(
            "axterm sim: --eeprom takes a file this simulator wrote, an empty one or a new \
             name; that file is left as it is and nothing is served"
        );
        return EXIT_USAGE;
    }
    if let (Some(file), Some(list)) = (&eeprom_file, &connection.address)
        && list.is_several()
    {
        for &address in list.as_slice() {
            eprintln!(
                "axterm sim: module {address} keeps its memory in {}",
                sim::bus::module_file(file, address).display()
            );
        }
    }
    eprintln!("{}", sim.help());
    if let Some(path) = connection.program.as_deref() {
        match sim_program::load_program_file(
            sim.as_mut(),
            crate::families::family_of(sim_kind),
            path,
        ) {
            Ok(said) => eprintln!("{said}"),
            Err(problems) => {
                for problem in problems {
                    eprintln!("{problem}");
                }
                eprintln!("axterm sim: nothing is served");
                return EXIT_USAGE;
            }
        }
    }
    match connection::drive_inputs(sim.as_mut(), &connection.input) {
        Ok(said) => {
            for line in said {
                eprintln!("axterm sim: {line}");
            }
        }
        Err(message) => {
            eprintln!("axterm sim: {message}");
            eprintln!("axterm sim: nothing is served");
            return EXIT_USAGE;
        }
    }
    // Settings typed while it serves; the reader ends quietly at the end of
    // standard input (or with none open), the server goes on.
    let settings = sim_serve::read_settings_from_stdin();
    // The signal handlers are in place before the endpoint is announced:
    // a script may send SIGTERM as soon as it has read that line.
    let runtime = match tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
    {
        Ok(runtime) => runtime,
        Err(e) => {
            eprintln!("axterm sim: cannot start: {e}");
            return EXIT_DEVICE;
        }
    };
    let stop_signals = match runtime.block_on(async { StopSignals::install() }) {
        Ok(signals) => signals,
        Err(e) => {
            eprintln!("axterm sim: cannot watch for signals: {e}");
            return EXIT_DEVICE;
        }
    };
    let stop = Arc::new(AtomicBool::new(false));
    let server_stop = Arc::clone(&stop);
    let (done_tx, done_rx) = tokio::sync::oneshot::channel();
    let server = std::thread::spawn(move || {
        let result = sim_serve::serve(sim, &endpoint, &line, settings, server_stop, &mut |name| {
            let mut out = std::io::stdout().lock();
            // The first line is the endpoint, for scripts that start us.
            let _ = writeln!(out, "{name}");
            let _ = out.flush();
        });
        let _ = done_tx.send(());
        result
    });
    runtime.block_on(stop_signals.wait(done_rx));
    stop.store(true, Ordering::Relaxed);
    let joined = server.join();
    if !faults.line.is_none() {
        eprintln!("axterm sim: faults injected: {}", faults.line.counts());
    }
    for module in &faults.modules {
        eprintln!(
            "axterm sim: faults injected at module {}: {}",
            module.address,
            module.plan.counts()
        );
    }
    match joined {
        Ok(Ok(())) => EXIT_OK,
        Ok(Err(e)) => {
            eprintln!("axterm sim: {e}");
            EXIT_DEVICE
        }
        Err(_) => {
            eprintln!("axterm sim: the simulator stopped unexpectedly");
            EXIT_DEVICE
        }
    }
}

/// SIGINT and SIGTERM, registered up front so that neither can arrive
/// unhandled (and kill us uncleanly) once we have announced ourselves.
struct StopSignals {
    #[cfg(unix)]
    interrupt: tokio::signal::unix::Signal,
    #[cfg(unix)]
    terminate: tokio::signal::unix::Signal,
}

impl StopSignals {
    /// Must run inside the tokio runtime.
    fn install() -> std::io::Result<StopSignals> {
        #[cfg(unix)]
        {
            use tokio::signal::unix::{SignalKind, signal};
            Ok(StopSignals {
                interrupt: signal(SignalKind::interrupt())?,
                terminate: signal(SignalKind::terminate())?,
            })
        }
        #[cfg(not(unix))]
        {
            Ok(StopSignals {})
        }
    }

    /// Wait for SIGINT, SIGTERM, or the server ending on its own.
    async fn wait(mut self, server_done: tokio::sync::oneshot::Receiver<()>) {
        #[cfg(unix)]
        tokio::select! {
            _ = self.interrupt.recv() => {}
            _ = self.terminate.recv() => {}
            _ = server_done => {}
        }
        #[cfg(not(unix))]
        tokio::select! {
            _ = tokio::signal::ctrl_c() => {}
            _ = server_done => {}
        }
    }
}

/// `axterm encode FAMILY LINE`: the bytes a console line becomes. A line
/// that does not parse or validate prints nothing on stdout and exits 2.
fn run_encode(
    family: &str,
    line: &str,
    address: Option<&AddressList>,
    mechanics: Option<&std::path::Path>,
) -> i32 {
    let Some(family) = crate::families::find_family(family) else {
        eprintln!(
            "axterm encode: unknown protocol family '{family}' (known: {})",
            crate::families::family_names()
        );
        return EXIT_USAGE;
    };
    if let Some(list) = address.filter(|list| list.is_several()) {
        eprintln!(
            "axterm encode: --address {list} names several modules; encode makes one frame: \
             give one address"
        );
        return EXIT_USAGE;
    }
    // Values in an axis's unit become raw first, with the file's own
    // settings for the module's (offline: nothing is read).
    let mechanics = match mechanics::load(mechanics) {
        Ok(m) => m.unwrap_or_default(),
        Err(message) => {
            eprintln!("axterm encode: {message}");
            return EXIT_USAGE;
        }
    };
    let converted = match mechanics.convert_offline(family.console.units(), line) {
        Ok(converted) => converted,
        Err(message) => {
            eprintln!("axterm encode: {message}; nothing encoded");
            return EXIT_USAGE;
        }
    };
    let said = converted.notes.join(", ");
    match (family.encode_line)(&converted.line, address.map(AddressList::first)) {
        Ok(bytes) => {
            if converted.changed() {
                eprintln!("axterm encode: {said}: {}", converted.line.trim());
            }
            println!("{}", (family.show_bytes)(&bytes));
            EXIT_OK
        }
        Err(message) if converted.changed() => {
            eprintln!("axterm encode: {said}, which the line does not take: {message}");
            EXIT_USAGE
        }
        Err(message) => {
            eprintln!("axterm encode: {message}");
            EXIT_USAGE
        }
    }
}

/// `axterm profiles`: each named connection and its options.
fn run_profiles(given: Option<&std::path::Path>) -> i32 {
    let file = given.map(std::path::Path::to_path_buf).or_else(|| {
        profiles::locate(
            &[],
            std::env::var_os(profiles::PROFILES_ENV),
            crate::ui::config::platform_config_dir(),
        )
    });
    let Some(file) = file else {
        eprintln!("axterm profiles: no config directory: give --profiles FILE");
        return EXIT_USAGE;
    };
    match read_profiles(&file) {
        Ok(book) if book.profiles.is_empty() => {
            eprintln!("axterm profiles: {}: no profiles", file.display());
            EXIT_OK
        }
        Ok(book) => {
            for profile in &book.profiles {
                println!("@{}  {}", profile.name, profile.arguments().join(" "));
            }
            EXIT_OK
        }
        Err(message) => {
            eprintln!("axterm profiles: {message}");
            EXIT_USAGE
        }
    }
}

/// `axterm ports`: one line per serial port found, with what the system
/// knows of the adapter, and below it, indented, each of its stable names
/// in /dev/serial/by-id. Pseudo-terminals are not serial ports here.
fn run_ports() -> i32 {
    let found = ports::listed_ports();
    report_ports(found, &mut std::io::stdout().lock(), &mut std::io::stderr())
}

fn report_ports(
    found: std::io::Result<Vec<ports::ListedPort>>,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> i32 {
    match found {
        Ok(ports) if ports.is_empty() => {
            let _ = writeln!(err, "axterm ports: no serial ports found");
            EXIT_OK
        }
        Ok(ports) => {
            for port in ports {
                let _ = writeln!(out, "{port}");
            }
            EXIT_OK
        }
        Err(e) => {
            let _ = writeln!(err, "axterm ports: cannot list serial ports: {e}");
            EXIT_DEVICE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every `--help` text, of the program and of each subcommand at any
    /// depth, with its name.
    fn every_help(command: &mut clap::Command, path: &str, helps: &mut Vec<(String, String)>) {
        helps.push((path.to_string(), command.render_long_help().to_string()));
        for sub in command.get_subcommands_mut() {
            let path = format!("{path} {}", sub.get_name());
            every_help(sub, &path, helps);
        }
    }

    /// Doc comments are `--help` text: rustdoc link markup (``[`links`]``)
    /// reads as noise there (issue 19, point 9).
    #[test]
    fn no_help_text_shows_rustdoc_link_markup() {
        use clap::CommandFactory;
        let mut command = Cli::command();
        command.build();
        let mut helps = Vec::new();
        every_help(&mut command, "axterm", &mut helps);
        assert!(helps.len() > 10, "{} help texts", helps.len());
        for (path, help) in helps {
            assert!(!help.contains("[`"), "{path} --help:\n{help}");
        }
    }

    #[test]
    fn sim_help_names_every_simulator_kind() {
        use clap::CommandFactory;
        let mut command = Cli::command();
        let sim = command
            .find_subcommand_mut("sim")
            .expect("the sim subcommand");
        let argument = sim
            .get_arguments()
            .find(|argument| argument.get_id() == "kind")
            .expect("the KIND argument");
        let help = argument
            .get_long_help()
            .or(argument.get_help())
            .map(ToString::to_string)
            .unwrap_or_default();
        for kind in crate::families::kinds() {
            assert!(
                help.contains(kind.name),
                "{} missing from: {help}",
                kind.name
            );
        }
    }

    #[test]
    fn ports_are_listed_one_per_line_and_none_is_not_an_error() {
        let (mut out, mut err) = (Vec::new(), Vec::new());
        let none = report_ports(Ok(Vec::new()), &mut out, &mut err);
        assert_eq!(none, EXIT_OK);
        assert!(out.is_empty());
        assert_eq!(err, b"axterm ports: no serial ports found\n");

        let (mut out, mut err) = (Vec::new(), Vec::new());
        let port = ports::PortInfo {
            path: "/dev/ttyACM0".into(),
            kind: ports::PortKind::Usb(ports::UsbIdentity {
                vid: 0x2a3c,
                pid: 0x0100,
                manufacturer: Some("Trinamic".into()),
                product: Some("StepRocker".into()),
                ..ports::UsbIdentity::default()
            }),
        };
        let listed = ports::ListedPort {
            port,
            by_id: vec!["/dev/serial/by-id/usb-Trinamic_StepRocker-if00".into()],
        };
        assert_eq!(report_ports(Ok(vec![listed]), &mut out, &mut err), EXIT_OK);
        assert_eq!(
            String::from_utf8_lossy(&out),
            "/dev/ttyACM0  usb 2a3c:0100  Trinamic  StepRocker\n    \
             /dev/serial/by-id/usb-Trinamic_StepRocker-if00\n"
        );
        assert!(err.is_empty());
    }

    #[test]
    fn sim_refuses_unknown_kinds_and_missing_endpoints() {
        let none = ConnectionArgs::default();
        assert_eq!(run_sim(&none, "nosuch", true, None), EXIT_USAGE);
        assert_eq!(run_sim(&none, "tmcm1110", false, None), EXIT_USAGE);
        let bad_fault = ConnectionArgs {
            fault: vec!["drop=2".into()],
            ..ConnectionArgs::default()
        };
        assert_eq!(run_sim(&bad_fault, "tmcm1110", true, None), EXIT_USAGE);
        let zero_baud = ConnectionArgs {
            baud: Some(0),
            ..ConnectionArgs::default()
        };
        assert_eq!(run_sim(&zero_baud, "tmcm1110", true, None), EXIT_USAGE);
        let bad_input = ConnectionArgs {
            input: vec!["IN1=1".into(), "IN9=1".into()],
            ..ConnectionArgs::default()
        };
        assert_eq!(run_sim(&bad_input, "tmcm1110", true, None), EXIT_USAGE);
    }

    #[test]
    fn the_address_list_and_its_first_module() {
        let cli = Cli::try_parse_from(["axterm", "--sim", "cmd4cr", "--address", "3,1-2"])
            .expect("parses");
        assert_eq!(cli.connection.addresses(), Some(&[3, 1, 2][..]));
        assert_eq!(cli.connection.first_address(), Some(3));
        let error = Cli::try_parse_from(["axterm", "--address", "4-1"]).expect_err("refused");
        assert!(
            error.to_string().contains("range 4-1 runs backwards"),
            "{error}"
        );
        assert_eq!(ConnectionArgs::default().addresses(), None);
    }
}
