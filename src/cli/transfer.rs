//! `axterm download CONNECTION FILE [--run] [--autostart]`, `axterm upload
//! CONNECTION` and `axterm disasm CONNECTION`: a family's program toolchain
//! against a module, through its program tool
//! ([`crate::protocol::program::ProgramTool`]: TMCL's today). The plans are
//! the tool's and the session's runner drives them
//! ([`crate::session::transfer`]); this reads and writes files, shows
//! progress and sets the exit code: 0 done (a download verified), 1 a
//! device error or a failed verification, 2 a program that does not check
//! or cannot be downloaded (nothing sent), 3 the connection could not be
//! opened.
//!
//! Progress goes to standard error as one updating line when it is a
//! terminal, and nowhere otherwise. Ctrl-C cancels a transfer between two
//! words: a download then leaves download mode before exiting (1).

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::Args;
use serde_json::json;

use super::asm::{SourceFiles, read_input};
use super::connection::{Target, run_to_exit};
use super::output::Format;
use super::{ConnectionArgs, EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::files::Existing;
use crate::protocol::Family;
use crate::protocol::program::{
    CheckedProgram, DownloadOptions, DownloadWay, FactValue, ProgramTool, Progress,
    TransferFailure, TransferReport, UploadExtent, download_plan,
};
use crate::session::{Cancel, Session};

#[derive(Debug, Clone, Args)]
pub struct DownloadArgs {
    /// The program source (- for standard input), or an image with --image.
    pub file: String,
    /// FILE is a program image (as `axterm asm -o` and `upload --image`
    /// write), not source.
    #[arg(long)]
    pub image: bool,
    /// Start the program once it is verified (129).
    #[arg(long)]
    pub run: bool,
    /// Make the module start the program at power-up (SGP 77, 0, 1).
    #[arg(long)]
    pub autostart: bool,
    /// text: a summary line; json: one object.
    #[arg(long, value_enum, default_value_t)]
    pub format: Format,
}

/// How much of the program memory to read (the module does not know its
/// program's length).
#[derive(Debug, Clone, Default, Args)]
pub struct ExtentArgs {
    /// Read exactly this many words (default: until the first blank word).
    #[arg(long, conflicts_with = "all")]
    pub words: Option<usize>,
    /// Read the whole program memory (trailing blank words left out).
    #[arg(long)]
    pub all: bool,
}

impl ExtentArgs {
    pub fn extent(&self) -> UploadExtent {
        match (self.words, self.all) {
            (Some(n), _) => UploadExtent::Units(n),
            (None, true) => UploadExtent::All,
            (None, false) => UploadExtent::UntilBlank,
        }
    }
}

#[derive(Debug, Clone, Args)]
pub struct UploadArgs {
    /// Write to this file instead of standard output.
    #[arg(long, short)]
    pub output: Option<PathBuf>,
    /// Replace the --output file if it exists (without it an existing
    /// file is refused, exit 2, before the module is asked anything).
    #[arg(long, requires = "output")]
    pub force: bool,
    /// Write the program image (hex words) instead of source.
    #[arg(long)]
    pub image: bool,
    #[command(flatten)]
    pub extent: ExtentArgs,
}

/// The program tool of `family`, or why there is none (a usage error).
fn tool_of(family: &'static Family) -> Result<&'static dyn ProgramTool, String> {
    family.console.program().ok_or_else(|| {
        format!(
            "{} modules keep no program that axterm can transfer",
            family.name
        )
    })
}

/// `axterm download`.
pub fn run_download(connection: &ConnectionArgs, args: &DownloadArgs) -> i32 {
    let target = match Target::resolve(connection) {
        Ok(target) => target,
        Err(message) => {
            eprintln!("axterm download: {message}");
            return EXIT_USAGE;
        }
    };
    let tool = match tool_of(target.family) {
        Ok(tool) => tool,
        Err(message) => {
            eprintln!("axterm download: {message}");
            return EXIT_USAGE;
        }
    };
    if let DownloadWay::SimulatorOnly { why, .. } = tool.download_way() {
        eprintln!(
            "axterm download: {why}; nothing was sent (a simulator takes the program with --program FILE)"
        );
        return EXIT_USAGE;
    }
    let program = match load_program(tool, &args.file, args.image) {
        Ok(program) => program,
        Err(code) => return code,
    };
    let options = DownloadOptions {
        run: args.run,
        autostart: args.autostart,
    };
    let plan = match download_plan(program.as_ref(), target.address, options) {
        Ok(plan) => plan,
        Err(failure) => {
            eprintln!(
                "axterm download: {}: {failure}; nothing was sent",
                args.file
            );
            return EXIT_USAGE;
        }
    };
    let format = args.format;
    let unit = tool.unit();
    run_to_exit("download", async move {
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm download: {e}");
                return EXIT_CONNECTION;
            }
        };
        let cancel = cancel_on_interrupt();
        let mut line = ProgressLine::new("download", unit);
        let outcome = session.transfer(plan, &cancel, &mut |p| line.show(p)).await;
        line.clear();
        let byte_time = target.spec.byte_time();
        match format {
            Format::Text => print_download_text(&outcome, byte_time, unit),
            Format::Json => print_download_json(&outcome, byte_time, unit),
        }
        match outcome {
            Ok(_) => EXIT_OK,
            Err(e) if e.nothing_sent() => EXIT_USAGE,
            Err(_) => EXIT_DEVICE,
        }
    })
}

