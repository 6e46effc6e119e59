//! The variables watched beside the program, kept in the data directory
//! between runs: one list per program tool, under its
//! [`crate::protocol::program::VariableSet::key`], in a small JSON file
//! written atomically like the safety copy.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The watch list's file name in the data directory.
pub const WATCH_FILE: &str = "editor-watch.json";

/// Variables watched at most: the side panel shows them all at 80×24.
pub const MAX_WATCHED: usize = 12;

/// Every tool's list, by its key.
type WatchFile = BTreeMap<String, Vec<u8>>;

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

/// Where the watch list lives in `data_dir`.
pub fn watch_path(data_dir: &Path) -> PathBuf {
    data_dir.join(WATCH_FILE)
}

/// The variables watched last time under `key`; none when there is no
/// list, or it cannot be read (it is only a convenience: it is written
/// again at the next change).
pub fn load_watch_list(data_dir: &Path, key: &str) -> Vec<u8> {
    tidy(read_watch_file(data_dir).remove(key).unwrap_or_default())
}

/// Keep `variables` as the list under `key` in `data_dir` (the other
/// tools' lists stay).
pub fn save_watch_list(data_dir: &Path, key: &str, variables: &[u8]) -> Result<(), String> {
    let mut file = read_watch_file(data_dir);
    file.insert(key.to_string(), variables.to_vec());
    write_watch_file(data_dir, &file)
}

#[cfg(test)]
mod tests {
    use super::*;

    const USER: &str = "user_variables";

    #[test]
    fn the_list_is_kept_between_runs_and_a_broken_one_is_empty() {
        let dir = tempfile::tempdir().expect("temp dir");
        assert!(load_watch_list(dir.path(), USER).is_empty());
        save_watch_list(dir.path(), USER, &[5, 7]).expect("saved");
        assert_eq!(load_watch_list(dir.path(), USER), [5, 7]);
        std::fs::write(watch_path(dir.path()), "{not json").expect("written");
        assert!(load_watch_list(dir.path(), USER).is_empty());
        std::fs::write(
            watch_path(dir.path()),
            r#"{"user_variables": [9, 3, 9, 300]}"#,
        )
        .expect("written");
        // 300 is no variable number (u8): the file is not taken.
        assert!(load_watch_list(dir.path(), USER).is_empty());
        std::fs::write(watch_path(dir.path()), r#"{"user_variables": [9, 3, 9]}"#)
            .expect("written");
        assert_eq!(load_watch_list(dir.path(), USER), [3, 9]);
    }

    #[test]
    fn each_tools_list_is_kept_beside_the_others() {
        let dir = tempfile::tempdir().expect("temp dir");
        save_watch_list(dir.path(), USER, &[200, 3]).expect("save");
        save_watch_list(dir.path(), "ascript_variables", &[99, 7, 7]).expect("save");
        assert_eq!(load_watch_list(dir.path(), USER), [3, 200]);
        assert_eq!(load_watch_list(dir.path(), "ascript_variables"), [7, 99]);
        save_watch_list(dir.path(), USER, &[1]).expect("save");
        assert_eq!(load_watch_list(dir.path(), "ascript_variables"), [7, 99]);
    }
}
