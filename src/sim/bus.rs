//! Several simulated modules on one multi-drop line (`axterm sim KIND
//! --address 1-4`, `--sim KIND --address 1-4`): a [`SimulatedController`]
//! that holds the modules and merges what they say.
//!
//! Every module hears every byte the host writes, each with its own state
//! and clock; a module answers only the frames addressed to it, as each
//! simulator already does alone (TMCL GP66/GP87, CMD-4CR `@NN`, SIXpack 2
//! the rotary address), so a frame for an absent address gets no answer.
//! None of the three manuals names a broadcast address (TMCL digest §1.2,
//! CMD-4CR §2.1.1.1 and §3.3, SIXpack 2 §6.2), so no frame makes two
//! modules answer at once: the bus stays strict master/slave.
//!
//! The modules hear the host only, not each other's replies: the line is
//! the host's transmit pair to every module and their shared answer pair
//! back (a four-wire RS-485 bus, or the two-wire bus of a module that
//! ignores what is not a frame for it).
//!
//! A module may carry faults of its own (`--fault 3:drop=1`): they act on
//! its answers only (dropped, corrupted, garbage before them, held back),
//! `disconnect-after=N` takes it off the bus after it has answered N
//! requests (its drop cable cut: it hears and says nothing more, the
//! others go on), and `corrupt-store` is armed in it alone. The faults of
//! the whole line (`--fault SPEC`) stay the line's ([`crate::link::sim_line`]).

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::time::Duration;

use super::faults::{FaultInjector, FaultPlan, Passage};
use super::{SimKind, SimOptions, SimulatedController};

/// One module on the bus.
struct BusModule {
    address: u8,
    controller: Box<dyn SimulatedController>,
    faults: Option<ModuleFaults>,
}

/// The faults of one module, applied to what it says.
struct ModuleFaults {
    plan: FaultPlan,
    injector: FaultInjector,
    /// Answers held back by a delay fault, with their release time on the
    /// bus's clock, in order: a late answer holds up the module's next.
    held: VecDeque<(Duration, Vec<u8>)>,
    /// `disconnect-after` took the module off the bus.
    cut: bool,
}

/// Modules sharing one line.
pub struct SimBus {
    modules: Vec<BusModule>,
    /// Virtual time since the bus was made.
    clock: Duration,
    output: Vec<u8>,
}

impl SimBus {
    /// A bus of `modules`, each at its address; an error when two share
    /// an address or there are none.
    pub fn new(modules: Vec<(u8, Box<dyn SimulatedController>)>) -> Result<SimBus, String> {
        if modules.is_empty() {
            return Err("a bus needs at least one module".into());
        }
        for (i, (address, _)) in modules.iter().enumerate() {
            if modules[..i].iter().any(|(a, _)| a == address) {
                return Err(format!("two modules at address {address} on one bus"));
            }
        }
        Ok(SimBus {
            modules: modules
                .into_iter()
                .map(|(address, controller)| BusModule {
                    address,
                    controller,
                    faults: None,
                })
                .collect(),
            clock: Duration::ZERO,
            output: Vec::new(),
        })
    }

    /// A bus of `kind` simulators, one at each of `addresses`. With
    /// `memory_file`, each module keeps its EEPROM/flash in a file of its
    /// own named after it ([`module_file`]).
    pub fn of_kind(
        kind: &SimKind,
        addresses: &[u8],
        memory_file: Option<&Path>,
    ) -> Result<SimBus, String> {
        let modules = addresses
            .iter()
            .map(|&address| {
                let options = SimOptions {
                    address: Some(address),
                    eeprom_file: memory_file.map(|file| module_file(file, address)),
                };
                (address, (kind.build)(&options))
            })
            .collect();
        SimBus::new(modules)
    }

    /// The module addresses, in the order the modules were given.
    pub fn addresses(&self) -> Vec<u8> {
        self.modules.iter().map(|m| m.address).collect()
    }

