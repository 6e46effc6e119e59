//! Keys of the console: a [`Keymap`] binds [`KeyChord`]s to [`Action`]s,
//! per [`Context`] (the global bindings, and one set per pane).
//!
//! Global bindings are looked up first, in every pane, so the emergency
//! stop works everywhere: in the program editor and while typing a
//! command too. Hence a global key may not be a plain character (it would
//! be taken from typed text), and a pane may not bind a key that a global
//! binding already holds (that binding could never fire): both are
//! refused when the keymap loads, as is a keymap without an emergency
//! stop, or with two actions on one key in one pane.
//!
//! Keymaps are TOML files: one section per context, action names as keys,
//! a key or a list of keys as values. The built-ins in `keymaps/` are
//! compiled in; a user's `keymaps/NAME.toml` in the platform config
//! directory overrides the built-in of the same name action by action:
//! what it does not mention comes from its `base` (a built-in name, by
//! default the built-in of the same name, else `default`), and
//! `action = []` unbinds.

mod chord;

pub use chord::{ChordError, Key, KeyChord, MAX_FUNCTION_KEY, Modifiers};

use std::collections::BTreeMap;
use std::fmt;
use std::ops::Range;
use std::path::Path;

use ratatui::crossterm::event::{KeyEvent, KeyEventKind};
use serde::Deserialize;
use serde::de::{Deserializer, SeqAccess, Visitor};
use toml::Spanned;

use super::config::{self, ConfigError, ConfigKind, Loaded, line_column, load_config};

/// Where a key is pressed: a section of a keymap file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Context {
    /// Checked first, whatever pane has the focus.
    Global,
    /// The command line and its output.
    Command,
    /// The axis gauges.
    Axis,
    /// The parameter table.
    Parameters,
    /// The traffic monitor.
    Traffic,
    /// The plots.
    Plot,
    /// The program editor.
    Editor,
    /// The bring-up pane: jogging an axis, its inputs.
    BringUp,
    /// The tuning pane: a step test or a load sweep.
    Tuning,
}

impl Context {
    pub const ALL: [Context; 9] = [
        Context::Global,
        Context::Command,
        Context::Axis,
        Context::Parameters,
        Context::Traffic,
        Context::Plot,
        Context::Editor,
        Context::BringUp,
        Context::Tuning,
    ];

    /// The section name in keymap files.
    pub fn name(self) -> &'static str {
        match self {
            Context::Global => "global",
            Context::Command => "command",
            Context::Axis => "axis",
            Context::Parameters => "parameters",
            Context::Traffic => "traffic",
            Context::Plot => "plot",
            Context::Editor => "editor",
            Context::BringUp => "bringup",
            Context::Tuning => "tuning",
        }
    }

    /// Whether plain characters are typed text here: the command line and
    /// the editor, and the global bindings, which are active in both. A
    /// pane that takes typed text for a moment (a parameter value, a
    /// filter) looks keys up in [`Context::Command`] meanwhile.
    pub fn takes_text(self) -> bool {
        matches!(self, Context::Global | Context::Command | Context::Editor)
    }
}

impl fmt::Display for Context {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Everything a key can do in the console.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Action {
    EmergencyStop,
    Quit,
    Help,
    NextPane,
    PreviousPane,
    FocusPane1,
    FocusPane2,
    FocusPane3,
    FocusPane4,
    FocusPane5,
    FocusPane6,
    FocusPane7,
    FocusPane8,
    FocusPane9,
    ClearErrors,
    Submit,
    Cancel,
    Complete,
    HistoryPrevious,
    HistoryNext,
    ScrollUp,
    ScrollDown,
    ScrollPageUp,
    ScrollPageDown,
    ScrollTop,
    ScrollBottom,
    ClearOutput,
    SelectPrevious,
    SelectNext,
    AxisStop,
    ToggleUnits,
    ParameterEdit,
    ParameterWrite,
    ParameterStore,
    ParameterRestore,
    ParameterRefresh,
    ParameterFilter,
    ParameterExport,
    ParameterImport,
    ParameterDiff,
    PauseTraffic,
    ToggleHidePolls,
    TrafficLink,
    ClearTraffic,
    SaveTraffic,
    PlotZoomIn,
    PlotZoomOut,
    PlotZoomReset,
    PlotPause,
    PlotPick,
    EditorSave,
    EditorOpen,
    EditorAssemble,
    EditorDownload,
    EditorRun,
    EditorStop,
    EditorStep,
    EditorSaveAs,
    EditorNextError,
    EditorVerify,
    EditorUpload,
    EditorReset,
    EditorWatch,
    EditorHostRun,
    EditorLanguage,
    JogPositive,
    JogNegative,
    StepPositive,
    StepNegative,
    StepLarger,
    StepSmaller,
    JogFaster,
    JogSlower,
    OutputNext,
    OutputPrevious,
    OutputToggle,
    WiringCheck,
    TuneRun,
    TuneKeepFree,
    TuneApply,
    TuneTool,
}

/// An action's name in keymap files, its word in the status bar, what it
/// does (for the help), and the sections that may bind it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ActionInfo {
    pub action: Action,
    pub name: &'static str,
    pub title: &'static str,
    pub description: &'static str,
    pub contexts: &'static [Context],
}

