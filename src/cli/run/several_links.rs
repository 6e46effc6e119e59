//! `axterm run` on several links at once (`--port A --port B`): the file
//! checked for every link's family and modules first, then run link by
//! link, module by module.

use super::*;

/// The file on every module of several links (`--port A --port B`): the
/// whole file checked for each link's family and modules first, the
/// family's cautions said once a family; then link by link, module by
/// module, each run ended as a single one is.
pub(super) fn run_on_links(connection: &ConnectionArgs, args: &RunArgs) -> i32 {
    let links = match FleetLink::resolve_all(connection, &args.fleet) {
        Ok(links) => links,
        Err(message) => {
            eprintln!("axterm run: {message}");
            return EXIT_USAGE;
        }
    };
    let sheet = match sheet_request(args) {
        Ok(sheet) => sheet,
        Err(code) => return code,
    };
    let (name, text) = match read_source(&args.file) {
        Ok(source) => source,
        Err(message) => {
            eprintln!("axterm run: {message}");
            return EXIT_USAGE;
        }
    };
    let mut ok = true;
    let mut cautioned: Vec<&'static Family> = Vec::new();
    let mut lines = 0;
    for link in &links {
        let family = link.target.family;
        let mut addresses = vec![link.target.address];
        if let Modules::List(listed) = &link.modules {
            addresses.extend(listed);
        }
        let on = link.name.as_ref().map_or(String::new(), |n| {
            format!("{} ({}): ", n.label, n.connection)
        });
        if !checks_at(&on, &name, &text, family, &addresses) {
            ok = false;
            continue;
        }
        if cautioned.iter().any(|f| std::ptr::eq(*f, family)) {
            continue;
        }
        cautioned.push(family);
        match check_script(&name, &text, family, link.target.address) {
            Ok(checked) => {
                lines = checked.iter().filter(|c| c.line.is_some()).count();
                ok &= said_cautions(&name, family, &checked, args.yes);
            }
            Err(_) => ok = false,
        }
    }
    if !ok {
        eprintln!("axterm run: {name}: nothing was sent");
        return EXIT_USAGE;
    }
    if args.dry_run {
        eprintln!(
            "axterm run: {name}: {lines} console lines valid on {} links, nothing sent (dry run)",
            links.len()
        );
        return EXIT_OK;
    }
    let fleet_run = FleetRun {
        name,
        text,
        format: args.format,
        keep_going: args.keep_going,
        policy: StopOnFailure::from_flag(args.no_stop_on_failure),
        stop_on_failure: args.fleet.stop_on_failure,
        sheet: sheet.map(|request| (request, Mutex::new(Vec::new()))),
        link: crate::cli::links::describe_links(connection),
    };
    run_to_exit("run", async move { fleet_run.run(&links).await })
}

/// Print the family's warnings about every line of the file, and each
/// line it wants confirmed when `--yes` was not given; false if there was
/// such a line.
pub(super) fn said_cautions(
    name: &str,
    family: &Family,
    checked: &[CheckedStep],
    yes: bool,
) -> bool {
    let mut ok = true;
    let mut known = SettingsCache::default();
    for item in checked {
        let Some(line) = &item.line else { continue };
        let said = cautions(family.console, line, &known, yes);
        after_line(family.console, line, &mut known);
        let at = format!("{name}:{}: `{}`: ", item.step.line_number, line.canonical);
        for warning in &said.warnings {
            eprintln!("{at}{warning}");
        }
        if let Some(refusal) = said.refusal {
            eprintln!("{at}{refusal}");
            ok = false;
        }
    }
    ok
}

/// The file on several modules of a bus, one after another.
pub(super) struct FleetRun {
    pub(super) name: String,
    pub(super) text: String,
    pub(super) format: Format,
    pub(super) keep_going: bool,
    pub(super) policy: StopOnFailure,
    pub(super) stop_on_failure: bool,
    /// The sheet asked for, and each module's section as it ends.
    pub(super) sheet: Option<(SheetRequest, Mutex<Vec<crate::report::ModuleSheet>>)>,
    /// The link as given, for a module of a single link.
    pub(super) link: String,
}

