//! The sheet as one self-contained HTML page: inline CSS and inline SVG,
//! no scripts, no external assets. It prints on A4 in black on white, and
//! every result is said in words and marks (PASS ✓ / FAIL ✗), never by
//! colour alone. Every text that came from a module, a file or a user is
//! escaped.

use super::facts::{
    CheckOutcome, Ending, LineKind, LineOutcome, ModuleSheet, Sheet, Tuning, Verdict,
};
use super::svg::plot_svg;

/// `text` safe in HTML text and in a quoted attribute.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            // Control characters from a module's answer would garble the
            // page: shown as the replacement character.
            c if c.is_control() && c != '\n' && c != '\t' => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

const STYLE: &str = "\
@page { size: A4; margin: 15mm; }
body { font-family: sans-serif; font-size: 10pt; color: #000; background: #fff; margin: 0 auto; max-width: 180mm; }
h1 { font-size: 16pt; margin: 0 0 4mm; }
h2 { font-size: 13pt; border-bottom: 1px solid #000; margin-top: 6mm; }
h3 { font-size: 11pt; margin: 4mm 0 2mm; }
table { border-collapse: collapse; width: 100%; margin-bottom: 3mm; }
th, td { border: 1px solid #444; padding: 1mm 2mm; text-align: left; vertical-align: top; }
th { background: #eee; }
thead { display: table-header-group; }
tr { page-break-inside: avoid; break-inside: avoid; }
code, .mono { font-family: monospace; white-space: pre-wrap; word-break: break-all; }
.verdict { border: 2px solid #000; padding: 3mm; margin-bottom: 4mm; }
.verdict.fail { border-style: double; border-width: 4px; }
.headline { font-size: 13pt; font-weight: bold; margin: 0; }
.mark { font-weight: bold; white-space: nowrap; }
tr.fail td { font-weight: bold; }
tr.differs td { font-style: italic; }
.comment td { color: #333; font-style: italic; }
svg.plot { width: 100%; height: auto; page-break-inside: avoid; break-inside: avoid; }
section.module { page-break-before: auto; }
";

/// The page for `sheet`.
pub fn sheet_html(sheet: &Sheet) -> String {
    let verdict = sheet.verdict();
    let mut page = String::new();
    page += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
    page += &format!(
        "<title>Commissioning sheet: {}</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n",
        escape(&sheet.run_file)
    );
    page += "<h1>Commissioning sheet</h1>\n";
    page += &verdict_section(&verdict);
    page += "<section id=\"run\">\n<h2>Run</h2>\n<table>\n<tbody>\n";
    for (label, value) in [
        ("Run file", &sheet.run_file),
        ("Operator", &sheet.operator),
        ("axterm version", &sheet.axterm_version),
        ("Started (UTC)", &sheet.started_utc),
        ("Ended (UTC)", &sheet.ended_utc),
    ] {
        page += &row_th(label, &escape(value));
    }
    page += &row_th("Modules", &sheet.modules.len().to_string());
    page += "</tbody>\n</table>\n</section>\n";
    for (index, module) in sheet.modules.iter().enumerate() {
        page += &module_section(index + 1, module, sheet.modules.len() > 1);
    }
    page += "</body>\n</html>\n";
    page
}

fn row_th(label: &str, value_html: &str) -> String {
    format!("<tr><th scope=\"row\">{label}</th><td>{value_html}</td></tr>\n")
}

/// ✓ PASS or ✗ FAIL.
fn pass_mark(passed: bool) -> &'static str {
    if passed {
        "<span class=\"mark\">✓ PASS</span>"
    } else {
        "<span class=\"mark\">✗ FAIL</span>"
    }
}

fn verdict_section(verdict: &Verdict) -> String {
    let class = if verdict.passed { "pass" } else { "fail" };
    let mut html = format!(
        "<section id=\"verdict\" class=\"verdict {class}\">\n<p class=\"headline\">{} — {}</p>\n",
        pass_mark(verdict.passed),
        escape(&verdict.headline)
    );
    if !verdict.failures.is_empty() {
        html += "<ul class=\"failures\">\n";
        for failure in &verdict.failures {
            html += &format!("<li>✗ {}</li>\n", escape(failure));
        }
        html += "</ul>\n";
    }
    html += "</section>\n";
    html
}

/// Module `position` (1-based) of the sheet: its section's id is
/// `module-POSITION` (addresses repeat across links).
fn module_section(position: usize, module: &ModuleSheet, several: bool) -> String {
    let id = &module.identity;
    let mut html = format!(
        "<section class=\"module\" id=\"module-{position}\" data-address=\"{}\">\n\
         <h2>Module {} ({}, {})</h2>\n",
        id.address,
        id.address,
        escape(&id.family),
        escape(&id.link)
    );
    if several {
        html += &verdict_section(&module.verdict());
    }
    // Identity.
    html += "<section class=\"identity\">\n<h3>Identity</h3>\n<table>\n<tbody>\n";
    html += &row_th("Family", &escape(&id.family));
    html += &row_th("Link", &format!("<code>{}</code>", escape(&id.link)));
    html += &row_th("Address", &id.address.to_string());
    html += &row_th(
        "Firmware",
        &format!("<code>{}</code>", escape(&id.firmware)),
    );
    html += "</tbody>\n</table>\n</section>\n";
    html += &settings_section(module);
    html += &checks_section(module);
    html += &tuning_section(module.tuning.as_ref());
    html += "</section>\n";
    html
}

fn settings_section(module: &ModuleSheet) -> String {
    let settings = &module.settings;
    let mut html =
        String::from("<section class=\"settings\">\n<h3>Settings</h3>\n<table>\n<tbody>\n");
    html += &row_th(
        "Parameter file applied",
        &settings
            .parameter_file
            .as_deref()
            .map_or("none".to_string(), |f| {
                format!("<code>{}</code>", escape(f))
            }),
    );
    html += &row_th(
        "Stored to EEPROM",
        if settings.eeprom_stored {
            "yes"
        } else {
            "no (the settings are lost at power-off)"
        },
    );
    if let Some(read) = &settings.read {
        html += &row_th("Settings read", &escape(read));
    }
    html += "</tbody>\n</table>\n";
    if settings.rows.is_empty() {
        html += "<p>No setting with a factory default was read.</p>\n";
    } else {
        let differing = settings.rows.iter().filter(|r| r.differs()).count();
        html += &format!(
            "<p>{differing} of {} settings differ from the factory default (marked ≠).</p>\n",
            settings.rows.len()
        );
        html += "<table class=\"settings-table\">\n<thead><tr><th>Where</th><th>No.</th>\
                 <th>Setting</th><th>Value</th><th>Factory default</th><th>Unit</th><th></th></tr></thead>\n<tbody>\n";
        for row in &settings.rows {
            // As the family writes it (its unit in a column of its own:
            // TMCL's are such as `10 ms`).
            let shown = |raw: i64, text: &Option<String>| {
                escape(&text.clone().unwrap_or_else(|| raw.to_string()))
            };
            let value = match (row.value, &row.note) {
                (Some(v), _) => shown(v, &row.value_text),
                (None, Some(note)) => format!("({})", escape(note)),
                (None, None) => "(not read)".into(),
            };
            let default = row
                .factory_default
                .map_or("—".into(), |d| shown(d, &row.default_text));
            let (class, mark) = if row.differs() {
                (
                    " class=\"differs\"",
                    "<span class=\"mark\">≠ differs</span>",
                )
            } else {
                ("", "")
            };
            html += &format!(
                "<tr{class}><td>{}</td><td>{}</td><td>{}</td><td>{value}</td><td>{default}</td><td>{}</td><td>{mark}</td></tr>\n",
                escape(&row.scope),
                row.number,
                escape(&row.name),
                escape(&row.unit)
            );
        }
        html += "</tbody>\n</table>\n";
    }
    html += "</section>\n";
    html
}

fn checks_section(module: &ModuleSheet) -> String {
    let checks = &module.checks;
    let mut html = String::from("<section class=\"checks\">\n<h3>Checks</h3>\n");
    // The expectations first: they are what the supervisor reads.
    html += "<table class=\"expectations\">\n<thead><tr><th>Line</th><th>Check</th>\
             <th>Expected</th><th>Actual</th><th>Result</th></tr></thead>\n<tbody>\n";
    if checks.expectations.is_empty() {
        html += "<tr><td colspan=\"5\">The run file has no :expect or :wait-until.</td></tr>\n";
    }
    for e in &checks.expectations {
        let (class, mark) = match e.outcome {
            CheckOutcome::Pass => ("pass", "<span class=\"mark\">✓ PASS</span>"),
            CheckOutcome::Fail => ("fail", "<span class=\"mark\">✗ FAIL</span>"),
            CheckOutcome::NotRun => ("fail", "<span class=\"mark\">– NOT RUN</span>"),
        };
        html += &format!(
            "<tr class=\"{class}\"><td>{}</td><td><code>:{} {}</code></td><td><code>{}</code></td>\
             <td><code>{}</code></td><td>{mark}</td></tr>\n",
            e.number,
            escape(&e.directive),
            escape(&e.line),
            escape(&e.expected),
            escape(e.actual.as_deref().unwrap_or("—")),
        );
    }
    html += "</tbody>\n</table>\n";
    if let Some(wiring) = &checks.wiring {
        html += &format!(
            "<section class=\"wiring\">\n<h3>Wiring check {}</h3>\n<ul>\n",
            pass_mark(wiring.wired_right)
        );
        for finding in &wiring.findings {
            html += &format!("<li>{}</li>\n", escape(finding));
        }
        html += "</ul>\n</section>\n";
    }
    html += "<section class=\"run-end\">\n<h3>Run end</h3>\n";
    let ending = match checks.run_end.ending {
        Ending::Completed => "✓ completed",
        Ending::Failed => "✗ failed",
        Ending::Cancelled => "✗ cancelled",
    };
    html += &format!(
        "<p><span class=\"mark\">{ending}</span>{}</p>\n",
        if checks.run_end.summary.is_empty() {
            String::new()
        } else {
            format!(": {}", escape(&checks.run_end.summary))
        }
    );
    if !checks.run_end.stopped_axes.is_empty() {
        html += &format!(
            "<p>Axes stopped at the end: {}</p>\n",
            escape(&checks.run_end.stopped_axes.join(", "))
        );
    }
    match &checks.emergency_stop {
        None => html += "<p class=\"emergency-stop\">No emergency stop was sent.</p>\n",
        Some(stop) => {
            html += &format!(
                "<div class=\"emergency-stop\">\n<p><span class=\"mark\">⚠ EMERGENCY STOP</span>: {}</p>\n<ul>\n",
                escape(&stop.reason)
            );
            for line in &stop.lines {
                html += &format!("<li><code>{}</code></li>\n", escape(line));
            }
            html += "</ul>\n</div>\n";
        }
    }
    html += "</section>\n";
    // Every line of the run, last: the record behind the checks.
    html += "<table class=\"lines\">\n<thead><tr><th>Line</th><th>Text</th><th>Answer</th>\
             <th>Result</th></tr></thead>\n<tbody>\n";
    for line in &checks.lines {
        let (class, mark) = match line.outcome {
            LineOutcome::Ok => ("ok", "✓ ok"),
            LineOutcome::Failed => ("fail", "✗ FAILED"),
            LineOutcome::NotRun => ("not-run", "– not run"),
            LineOutcome::Nothing => ("comment", ""),
        };
        let class = if line.kind == LineKind::Comment {
            "comment"
        } else {
            class
        };
        html += &format!(
            "<tr class=\"{class}\"><td>{}</td><td><code>{}</code></td><td><code>{}</code></td>\
             <td><span class=\"mark\">{mark}</span></td></tr>\n",
            line.number,
            escape(&line.text),
            escape(line.answer.as_deref().unwrap_or("")),
        );
    }
    html += "</tbody>\n</table>\n</section>\n";
    html
}

fn tuning_section(tuning: Option<&Tuning>) -> String {
    let mut html = String::from("<section class=\"tuning\">\n<h3>Tuning</h3>\n");
    match tuning {
        None => html += "<p>No tuning was done in this run.</p>\n",
        Some(tuning) => {
            if tuning.plots.is_empty() && tuning.figures.is_empty() {
                html += "<p>No tuning results.</p>\n";
            }
            if !tuning.figures.is_empty() {
                html += "<ul class=\"figures\">\n";
                for figure in &tuning.figures {
                    html += &format!("<li>{}</li>\n", escape(figure));
                }
                html += "</ul>\n";
            }
            for plot in &tuning.plots {
                html += "<figure>\n";
                html += &plot_svg(plot);
                html += &format!(
                    "<figcaption>{}</figcaption>\n</figure>\n",
                    escape(&plot.title)
                );
            }
        }
    }
    html += "</section>\n";
    html
}
