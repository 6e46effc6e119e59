//! Where `#include`d files come from. The assembler stays pure: it asks a
//! [`SourceLoader`] for the text of a path; the command line reads files,
//! tests hand over a map.

pub use crate::protocol::program::{NoIncludes, SourceLoader};

/// The path of `name` included from the file `including`: relative to the
/// including file's directory (digest D10: `#include File` names a file
/// beside the program), unless `name` is absolute. `/` and `\` both
/// separate directories (TMCL-IDE sources come from Windows); the result
/// uses `/`, with `.` and `..` resolved where they can be, so one file
/// always gets one path and include cycles are recognised.
pub fn include_path(including: &str, name: &str) -> String {
    let is_separator = |c: char| c == '/' || c == '\\';
    let absolute = name.starts_with(is_separator) || has_drive(name);
    let mut joined = String::new();
    if !absolute && let Some(end) = including.rfind(is_separator) {
        joined.push_str(including.get(..=end).unwrap_or(""));
    }
    joined.push_str(name);
    normalize(&joined)
}

fn has_drive(path: &str) -> bool {
    let mut chars = path.chars();
    matches!(
        (chars.next(), chars.next()),
        (Some(letter), Some(':')) if letter.is_ascii_alphabetic()
    )
}

fn normalize(path: &str) -> String {
    let rooted = path.starts_with(['/', '\\']);
    let mut parts: Vec<&str> = Vec::new();
    for part in path.split(['/', '\\']) {
        match part {
            "" | "." => {}
            ".." if parts
                .last()
                .is_some_and(|p| *p != ".." && !p.ends_with(':')) =>
            {
                parts.pop();
            }
            ".." if rooted && parts.is_empty() => {}
            _ => parts.push(part),
        }
    }
    let joined = parts.join("/");
    if rooted { format!("/{joined}") } else { joined }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    #[test]
    fn includes_are_relative_to_the_including_file() {
        assert_eq!(include_path("main.tmc", "Interrupts.inc"), "Interrupts.inc");
        assert_eq!(include_path("prog/main.tmc", "a.inc"), "prog/a.inc");
        assert_eq!(
            include_path("prog/main.tmc", "lib\\b.inc"),
            "prog/lib/b.inc"
        );
        assert_eq!(include_path("prog/lib/b.inc", "../c.inc"), "prog/c.inc");
        assert_eq!(include_path("./main.tmc", "./x.inc"), "x.inc");
        assert_eq!(include_path("main.tmc", "../up.inc"), "../up.inc");
        assert_eq!(include_path("../a/main.tmc", "../../b.inc"), "../../b.inc");
    }

    #[test]
    fn absolute_names_stay_absolute() {
        assert_eq!(include_path("prog/main.tmc", "/etc/x.inc"), "/etc/x.inc");
        assert_eq!(include_path("/p/main.tmc", "x.inc"), "/p/x.inc");
        assert_eq!(include_path("/main.tmc", "../x.inc"), "/x.inc");
        assert_eq!(
            include_path("prog/main.tmc", "C:\\TMCL\\TMCLParam.tmc"),
            "C:/TMCL/TMCLParam.tmc"
        );
    }

    #[test]
    fn memory_sources_name_missing_files() {
        let mut files = BTreeMap::new();
        files.insert("a.inc".to_string(), "X = 1".to_string());
        let load = |path| files.load(path).map_err(|e| e.to_string());
        assert_eq!(load("a.inc"), Ok("X = 1".to_string()));
        assert_eq!(load("b.inc"), Err("no such file".to_string()));
        assert!(NoIncludes.load("a.inc").is_err());
    }
}
