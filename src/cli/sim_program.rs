//! `--program FILE`: A-Script source loaded into a simulator's program
//! memory, as NPA's Windows utility would write it into a CMD-4CR (the
//! manual documents no wire format for that, §2.7.7, §5.1.5). For
//! `axterm sim cmd4cr` and the in-process `--sim cmd4cr` of the console,
//! `exec`, `run` and `run-ascript` alike. The file is checked first: a
//! compile error stops everything with `FILE:LINE:`.

use std::path::Path;

use crate::protocol::cmd4cr::ascript;
use crate::sim::SimulatedController;

/// Load the program in `path` into `sim`, which speaks `family`. On
/// success, a line saying what is there and how to start it; else every
/// problem, as `FILE:LINE: …` where it has a line.
pub fn load_program_file(
    sim: &mut dyn SimulatedController,
    family: &str,
    path: &Path,
) -> Result<String, Vec<String>> {
    let name = path.display().to_string();
    let source =
        crate::files::read_text(path).map_err(|e| vec![format!("{name}: cannot read it: {e}")])?;
    let program = if family == "cmd4cr" {
        Some(ascript::compile(&source).map_err(|errors| {
            errors
                .iter()
                .map(|e| format!("{name}:{}: {}: {}", e.line, e.code, e.detail))
                .collect::<Vec<_>>()
        })?)
    } else {
        None
    };
    sim.load_program(&source).map_err(|problems| {
        problems
            .iter()
            .map(|p| format!("{name}: {p}"))
            .collect::<Vec<_>>()
    })?;
    let programs: Vec<String> = program
        .iter()
        .flat_map(|p| p.program_numbers())
        .map(|n| format!("PRG {n}"))
        .collect();
    let first = program
        .as_ref()
        .and_then(|p| p.program_numbers().next())
        .unwrap_or(0);
    Ok(format!(
        "{name} loaded into the simulator: {} (start with SACTRL{first}=1)",
        if programs.is_empty() {
            "no PRG block".to_string()
        } else {
            programs.join(", ")
        }
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{SimOptions, find_kind};

    fn build(kind: &str) -> Box<dyn SimulatedController> {
        (find_kind(kind).expect("registered").build)(&SimOptions::default())
    }

    #[test]
    fn a_program_is_checked_first_and_its_errors_name_file_and_line() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("bad.asc");
        std::fs::write(&path, "PRG 0\n    V200=1\n    DO10=1\nEND\n").expect("write");
        let mut sim = build("cmd4cr");
        let problems = load_program_file(sim.as_mut(), "cmd4cr", &path).expect_err("errors");
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
    fn a_good_program_is_loaded_and_the_simulator_has_it() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("ok.asc");
        std::fs::write(&path, "PRG 2\n    V7=42\nEND\nPRG 1\nEND\n").expect("write");
        let mut sim = build("cmd4cr");
        let said = load_program_file(sim.as_mut(), "cmd4cr", &path).expect("loads");
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
        let problems = load_program_file(sim.as_mut(), "cmd4cr", missing).expect_err("missing");
        assert!(problems[0].contains("cannot read it"), "{problems:?}");
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("p.asc");
        std::fs::write(&path, "PRG 0\nEND\n").expect("write");
        let mut tmcl = build("tmcm1110");
        let problems = load_program_file(tmcl.as_mut(), "tmcl", &path).expect_err("no programs");
        assert!(problems[0].contains("runs no A-Script"), "{problems:?}");
    }
}