use Context::{Axis, BringUp, Command, Editor, Global, Parameters, Plot, Traffic, Tuning};

const ONLY_GLOBAL: &[Context] = &[Global];
/// Moving about: global, and in the panes where letters are not text.
const NAVIGATION: &[Context] = &[Global, Axis, Parameters, Traffic, Plot, BringUp, Tuning];
const EVERYWHERE: &[Context] = &[
    Global, Command, Axis, Parameters, Traffic, Plot, Editor, BringUp, Tuning,
];
const COMMAND_LINE: &[Context] = &[Command];
const CANCELLING: &[Context] = &[Command, Parameters, Editor, BringUp, Tuning];
const SCROLLING: &[Context] = &[Command, Parameters, Traffic];
const LISTS: &[Context] = &[Axis, Parameters, BringUp, Tuning];
const AXES: &[Context] = &[Axis, BringUp];
const JOGGING: &[Context] = &[BringUp];
const EDITING: &[Context] = &[Parameters, Tuning];
const TUNING: &[Context] = &[Tuning];
const UNITS: &[Context] = &[Axis, Parameters, Plot];
const PARAMETERS: &[Context] = &[Parameters];
const TRAFFIC_ANYWHERE: &[Context] = &[Global, Traffic];
const TRAFFIC: &[Context] = &[Traffic];
const PLOTS: &[Context] = &[Plot];
const EDITOR: &[Context] = &[Editor];

const fn info(
    action: Action,
    name: &'static str,
    title: &'static str,
    description: &'static str,
    contexts: &'static [Context],
) -> ActionInfo {
    ActionInfo {
        action,
        name,
        title,
        description,
        contexts,
    }
}

