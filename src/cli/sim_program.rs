//! `--program FILE`: A-Script source loaded into a simulator's program
//! memory, as NPA's Windows utility would write it into a CMD-4CR (the
//! manual documents no wire format for that, §2.7.7, §5.1.5). For
//! `axterm sim cmd4cr` and the in-process `--sim cmd4cr` of the console,
//! `exec`, `run` and `run-ascript` alike. The file is checked first: a
//! compile error stops everything with `FILE:LINE:`.

use std::path::Path;

use crate::protocol::Family;
use crate::protocol::program::{ControlKey, DownloadWay, NoIncludes};
use crate::sim::SimulatedController;

/// Load the program in `path` into `sim`, which speaks `family`. On
/// success, a line saying what is there and how to start it; else every
/// problem, as `FILE:LINE: …` where it has a line.
pub fn load_program_file(
    sim: &mut dyn SimulatedController,
    family: Option<&'static Family>,
    path: &Path,
) -> Result<String, Vec<String>> {
    let name = path.display().to_string();
    let source =
        crate::files::read_text(path).map_err(|e| vec![format!("{name}: cannot read it: {e}")])?;
    // The family's program tool checks what only a simulator takes.
    let tool = family
        .and_then(|f| f.console.program())
        .filter(|t| matches!(t.download_way(), DownloadWay::SimulatorOnly { .. }));
    let program = match tool {
        Some(tool) => {
            let checked = tool.check(&name, &source, &NoIncludes);
            match checked.program {
                // Loaded, it would read as a program there: refused as
                // an empty download is.
                Some(program) if program.size() == 0 => {
                    return Err(vec![format!(
                        "{name}: the program holds nothing to load (the file is empty, or only \
                         blank lines)"
                    )]);
                }
                Some(program) => Some((tool, program)),
                None => {
                    return Err(checked
                        .errors()
                        .map(|p| format!("{name}:{}: {}", p.line, p.message))
                        .collect());
                }
            }
        }
        None => None,
    };
    sim.load_program(&source).map_err(|problems| {
        problems
            .iter()
            .map(|p| format!("{name}: {p}"))
            .collect::<Vec<_>>()
    })?;
    let control = program.as_ref().and_then(|(tool, _)| tool.control());
    let numbers = program
        .as_ref()
        .map(|(_, p)| p.programs())
        .unwrap_or_default();
    let names: Vec<String> = numbers
        .iter()
        .map(|&n| {
            control
                .and_then(|c| c.program_name(n))
                .unwrap_or_else(|| format!("program {n}"))
        })
        .collect();
    let first = numbers.first().copied().unwrap_or(0);
    let start = control.map_or_else(String::new, |c| {
        format!(
            " (start with {})",
            c.control(ControlKey::Run, first, None).line
        )
    });
    Ok(format!(
        "{name} loaded into the simulator: {}{start}",
        if names.is_empty() {
            "no program to start".to_string()
        } else {
            names.join(", ")
        }
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::find_family;
    use crate::families::find_kind;
    use crate::sim::SimOptions;

    fn build(kind: &str) -> Box<dyn SimulatedController> {
        (find_kind(kind).expect("registered").build)(&SimOptions::default())
    }

    #[test]
    fn a_program_is_checked_first_and_its_errors_name_file_and_line() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("bad.asc");
        std::fs::write(&path, "PRG 0\n    V200=1\n    DO10=1\nEND\n").expect("write");
        let mut sim = build("cmd4cr");
        let problems =
            load_program_file(sim.as_mut(), find_family("cmd4cr"), &path).expect_err("errors");
        let name = path.display().to_string();
        assert_eq!(problems.len(), 2, "{problems:?}");
        assert!(
            problems[0].starts_with(&format!("{name}:2: Var Range Error")),
            "{problems:?}"
        );
        assert!(
            problems[1].starts_with(&format!("{name}:3: BIT Error")),
            "{problems:?}"
        );
    }

    #[test]
    fn an_empty_program_is_not_loaded() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("empty.asc");
        for text in ["", "\n  \n"] {
            std::fs::write(&path, text).expect("write");
            let mut sim = build("cmd4cr");
            let problems =
                load_program_file(sim.as_mut(), find_family("cmd4cr"), &path).expect_err("empty");
            assert_eq!(
                problems,
                [format!(
                    "{}: the program holds nothing to load (the file is empty, or only blank \
                     lines)",
                    path.display()
                )]
            );
        }
    }

    #[test]
    fn a_good_program_is_loaded_and_the_simulator_has_it() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("ok.asc");
        std::fs::write(&path, "PRG 2\n    V7=42\nEND\nPRG 1\nEND\n").expect("write");
        let mut sim = build("cmd4cr");
        let said = load_program_file(sim.as_mut(), find_family("cmd4cr"), &path).expect("loads");
        assert!(
            said.ends_with("PRG 1, PRG 2 (start with SACTRL1=1)"),
            "{said}"
        );
        sim.feed(b"@01SASTAT2\r@01SASTAT0\r");
        assert_eq!(sim.take_output(), b"0\r3\r", "PRG 2 idle, no PRG 0");
    }

    #[test]
    fn a_missing_file_or_a_simulator_without_programs_is_refused() {
        let mut sim = build("cmd4cr");
        let missing = Path::new("no-such-dir/none.asc");
        let problems =
            load_program_file(sim.as_mut(), find_family("cmd4cr"), missing).expect_err("missing");
        assert!(problems[0].contains("cannot read it"), "{problems:?}");
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("p.asc");
        std::fs::write(&path, "PRG 0\nEND\n").expect("write");
        let mut tmcl = build("tmcm1110");
        let problems =
            load_program_file(tmcl.as_mut(), find_family("tmcl"), &path).expect_err("no programs");
        assert!(problems[0].contains("runs no A-Script"), "{problems:?}");
    }
}