/// The program from source or an image file, checked by `tool`; the exit
/// code (2) after saying what is wrong.
fn load_program(
    tool: &dyn ProgramTool,
    file: &str,
    image: bool,
) -> Result<Arc<dyn CheckedProgram>, i32> {
    let (name, text) = read_input(file).map_err(|message| {
        eprintln!("axterm download: {message}");
        EXIT_USAGE
    })?;
    if image {
        return match tool.load_image(&name, &text) {
            Some(Ok(program)) => Ok(program),
            Some(Err(problems)) => {
                for problem in &problems {
                    eprintln!("{problem}");
                }
                eprintln!("axterm download: {name} is not a program image; nothing was sent");
                Err(EXIT_USAGE)
            }
            None => {
                eprintln!(
                    "axterm download: {} programs have no image file; nothing was sent",
                    tool.name()
                );
                Err(EXIT_USAGE)
            }
        };
    }
    let checked = tool.check(&name, &text, &SourceFiles);
    for problem in &checked.problems {
        eprintln!("{}", problem.text);
    }
    match checked.program {
        Some(program) => Ok(program),
        None => {
            let errors = checked.errors().count();
            eprintln!(
                "axterm download: {errors} error{} in {name}; nothing was sent",
                plural(errors)
            );
            Err(EXIT_USAGE)
        }
    }
}

/// Above this share of the wire's limit the baud rate cannot be the
/// line's (clock and buffering jitter allow a little over 1).
const MAX_PLAUSIBLE_SHARE: f64 = 1.1;

fn print_download_text(
    outcome: &Result<TransferReport, TransferFailure>,
    byte_time: Option<Duration>,
    unit: &str,
) {
    match outcome {
        Ok(report) => {
            let mut summary = format!(
                "downloaded {} {unit}{} to module {} and verified them in {:.2} s",
                report.count,
                plural(report.count),
                report.module,
                report.elapsed.as_secs_f64()
            );
            // Faster than the wire means the baud rate is not the line's
            // (a USB virtual COM port, a pseudo-terminal): no figure then.
            if let Some(byte_time) = byte_time
                && report.wire_share(byte_time) <= MAX_PLAUSIBLE_SHARE
            {
                summary.push_str(&format!(
                    " ({:.0}% of the wire's limit, {:.2} s)",
                    report.wire_share(byte_time) * 100.0,
                    report.wire_time(byte_time).as_secs_f64()
                ));
            }
            println!("{summary}");
            for told in report.facts.iter().filter_map(|f| f.told.as_ref()) {
                if told.note {
                    eprintln!("axterm download: note: {}", told.text);
                } else {
                    println!("{}", told.text);
                }
            }
        }
        Err(error) => {
            eprintln!("axterm download: {error}");
            if !error.nothing_sent() {
                eprintln!("axterm download: the program on the module is NOT verified");
            }
        }
    }
}