/// Every action, in [`Action`] order.
#[rustfmt::skip]
pub const ACTIONS: &[ActionInfo] = &[
    info(Action::EmergencyStop, "emergency_stop", "STOP", "stop every axis now, ahead of anything queued", ONLY_GLOBAL),
    info(Action::Quit, "quit", "Quit", "leave axterm", NAVIGATION),
    info(Action::Help, "help", "Help", "show the keys of the pane", NAVIGATION),
    info(Action::NextPane, "next_pane", "Next pane", "move the focus to the next pane", NAVIGATION),
    info(Action::PreviousPane, "previous_pane", "Prev pane", "move the focus to the previous pane", NAVIGATION),
    info(Action::FocusPane1, "focus_pane_1", "Pane 1", "focus pane 1", NAVIGATION),
    info(Action::FocusPane2, "focus_pane_2", "Pane 2", "focus pane 2", NAVIGATION),
    info(Action::FocusPane3, "focus_pane_3", "Pane 3", "focus pane 3", NAVIGATION),
    info(Action::FocusPane4, "focus_pane_4", "Pane 4", "focus pane 4", NAVIGATION),
    info(Action::FocusPane5, "focus_pane_5", "Pane 5", "focus pane 5", NAVIGATION),
    info(Action::FocusPane6, "focus_pane_6", "Pane 6", "focus pane 6", NAVIGATION),
    info(Action::FocusPane7, "focus_pane_7", "Pane 7", "focus pane 7", NAVIGATION),
    info(Action::FocusPane8, "focus_pane_8", "Pane 8", "focus pane 8", NAVIGATION),
    info(Action::FocusPane9, "focus_pane_9", "Pane 9", "focus pane 9", NAVIGATION),
    info(Action::ClearErrors, "clear_errors", "Clear errors", "acknowledge and clear the error messages", EVERYWHERE),
    info(Action::Submit, "submit", "Send", "send the command line", COMMAND_LINE),
    info(Action::Cancel, "cancel", "Cancel", "drop the line being typed, the filter, or the editor's prompt", CANCELLING),
    info(Action::Complete, "complete", "Complete", "complete the word being typed", COMMAND_LINE),
    info(Action::HistoryPrevious, "history_previous", "History back", "recall the previous command", COMMAND_LINE),
    info(Action::HistoryNext, "history_next", "History fwd", "recall the next command", COMMAND_LINE),
    info(Action::ScrollUp, "scroll_up", "Scroll up", "scroll up one line", SCROLLING),
    info(Action::ScrollDown, "scroll_down", "Scroll down", "scroll down one line", SCROLLING),
    info(Action::ScrollPageUp, "scroll_page_up", "Page up", "scroll up one page", SCROLLING),
    info(Action::ScrollPageDown, "scroll_page_down", "Page down", "scroll down one page", SCROLLING),
    info(Action::ScrollTop, "scroll_top", "Top", "go to the first line", SCROLLING),
    info(Action::ScrollBottom, "scroll_bottom", "Bottom", "go to the last line and follow new ones", SCROLLING),
    info(Action::ClearOutput, "clear_output", "Clear", "clear the command output", COMMAND_LINE),
    info(Action::SelectPrevious, "select_previous", "Previous", "select the previous axis or row", LISTS),
    info(Action::SelectNext, "select_next", "Next", "select the next axis or row", LISTS),
    info(Action::AxisStop, "axis_stop", "Stop axis", "stop the selected axis (a normal stop)", AXES),
    info(Action::ToggleUnits, "toggle_units", "Units", "switch between raw and physical units", UNITS),
    info(Action::ParameterEdit, "parameter_edit", "Edit", "type a new value for the selected parameter (the tuning pane: the selected gain or setting)", EDITING),
    info(Action::ParameterWrite, "parameter_write", "Write", "send the edited value to the controller", PARAMETERS),
    info(Action::ParameterStore, "parameter_store", "Store", "store the parameter in the controller's EEPROM", PARAMETERS),
    info(Action::ParameterRestore, "parameter_restore", "Restore", "restore the parameter from the controller's EEPROM", PARAMETERS),
    info(Action::ParameterRefresh, "parameter_refresh", "Refresh", "read every parameter again (the tuning pane: the gains)", EDITING),
    info(Action::ParameterFilter, "parameter_filter", "Filter", "show only parameters whose name matches", PARAMETERS),
    info(Action::ParameterExport, "parameter_export", "Export", "save every setting of the module to a TOML file", PARAMETERS),
    info(Action::ParameterImport, "parameter_import", "Import", "load settings from a TOML file: the differences are shown before anything is written", PARAMETERS),
    info(Action::ParameterDiff, "parameter_diff", "Diff", "compare the module with a TOML file of settings", PARAMETERS),
    info(Action::PauseTraffic, "pause_traffic", "Pause", "freeze or resume the traffic monitor", TRAFFIC_ANYWHERE),
    info(Action::ToggleHidePolls, "toggle_hide_polls", "Hide polls", "hide or show the console's status polls", TRAFFIC_ANYWHERE),
    info(Action::TrafficLink, "traffic_link", "Link", "show one link's traffic, then the next's, then every link's again", TRAFFIC),
    info(Action::ClearTraffic, "clear_traffic", "Clear", "clear the traffic monitor", TRAFFIC),
    info(Action::SaveTraffic, "save_traffic", "Save", "save the frames shown in the traffic monitor to a file", TRAFFIC),
    info(Action::PlotZoomIn, "plot_zoom_in", "Zoom in", "show a shorter time span", PLOTS),
    info(Action::PlotZoomOut, "plot_zoom_out", "Zoom out", "show a longer time span", PLOTS),
    info(Action::PlotZoomReset, "plot_zoom_reset", "Zoom reset", "show the default time span", PLOTS),
    info(Action::PlotPause, "plot_pause", "Freeze", "freeze or resume the plots", PLOTS),
    info(Action::PlotPick, "plot_pick", "Pick", "list what the selected axis can plot (status values, then its parameters; typing filters): Enter plots or stops plotting one", PLOTS),
    info(Action::EditorSave, "editor_save", "Save", "save the program source", EDITOR),
    info(Action::EditorOpen, "editor_open", "Open", "open a program source file", EDITOR),
    info(Action::EditorAssemble, "editor_assemble", "Assemble", "assemble the program and show its errors", EDITOR),
    info(Action::EditorDownload, "editor_download", "Download", "assemble and download the program to the controller", EDITOR),
    info(Action::EditorRun, "editor_run", "Run", "run the program on the controller", EDITOR),
    info(Action::EditorStop, "editor_stop", "Stop", "stop the program on the controller", EDITOR),
    info(Action::EditorStep, "editor_step", "Step", "execute one instruction of the program", EDITOR),
    info(Action::EditorSaveAs, "editor_save_as", "Save as", "save the program source under a new name (--force FILE to replace another file)", EDITOR),
    info(Action::EditorNextError, "editor_next_error", "Next error", "go to the next line that does not assemble", EDITOR),
    info(Action::EditorVerify, "editor_verify", "Verify", "compare the program in the controller with the source", EDITOR),
    info(Action::EditorUpload, "editor_upload", "Upload", "read the program from the controller into a new buffer", EDITOR),
    info(Action::EditorReset, "editor_reset", "Reset", "reset the program on the controller to its start", EDITOR),
    info(Action::EditorWatch, "editor_watch", "Watch", "watch the user variable of the line (GGP/SGP n, 2; A-Script: V[n]), or one typed, beside the program; again stops", EDITOR),
    info(Action::EditorHostRun, "editor_host_run", "Run from host", "run the text from the host, statement by statement (A-Script: the CMD-4CR takes no program download over the wire; SQPack macros: the SIXpack 2 stores no program)", EDITOR),
    info(Action::EditorLanguage, "editor_language", "Language", "switch the text to the next program language (one per family)", EDITOR),
    info(Action::JogPositive, "jog_positive", "Jog +", "run the axis in + while the key repeats (held): it stops when the repeats stop", JOGGING),
    info(Action::JogNegative, "jog_negative", "Jog -", "run the axis in - while the key repeats (held): it stops when the repeats stop", JOGGING),
    info(Action::StepPositive, "step_positive", "Step +", "move the axis one step in +", JOGGING),
    info(Action::StepNegative, "step_negative", "Step -", "move the axis one step in -", JOGGING),
    info(Action::StepLarger, "step_larger", "Step size +", "make the step larger", JOGGING),
    info(Action::StepSmaller, "step_smaller", "Step size -", "make the step smaller", JOGGING),
    info(Action::JogFaster, "jog_faster", "Faster", "jog faster", JOGGING),
    info(Action::JogSlower, "jog_slower", "Slower", "jog slower", JOGGING),
    info(Action::OutputNext, "output_next", "Next output", "choose the next output of the module", JOGGING),
    info(Action::OutputPrevious, "output_previous", "Previous output", "choose the previous output of the module", JOGGING),
    info(Action::OutputToggle, "output_toggle", "Switch output", "switch the chosen output on or off, after a y/n question (an output can move machinery)", JOGGING),
    info(Action::WiringCheck, "wiring_check", "Wiring check", "jog the axis toward + and then - until a limit switch fires, after a y/n question, and say which switch fired where (Esc stops it)", JOGGING),
    info(Action::TuneRun, "tune_run", "Run test", "run the tuning pane's test (a step or a sweep), after a y/n question: it moves the axis (Esc stops it)", TUNING),
    info(Action::TuneKeepFree, "tune_keep_free", "Keep as free", "keep the last sweep as the one without load: the next (with the load applied) is compared with it", TUNING),
    info(Action::TuneApply, "tune_apply", "Send suggestion", "send the lines the sweeps suggest, after a y/n question", TUNING),
    info(Action::TuneTool, "tune_tool", "Next tool", "switch the tuning pane to the family's next tool (TMCL: the StallGuard2 sweep and the CoolStep current control)", TUNING),
];

