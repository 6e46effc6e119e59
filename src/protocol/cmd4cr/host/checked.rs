//! A source checked for a host run before anything is sent (the compile
//! errors of Table 5-43 and the statements without an ASCII equivalent).

use super::*;

/// A source checked for a host run: it compiles and every statement has
/// an ASCII equivalent.
#[derive(Debug, Clone)]
pub struct HostProgram {
    name: String,
    pub(super) program: Arc<Program>,
    pub(super) start: Vec<u8>,
    warnings: Vec<String>,
}

impl HostProgram {
    /// Check `source` (called `name` in messages) for a host run of the
    /// PRG blocks `start` (every PRG block when `None`). Every problem is
    /// listed as `NAME:LINE: …`, in line order; nothing may be sent when
    /// there is one.
    pub fn check(
        name: &str,
        source: &str,
        start: Option<&[u8]>,
    ) -> Result<HostProgram, Vec<String>> {
        let program = ascript::compile(source).map_err(|errors| {
            errors
                .iter()
                .map(|e| format!("{name}:{}: {}: {}", e.line, e.code, e.detail))
                .collect::<Vec<_>>()
        })?;
        let mut problems: Vec<(usize, String)> = program
            .host_problems()
            .iter()
            .map(|p| {
                (
                    p.line,
                    format!(
                        "{name}:{}: `{}` cannot run from the host: {}",
                        p.line, p.statement, p.reason
                    ),
                )
            })
            .collect();
        let defined: Vec<u8> = program.program_numbers().collect();
        let start = match start {
            None => defined.clone(),
            Some(chosen) => {
                for n in chosen {
                    if !defined.contains(n) {
                        problems.push((
                            0,
                            format!(
                                "{name}: there is no PRG {n} to start (the file defines {})",
                                list_programs(&defined)
                            ),
                        ));
                    }
                }
                let mut chosen = chosen.to_vec();
                chosen.sort_unstable();
                chosen.dedup();
                chosen
            }
        };
        if defined.is_empty() {
            problems.push((
                0,
                format!(
                    "{name}: no PRG block: nothing to run (a SUB runs only when called, §2.7.4)"
                ),
            ));
        }
        if !problems.is_empty() {
            problems.sort_by_key(|(line, _)| *line);
            return Err(problems.into_iter().map(|(_, p)| p).collect());
        }
        let warnings = program
            .warnings
            .iter()
            .map(|w| format!("{name}:{}: warning: {}", w.line, w.message))
            .collect();
        Ok(HostProgram {
            name: name.to_string(),
            program: Arc::new(program),
            start,
            warnings,
        })
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// The compiled program.
    pub fn program(&self) -> &Program {
        &self.program
    }

    /// The PRG blocks the run starts with.
    pub fn start(&self) -> &[u8] {
        &self.start
    }

    /// What compiles but is likely not meant (a GOSUB to a SUB the file
    /// does not define), as `NAME:LINE: warning: …`.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// "PRG 0 and PRG 1", for messages.
    pub fn started(&self) -> String {
        list_programs(&self.start)
    }
}

pub(super) fn list_programs(numbers: &[u8]) -> String {
    let names: Vec<String> = numbers.iter().map(|n| format!("PRG {n}")).collect();
    match names.split_last() {
        None => "no PRG".to_string(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
    }
}
