//! Which program tool the editor's text is written for: the one a file's
//! extension names, else the connected family's (unless the file or the
//! user chose), the language key going through the tools there are. The
//! editor names no language: it holds the tool
//! ([`crate::protocol::program::ProgramTool`]) and asks it.

use std::path::Path;

use super::EditorPane;
use crate::families::FAMILIES;
use crate::protocol::Family;
use crate::protocol::program::{ProgramTool, SyntaxClass, is_file_of};
use crate::ui::keymap::{Action, Context};
use crate::ui::pane::{Notice, Outcome, View, key_label};
use crate::ui::theme::Role;

/// Every registered family's program tool, in the order of the families.
pub fn registered_tools() -> Vec<&'static dyn ProgramTool> {
    let mut tools: Vec<&'static dyn ProgramTool> = Vec::new();
    for tool in FAMILIES.iter().filter_map(|f| f.console.program()) {
        if !tools.iter().any(|t| same(*t, tool)) {
            tools.push(tool);
        }
    }
    tools
}

/// The tool a buffer starts with: the first family's.
pub fn default_tool() -> Option<&'static dyn ProgramTool> {
    registered_tools().first().copied()
}

/// The registered family whose programs `tool` writes.
pub fn family_of(tool: &dyn ProgramTool) -> Option<&'static Family> {
    FAMILIES
        .iter()
        .find(|f| f.console.program().is_some_and(|t| same(t, tool)))
        .map(|f| f.family)
}

/// How to name a simulator of `tool`'s family on `:connect` (`--sim
/// cmd4cr`), if it has one.
pub fn simulator_of(tool: &dyn ProgramTool) -> Option<String> {
    let kind = crate::families::simulators_of(family_of(tool)?).first()?;
    Some(format!("--sim {}", kind.name))
}

/// Whether `a` and `b` are the same tool (tools are told by their names).
pub fn same(a: &dyn ProgramTool, b: &dyn ProgramTool) -> bool {
    a.name() == b.name()
}

/// The tools this editor knows now: the registered ones and the connected
/// family's.
fn known_tools(view: &View) -> Vec<&'static dyn ProgramTool> {
    let mut tools = registered_tools();
    if let Some(tool) = view.session.and_then(|s| s.family.console.program())
        && !tools.iter().any(|t| same(*t, tool))
    {
        tools.push(tool);
    }
    tools
}

/// The tool whose extensions `path` has, among `tools`.
pub fn tool_of_file(
    tools: &[&'static dyn ProgramTool],
    path: &Path,
) -> Option<&'static dyn ProgramTool> {
    tools.iter().copied().find(|tool| is_file_of(*tool, path))
}

/// The colour of a syntax class.
pub fn role_of(class: SyntaxClass) -> Option<Role> {
    match class {
        SyntaxClass::Plain => None,
        SyntaxClass::Keyword => Some(Role::CodeMnemonic),
        SyntaxClass::Label => Some(Role::CodeLabel),
        SyntaxClass::Number => Some(Role::CodeNumber),
        SyntaxClass::Comment => Some(Role::CodeComment),
        SyntaxClass::Variable => Some(Role::Accent),
        SyntaxClass::Invalid => Some(Role::CodeError),
    }
}

impl EditorPane {
    /// The tool the file's extension names, if one does: a registered
    /// one, or the text's own.
    pub(super) fn tool_of_file(&mut self, path: &Path) {
        let mut tools = registered_tools();
        if !tools.iter().any(|t| same(*t, self.tool)) {
            tools.push(self.tool);
        }
        if let Some(tool) = tool_of_file(&tools, path) {
            self.set_tool(tool);
            self.tool_fixed = true;
        }
    }

    /// Write the text for `tool`: checked again, coloured again; the
    /// watched variables are the tool's own.
    pub(super) fn set_tool(&mut self, tool: &'static dyn ProgramTool) {
        if same(tool, self.tool) {
            return;
        }
        self.tool = tool;
        self.current = None;
        self.failed_line = None;
        self.state = super::control::ProgramState::default();
        self.host_values = None;
        self.load_variables();
        self.assemble();
    }

    /// The language key: the next tool there is.
    pub(super) fn switch_language(&mut self, view: &View) -> Outcome {
        if self.host.is_some() {
            self.message = Some(Notice::warning(format!(
                "the text runs from the host: {} stops it first",
                key_label(view.keymap, Context::Editor, Action::Cancel)
            )));
            return Outcome::redraw();
        }
        let tools = known_tools(view);
        let at = tools.iter().position(|t| same(*t, self.tool));
        let next = at.map_or(0, |at| (at + 1) % tools.len().max(1));
        let Some(&to) = tools.get(next) else {
            return Outcome::Ignored;
        };
        if same(to, self.tool) {
            self.message = Some(Notice::info(format!(
                "the text is {}: no other program language is known",
                to.name()
            )));
            return Outcome::redraw();
        }
        self.set_tool(to);
        self.tool_fixed = true;
        // The safety copy names the language: a start after a crash
        // brings the text back in this one, not the one it was typed in.
        if self.modified() {
            self.write_safety_copy();
        }
        let again = if tools.len() == 2 {
            "switches back"
        } else {
            "switches to the next"
        };
        self.message = Some(Notice::info(format!(
            "the text is {} now ({} {again})",
            to.name(),
            key_label(view.keymap, Context::Editor, Action::EditorLanguage)
        )));
        Outcome::redraw()
    }

    /// A connection's family decides, unless the file or the user did; a
    /// family without programs changes nothing.
    pub(super) fn follow_family(&mut self, view: &View) -> bool {
        let Some(tool) = view.session.and_then(|s| s.family.console.program()) else {
            return false;
        };
        if self.tool_fixed || same(tool, self.tool) {
            return false;
        }
        self.set_tool(tool);
        if self.modified() {
            self.write_safety_copy();
        }
        true
    }

    /// Whether the connected module runs programs of this text's tool;
    /// if it speaks another family's, why not.
    pub(super) fn other_family(&self, view: &View) -> Option<Notice> {
        let family = view.session?.family;
        let speaks = family
            .console
            .program()
            .is_some_and(|tool| same(tool, self.tool));
        (!speaks).then(|| {
            Notice::error(format!(
                "the connected module speaks {}: {} programs are the {}'s",
                family.name,
                self.tool.name(),
                self.tool.controller()
            ))
        })
    }

    /// What to say when nothing is connected: how to connect to a
    /// controller of this text's tool.
    pub(super) fn not_connected(&self) -> String {
        match family_of(self.tool) {
            Some(family) => {
                let sim = simulator_of(self.tool).map_or_else(String::new, |s| format!("{s} (or "));
                let close = if sim.is_empty() { "" } else { ")" };
                format!(
                    "not connected: give :connect {sim}--port PATH --protocol {}, --tcp HOST:PORT{close}",
                    family.name
                )
            }
            None => "not connected: give :connect CONNECTION".to_string(),
        }
    }
}
