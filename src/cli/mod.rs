//! Command-line front ends: argument parsing and the subcommands.

use clap::{Args, Parser, Subcommand};

/// Exit code when everything went well.
pub const EXIT_OK: i32 = 0;
/// Exit code when a device replied with an error or timed out.
pub const EXIT_DEVICE: i32 = 1;
/// Exit code for bad usage or a line that does not parse (nothing was sent).
pub const EXIT_USAGE: i32 = 2;

#[derive(Debug, Parser)]
#[command(
    name = "axterm",
    version,
    about = "A terminal console for commissioning stepper and servo axes"
)]
pub struct Cli {
    #[command(flatten)]
    pub connection: ConnectionArgs,
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// Where the controller is: a serial port, a TCP bridge or a built-in simulator.
#[derive(Debug, Clone, Default, Args)]
pub struct ConnectionArgs {
    /// Serial port (e.g. /dev/ttyUSB0, COM3).
    #[arg(long, global = true, conflicts_with_all = ["tcp", "sim"])]
    pub port: Option<String>,
    /// Serial-over-TCP bridge, HOST:PORT.
    #[arg(long, global = true, conflicts_with = "sim")]
    pub tcp: Option<String>,
    /// Built-in simulator: tmcm1110.
    #[arg(long, global = true)]
    pub sim: Option<String>,
    /// Protocol family: tmcl.
    #[arg(long, global = true)]
    pub protocol: Option<String>,
    /// Serial baud rate.
    #[arg(long, global = true)]
    pub baud: Option<u32>,
    /// Module address on the bus.
    #[arg(long, global = true)]
    pub address: Option<u8>,
    /// Reply timeout in milliseconds.
    #[arg(long, global = true)]
    pub timeout: Option<u64>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Print the bytes a console line becomes.
    Encode {
        /// Protocol family: tmcl.
        family: String,
        /// The console line, e.g. 'MVP ABS, 0, 1000'.
        line: String,
    },
    /// Serve a simulated controller to other programs.
    Sim {
        /// Which controller: tmcm1110.
        kind: String,
        /// Serve it on a new pseudo-terminal and print its path.
        #[arg(long, conflicts_with = "listen")]
        pty: bool,
        /// Serve it on a TCP socket, ADDR:PORT (loopback unless the address says otherwise).
        #[arg(long = "listen", value_name = "ADDR")]
        listen: Option<String>,
        /// File keeping the simulated EEPROM between runs.
        #[arg(long)]
        eeprom: Option<std::path::PathBuf>,
    },
    /// Run console lines one by one and print one result line each.
    Exec { lines: Vec<String> },
    /// Run a batch file of console lines (- for standard input).
    Run { file: String },
    /// List serial ports.
    Ports,
    /// Look for modules on a bus.
    Scan,
    /// Assemble a TMCL program.
    Asm { file: String },
    /// Disassemble a program image or a module's program.
    Disasm { file: Option<String> },
    /// Download a program to a module.
    Download { file: String },
    /// Read a module's program back as source.
    Upload,
    /// Measure the link and the device task.
    Bench,
}

/// Run a parsed command line; returns the process exit code.
pub fn run(cli: Cli) -> i32 {
    match cli.command {
        Some(other) => {
            eprintln!("axterm: {other:?} is not built yet");
            EXIT_USAGE
        }
        None => {
            eprintln!("axterm: the console is not built yet");
            EXIT_USAGE
        }
    }
}