impl Action {
    fn info(self) -> Option<&'static ActionInfo> {
        ACTIONS.iter().find(|info| info.action == self)
    }

    /// Its name in keymap files.
    pub fn name(self) -> &'static str {
        self.info().map_or("?", |info| info.name)
    }

    /// Its word in the status bar ("STOP", "Quit").
    pub fn title(self) -> &'static str {
        self.info().map_or("?", |info| info.title)
    }

    /// What it does, for the help.
    pub fn description(self) -> &'static str {
        self.info().map_or("", |info| info.description)
    }

    /// The sections of a keymap that may bind it.
    pub fn contexts(self) -> &'static [Context] {
        self.info().map_or(&[], |info| info.contexts)
    }

    /// The action a keymap file names, if any.
    pub fn from_name(name: &str) -> Option<Action> {
        ACTIONS
            .iter()
            .find(|info| info.name == name)
            .map(|info| info.action)
    }

    /// For the focus actions, the pane number (1–9).
    pub fn pane_number(self) -> Option<u8> {
        let number = match self {
            Action::FocusPane1 => 1,
            Action::FocusPane2 => 2,
            Action::FocusPane3 => 3,
            Action::FocusPane4 => 4,
            Action::FocusPane5 => 5,
            Action::FocusPane6 => 6,
            Action::FocusPane7 => 7,
            Action::FocusPane8 => 8,
            Action::FocusPane9 => 9,
            _ => return None,
        };
        Some(number)
    }
}

impl fmt::Display for Action {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The keys of one action in one section, as loaded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Binding {
    pub context: Context,
    pub action: Action,
    /// In the order the file gives them; the first is the one shown.
    pub chords: Vec<KeyChord>,
}

/// The keymap the console starts with when none is asked for.
pub const DEFAULT_KEYMAP: &str = "default";

/// The built-in keymaps, compiled in: name and TOML text.
pub const BUILTIN_KEYMAPS: &[(&str, &str)] = &[
    ("default", include_str!("../../keymaps/default.toml")),
    ("vim", include_str!("../../keymaps/vim.toml")),
];

/// Keys to actions, per context; always with an emergency stop.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Keymap {
    name: String,
    description: String,
    bindings: Vec<Binding>,
    lookup: BTreeMap<(Context, KeyChord), Action>,
    emergency_stop: KeyChord,
}

impl Keymap {
    pub fn name(&self) -> &str {
        &self.name
    }

    /// One line on what the keymap is for, from its file.
    pub fn description(&self) -> &str {
        &self.description
    }

    /// What a key press does in `context`: the global bindings first (so
    /// the emergency stop wins everywhere), then the context's. Key
    /// releases (reported on Windows) do nothing.
    pub fn action_for(&self, context: Context, event: &KeyEvent) -> Option<Action> {
        if event.kind == KeyEventKind::Release {
            return None;
        }
        self.action_for_chord(context, KeyChord::from_event(event)?)
    }

    /// What `chord` does in `context`, global bindings first.
    pub fn action_for_chord(&self, context: Context, chord: KeyChord) -> Option<Action> {
        self.lookup
            .get(&(Context::Global, chord))
            .or_else(|| self.lookup.get(&(context, chord)))
            .copied()
    }

    /// The keys that do `action` in `context` (global ones first).
    pub fn chords(&self, context: Context, action: Action) -> Vec<KeyChord> {
        let mut chords: Vec<KeyChord> = Vec::new();
        for binding in &self.bindings {
            let applies = binding.context == Context::Global || binding.context == context;
            if applies && binding.action == action {
                for chord in &binding.chords {
                    if !chords.contains(chord) {
                        chords.push(*chord);
                    }
                }
            }
        }
        chords
    }

    /// The status bar hint for `action` in `context`: its first key and
    /// its word, `"F12 STOP"`; `None` when nothing does it there.
    pub fn hint(&self, context: Context, action: Action) -> Option<String> {
        let chord = self.chords(context, action).into_iter().next()?;
        Some(format!("{} {}", chord.label(), action.title()))
    }

