//! `axterm asm FILE [--listing] [-o IMAGE]` and `axterm disasm IMAGEFILE`:
//! a family's program toolchain offline, through its program tool
//! ([`crate::protocol::program::ProgramTool`]; TMCL's assembler today):
//! the tool a `--protocol` or `--sim` names, else the one the file's
//! extension names, else the first family's. This reads and writes the
//! files. `axterm disasm CONNECTION` reads the program from a module
//! ([`super::transfer`]).

use std::io::Write;
use std::path::Path;

use super::connection::family_of;
use super::transfer::ExtentArgs;
use super::{ConnectionArgs, EXIT_OK, EXIT_USAGE};
use crate::families::FAMILIES;
use crate::protocol::program::{ProgramTool, is_file_of};

/// The name standard input goes by in messages; includes from it are
/// relative to the working directory.
const STDIN_NAME: &str = "<stdin>";

pub use crate::files::SourceFiles;

fn describe_io(error: &std::io::Error) -> String {
    match error.kind() {
        std::io::ErrorKind::NotFound => "no such file".to_string(),
        std::io::ErrorKind::PermissionDenied => "permission denied".to_string(),
        std::io::ErrorKind::InvalidData => "not a text file (UTF-8)".to_string(),
        _ => error.to_string(),
    }
}

/// A file's text, or standard input for `-`; the name to show for it.
pub(super) fn read_input(file: &str) -> Result<(String, String), String> {
    if file == "-" {
        let text = crate::files::read_stdin_text()
            .map_err(|e| format!("cannot read standard input: {e}"))?;
        Ok((STDIN_NAME.to_string(), text))
    } else {
        let text = crate::files::read_text(file).map_err(|e| format!("cannot read {file}: {e}"))?;
        Ok((file.to_string(), text))
    }
}

/// The program tool for `file`: the family `connection` names, else the
/// one whose extension the file has, else the first family's.
pub(super) fn tool_for(
    file: &str,
    connection: &ConnectionArgs,
) -> Result<&'static dyn ProgramTool, String> {
    let named = connection.protocol.is_some() || connection.sim.is_some();
    let tools = || FAMILIES.iter().filter_map(|f| f.console.program());
    let tool = if named {
        let family = family_of(connection)?;
        family
            .console
            .program()
            .ok_or_else(|| format!("{} modules keep no program axterm can build", family.name))?
    } else {
        let by_extension = tools().find(|t| is_file_of(*t, Path::new(file)));
        by_extension
            .or_else(|| tools().next())
            .ok_or_else(|| "no family has programs".to_string())?
    };
    Ok(tool)
}

/// `axterm asm`: the image on standard output (or in `output`), or the
/// listing. On errors: every error on standard error, nothing written,
/// exit 2.
pub fn run_asm(
    file: &str,
    listing: bool,
    output: Option<&Path>,
    existing: crate::files::Existing,
    connection: &ConnectionArgs,
) -> i32 {
    let tool = match tool_for(file, connection) {
        Ok(tool) => tool,
        Err(message) => {
            eprintln!("axterm asm: {message}");
            return EXIT_USAGE;
        }
    };
    let (name, source) = match read_input(file) {
        Ok(input) => input,
        Err(message) => {
            eprintln!("axterm asm: {message}");
            return EXIT_USAGE;
        }
    };
    let checked = tool.check(&name, &source, &SourceFiles);
    for problem in &checked.problems {
        eprintln!("{}", problem.text);
    }
    let Some(program) = checked.program else {
        let errors = checked.errors().count();
        eprintln!(
            "axterm asm: {errors} error{} in {name}; nothing written",
            if errors == 1 { "" } else { "s" }
        );
        return EXIT_USAGE;
    };
    let Some(image) = program.image() else {
        eprintln!(
            "axterm asm: {name} {}, but {} programs have no image file: nothing written",
            tool.wording().passes,
            tool.name()
        );
        return EXIT_USAGE;
    };
    if let Some(path) = output
        && let Err(e) = crate::files::save(path, image.as_bytes(), existing)
    {
        let why = match &e {
            crate::files::WriteError::Io(io) => describe_io(io),
            other => other.to_string(),
        };
        eprintln!("axterm asm: cannot write {}: {why}", path.display());
        return EXIT_USAGE;
    }
    let shown = if listing {
        program.listing().unwrap_or_default()
    } else if output.is_none() {
        image
    } else {
        String::new()
    };
    print_out(&shown)
}

/// `axterm disasm`: the source of an image file, or of the program of the
/// module `connection` names when no file is given.
pub fn run_disasm(file: Option<&str>, connection: &ConnectionArgs, extent: &ExtentArgs) -> i32 {
    let Some(file) = file else {
        return disasm_from_module(connection, extent);
    };
    let tool = match tool_for(file, connection) {
        Ok(tool) => tool,
        Err(message) => {
            eprintln!("axterm disasm: {message}");
            return EXIT_USAGE;
        }
    };
    let (name, text) = match read_input(file) {
        Ok(input) => input,
        Err(message) => {
            eprintln!("axterm disasm: {message}");
            return EXIT_USAGE;
        }
    };
    match tool.disassemble(&name, &text) {
        Some(Ok(source)) => print_out(&source),
        Some(Err(problems)) => {
            for problem in &problems {
                eprintln!("{problem}");
            }
            eprintln!("axterm disasm: {name} is not a program image");
            EXIT_USAGE
        }
        None => {
            eprintln!("axterm disasm: {} programs have no image file", tool.name());
            EXIT_USAGE
        }
    }
}

/// `axterm disasm --port …`: read the program back through the family's
/// upload plan, as source.
fn disasm_from_module(connection: &ConnectionArgs, extent: &ExtentArgs) -> i32 {
    let connected =
        connection.port.is_some() || connection.tcp.is_some() || connection.sim.is_some();
    if !connected {
        eprintln!(
            "axterm disasm: give an image file (written by `axterm asm FILE -o IMAGE`) or a \
             connection (--sim, --port, --tcp) to read the module's program"
        );
        return EXIT_USAGE;
    }
    super::transfer::run_disasm(connection, extent)
}

fn print_out(text: &str) -> i32 {
    let mut out = std::io::stdout().lock();
    // A closed pipe (`| head`) is not an error of ours.
    let _ = out.write_all(text.as_bytes());
    let _ = out.flush();
    EXIT_OK
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::program::SourceLoader;

    #[test]
    fn missing_files_are_named() {
        let loaded = SourceFiles
            .load("no/such/dir/x.inc")
            .map_err(|e| e.to_string());
        assert_eq!(loaded, Err("no such file".to_string()));
        assert_eq!(
            run_asm(
                "no/such/dir/x.tmc",
                false,
                None,
                crate::files::Existing::Refuse,
                &ConnectionArgs::default()
            ),
            EXIT_USAGE
        );
        assert_eq!(
            run_disasm(
                Some("no/such/dir/x.hex"),
                &ConnectionArgs::default(),
                &ExtentArgs::default()
            ),
            EXIT_USAGE
        );
    }

    #[test]
    fn disasm_needs_a_file_or_a_connection() {
        let none = ConnectionArgs::default();
        assert_eq!(run_disasm(None, &none, &ExtentArgs::default()), EXIT_USAGE);
        // A fresh simulator's memory is blank: an empty program.
        let sim = ConnectionArgs {
            sim: Some("tmcm1110".to_string()),
            ..ConnectionArgs::default()
        };
        assert_eq!(run_disasm(None, &sim, &ExtentArgs::default()), EXIT_OK);
    }
}