fn print_download_json(
    outcome: &Result<TransferReport, TransferFailure>,
    byte_time: Option<Duration>,
    unit: &str,
) {
    let object = match outcome {
        Ok(report) => {
            let mut object = serde_json::Map::new();
            object.insert("ok".into(), json!(true));
            object.insert("verified".into(), json!(true));
            object.insert("module".into(), json!(report.module));
            object.insert(format!("{unit}s"), json!(report.count));
            for fact in &report.facts {
                let value = match &fact.value {
                    FactValue::Flag(b) => json!(b),
                    FactValue::Number(n) => json!(n),
                    FactValue::Text(t) => json!(t),
                    FactValue::Absent => serde_json::Value::Null,
                };
                object.insert(fact.key.into(), value);
            }
            object.insert(
                "elapsed_us".into(),
                json!(u64::try_from(report.elapsed.as_micros()).unwrap_or(u64::MAX)),
            );
            object.insert("transactions".into(), json!(report.transactions));
            object.insert(
                "wire_limit_us".into(),
                json!(byte_time.map(|t| u64::try_from(report.wire_time(t).as_micros())
                    .unwrap_or(u64::MAX))),
            );
            object.insert(
                "wire_share".into(),
                json!(byte_time.map(|t| report.wire_share(t))),
            );
            serde_json::Value::Object(object)
        }
        Err(error) => json!({
            "ok": false,
            "verified": false,
            "error": error.to_string(),
            "address": error.address(),
            "nothing_sent": error.nothing_sent(),
        }),
    };
    println!("{object}");
    if let Err(error) = outcome {
        eprintln!("axterm download: {error}");
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// `axterm upload`: the program as source (or an image) on standard
/// output or in a file.
pub fn run_upload(connection: &ConnectionArgs, args: &UploadArgs) -> i32 {
    let output = args.output.clone();
    let image = args.image;
    let existing = Existing::from_force(args.force);
    // A file that cannot be written is known before the module is asked.
    if let Some(path) = &output
        && let Err(e) = crate::files::check_destination(path, existing)
    {
        eprintln!("axterm upload: cannot write {}: {e}", path.display());
        eprintln!("axterm upload: nothing was sent");
        return EXIT_USAGE;
    }
    read_program("upload", connection, &args.extent, move |tool, read| {
        let text = if image {
            read.image
                .clone()
                .ok_or_else(|| format!("{} programs have no image file", tool.name()))?
        } else {
            read.source.clone()
        };
        match &output {
            Some(path) => crate::files::save(path, text.as_bytes(), existing)
                .map_err(|e| format!("cannot write {}: {e}", path.display())),
            None => {
                print_out(&text);
                Ok(())
            }
        }
    })
}

/// `axterm disasm CONNECTION`: the module's program as source.
pub fn run_disasm(connection: &ConnectionArgs, extent: &ExtentArgs) -> i32 {
    read_program("disasm", connection, extent, |_, read| {
        print_out(&read.source);
        Ok(())
    })
}

/// Read the program and hand it to `write` (whose error is a usage error:
/// a file that cannot be written).
fn read_program(
    command: &'static str,
    connection: &ConnectionArgs,
    extent: &ExtentArgs,
    write: impl FnOnce(&dyn ProgramTool, &crate::protocol::program::ReadProgram) -> Result<(), String>
    + Send
    + 'static,
) -> i32 {
    let target = match Target::resolve(connection) {
        Ok(target) => target,
        Err(message) => {
            eprintln!("axterm {command}: {message}");
            return EXIT_USAGE;
        }
    };
    let tool = match tool_of(target.family) {
        Ok(tool) => tool,
        Err(message) => {
            eprintln!("axterm {command}: {message}");
            return EXIT_USAGE;
        }
    };
    let plan = match tool.upload(target.address, extent.extent()) {
        Ok(plan) => plan,
        Err(failure) => {
            eprintln!("axterm {command}: {failure}");
            return EXIT_USAGE;
        }
    };
    let unit = tool.unit();
    run_to_exit(command, async move {
        let session: Session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm {command}: {e}");
                return EXIT_CONNECTION;
            }
        };
        let cancel = cancel_on_interrupt();
        let mut line = ProgressLine::new(command, unit);
        let outcome = session.transfer(plan, &cancel, &mut |p| line.show(p)).await;
        line.clear();
        match outcome {
            Ok(report) => {
                let empty = crate::protocol::program::ReadProgram {
                    source: String::new(),
                    image: None,
                    units: 0,
                };
                let read = report.program.as_ref().unwrap_or(&empty);
                if let Err(message) = write(tool, read) {
                    eprintln!("axterm {command}: {message}");
                    return EXIT_USAGE;
                }
                if std::io::stderr().is_terminal() {
                    eprintln!(
                        "axterm {command}: read {} {unit}{} from module {} in {:.2} s",
                        report.count,
                        plural(report.count),
                        report.module,
                        report.elapsed.as_secs_f64()
                    );
                }
                EXIT_OK
            }
            Err(error) => {
                eprintln!("axterm {command}: {error}");
                if error.nothing_sent() {
                    EXIT_USAGE
                } else {
                    EXIT_DEVICE
                }
            }
        }
    })
}