    /// The emergency stop's (first) key: every keymap has one.
    pub fn emergency_stop(&self) -> KeyChord {
        self.emergency_stop
    }

    /// The status bar's emergency stop hint, `"F12 STOP"`.
    pub fn stop_hint(&self) -> String {
        format!(
            "{} {}",
            self.emergency_stop.label(),
            Action::EmergencyStop.title()
        )
    }

    /// Every binding, section by section, for the help.
    pub fn bindings(&self) -> &[Binding] {
        &self.bindings
    }

    /// The built-in keymap `name`.
    pub fn builtin(name: &str) -> Option<Keymap> {
        let (name, text) = BUILTIN_KEYMAPS.iter().find(|(n, _)| *n == name)?;
        let draft = read_keymap(text, Some(name)).ok()?;
        if draft.base.is_some() {
            return None;
        }
        assemble(
            name,
            draft.description.unwrap_or_default(),
            draft.entries,
            text,
        )
        .ok()
    }

    /// The names of the built-in keymaps.
    pub fn builtin_names() -> impl Iterator<Item = &'static str> {
        BUILTIN_KEYMAPS.iter().map(|(name, _)| *name)
    }

    /// The default built-in; if that were ever broken (the tests see that
    /// it is not), F12 to stop and F10 to quit.
    fn fallback() -> Keymap {
        Keymap::builtin(DEFAULT_KEYMAP).unwrap_or_else(|| {
            let stop = KeyChord {
                key: Key::F(12),
                modifiers: Modifiers::NONE,
            };
            let quit = KeyChord {
                key: Key::F(10),
                modifiers: Modifiers::NONE,
            };
            let bindings = vec![
                Binding {
                    context: Context::Global,
                    action: Action::EmergencyStop,
                    chords: vec![stop],
                },
                Binding {
                    context: Context::Global,
                    action: Action::Quit,
                    chords: vec![quit],
                },
            ];
            let lookup = BTreeMap::from([
                ((Context::Global, stop), Action::EmergencyStop),
                ((Context::Global, quit), Action::Quit),
            ]);
            Keymap {
                name: DEFAULT_KEYMAP.to_string(),
                description: String::new(),
                bindings,
                lookup,
                emergency_stop: stop,
            }
        })
    }
}

/// The keymap the console starts with: `flag` (the `--keymap` value) when
/// given, else `default`; looked up in `config_dir` first, then among the
/// built-ins. Never fails: a problem comes back beside the fallback.
pub fn choose_keymap(flag: Option<&str>, config_dir: Option<&Path>) -> Loaded<Keymap> {
    load_keymap(flag.unwrap_or(DEFAULT_KEYMAP), config_dir)
}

/// The keymap `name`: the user's `keymaps/NAME.toml` in `config_dir` over
/// the built-in of that name. A user file that cannot be used gives a
/// [`ConfigProblem`] and the built-in of that name (else `default`).
pub fn load_keymap(name: &str, config_dir: Option<&Path>) -> Loaded<Keymap> {
    load_config(&KEYMAPS, name, config_dir)
}

/// Keymaps as the configuration loader knows them.
const KEYMAPS: ConfigKind<Keymap> = ConfigKind {
    folder: "keymaps",
    noun: "keymap",
    default_name: DEFAULT_KEYMAP,
    builtin: Keymap::builtin,
    builtin_names: || Keymap::builtin_names().collect(),
    last_resort: Keymap::fallback,
    parse: parse_keymap,
};

/// Parses a user's keymap file named `name` over its base (a built-in; by
/// default the built-in of the same name, else `default`): each action it
/// mentions in a section replaces the base's keys for that action there.
/// Every mistake found is returned, in file order.
pub fn parse_keymap(name: &str, text: &str) -> Result<Keymap, Vec<ConfigError>> {
    let draft = read_keymap(text, None)?;
    let base_name = config::base_name(&KEYMAPS, draft.base.as_ref(), name, text)?;
    let (base_name, base_text) = BUILTIN_KEYMAPS
        .iter()
        .find(|(n, _)| *n == base_name)
        .copied()
        .unwrap_or(("", ""));
    let base = read_keymap(base_text, Some(base_name)).map_err(|_| {
        vec![ConfigError::general(format!(
            "the built-in keymap `{base_name}` is broken"
        ))]
    })?;
    let mut entries = base.entries;
    entries.extend(draft.entries);
    let description = draft.description.or(base.description).unwrap_or_default();
    assemble(name, description, entries, text)
}

/// Where a binding was written: the file being read (`source` `None`), or
/// a built-in base.
#[derive(Debug, Clone)]
struct Place {
    source: Option<&'static str>,
    span: Range<usize>,
    line: usize,
    column: usize,
}

impl Place {
    fn describe(&self) -> String {
        match self.source {
            None => format!("line {}", self.line),
            Some(builtin) => format!("built-in keymap `{builtin}`, line {}", self.line),
        }
    }
}

/// One action's keys in one section, as read.
#[derive(Debug, Clone)]
struct Entry {
    key_place: Place,
    chords: Vec<(KeyChord, Place)>,
}

type Entries = BTreeMap<(Context, Action), Entry>;

struct KeymapDraft {
    description: Option<String>,
    base: Option<(String, Range<usize>)>,
    entries: Entries,
}