impl FleetRun {
    pub(super) async fn run(&self, links: &[FleetLink]) -> i32 {
        let mut interrupt = match Interrupt::watch() {
            Ok(interrupt) => interrupt,
            Err(e) => {
                eprintln!("axterm run: cannot watch for Ctrl-C: {e}");
                return EXIT_DEVICE;
            }
        };
        let mut walk = Walk::new(links, "run", self.stop_on_failure);
        loop {
            let module = match walk.next().await {
                Ok(Some(module)) => module,
                Ok(None) => break,
                Err(e) => {
                    eprintln!("axterm run: {e}");
                    return EXIT_CONNECTION;
                }
            };
            let (row, ending) = self.on_module(&module, &mut interrupt).await;
            if ending == RunEnding::Cancelled {
                walk.end_all("the run was cancelled (Ctrl-C)".into());
            }
            walk.record(&module, row);
        }
        let code = fleet::finish(&walk.rows(), &["lines", "failed"], self.format);
        match &self.sheet {
            Some((request, modules)) => {
                let modules =
                    std::mem::take(&mut *modules.lock().unwrap_or_else(|e| e.into_inner()));
                sheet_written(request, &self.name, modules, code)
            }
            None => code,
        }
    }

    /// A module the run never reached, on the sheet as a failed run that
    /// sent nothing, saying `why`.
    pub(super) fn unreached(&self, session: &Session, link: &str, identity: &Identity, why: &str) {
        if let Some((_, modules)) = &self.sheet {
            let section =
                ModuleRecord::unreached(&self.text, sheet_identity(session, link, identity), why);
            modules
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(section);
        }
    }

    /// The whole file on one module, ended as a single run is.
    pub(super) async fn on_module(
        &self,
        module: &FleetModule,
        interrupt: &mut Interrupt,
    ) -> (ModuleRow, RunEnding) {
        let session = &module.session;
        let address = session.address();
        let who = module.who();
        let identity = Identity::ask(session).await;
        let mut row = module.row(identity.shown());
        let link = module
            .link
            .as_ref()
            .map_or(self.link.clone(), |l| l.label.clone());
        if let Identity::Silent(why) = &identity {
            let on = module
                .link
                .as_ref()
                .map_or(String::new(), |l| format!("{}: ", l.label));
            eprintln!("axterm run: {on}{}: {why}", self.name);
            row.failed = 1;
            row.note = why.clone();
            self.unreached(session, &link, &identity, why);
            return (row, RunEnding::Failed);
        }
        let checked = match check_script(&self.name, &self.text, session.family(), address) {
            Ok(checked) => checked,
            Err(problems) => {
                for problem in &problems {
                    eprintln!("{who}: {problem}");
                }
                row.failed = problems.len();
                row.note = "the file does not check for this address: nothing sent".into();
                self.unreached(session, &link, &identity, &row.note);
                return (row, RunEnding::Failed);
            }
        };
        let params = match load_params(&self.name, &checked, session.family()) {
            Ok(params) => params,
            Err(problems) => {
                for problem in &problems {
                    eprintln!("{who}: {problem}");
                }
                row.failed = problems.len();
                row.note = "a parameter file does not check: nothing sent".into();
                self.unreached(session, &link, &identity, &row.note);
                return (row, RunEnding::Failed);
            }
        };
        let record = self
            .sheet
            .as_ref()
            .map(|_| ModuleRecord::new(&self.text, &checked));
        let runner = Runner {
            session,
            name: &self.name,
            format: self.format,
            module: Some(module),
            record: record.as_ref(),
            params: &params,
        };
        // Counted by the work, read after it ended (or was dropped).
        let (done, failed) = (AtomicUsize::new(0), AtomicUsize::new(0));
        let work = async {
            for item in &checked {
                let ok = runner.step(item).await;
                let count = if ok { &done } else { &failed };
                count.fetch_add(1, Ordering::Relaxed);
                if !ok && !self.keep_going {
                    return false;
                }
            }
            failed.load(Ordering::Relaxed) == 0
        };
        let prefix = format!("axterm run: {who}: {}: ", self.name);
        let report = RunReport {
            prefix: &prefix,
            format: self.format,
            at_the_end: AtTheEnd::of_script(&checked),
        };
        let (ending, aftermath) =
            run_then_end_with(session, interrupt, self.policy, &report, work).await;
        row.written = done.load(Ordering::Relaxed);
        row.failed = failed.load(Ordering::Relaxed);
        if let (Some((_, modules)), Some(record)) = (&self.sheet, record) {
            let section = record
                .finish(
                    session,
                    sheet_identity(session, &link, &identity),
                    ending,
                    aftermath.as_ref(),
                )
                .await;
            modules
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(section);
        }
        row.ok = ending == RunEnding::Completed;
        if ending == RunEnding::Cancelled {
            row.note = "cancelled (Ctrl-C)".into();
        }
        (row, ending)
    }
}
