//! User variables watched beside the program (TMCL global parameter bank
//! 2, §5.3): which one an instruction names, the line that reads one, and
//! the list kept in the data directory between runs (a small JSON file,
//! written atomically like the safety copy).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::protocol::tmcl::asm::ProgramWord;
use crate::protocol::tmcl::command::opcode;

/// The watch list's file name in the data directory.
pub const WATCH_FILE: &str = "editor-watch.json";

/// Variables watched at most: the side panel shows them all at 80×24.
pub const MAX_WATCHED: usize = 12;

/// The bank of the user variables (§5.3).
const USER_BANK: u8 = 2;

#[derive(Debug, Default, Serialize, Deserialize)]
struct WatchFile {
    #[serde(default)]
    user_variables: Vec<u8>,
    /// A-Script's V0–V99 (CMD-4CR), a list of their own.
    #[serde(default)]
    ascript_variables: Vec<u8>,
}

fn read_watch_file(data_dir: &Path) -> WatchFile {
    crate::files::read_text(watch_path(data_dir))
        .ok()
        .and_then(|text| serde_json::from_str::<WatchFile>(&text).ok())
        .unwrap_or_default()
}

fn tidy(mut list: Vec<u8>) -> Vec<u8> {
    list.sort_unstable();
    list.dedup();
    list.truncate(MAX_WATCHED);
    list
}

fn write_watch_file(data_dir: &Path, file: &WatchFile) -> Result<(), String> {
    let json =
        serde_json::to_string(file).map_err(|e| format!("cannot keep the watch list: {e}"))?;
    std::fs::create_dir_all(data_dir)
        .map_err(|e| format!("cannot keep the watch list in {}: {e}", data_dir.display()))?;
    let path = watch_path(data_dir);
    crate::files::write_atomically(&path, json.as_bytes())
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// The A-Script variables watched last time (see [`load_watch_list`]).
pub fn load_script_watch_list(data_dir: &Path) -> Vec<u8> {
    tidy(read_watch_file(data_dir).ascript_variables)
}

/// Keep `variables` as the A-Script watch list (the TMCL one stays).
pub fn save_script_watch_list(data_dir: &Path, variables: &[u8]) -> Result<(), String> {
    let mut file = read_watch_file(data_dir);
    file.ascript_variables = variables.to_vec();
    write_watch_file(data_dir, &file)
}

/// Where the watch list lives in `data_dir`.
pub fn watch_path(data_dir: &Path) -> PathBuf {
    data_dir.join(WATCH_FILE)
}

/// The variables watched last time; none when there is no list, or it
/// cannot be read (it is only a convenience: it is written again at the
/// next change).
pub fn load_watch_list(data_dir: &Path) -> Vec<u8> {
    tidy(read_watch_file(data_dir).user_variables)
}

/// Keep `variables` as the watch list in `data_dir` (the A-Script one
/// stays).
pub fn save_watch_list(data_dir: &Path, variables: &[u8]) -> Result<(), String> {
    let mut file = read_watch_file(data_dir);
    file.user_variables = variables.to_vec();
    write_watch_file(data_dir, &file)
}

/// The console line reading user variable `n` (GGP, §3.6.10).
pub fn variable_line(n: u8) -> String {
    format!("GGP {n}, {USER_BANK}")
}

/// The variable a line made by [`variable_line`] reads.
pub fn variable_of_line(line: &str) -> Option<u8> {
    line.strip_prefix("GGP ")?.strip_suffix(", 2")?.parse().ok()
}

/// The user variable an instruction names, if it is one of the global
/// parameter commands on bank 2: SGP, GGP, STGP, RSGP (§3.6.9–3.6.12) and
/// AGP (§3.6.30); their type byte is the variable's number.
pub fn variable_of_word(word: &ProgramWord) -> Option<u8> {
    let global = matches!(
        word.opcode,
        opcode::SGP | opcode::GGP | opcode::STGP | opcode::RSGP | opcode::AGP
    );
    (global && word.motor_bank == USER_BANK).then_some(word.kind)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::tmcl::asm::{NoIncludes, assemble};

    fn word(line: &str) -> ProgramWord {
        let program = assemble("t.tmc", line, &NoIncludes).expect("assembles");
        program.words[0]
    }

    #[test]
    fn global_parameter_commands_on_bank_2_name_a_user_variable() {
        for line in [
            "GGP 5, 2",
            "SGP 5, 2, -1",
            "STGP 5, 2",
            "RSGP 5, 2",
            "AGP 5, 2",
        ] {
            assert_eq!(variable_of_word(&word(line)), Some(5), "{line}");
        }
        // Bank 0 is module configuration; other commands name no variable.
        assert_eq!(variable_of_word(&word("GGP 65, 0")), None);
        assert_eq!(variable_of_word(&word("GAP 5, 0")), None);
        assert_eq!(variable_of_word(&word("MVP ABS, 0, 2")), None);
    }

    #[test]
    fn the_read_line_names_its_variable() {
        assert_eq!(variable_line(42), "GGP 42, 2");
        assert_eq!(variable_of_line(&variable_line(255)), Some(255));
        assert_eq!(variable_of_line("GGP 5, 0"), None);
        assert_eq!(variable_of_line("APPSTATUS X"), None);
        assert_eq!(variable_of_line("GGP 300, 2"), None);
    }

    #[test]
    fn the_list_is_kept_between_runs_and_a_broken_one_is_empty() {
        let dir = tempfile::tempdir().expect("temp dir");
        assert!(load_watch_list(dir.path()).is_empty());
        save_watch_list(dir.path(), &[5, 7]).expect("saved");
        assert_eq!(load_watch_list(dir.path()), [5, 7]);
        std::fs::write(watch_path(dir.path()), "{not json").expect("written");
        assert!(load_watch_list(dir.path()).is_empty());
        std::fs::write(
            watch_path(dir.path()),
            r#"{"user_variables": [9, 3, 9, 300]}"#,
        )
        .expect("written");
        // 300 is no variable number (u8): the file is not taken.
        assert!(load_watch_list(dir.path()).is_empty());
        std::fs::write(watch_path(dir.path()), r#"{"user_variables": [9, 3, 9]}"#)
            .expect("written");
        assert_eq!(load_watch_list(dir.path()), [3, 9]);
    }

    #[test]
    fn the_a_script_list_is_kept_beside_the_tmcl_one() {
        let dir = tempfile::tempdir().expect("temp dir");
        save_watch_list(dir.path(), &[200, 3]).expect("save");
        save_script_watch_list(dir.path(), &[99, 7, 7]).expect("save");
        assert_eq!(load_watch_list(dir.path()), [3, 200]);
        assert_eq!(load_script_watch_list(dir.path()), [7, 99]);
        save_watch_list(dir.path(), &[1]).expect("save");
        assert_eq!(load_script_watch_list(dir.path()), [7, 99]);
    }
}
