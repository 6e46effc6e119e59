//! The assembler listing: per instruction its address (decimal, as the
//! manual gives addresses), its seven bytes and its source line; labels on
//! rows of their own; the symbol table (labels → addresses, what the
//! TMCL-IDE's "Generate symbol file" gives, §8.6) at the end.

use std::collections::BTreeMap;
use std::fmt::Write;

use super::super::hex::to_hex;
use super::Program;

/// Width of the address and bytes columns, so sources line up.
const BYTES_WIDTH: usize = 3 * super::ProgramWord::LEN - 1;

/// The listing of `program`.
pub fn listing(program: &Program) -> String {
    let mut at_address: BTreeMap<u16, Vec<&str>> = BTreeMap::new();
    for (name, address) in &program.symbols {
        at_address.entry(*address).or_default().push(name);
    }
    let mut out = String::new();
    let _ = writeln!(out, "{:>4}  {:<BYTES_WIDTH$}  source", "addr", "bytes");
    let label_rows = |out: &mut String, names: &[&str]| {
        for name in names {
            let _ = writeln!(out, "{:>4}  {:<BYTES_WIDTH$}  {name}:", "", "");
        }
    };
    let mut file = program.source_name.as_str();
    for (word, line) in program.words.iter().zip(&program.lines) {
        if line.file != file {
            file = &line.file;
            let _ = writeln!(out, "{:>4}  {:<BYTES_WIDTH$}  // {file}", "", "");
        }
        if let Some(names) = at_address.get(&line.address) {
            label_rows(&mut out, names);
        }
        let _ = writeln!(
            out,
            "{:>4}  {}  {}",
            line.address,
            to_hex(&word.to_bytes()),
            line.text
        );
    }
    let end = u16::try_from(program.words.len()).unwrap_or(u16::MAX);
    for (_, names) in at_address.range(end..) {
        label_rows(&mut out, names);
    }
    if !program.symbols.is_empty() {
        let _ = writeln!(out, "\nlabels:");
        let width = program.symbols.keys().map(|k| k.len()).max().unwrap_or(0);
        for (address, names) in &at_address {
            for name in names {
                let _ = writeln!(out, "  {name:<width$}  {address}");
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;
    use crate::protocol::tmcl::asm::assemble;

    #[test]
    fn rows_show_address_bytes_source_and_labels() {
        let mut files = BTreeMap::new();
        files.insert("sub.inc".to_string(), "Sub: RSUB // back".to_string());
        let source = "CSUB Sub // call\nLoop:\n  JA Loop\n#include sub.inc\nEnd:";
        let program = assemble("main.tmc", source, &files).unwrap();
        let expected = "\
addr  bytes                 source
   0  17 00 00 00 00 00 02  CSUB Sub // call
                            Loop:
   1  16 00 00 00 00 00 01  JA Loop
                            // sub.inc
                            Sub:
   2  18 00 00 00 00 00 00  RSUB // back
                            End:

labels:
  Loop  1
  Sub   2
  End   3
";
        assert_eq!(listing(&program), expected);
    }
}