/// A keymap file as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct KeymapFile {
    /// Informational: the file name is the keymap's name.
    #[serde(default, rename = "name")]
    _name: Option<String>,
    #[serde(default)]
    description: Option<String>,
    #[serde(default)]
    base: Option<Spanned<String>>,
    #[serde(default)]
    global: Section,
    #[serde(default)]
    command: Section,
    #[serde(default)]
    axis: Section,
    #[serde(default)]
    parameters: Section,
    #[serde(default)]
    traffic: Section,
    #[serde(default)]
    plot: Section,
    #[serde(default)]
    editor: Section,
    #[serde(default)]
    bringup: Section,
    #[serde(default)]
    tuning: Section,
}

type Section = BTreeMap<Spanned<String>, Spanned<ChordList>>;

/// `"f12"` or `["f1", "alt-h"]`, each key with its place when the file
/// gives one (a lone string takes the place of its value).
struct ChordList(Vec<(String, Option<Range<usize>>)>);

impl<'de> Deserialize<'de> for ChordList {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ChordListVisitor;

        impl<'de> Visitor<'de> for ChordListVisitor {
            type Value = ChordList;

            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(r#"a key such as "f12", or a list of keys such as ["f1", "alt-h"]"#)
            }

            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<ChordList, E> {
                Ok(ChordList(vec![(v.to_string(), None)]))
            }

            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<ChordList, A::Error> {
                let mut keys = Vec::new();
                while let Some(key) = seq.next_element::<Spanned<String>>()? {
                    let span = key.span();
                    keys.push((key.into_inner(), Some(span)));
                }
                Ok(ChordList(keys))
            }
        }

        deserializer.deserialize_any(ChordListVisitor)
    }
}

impl KeymapFile {
    fn sections(&self) -> [(Context, &Section); 9] {
        [
            (Context::Global, &self.global),
            (Context::Command, &self.command),
            (Context::Axis, &self.axis),
            (Context::Parameters, &self.parameters),
            (Context::Traffic, &self.traffic),
            (Context::Plot, &self.plot),
            (Context::Editor, &self.editor),
            (Context::BringUp, &self.bringup),
            (Context::Tuning, &self.tuning),
        ]
    }
}

/// Reads a keymap file's entries, refusing unknown actions, actions in a
/// section that cannot bind them, chords that do not parse, and
/// characters where text is typed. `source` names a built-in.
fn read_keymap(text: &str, source: Option<&'static str>) -> Result<KeymapDraft, Vec<ConfigError>> {
    let file: KeymapFile =
        toml::from_str(text).map_err(|e| vec![ConfigError::from_toml(text, &e)])?;
    let place = |span: Range<usize>| {
        let (line, column) = line_column(text, span.start);
        Place {
            source,
            span,
            line,
            column,
        }
    };
    let mut errors = Vec::new();
    let mut entries = Entries::new();
    for (context, section) in file.sections() {
        for (action_name, list) in section {
            let key = format!("{context}.{}", action_name.get_ref());
            let Some(action) = Action::from_name(action_name.get_ref()) else {
                errors.push(ConfigError::at(
                    text,
                    action_name.span(),
                    &key,
                    format!("unknown action `{}`", action_name.get_ref()),
                ));
                continue;
            };
            if !action.contexts().contains(&context) {
                let homes: Vec<String> =
                    action.contexts().iter().map(|c| format!("[{c}]")).collect();
                errors.push(ConfigError::at(
                    text,
                    action_name.span(),
                    &key,
                    format!(
                        "`{action}` cannot be bound in [{context}]; it belongs in {}",
                        homes.join(", ")
                    ),
                ));
                continue;
            }
            let mut chords = Vec::new();
            for (written, span) in &list.get_ref().0 {
                let span = span.clone().unwrap_or_else(|| list.span());
                match written.parse::<KeyChord>() {
                    Ok(chord) if context.takes_text() && chord.is_text() => {
                        let why = if context == Context::Global {
                            "global keys work in every pane, so it would be taken from text \
                             typed in the command line and the editor"
                        } else {
                            "it is text there"
                        };
                        errors.push(ConfigError::at(
                            text,
                            span,
                            &key,
                            format!(
                                "`{written}` cannot be bound in [{context}]: {why}; use a \
                                 function key or a ctrl- or alt- chord"
                            ),
                        ));
                    }
                    Ok(chord) => {
                        if !chords.iter().any(|(c, _)| *c == chord) {
                            chords.push((chord, place(span)));
                        }
                    }
                    Err(e) => errors.push(ConfigError::at(
                        text,
                        span,
                        &key,
                        format!("`{written}`: {e}"),
                    )),
                }
            }
            entries.insert(
                (context, action),
                Entry {
                    key_place: place(action_name.span()),
                    chords,
                },
            );
        }
    }
    if !errors.is_empty() {
        config::sort_errors(&mut errors);
        return Err(errors);
    }
    Ok(KeymapDraft {
        description: file.description,
        base: file.base.map(|b| {
            let span = b.span();
            (b.into_inner(), span)
        }),
        entries,
    })
}