fn print_out(text: &str) {
    let mut out = std::io::stdout().lock();
    // A closed pipe (`| head`) is not an error of ours.
    let _ = out.write_all(text.as_bytes());
    let _ = out.flush();
}

/// A cancel handle that Ctrl-C sets. Must be called within the runtime.
fn cancel_on_interrupt() -> Cancel {
    let cancel = Cancel::new();
    let on_interrupt = cancel.clone();
    tokio::spawn(async move {
        if tokio::signal::ctrl_c().await.is_ok() {
            on_interrupt.cancel();
        }
    });
    cancel
}

/// One updating progress line on a terminal's standard error.
struct ProgressLine {
    command: &'static str,
    unit: &'static str,
    enabled: bool,
    shown: Option<Instant>,
    drawn: bool,
}

/// How often the line is redrawn at most: often enough to look alive,
/// rarely enough to cost nothing on a slow SSH session.
const REDRAW_EVERY: Duration = Duration::from_millis(100);

impl ProgressLine {
    fn new(command: &'static str, unit: &'static str) -> ProgressLine {
        ProgressLine {
            command,
            unit,
            enabled: std::io::stderr().is_terminal(),
            shown: None,
            drawn: false,
        }
    }

    fn show(&mut self, progress: Progress) {
        if !self.enabled {
            return;
        }
        let finished = progress.total == Some(progress.done);
        let due = self.shown.is_none_or(|at| at.elapsed() >= REDRAW_EVERY);
        if !due && !finished && progress.done != 0 {
            return;
        }
        self.shown = Some(Instant::now());
        let mut err = std::io::stderr().lock();
        let of = progress.total.map_or(String::new(), |t| format!("/{t}"));
        let _ = write!(
            err,
            "\r\x1b[2Kaxterm {}: {} {} {}{of}",
            self.command,
            progress.phase.name(),
            self.unit,
            progress.done
        );
        let _ = err.flush();
        self.drawn = true;
    }

    fn clear(&mut self) {
        if self.drawn {
            let mut err = std::io::stderr().lock();
            let _ = write!(err, "\r\x1b[2K");
            let _ = err.flush();
            self.drawn = false;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extent_follows_the_flags() {
        assert_eq!(ExtentArgs::default().extent(), UploadExtent::UntilBlank);
        let words = ExtentArgs {
            words: Some(12),
            all: false,
        };
        assert_eq!(words.extent(), UploadExtent::Units(12));
        let all = ExtentArgs {
            words: None,
            all: true,
        };
        assert_eq!(all.extent(), UploadExtent::All);
    }

    #[test]
    fn a_missing_file_is_a_usage_error_before_connecting() {
        let args = DownloadArgs {
            file: "no/such/dir/x.tmc".into(),
            image: false,
            run: false,
            autostart: false,
            format: Format::Text,
        };
        // A port that cannot exist: connecting would have exited 3.
        let connection = ConnectionArgs {
            port: Some("/nonexistent/tty".into()),
            ..ConnectionArgs::default()
        };
        assert_eq!(run_download(&connection, &args), EXIT_USAGE);
    }
}