    /// Give the module at `address` faults of its own (replacing any it
    /// had); an error naming the modules there are when none is there.
    pub fn fault_module(&mut self, address: u8, plan: &FaultPlan) -> Result<(), String> {
        let addresses = self.describe_addresses();
        let module = self
            .modules
            .iter_mut()
            .find(|m| m.address == address)
            .ok_or_else(|| format!("no module at address {address} on this bus ({addresses})"))?;
        module.faults = Some(ModuleFaults {
            plan: plan.clone(),
            injector: FaultInjector::new(plan),
            held: VecDeque::new(),
            cut: false,
        });
        Ok(())
    }

    fn describe_addresses(&self) -> String {
        let list = self
            .modules
            .iter()
            .map(|m| m.address.to_string())
            .collect::<Vec<_>>()
            .join(", ");
        if self.modules.len() == 1 {
            format!("the module is at address {list}")
        } else {
            format!("modules at addresses {list}")
        }
    }

    /// What every module has said, through its faults, onto the line.
    fn collect(&mut self) {
        let now = self.clock;
        for module in &mut self.modules {
            let said = module.controller.take_output();
            let Some(faults) = &mut module.faults else {
                self.output.extend_from_slice(&said);
                continue;
            };
            if faults.cut {
                continue;
            }
            let Some(delivery) = faults.injector.to_host(said) else {
                continue;
            };
            if delivery.delay.is_zero() && faults.held.is_empty() {
                self.output.extend_from_slice(&delivery.bytes);
            } else {
                let after_last = faults.held.back().map_or(Duration::ZERO, |(t, _)| *t);
                faults
                    .held
                    .push_back(((now + delivery.delay).max(after_last), delivery.bytes));
            }
        }
        for module in &mut self.modules {
            let Some(faults) = &mut module.faults else {
                continue;
            };
            while let Some((_, bytes)) = faults.held.pop_front_if(|(at, _)| *at <= now) {
                self.output.extend_from_slice(&bytes);
            }
        }
    }

    /// The next time a held answer is due, if before `until`.
    fn next_release(&self, until: Duration) -> Option<Duration> {
        self.modules
            .iter()
            .filter_map(|m| m.faults.as_ref()?.held.front().map(|(at, _)| *at))
            .filter(|at| *at <= until)
            .min()
    }

    fn advance_modules_to(&mut self, at: Duration) {
        let dt = at.saturating_sub(self.clock);
        if dt.is_zero() {
            return;
        }
        for module in &mut self.modules {
            module.controller.advance(dt);
        }
        self.clock = at;
    }

    /// The module `N:` at the front of `text` names (`3:IO5=1`), and the
    /// rest; `None` for text meant for every module.
    fn addressed<'a>(&self, text: &'a str) -> Result<Option<(usize, &'a str)>, String> {
        let Some((address, rest)) = split_module_prefix(text)? else {
            return Ok(None);
        };
        match self.modules.iter().position(|m| m.address == address) {
            Some(index) => Ok(Some((index, rest))),
            None => Err(format!(
                "no module at address {address} on this bus ({})",
                self.describe_addresses()
            )),
        }
    }
}

/// `3:drop=1` → (3, `drop=1`): text for one module, marked by its address
/// and a colon before anything else. Text whose first colon follows
/// something else (`delay=0.1:50`) is for the whole line; digits that are
/// no address (`300:`) are an error.
pub fn split_module_prefix(text: &str) -> Result<Option<(u8, &str)>, String> {
    let Some((head, rest)) = text.split_once(':') else {
        return Ok(None);
    };
    let head = head.trim();
    if head.is_empty() || !head.bytes().all(|b| b.is_ascii_digit()) {
        return Ok(None);
    }
    match head.parse() {
        Ok(address) => Ok(Some((address, rest.trim()))),
        Err(_) => Err(format!("`{head}` is not a module address 0..255")),
    }
}

/// The memory file of the module at `address` when the bus is given
/// `file`: the module's address before the extension (`line.json` →
/// `line-3.json`), so that each module keeps its own and the files of one
/// bus sort together.
pub fn module_file(file: &Path, address: u8) -> PathBuf {
    let stem = file.file_stem().map_or_else(
        || std::ffi::OsString::from("eeprom"),
        std::ffi::OsStr::to_os_string,
    );
    let mut name = stem;
    name.push(format!("-{address}"));
    if let Some(extension) = file.extension() {
        name.push(".");
        name.push(extension);
    }
    file.with_file_name(name)
}