/// The error for a mistake at `place`, in the file being read (`text`) or
/// in a built-in.
fn error_at(text: &str, place: &Place, key: &str, message: String) -> ConfigError {
    match place.source {
        None => ConfigError::at(text, place.span.clone(), key, message),
        Some(builtin) => ConfigError {
            line: Some(place.line),
            column: Some(place.column),
            key: Some(key.to_string()),
            message: format!("(in the built-in keymap `{builtin}`) {message}"),
        },
    }
}

/// The keymap of `entries`, once it is seen to have an emergency stop and
/// no key that does two things in one pane.
fn assemble(
    name: &str,
    description: String,
    entries: Entries,
    text: &str,
) -> Result<Keymap, Vec<ConfigError>> {
    let mut errors = Vec::new();
    let stop_key = format!("{}.{}", Context::Global, Action::EmergencyStop);
    let emergency_stop = match entries.get(&(Context::Global, Action::EmergencyStop)) {
        Some(entry) => match entry.chords.first() {
            Some((chord, _)) => Some(*chord),
            None => {
                errors.push(error_at(
                    text,
                    &entry.key_place,
                    &stop_key,
                    "the keymap has no emergency stop: give `emergency_stop` a key in [global]; \
                     a console without one must not start"
                        .to_string(),
                ));
                None
            }
        },
        None => {
            errors.push(ConfigError {
                line: None,
                column: None,
                key: Some(stop_key),
                message: "the keymap has no emergency stop: give `emergency_stop` a key in \
                          [global]; a console without one must not start"
                    .to_string(),
            });
            None
        }
    };

    // Global bindings first (BTreeMap order: Context::Global sorts first),
    // then each pane's, each in file order.
    let mut ordered: Vec<(&(Context, Action), &Entry)> = entries.iter().collect();
    ordered.sort_by_key(|((context, _), entry)| {
        (
            *context,
            entry.key_place.source.is_none(),
            entry.key_place.span.start,
        )
    });
    let mut lookup: BTreeMap<(Context, KeyChord), Action> = BTreeMap::new();
    let mut places: BTreeMap<(Context, KeyChord), Place> = BTreeMap::new();
    let mut bindings = Vec::new();
    for ((context, action), entry) in ordered {
        let (context, action) = (*context, *action);
        let mut chords = Vec::new();
        for (chord, place) in &entry.chords {
            let held = |c: Context| {
                lookup
                    .get(&(c, *chord))
                    .filter(|other| **other != action)
                    .map(|other| (c, *other))
            };
            let shadowing = match context {
                Context::Global => None,
                _ => held(Context::Global),
            };
            let holder = shadowing
                .map(|(c, other)| (c, other, true))
                .or_else(|| held(context).map(|(c, other)| (c, other, false)));
            if let Some((other_context, other, shadowed)) = holder {
                let other_place = places.get(&(other_context, *chord)).cloned();
                let other_where = other_place
                    .as_ref()
                    .map_or(String::new(), |p| format!(" ({})", p.describe()));
                let mut message = format!(
                    "`{chord}` is bound to both `{other}` in [{other_context}]{other_where} and \
                     `{action}` in [{context}] ({})",
                    place.describe()
                );
                if shadowed {
                    message.push_str(
                        "; global keys work in every pane, so the pane's binding could never be used",
                    );
                }
                // Blame the binding in the file being read.
                let (blamed, key) = match (&place.source, other_place) {
                    (Some(_), Some(other_place)) if other_place.source.is_none() => {
                        (other_place, format!("{other_context}.{other}"))
                    }
                    _ => (place.clone(), format!("{context}.{action}")),
                };
                errors.push(error_at(text, &blamed, &key, message));
                continue;
            }
            lookup.insert((context, *chord), action);
            places.insert((context, *chord), place.clone());
            chords.push(*chord);
        }
        if !chords.is_empty() {
            bindings.push(Binding {
                context,
                action,
                chords,
            });
        }
    }
    match emergency_stop {
        Some(emergency_stop) if errors.is_empty() => Ok(Keymap {
            name: name.to_string(),
            description,
            bindings,
            lookup,
            emergency_stop,
        }),
        _ => {
            config::sort_errors(&mut errors);
            Err(errors)
        }
    }
}

#[cfg(test)]
mod tests {
    /// The language key goes through every family's language, not two
    /// (issue 19, point 7): its help names none of them.
    #[test]
    fn the_language_key_names_no_single_language() {
        let said = Action::EditorLanguage.description();
        for tool in crate::ui::editor::language::registered_tools() {
            assert!(!said.contains(tool.name()), "{said}");
        }
    }

    use super::*;
    use ratatui::crossterm::event::{KeyCode, KeyModifiers};

    fn chord(text: &str) -> KeyChord {
        text.parse().unwrap_or_else(|e| panic!("{text}: {e}"))
    }

    #[test]
    fn the_action_table_follows_the_enum_order_and_names_are_unique() {
        for (index, info) in ACTIONS.iter().enumerate() {
            assert_eq!(info.action as usize, index, "{}", info.name);
            assert_eq!(Action::from_name(info.name), Some(info.action));
            assert!(!info.contexts.is_empty(), "{}", info.name);
        }
    }