/// The faults `--fault` gives (repeatable): at most one spec for the
/// whole line, and at most one per module (`ADDRESS:SPEC`).
#[derive(Debug, Clone, Default)]
pub struct BusFaults {
    pub line: FaultPlan,
    pub modules: Vec<ModuleFault>,
}

/// `--fault ADDRESS:SPEC`: the faults of one module.
#[derive(Debug, Clone)]
pub struct ModuleFault {
    pub address: u8,
    pub plan: FaultPlan,
    /// The value as given, for messages.
    pub given: String,
}

impl BusFaults {
    /// Parse every `--fault` value; the error names the value that is wrong.
    pub fn parse(specs: &[String]) -> Result<BusFaults, String> {
        let mut faults = BusFaults::default();
        let mut line_given = false;
        for spec in specs {
            let wrong = |e: String| format!("--fault {spec}: {e}");
            match split_module_prefix(spec).map_err(wrong)? {
                Some((address, rest)) => {
                    if faults.modules.iter().any(|m| m.address == address) {
                        return Err(wrong(format!(
                            "module {address} is given faults twice; join them in one spec, \
                             e.g. {address}:drop=0.1,corrupt=0.1"
                        )));
                    }
                    let plan = FaultPlan::parse(rest).map_err(|e| wrong(e.to_string()))?;
                    faults.modules.push(ModuleFault {
                        address,
                        plan,
                        given: spec.trim().to_string(),
                    });
                }
                None => {
                    if line_given {
                        return Err(wrong(
                            "the whole line is given faults twice; join them in one spec, \
                             e.g. drop=0.1,corrupt=0.1"
                                .into(),
                        ));
                    }
                    faults.line = FaultPlan::parse(spec).map_err(|e| wrong(e.to_string()))?;
                    line_given = true;
                }
            }
        }
        Ok(faults)
    }

    /// True when no module has faults of its own.
    pub fn no_module_faults(&self) -> bool {
        self.modules.is_empty()
    }

    /// Put each module's faults on `bus`: an error for an address that is
    /// not on it.
    pub fn apply(&self, bus: &mut SimBus) -> Result<(), String> {
        for module in &self.modules {
            bus.fault_module(module.address, &module.plan)
                .map_err(|e| format!("--fault {}: {e}", module.given))?;
        }
        Ok(())
    }
}

impl SimulatedController for SimBus {
    /// Byte by byte, every module hearing each, so that the answers to
    /// frames written back to back leave in the order of the frames.
    fn feed(&mut self, bytes: &[u8]) {
        for byte in bytes.chunks(1) {
            for module in &mut self.modules {
                if let Some(faults) = &mut module.faults {
                    if faults.cut {
                        continue;
                    }
                    if faults.injector.to_controller(byte) == Passage::Cut {
                        faults.cut = true;
                        faults.held.clear();
                        continue;
                    }
                }
                module.controller.feed(byte);
            }
            self.collect();
        }
    }

    fn advance(&mut self, dt: Duration) {
        let until = self.clock + dt;
        while let Some(at) = self.next_release(until) {
            self.advance_modules_to(at);
            self.collect();
        }
        self.advance_modules_to(until);
        self.collect();
    }

    fn take_output(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.output)
    }

    fn help(&self) -> String {
        let first = self
            .modules
            .first()
            .map(|m| m.controller.help())
            .unwrap_or_default();
        format!(
            "A bus of {} ({}), each module its own simulator: {first}",
            self.modules.len(),
            self.describe_addresses()
        )
    }

    /// The line's plan goes to every module; a module with a
    /// `corrupt-store` of its own takes its own plan instead.
    fn arm_faults(&mut self, plan: &FaultPlan) {
        for module in &mut self.modules {
            match &module.faults {
                Some(own) if own.plan.corrupt_store.is_some() => {
                    module.controller.arm_faults(&own.plan)
                }
                _ => module.controller.arm_faults(plan),
            }
        }
    }

    /// `3:IO5=1` drives module 3's input; `IO5=1` every module's.
    fn drive_input(&mut self, setting: &str) -> Result<String, String> {
        if let Some((index, rest)) = self.addressed(setting)? {
            let module = &mut self.modules[index];
            return module
                .controller
                .drive_input(rest)
                .map(|said| format!("module {}: {said}", module.address));
        }
        let mut said = Vec::new();
        for module in &mut self.modules {
            let line = module
                .controller
                .drive_input(setting)
                .map_err(|e| format!("module {}: {e}", module.address))?;
            said.push(format!("module {}: {line}", module.address));
        }
        Ok(said.join("; "))
    }

    /// The same program into every module.
    fn load_program(&mut self, source: &str) -> Result<(), Vec<String>> {
        for module in &mut self.modules {
            let address = module.address;
            module.controller.load_program(source).map_err(|problems| {
                problems
                    .into_iter()
                    .map(|p| format!("module {address}: {p}"))
                    .collect::<Vec<_>>()
            })?;
        }
        Ok(())
    }

    fn line_break(&mut self) {
        for module in &mut self.modules {
            module.controller.line_break();
        }
    }

    fn refused_memory_file(&self) -> Option<String> {
        self.modules.iter().find_map(|m| {
            m.controller
                .refused_memory_file()
                .map(|why| format!("module {}: {why}", m.address))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::find_kind;

    const MS: Duration = Duration::from_millis(1);

    /// A TMCL request frame written out by hand: address, command, type,
    /// motor, value (big-endian), checksum over the first eight (§3.1).
    fn tmcl(address: u8, command: u8, kind: u8, value: i32) -> [u8; 9] {
        let v = value.to_be_bytes();
        let mut frame = [address, command, kind, 0, v[0], v[1], v[2], v[3], 0];
        frame[8] = frame[..8].iter().fold(0u8, |sum, b| sum.wrapping_add(*b));
        frame
    }

    fn tmcl_bus(addresses: &[u8]) -> SimBus {
        SimBus::of_kind(find_kind("tmcm1110").expect("kind"), addresses, None).expect("bus")
    }

    /// The reply's module address (byte 1) and value (bytes 4..8).
    fn module_and_value(reply: &[u8]) -> (u8, i32) {
        assert_eq!(reply.len(), 9, "{reply:02X?}");
        (
            reply[1],
            i32::from_be_bytes([reply[4], reply[5], reply[6], reply[7]]),
        )
    }

    #[test]
    fn only_the_addressed_module_answers_and_each_keeps_its_own_state() {
        let mut bus = tmcl_bus(&[1, 2, 3, 4]);
        // SAP 4 (maximum speed) on module 2 only.
        bus.feed(&tmcl(2, 5, 4, 1234));
        let reply = bus.take_output();
        assert_eq!(
            (module_and_value(&reply).0, reply[2]),
            (2, 100),
            "status 100"
        );
        bus.feed(&tmcl(2, 6, 4, 0));
        assert_eq!(module_and_value(&bus.take_output()), (2, 1234));
        bus.feed(&tmcl(3, 6, 4, 0));
        let (module, value) = module_and_value(&bus.take_output());
        assert_eq!(module, 3);
        assert_ne!(value, 1234, "module 3 keeps its own maximum speed");
    }

    #[test]
    fn a_frame_for_an_absent_address_gets_no_answer() {
        let mut bus = tmcl_bus(&[1, 2, 3, 4]);
        for address in [0, 5, 255] {
            bus.feed(&tmcl(address, 6, 1, 0));
            bus.advance(100 * MS);
            assert_eq!(bus.take_output(), b"", "address {address}");
        }
        // And the modules are still in step with the frames after it.
        bus.feed(&tmcl(4, 6, 1, 0));
        assert_eq!(module_and_value(&bus.take_output()).0, 4);
    }

    #[test]
    fn every_module_keeps_time() {
        // CMD-4CR: a move on module 2 runs on while module 1 is asked.
        let kind = find_kind("cmd4cr").expect("kind");
        let mut bus = SimBus::of_kind(kind, &[1, 2], None).expect("bus");
        bus.feed(b"@02EO=1\r@02ABS\r@02HSPD=1000\r@02X1000\r");
        assert_eq!(bus.take_output(), b"OK\rOK\rOK\rOK\r");
        bus.advance(2000 * MS);
        bus.feed(b"@02PX\r@01PX\r");
        assert_eq!(bus.take_output(), b"1000\r0\r");
    }

    #[test]
    fn two_modules_at_one_address_are_refused() {
        let kind = find_kind("cmd4cr").expect("kind");
        let error = SimBus::of_kind(kind, &[3, 3], None).err().expect("refused");
        assert_eq!(error, "two modules at address 3 on one bus");
        assert!(SimBus::new(Vec::new()).is_err());
    }

    #[test]
    fn a_dropping_module_is_silent_while_the_others_answer() {
        let mut bus = tmcl_bus(&[1, 2, 3, 4]);
        let faults = BusFaults::parse(&["3:drop=1".into()]).expect("parses");
        faults.apply(&mut bus).expect("module 3 is there");
        for address in [1, 2, 3, 4, 3] {
            bus.feed(&tmcl(address, 136, 1, 0));
        }
        let said = bus.take_output();
        let modules: Vec<u8> = said.chunks(9).map(|r| r[1]).collect();
        assert_eq!(modules, [1, 2, 4]);
        assert_eq!(faults.modules[0].plan.counts().dropped, 2);
    }

    #[test]
    fn a_late_module_answers_when_its_delay_is_over() {
        let mut bus = tmcl_bus(&[1, 2]);
        bus.fault_module(2, &FaultPlan::parse("delay=1:30").expect("parses"))
            .expect("module 2");
        bus.feed(&tmcl(2, 6, 1, 0));
        assert_eq!(bus.take_output(), b"");
        bus.advance(29 * MS);
        assert_eq!(bus.take_output(), b"");
        // Module 1 is not held up by module 2's late answer.
        bus.feed(&tmcl(1, 6, 1, 0));
        assert_eq!(module_and_value(&bus.take_output()).0, 1);
        bus.advance(MS);
        assert_eq!(module_and_value(&bus.take_output()).0, 2);
    }

    #[test]
    fn a_module_cut_off_leaves_the_others_on_the_line() {
        let mut bus = tmcl_bus(&[1, 2]);
        bus.fault_module(1, &FaultPlan::parse("disconnect-after=2").expect("parses"))
            .expect("module 1");
        let mut answers = Vec::new();
        for address in [1, 2, 1, 2, 1, 2, 1] {
            bus.feed(&tmcl(address, 6, 1, 0));
            let said = bus.take_output();
            answers.push(if said.is_empty() { 0 } else { said[1] });
        }
        assert_eq!(answers, [1, 2, 1, 2, 0, 2, 0]);
    }

    #[test]
    fn a_fault_for_a_module_not_on_the_bus_is_refused() {
        let mut bus = tmcl_bus(&[1, 2, 3, 4]);
        let faults = BusFaults::parse(&["7:drop=1".into()]).expect("parses");
        assert_eq!(
            faults.apply(&mut bus).unwrap_err(),
            "--fault 7:drop=1: no module at address 7 on this bus \
             (modules at addresses 1, 2, 3, 4)"
        );
    }

    #[test]
    fn fault_specs_for_the_line_and_for_modules() {
        let faults = BusFaults::parse(&[
            "delay=0.5:20".into(),
            "3:drop=1".into(),
            " 4 : corrupt=1,seed=3".into(),
        ])
        .expect("parses");
        assert_eq!((faults.line.delay, faults.line.delay_ms), (0.5, 20));
        assert_eq!(faults.modules.len(), 2);
        assert_eq!(faults.modules[0].address, 3);
        assert_eq!(faults.modules[0].plan.drop, 1.0);
        let fourth = &faults.modules[1];
        assert_eq!((fourth.address, fourth.plan.seed), (4, 3));
        let cases = [
            (vec!["3:drop=2"], "--fault 3:drop=2: bad fault 'drop=2'"),
            (
                vec!["drop=1", "corrupt=1"],
                "the whole line is given faults twice",
            ),
            (
                vec!["3:drop=1", "3:corrupt=1"],
                "module 3 is given faults twice",
            ),
            (
                vec!["300:drop=1"],
                "--fault 300:drop=1: `300` is not a module address 0..255",
            ),
        ];
        for (specs, needle) in cases {
            let specs: Vec<String> = specs.into_iter().map(String::from).collect();
            let error = BusFaults::parse(&specs).expect_err(needle);
            assert!(error.contains(needle), "{error}");
        }
    }

    #[test]
    fn inputs_go_to_one_module_or_to_every_one() {
        let kind = find_kind("cmd4cr").expect("kind");
        let mut bus = SimBus::of_kind(kind, &[1, 2], None).expect("bus");
        let said = bus.drive_input("2:DI1=1").expect("module 2");
        assert!(said.starts_with("module 2: "), "{said}");
        bus.feed(b"@01DI\r@02DI\r");
        assert_eq!(bus.take_output(), b"0\r1\r");
        let said = bus.drive_input("DI2=1").expect("every module");
        assert!(
            said.contains("module 1: ") && said.contains("module 2: "),
            "{said}"
        );
        bus.feed(b"@01DI\r@02DI\r");
        assert_eq!(bus.take_output(), b"2\r3\r");
        let error = bus.drive_input("5:DI1=1").expect_err("no module 5");
        assert!(error.contains("no module at address 5"), "{error}");
    }

    #[test]
    fn module_files_carry_the_address() {
        assert_eq!(
            module_file(Path::new("dir/line.json"), 3),
            Path::new("dir/line-3.json")
        );
        assert_eq!(module_file(Path::new("flash"), 12), Path::new("flash-12"));
    }

    #[test]
    fn each_module_keeps_its_own_memory_file() {
        let dir = tempfile::tempdir().expect("temp dir");
        let file = dir.path().join("flash.json");
        let kind = find_kind("cmd4cr").expect("kind");
        let mut bus = SimBus::of_kind(kind, &[1, 2], Some(&file)).expect("bus");
        bus.feed(b"@01POLX\r");
        let factory = bus.take_output();
        assert_ne!(factory, b"3\r");
        bus.feed(b"@02POLX=3\r@02STORE\r");
        assert_eq!(bus.take_output(), b"OK\rOK\r");
        drop(bus);
        let mut bus = SimBus::of_kind(kind, &[1, 2], Some(&file)).expect("bus");
        bus.feed(b"@02POLX\r");
        assert_eq!(bus.take_output(), b"3\r");
        bus.feed(b"@01POLX\r");
        assert_eq!(bus.take_output(), factory);
        assert!(dir.path().join("flash-2.json").exists());
        assert!(!file.exists(), "the name given is only the pattern");
    }

    proptest::proptest! {
        #[test]
        fn any_fault_value_parses_or_is_refused_by_name(spec in ".{0,30}") {
            match BusFaults::parse(std::slice::from_ref(&spec)) {
                Ok(faults) => proptest::prop_assert!(faults.modules.len() <= 1),
                Err(e) => {
                    let prefix = format!("--fault {spec}: ");
                    proptest::prop_assert!(e.starts_with(&prefix), "{}", e);
                }
            }
        }

        #[test]
        fn a_module_prefix_names_its_module(address in proptest::prelude::any::<u8>(), p in 0.0f64..=1.0) {
            let spec = format!("{address}:drop={p}");
            let faults = BusFaults::parse(&[spec]).expect("parses");
            proptest::prop_assert_eq!(faults.modules[0].address, address);
            proptest::prop_assert_eq!(faults.modules[0].plan.drop, p);
            proptest::prop_assert!(faults.line.is_none());
        }
    }

    #[test]
    fn module_prefixes() {
        assert_eq!(split_module_prefix("3:drop=1"), Ok(Some((3, "drop=1"))));
        assert_eq!(split_module_prefix("delay=0.1:50"), Ok(None));
        assert_eq!(split_module_prefix("drop=1"), Ok(None));
        assert_eq!(split_module_prefix(":drop=1"), Ok(None));
        assert!(split_module_prefix("999:drop=1").is_err());
    }
}