    #[test]
    fn chords_parse_as_written() {
        assert_eq!(
            chord("ctrl-c"),
            KeyChord::new(Key::Char('c'), Modifiers::CTRL).unwrap()
        );
        assert_eq!(chord("F12"), KeyChord::plain(Key::F(12)).unwrap());
        assert_eq!(chord("shift-tab").to_string(), "shift-tab");
        assert_eq!(chord("backtab"), chord("shift-tab"));
        assert_eq!(chord("shift-tab").key(), Key::Tab);
        assert_eq!(chord("alt-1").modifiers(), Modifiers::ALT);
        assert_eq!(chord("esc").key(), Key::Esc);
        assert_eq!(chord("Escape").key(), Key::Esc);
        assert_eq!(chord("space").key(), Key::Char(' '));
        assert_eq!(chord("pageup").key(), Key::PageUp);
        assert_eq!(chord("PgDn").key(), Key::PageDown);
        assert_eq!(chord("-").key(), Key::Char('-'));
        assert_eq!(
            chord("ctrl--"),
            KeyChord::new(Key::Char('-'), Modifiers::CTRL).unwrap()
        );
        assert_eq!(chord("f").key(), Key::Char('f'));
    }

    #[test]
    fn chords_take_one_form() {
        assert_eq!(chord("shift-a"), chord("A"));
        assert_eq!(chord("ctrl-C"), chord("ctrl-c"));
        assert_eq!(chord("Control-Alt-x"), chord("ctrl-alt-x"));
        assert_eq!(chord("ctrl-alt-x").to_string(), "ctrl-alt-x");
        assert_eq!(chord("alt-A").to_string(), "alt-A");
    }

    #[test]
    fn chords_a_terminal_cannot_send_are_refused() {
        assert_eq!("".parse::<KeyChord>(), Err(ChordError::Empty));
        assert_eq!(
            "ctrl-".parse::<KeyChord>(),
            Err(ChordError::UnknownKey("ctrl-".into()))
        );
        assert_eq!(
            "f25".parse::<KeyChord>(),
            Err(ChordError::FunctionKeyOutOfRange(25))
        );
        assert_eq!(
            "f0".parse::<KeyChord>(),
            Err(ChordError::FunctionKeyOutOfRange(0))
        );
        assert_eq!(
            "f99999999999".parse::<KeyChord>(),
            Err(ChordError::FunctionKeyOutOfRange(u32::MAX))
        );
        assert_eq!(
            "shift-1".parse::<KeyChord>(),
            Err(ChordError::ShiftedSymbol('1'))
        );
        assert_eq!(
            "ctrl-shift-a".parse::<KeyChord>(),
            Err(ChordError::CtrlShift('a'))
        );
        assert_eq!(
            "ctrl-i".parse::<KeyChord>(),
            Err(ChordError::SameAs('i', "tab"))
        );
        assert_eq!(
            "ctrl-M".parse::<KeyChord>(),
            Err(ChordError::SameAs('m', "enter"))
        );
        assert_eq!(
            "ctrl-[".parse::<KeyChord>(),
            Err(ChordError::SameAs('[', "esc"))
        );
        assert_eq!(
            "ctrl-ctrl-a".parse::<KeyChord>(),
            Err(ChordError::RepeatedModifier(
                "ctrl-ctrl-a".into(),
                "ctrl".into()
            ))
        );
        assert_eq!("\t".parse::<KeyChord>(), Err(ChordError::ControlCharacter));
        assert_eq!(
            "hyper-x".parse::<KeyChord>(),
            Err(ChordError::UnknownKey("hyper-x".into()))
        );
    }

    #[test]
    fn labels_read_like_key_caps() {
        assert_eq!(chord("f12").label(), "F12");
        assert_eq!(chord("ctrl-c").label(), "Ctrl-C");
        assert_eq!(chord("shift-tab").label(), "Shift-Tab");
        assert_eq!(chord("alt-1").label(), "Alt-1");
        assert_eq!(chord("pageup").label(), "PgUp");
        assert_eq!(chord("space").label(), "Space");
        assert_eq!(chord("q").label(), "q");
    }

    #[test]
    fn terminal_events_become_chords() {
        let event = |code, m| KeyChord::from_event(&KeyEvent::new(code, m));
        assert_eq!(
            event(KeyCode::BackTab, KeyModifiers::SHIFT),
            Some(chord("shift-tab"))
        );
        assert_eq!(
            event(KeyCode::Char('A'), KeyModifiers::SHIFT),
            Some(chord("A"))
        );
        assert_eq!(
            event(KeyCode::Char('A'), KeyModifiers::NONE),
            Some(chord("A"))
        );
        assert_eq!(
            event(KeyCode::Char('a'), KeyModifiers::SHIFT),
            Some(chord("A"))
        );
        assert_eq!(
            event(KeyCode::Char('!'), KeyModifiers::SHIFT),
            Some(chord("!"))
        );
        assert_eq!(
            event(
                KeyCode::Char('C'),
                KeyModifiers::CONTROL | KeyModifiers::SHIFT
            ),
            Some(chord("ctrl-c"))
        );
        assert_eq!(
            event(KeyCode::F(12), KeyModifiers::NONE),
            Some(chord("f12"))
        );
        assert_eq!(event(KeyCode::F(30), KeyModifiers::NONE), None);
        assert_eq!(event(KeyCode::CapsLock, KeyModifiers::NONE), None);
        assert_eq!(event(KeyCode::Char('x'), KeyModifiers::SUPER), None);
    }
}
