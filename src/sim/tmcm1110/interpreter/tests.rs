//! The interpreter on virtual time: programs are `Command` values written
//! into program memory; the host side talks in frames.

use std::time::Duration;

use super::*;
use crate::protocol::tmcl::command::{CalcOp, ClearFlag, MoveMode, RfsAction, StatusQuery};
use crate::protocol::tmcl::{Command, Reply, Status};
use crate::sim::SimulatedController;
use crate::sim::tmcm1110::SimConfig;

use Command as C;

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

fn us(n: u64) -> Duration {
    Duration::from_micros(n)
}

fn word(command: Command) -> ProgramWord {
    let (opcode, kind, motor_bank, value) = command.fields();
    ProgramWord {
        opcode,
        kind,
        motor_bank,
        value,
    }
}

/// Write `program` into program memory from `start`.
fn load(sim: &mut Tmcm1110, start: usize, program: &[Command]) {
    for (offset, &command) in program.iter().enumerate() {
        sim.eeprom.image.program[start + offset] = word(command);
    }
}

fn sim_with(program: &[Command]) -> Tmcm1110 {
    let mut sim = Tmcm1110::new(SimConfig::default());
    load(&mut sim, 0, program);
    sim
}

/// A simulator without switches, for free-running motion.
fn quiet_sim_with(program: &[Command]) -> Tmcm1110 {
    let mut sim = sim_with(program);
    *sim.switch_layout_mut() = crate::sim::tmcm1110::motion::SwitchLayout::default();
    sim
}

fn host(sim: &mut Tmcm1110, command: Command) -> Reply {
    sim.feed(&command.to_request(1).to_bytes());
    let out = sim.take_output();
    let bytes: [u8; 9] = out
        .as_slice()
        .try_into()
        .unwrap_or_else(|_| panic!("one reply to {command:?}, got {out:02X?}"));
    Reply::from_bytes(&bytes).expect("reply checksum")
}

fn host_ok(sim: &mut Tmcm1110, command: Command) -> i32 {
    let reply = host(sim, command);
    assert_eq!(reply.status, Status::OK, "{command:?}");
    reply.value
}

fn run(sim: &mut Tmcm1110) {
    host_ok(sim, C::RunApplication { start: None });
}

fn step(sim: &mut Tmcm1110) {
    host_ok(sim, C::StepApplication);
}

fn status(sim: &mut Tmcm1110) -> i32 {
    host_ok(
        sim,
        C::Ggp {
            param: 128,
            bank: 0,
        },
    )
}

fn pc(sim: &mut Tmcm1110) -> i32 {
    host_ok(
        sim,
        C::Ggp {
            param: 130,
            bank: 0,
        },
    )
}

fn var(sim: &Tmcm1110, number: usize) -> i32 {
    sim.user_variables[number]
}

fn position(sim: &Tmcm1110) -> i32 {
    sim.axis.param(1)
}

/// Advance in 10 ms steps until the program stops; panics after `limit`.
fn run_until_stopped(sim: &mut Tmcm1110, limit: Duration) {
    let mut waited = Duration::ZERO;
    while sim.app.status != ApplicationStatus::Stopped {
        assert!(waited < limit, "program still running after {limit:?}");
        sim.advance(ms(10));
        waited += ms(10);
    }
}

// Short forms of the commands the programs below use.

fn set(var: u8, value: i32) -> Command {
    C::Calcv {
        op: CalcOp::Load,
        var,
        value,
    }
}

fn add(var: u8, value: i32) -> Command {
    C::Calcv {
        op: CalcOp::Add,
        var,
        value,
    }
}

fn times(var: u8, value: i32) -> Command {
    C::Calcv {
        op: CalcOp::Mul,
        var,
        value,
    }
}

fn load_a(value: i32) -> Command {
    C::Calc {
        op: CalcOp::Load,
        operand: value,
    }
}

fn a_to(var: u8) -> Command {
    C::Agp {
        param: var,
        bank: 2,
    }
}

fn ja(address: i32) -> Command {
    C::Ja { address }
}

fn wait(condition: WaitCondition, ticks: i32) -> Command {
    C::Wait {
        condition,
        motor: 0,
        ticks,
    }
}

fn gap(param: u8) -> Command {
    C::Gap { param, motor: 0 }
}

fn mvp(target: i32) -> Command {
    C::Mvp {
        mode: MoveMode::Abs,
        motor: 0,
        target,
    }
}

fn vect(interrupt: u8, address: i32) -> Command {
    C::Vect { interrupt, address }
}

fn ei(interrupt: u8) -> Command {
    C::Ei { interrupt }
}

fn interrupt_config(param: u8, value: i32) -> Command {
    C::Sgp {
        param,
        bank: 3,
        value,
    }
}

// ---- execution rate, single step ------------------------------------------

/// Commands execute at t = 0, 50 µs, …, 10 ms: 201 of them, every second
/// one counting, however `advance` slices the time.
#[test]
fn commands_run_at_the_instruction_rate_whatever_the_slicing() {
    let program = [add(0, 1), ja(0)];
    let mut whole = sim_with(&program);
    run(&mut whole);
    whole.advance(ms(10));
    assert_eq!(var(&whole, 0), 101);

    let mut sliced = sim_with(&program);
    run(&mut sliced);
    for _ in 0..1250 {
        sliced.advance(us(8));
    }
    assert_eq!(var(&sliced, 0), 101);

    let mut slow = Tmcm1110::new(SimConfig {
        instruction_time: ms(1),
        ..SimConfig::default()
    });
    load(&mut slow, 0, &program);
    run(&mut slow);
    slow.advance(ms(10));
    assert_eq!(var(&slow, 0), 6);
}

#[test]
fn an_endless_loop_does_not_hang_advance_and_the_host_is_answered() {
    let mut sim = sim_with(&[ja(0)]);
    run(&mut sim);
    sim.advance(Duration::from_secs(1));
    assert_eq!(status(&mut sim), 1);
    assert_eq!(pc(&mut sim), 0);
}

#[test]
fn single_step_advances_the_pc_one_command() {
    let mut sim = sim_with(&[
        C::Sap {
            param: 4,
            motor: 0,
            value: 500,
        },
        C::Sap {
            param: 5,
            motor: 0,
            value: 200,
        },
        ja(0),
    ]);
    step(&mut sim);
    assert_eq!(status(&mut sim), 2, "the step waits for the interpreter");
    sim.advance(ms(1));
    assert_eq!(status(&mut sim), 0);
    assert_eq!(pc(&mut sim), 1);
    assert_eq!(host_ok(&mut sim, gap(4)), 500);
    assert_eq!(host_ok(&mut sim, gap(5)), 100, "second command not run");
    sim.advance(ms(100));
    assert_eq!(pc(&mut sim), 1, "stopped after the step");
    step(&mut sim);
    sim.advance(ms(1));
    assert_eq!(pc(&mut sim), 2);
    assert_eq!(host_ok(&mut sim, gap(5)), 200);
    step(&mut sim);
    sim.advance(ms(1));
    assert_eq!(pc(&mut sim), 0, "JA stepped");
}

#[test]
fn a_stepped_wait_keeps_step_mode_until_it_ends() {
    let mut sim = sim_with(&[wait(WaitCondition::Ticks, 10), set(0, 1), C::Stop]);
    step(&mut sim);
    sim.advance(ms(50));
    assert_eq!(status(&mut sim), 2);
    let mode = host_ok(
        &mut sim,
        C::ApplicationStatus {
            query: StatusQuery::ProgramCounter,
        },
    );
    assert_eq!(mode, (2 << 24) | (1 << 16), "step mode, waiting, PC 0");
    sim.advance(ms(50));
    assert_eq!(status(&mut sim), 0);
    assert_eq!(pc(&mut sim), 1);
    assert_eq!(var(&sim, 0), 0, "the next command waits for a step");
}

#[test]
fn status_135_reports_the_program_registers() {
    let mut sim = sim_with(&[
        load_a(42),
        C::Calcx { op: CalcOp::Load },
        load_a(-7),
        wait(WaitCondition::Ticks, 100),
        C::Stop,
    ]);
    run(&mut sim);
    sim.advance(ms(10));
    let query = |query| C::ApplicationStatus { query };
    assert_eq!(host_ok(&mut sim, query(StatusQuery::Accumulator)), -7);
    assert_eq!(host_ok(&mut sim, query(StatusQuery::XRegister)), 42);
    assert_eq!(
        host_ok(&mut sim, query(StatusQuery::ProgramCounter)),
        (1 << 24) | (1 << 16) | 3,
        "running, waiting, at the WAIT"
    );
    let view = sim.view();
    assert_eq!((view.accumulator, view.x_register), (-7, 42));
    assert!(view.waiting);
}

// ---- subroutines, jumps --------------------------------------------------

/// A routine that calls itself: the ninth CSUB finds the stack full and
/// is ignored (§3.6.20), then eight RSUBs unwind to the caller.
#[test]
fn subroutines_nest_eight_deep() {
    let mut sim = sim_with(&[
        C::Csub { address: 2 },
        C::Stop,
        add(0, 1),
        C::Csub { address: 2 },
        add(1, 1),
        C::Rsub,
    ]);
    run(&mut sim);
    run_until_stopped(&mut sim, ms(100));
    assert_eq!((var(&sim, 0), var(&sim, 1)), (8, 8));
    assert_eq!(pc(&mut sim), 1);
    assert_eq!(sim.view().call_depth, 0);
}

#[test]
fn rsub_with_an_empty_stack_and_reti_outside_a_handler_are_ignored() {
    let mut sim = sim_with(&[C::Rsub, C::Reti, set(0, 1), C::Stop]);
    run(&mut sim);
    run_until_stopped(&mut sim, ms(10));
    assert_eq!(var(&sim, 0), 1);
    assert_eq!(pc(&mut sim), 3);
}

fn condition_cases() -> Vec<(Vec<Command>, Condition, bool)> {
    use Condition::*;
    let compare = |a: i32| vec![load_a(a), C::Comp { value: 5 }];
    let timeout = vec![wait(WaitCondition::LimSw, 1)];
    let mut cases = vec![
        (vec![load_a(0)], Ze, true),
        (vec![load_a(0)], Nz, false),
        (vec![load_a(3)], Ze, false),
        (vec![load_a(3)], Nz, true),
        (vec![], Eto, false),
        (timeout.clone(), Eto, true),
        (
            [
                timeout,
                vec![C::Cle {
                    flag: ClearFlag::Eto,
                }],
            ]
            .concat(),
            Eto,
            false,
        ),
        // Nothing on this module raises the external alarm or position
        // error flags.
        (vec![], Eal, false),
        (vec![], Epo, false),
        (vec![], Edv, false),
    ];
    for (a, holding) in [
        (5, [Eq, Ge, Le, Ze].as_slice()),
        (6, [Ne, Gt, Ge, Nz].as_slice()),
        (4, [Ne, Lt, Le, Nz].as_slice()),
    ] {
        for c in [Eq, Ne, Gt, Ge, Lt, Le, Ze, Nz] {
            cases.push((compare(a), c, holding.contains(&c)));
        }
    }
    cases
}

#[test]
fn jc_jumps_on_each_condition() {
    for (setup, condition, taken) in condition_cases() {
        let target = setup.len() as i32 + 3;
        let program = [
            setup.clone(),
            vec![
                C::Jc {
                    condition,
                    address: target,
                },
                set(0, 2),
                C::Stop,
                set(0, 1),
                C::Stop,
            ],
        ]
        .concat();
        let mut sim = sim_with(&program);
        run(&mut sim);
        run_until_stopped(&mut sim, ms(100));
        let expected = if taken { 1 } else { 2 };
        assert_eq!(var(&sim, 0), expected, "JC {condition:?} after {setup:?}");
    }
}

#[test]
fn call_calls_on_each_condition() {
    for (setup, condition, taken) in condition_cases() {
        let routine = setup.len() as i32 + 2;
        let program = [
            setup.clone(),
            vec![
                C::Call {
                    condition,
                    address: routine,
                },
                C::Stop,
                set(0, 1),
                C::Rsub,
            ],
        ]
        .concat();
        let mut sim = sim_with(&program);
        run(&mut sim);
        run_until_stopped(&mut sim, ms(100));
        assert_eq!(
            var(&sim, 0),
            i32::from(taken),
            "CALL {condition:?} after {setup:?}"
        );
        assert_eq!(pc(&mut sim), routine - 1, "back at the STOP");
    }
}

/// §3.6.44: one COMP serves three CALLs; RunLeft's `CALC MUL, -1` does
/// not make the following `CALL GT` call RunRight too.
#[test]
fn the_call_example_of_3_6_44_follows_the_analog_input() {
    use Condition::{Gt, Lt, Ze};
    let call = |condition, address| C::Call { condition, address };
    let program = [
        C::Gio { port: 0, bank: 1 },
        C::Calc {
            op: CalcOp::Sub,
            operand: 512,
        },
        C::Comp { value: 0 },
        call(Lt, 8),
        call(Ze, 11),
        call(Gt, 13),
        ja(0),
        C::Stop,
        // RunLeft
        C::Calc {
            op: CalcOp::Mul,
            operand: -1,
        },
        C::Rola { motor: 0 },
        C::Rsub,
        // MotorStop
        C::Mst { motor: 0 },
        C::Rsub,
        // RunRight
        C::Rora { motor: 0 },
        C::Rsub,
    ];
    for (analog, speed) in [(312, -200), (512, 0), (712, 200)] {
        let mut sim = quiet_sim_with(&program);
        sim.set_analog_input(analog);
        run(&mut sim);
        sim.advance(ms(100));
        assert_eq!(sim.axis.param(2), speed, "analog {analog}");
        assert_eq!(sim.axis.param(138), 2, "velocity mode");
    }
}

/// §3.6.43 with the misprinted byte corrected (variable 42) and shorter
/// pauses.
#[test]
fn djnz_counts_a_loop_down() {
    let mut sim = quiet_sim_with(&[
        C::Sgp {
            param: 42,
            bank: 2,
            value: 3,
        },
        C::Mvp {
            mode: MoveMode::Rel,
            motor: 0,
            target: 51200,
        },
        wait(WaitCondition::Pos, 0),
        wait(WaitCondition::Ticks, 10),
        C::Djnz {
            var: 42,
            address: 1,
        },
        C::Stop,
    ]);
    run(&mut sim);
    run_until_stopped(&mut sim, Duration::from_secs(20));
    assert_eq!(position(&sim), 3 * 51200);
    assert_eq!(var(&sim, 42), 0);
    assert_eq!(pc(&mut sim), 5);
}

/// §3.6.43's internal function: "if it is not zero" — a counter at 0
/// becomes −1 and jumps (the description's "greater than zero" would not).
#[test]
fn djnz_jumps_while_not_zero() {
    let mut sim = sim_with(&[
        C::Djnz { var: 0, address: 3 },
        set(1, 1),
        C::Stop,
        set(1, 2),
        C::Stop,
    ]);
    run(&mut sim);
    run_until_stopped(&mut sim, ms(10));
    assert_eq!((var(&sim, 0), var(&sim, 1)), (-1, 2));
}

/// §3.6.42: RST from a subroutine clears the stack each time, so the
/// routine can restart the program twenty times without overflowing it.
#[test]
fn rst_restarts_with_an_empty_stack() {
    let mut sim = sim_with(&[
        add(0, 1),
        C::Csub { address: 3 },
        C::Stop,
        C::Ggp { param: 0, bank: 2 },
        C::Comp { value: 20 },
        C::Jc {
            condition: Condition::Ge,
            address: 7,
        },
        C::Rst { address: 0 },
        C::Rsub,
    ]);
    run(&mut sim);
    run_until_stopped(&mut sim, ms(100));
    assert_eq!(var(&sim, 0), 20);
    assert_eq!(pc(&mut sim), 2);
}

// ---- WAIT ------------------------------------------------------------------

#[test]
fn wait_ticks_holds_ten_milliseconds_per_tick() {
    let mut sim = sim_with(&[wait(WaitCondition::Ticks, 50), set(0, 1), C::Stop]);
    run(&mut sim);
    sim.advance(ms(499));
    assert_eq!(var(&sim, 0), 0);
    assert!(sim.view().waiting);
    sim.advance(ms(1));
    assert_eq!(var(&sim, 0), 1);
    assert!(!sim.app.errors.timeout, "a TICKS wait is no timeout");
}

#[test]
fn wait_ticks_minus_one_takes_the_accumulator() {
    let mut sim = sim_with(&[
        load_a(20),
        wait(WaitCondition::Ticks, -1),
        set(0, 1),
        C::Stop,
    ]);
    run(&mut sim);
    // The WAIT starts with the second command, at 50 µs.
    sim.advance(ms(200));
    assert_eq!(var(&sim, 0), 0);
    sim.advance(us(50));
    assert_eq!(var(&sim, 0), 1);

    let mut negative = sim_with(&[
        load_a(-5),
        wait(WaitCondition::Ticks, -1),
        set(0, 1),
        C::Stop,
    ]);
    run(&mut negative);
    negative.advance(ms(1));
    assert_eq!(var(&negative, 0), 1, "a negative A waits nothing");
}

#[test]
fn wait_pos_holds_until_the_target_is_reached() {
    let mut sim = quiet_sim_with(&[
        mvp(5000),
        wait(WaitCondition::Pos, 0),
        gap(1),
        a_to(0),
        C::Stop,
    ]);
    run(&mut sim);
    sim.advance(ms(10));
    assert!(sim.view().waiting);
    run_until_stopped(&mut sim, Duration::from_secs(5));
    assert_eq!(var(&sim, 0), 5000);
    assert!(!sim.app.errors.timeout);
}

#[test]
fn wait_pos_times_out_and_sets_eto() {
    // The right limit switch at 200000 stops the motor short of its target.
    let mut sim = sim_with(&[
        mvp(300_000),
        wait(WaitCondition::Pos, 100),
        C::Jc {
            condition: Condition::Eto,
            address: 4,
        },
        C::Stop,
        set(0, 1),
        C::Stop,
    ]);
    run(&mut sim);
    sim.advance(ms(1000));
    assert!(sim.view().waiting, "1 s timeout from 50 µs");
    sim.advance(ms(1));
    assert!(sim.app.errors.timeout);
    assert_eq!(var(&sim, 0), 1);
}

#[test]
fn wait_refsw_holds_until_the_home_switch_is_reached() {
    // Home switch over −1000..1000; the carriage comes from 20000.
    let mut sim = sim_with(&[
        mvp(20_000),
        wait(WaitCondition::Pos, 0),
        mvp(-20_000),
        wait(WaitCondition::RefSw, 0),
        gap(1),
        a_to(0),
        C::Mst { motor: 0 },
        C::Stop,
    ]);
    run(&mut sim);
    run_until_stopped(&mut sim, Duration::from_secs(10));
    let at = var(&sim, 0);
    // Seen within a 1 ms poll plus one command at ≈ 30518 µsteps/s.
    assert!((960..=1000).contains(&at), "stopped waiting at {at}");
}

#[test]
fn wait_limsw_holds_until_a_limit_switch_is_hit() {
    let mut sim = sim_with(&[
        C::Ror {
            motor: 0,
            velocity: 1000,
        },
        wait(WaitCondition::LimSw, 0),
        gap(1),
        a_to(0),
        C::Stop,
    ]);
    run(&mut sim);
    sim.advance(Duration::from_secs(2));
    assert!(sim.view().waiting);
    run_until_stopped(&mut sim, Duration::from_secs(20));
    assert_eq!(var(&sim, 0), 200_000, "hard stop on the right switch");
}

#[test]
fn wait_rfs_holds_until_the_reference_search_ends() {
    let mut sim = sim_with(&[
        C::Rfs {
            action: RfsAction::Start,
            motor: 0,
        },
        C::Rfs {
            action: RfsAction::Status,
            motor: 0,
        },
        a_to(1),
        wait(WaitCondition::Rfs, 0),
        gap(1),
        a_to(0),
        set(2, 1),
        C::Stop,
    ]);
    sim.advance(ms(1));
    run(&mut sim);
    sim.advance(ms(100));
    assert!(sim.view().waiting);
    assert_ne!(var(&sim, 1), 0, "RFS STATUS loads A in a program");
    run_until_stopped(&mut sim, Duration::from_secs(60));
    assert_eq!((var(&sim, 0), var(&sim, 2)), (0, 1));
    assert!(!sim.axis.reference_search_active());
}

#[test]
fn wait_with_a_motor_other_than_0_does_nothing() {
    let mut sim = sim_with(&[
        C::Wait {
            condition: WaitCondition::Pos,
            motor: 1,
            ticks: 0,
        },
        set(0, 1),
        C::Stop,
    ]);
    run(&mut sim);
    sim.advance(ms(1));
    assert_eq!(var(&sim, 0), 1);
}

// ---- reading, registers, errors ---------------------------------------------

#[test]
fn reading_commands_load_the_accumulator() {
    let mut sim = sim_with(&[
        gap(4),
        a_to(0),
        C::Gio { port: 0, bank: 1 },
        a_to(1),
        C::Sco {
            coordinate: 1,
            motor: 0,
            position: 777,
        },
        C::Gco {
            coordinate: 1,
            motor: 0,
        },
        a_to(2),
        C::Cco {
            coordinate: 2,
            motor: 0,
        },
        a_to(3),
        load_a(9),
        C::Calcx { op: CalcOp::Load },
        C::Siv { value: -4 },
        load_a(0),
        C::Giv,
        a_to(4),
        C::Ggp { param: 9, bank: 2 },
        a_to(5),
        C::Stop,
    ]);
    sim.set_analog_input(1234);
    run(&mut sim);
    run_until_stopped(&mut sim, ms(10));
    assert_eq!(var(&sim, 0), 1000, "GAP 4");
    assert_eq!(var(&sim, 1), 1234, "GIO 0, 1");
    assert_eq!(var(&sim, 2), 777, "GCO");
    assert_eq!(var(&sim, 3), 777, "CCO leaves A alone");
    assert_eq!(var(&sim, 4), -4, "GIV");
    assert_eq!(var(&sim, 5), -4, "GGP");
}

#[test]
fn coordinates_and_indexed_variables_in_a_program() {
    let mut sim = quiet_sim_with(&[
        load_a(4000),
        C::Aco {
            coordinate: 5,
            motor: 0,
        },
        C::Mvp {
            mode: MoveMode::Coord,
            motor: 0,
            target: 5,
        },
        wait(WaitCondition::Pos, 0),
        load_a(30),
        C::Calcx { op: CalcOp::Load },
        gap(1),
        C::Aiv,
        C::Stop,
    ]);
    run(&mut sim);
    run_until_stopped(&mut sim, Duration::from_secs(5));
    assert_eq!(position(&sim), 4000, "MVP COORD to what ACO stored");
    assert_eq!(var(&sim, 30), 4000, "AIV stored A at var[X]");
}

#[test]
fn a_command_the_module_would_refuse_does_nothing_and_the_program_goes_on() {
    let mut sim = sim_with(&[
        C::Sap {
            param: 4,
            motor: 0,
            value: 5000,
        },
        C::Raw {
            command: op::JC,
            kind: 12,
            motor_bank: 0,
            value: 0,
        },
        set(0, 1),
        C::Stop,
    ]);
    run(&mut sim);
    run_until_stopped(&mut sim, ms(10));
    assert_eq!(var(&sim, 0), 1);
    assert_eq!(host_ok(&mut sim, gap(4)), 1000);
    assert_eq!(sim.view().program_fault, None);
}

#[test]
fn program_errors_stop_the_program_on_the_offending_command() {
    let mut empty = sim_with(&[set(0, 1)]);
    run(&mut empty);
    empty.advance(ms(1));
    assert_eq!(status(&mut empty), 0);
    assert_eq!(pc(&mut empty), 1);
    let fault = ProgramFault::UnknownCommand {
        address: 1,
        opcode: 0,
    };
    assert_eq!(empty.view().program_fault, Some(fault));
    assert_eq!(
        fault.to_string(),
        "program ran into empty memory at address 1"
    );

    let mut far = sim_with(&[set(0, 1), ja(5000)]);
    run(&mut far);
    far.advance(ms(1));
    assert_eq!(pc(&mut far), 1);
    assert_eq!(
        far.view().program_fault,
        Some(ProgramFault::TargetOutsideMemory {
            address: 1,
            target: 5000
        })
    );

    let mut end = sim_with(&[]);
    load(&mut end, 2047, &[set(0, 1)]);
    host_ok(&mut end, C::RunApplication { start: Some(2047) });
    end.advance(ms(1));
    assert_eq!(var(&end, 0), 1);
    assert_eq!(pc(&mut end), 2047);
    assert_eq!(end.view().program_fault, Some(ProgramFault::EndOfMemory));
    host_ok(&mut end, C::RunApplication { start: Some(0) });
    assert_eq!(end.view().program_fault, None, "a new run clears it");
}

// ---- control commands ------------------------------------------------------

#[test]
fn stop_and_continue_execute_an_interrupted_wait_afresh() {
    let mut sim = sim_with(&[wait(WaitCondition::Ticks, 10), set(0, 1), C::Stop]);
    run(&mut sim);
    sim.advance(ms(50));
    host_ok(&mut sim, C::StopApplication);
    assert!(!sim.view().waiting);
    sim.advance(ms(100));
    assert_eq!((var(&sim, 0), pc(&mut sim)), (0, 0));
    run(&mut sim);
    sim.advance(ms(99));
    assert_eq!(var(&sim, 0), 0, "the WAIT starts again");
    sim.advance(ms(1));
    assert_eq!(var(&sim, 0), 1);
}

#[test]
fn reset_clears_the_program_state_and_run_starts_at_0() {
    let mut sim = sim_with(&[
        load_a(3),
        C::Csub { address: 3 },
        C::Stop,
        wait(WaitCondition::Ticks, 100),
        C::Rsub,
    ]);
    run(&mut sim);
    sim.advance(ms(10));
    assert_eq!(sim.view().call_depth, 1);
    host_ok(&mut sim, C::ResetApplication);
    let view = sim.view();
    assert_eq!(view.application_status, ApplicationStatus::Reset);
    assert_eq!(
        (view.program_counter, view.accumulator, view.call_depth),
        (0, 0, 0)
    );
    assert!(!view.waiting);
    sim.advance(ms(10));
    assert_eq!(pc(&mut sim), 0, "reset stays stopped");
    run(&mut sim);
    sim.advance(ms(10));
    assert_eq!(sim.view().accumulator, 3);
    assert_eq!(pc(&mut sim), 3);
}

#[test]
fn run_from_an_address_drops_the_subroutine_stack() {
    let mut sim = sim_with(&[
        C::Csub { address: 2 },
        C::Stop,
        wait(WaitCondition::Ticks, 100),
        C::Rsub,
        C::Stop,
        set(0, 5),
        C::Rsub,
        C::Stop,
    ]);
    run(&mut sim);
    sim.advance(ms(10));
    host_ok(&mut sim, C::RunApplication { start: Some(5) });
    run_until_stopped(&mut sim, ms(10));
    // The RSUB at 6 finds no return address and goes on to the STOP at 7.
    assert_eq!((var(&sim, 0), pc(&mut sim)), (5, 7));
}

#[test]
fn autostart_runs_the_program_after_a_reset() {
    let mut sim = sim_with(&[add(0, 1), C::Stop]);
    host_ok(
        &mut sim,
        C::Sgp {
            param: 77,
            bank: 0,
            value: 1,
        },
    );
    sim.advance(ms(10));
    assert_eq!(status(&mut sim), 0, "GP77 acts at power-up only");
    host_ok(&mut sim, C::SoftwareReset);
    sim.advance(ms(10));
    assert_eq!(var(&sim, 0), 1);
    assert_eq!((status(&mut sim), pc(&mut sim)), (0, 1));
}

#[test]
fn autostart_at_power_up_from_the_eeprom_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let config = SimConfig {
        eeprom_file: Some(dir.path().join("eeprom.json")),
        ..SimConfig::default()
    };
    let mut first = Tmcm1110::new(config.clone());
    host_ok(&mut first, C::EnterDownload { address: 0 });
    for command in [add(0, 1), C::Stop] {
        assert_eq!(host(&mut first, command).status, Status::LOADED);
    }
    host_ok(&mut first, C::ExitDownload);
    host_ok(
        &mut first,
        C::Sgp {
            param: 77,
            bank: 0,
            value: 1,
        },
    );
    drop(first);

    let mut second = Tmcm1110::new(config);
    assert_eq!(status(&mut second), 1, "started at power-up");
    second.advance(ms(1));
    assert_eq!((var(&second, 0), status(&mut second)), (1, 0));
}

#[test]
fn the_program_does_not_run_in_download_mode() {
    let mut sim = sim_with(&[add(0, 1), ja(0)]);
    host_ok(&mut sim, C::EnterDownload { address: 100 });
    run(&mut sim);
    sim.advance(ms(10));
    assert_eq!(var(&sim, 0), 0);
    host_ok(&mut sim, C::ExitDownload);
    sim.advance(ms(1));
    assert!(var(&sim, 0) > 0);
}

// ---- direct mode beside a program (§8.6) -------------------------------------

#[test]
fn direct_mode_calculations_leave_the_program_registers_alone() {
    let mut sim = sim_with(&[
        load_a(5),
        C::Comp { value: 5 },
        wait(WaitCondition::Ticks, 10),
        C::Jc {
            condition: Condition::Eq,
            address: 5,
        },
        C::Stop,
        a_to(0),
        C::Stop,
    ]);
    run(&mut sim);
    sim.advance(ms(50));
    let calc = |op, operand| C::Calc { op, operand };
    assert_eq!(host_ok(&mut sim, calc(CalcOp::Load, 99)), 99);
    assert_eq!(host_ok(&mut sim, calc(CalcOp::Sub, 1)), 1);
    host_ok(&mut sim, C::Calcx { op: CalcOp::Load });
    host_ok(
        &mut sim,
        C::Calcav {
            op: CalcOp::Comp,
            var: 3,
        },
    );
    // The host's own A: AGP stores 98.
    host_ok(&mut sim, a_to(10));
    assert_eq!(var(&sim, 10), 98);
    assert_eq!(host_ok(&mut sim, gap(1)), 0);
    assert_eq!(
        host_ok(
            &mut sim,
            C::ApplicationStatus {
                query: StatusQuery::Accumulator
            }
        ),
        5
    );
    run_until_stopped(&mut sim, ms(200));
    assert_eq!(var(&sim, 0), 5, "A and the EQ flag survived");
}

#[test]
fn a_program_move_is_reported_by_command_138() {
    let mut sim = quiet_sim_with(&[mvp(1000), C::Stop]);
    host_ok(
        &mut sim,
        C::TargetReachedEvent {
            mode: crate::protocol::tmcl::EventMode::Always,
            motor_mask: 1,
        },
    );
    run(&mut sim);
    let mut out = Vec::new();
    for _ in 0..200 {
        sim.advance(ms(10));
        out.extend(sim.take_output());
    }
    assert_eq!(out.get(2), Some(&128), "status 128 message: {out:02X?}");
}

// ---- interrupts ---------------------------------------------------------------

/// Two timers expire while interrupts are globally off; EI 255 serves
/// timer 0 first (§5.4: lower number, higher priority).
#[test]
fn the_lower_interrupt_number_is_served_first() {
    let mut program = vec![
        vect(0, 20),
        vect(1, 30),
        interrupt_config(0, 100),
        interrupt_config(1, 100),
        ei(0),
        ei(1),
        wait(WaitCondition::Ticks, 20),
        ei(255),
        wait(WaitCondition::Ticks, 5),
        C::Stop,
    ];
    program.resize(20, C::Stop);
    program.extend([times(0, 10), add(0, 1), C::Reti]);
    program.resize(30, C::Stop);
    program.extend([times(0, 10), add(0, 2), C::Reti]);
    let mut sim = sim_with(&program);
    run(&mut sim);
    sim.advance(ms(200));
    assert_eq!(var(&sim, 0), 0, "interrupts globally off");
    assert_eq!(
        sim.app
            .interrupts
            .pending
            .iter()
            .copied()
            .collect::<Vec<_>>(),
        [0, 1]
    );
    sim.advance(ms(50));
    assert_eq!(var(&sim, 0), 12);
}

/// A request that arrives while a handler runs waits for its RETI
/// (§3.5.6.2: no nesting).
#[test]
fn a_handler_is_not_interrupted() {
    let mut program = vec![
        vect(0, 20),
        vect(1, 30),
        ei(0),
        ei(1),
        ei(255),
        interrupt_config(1, 50),
        interrupt_config(0, 60),
        wait(WaitCondition::Ticks, 100),
        ja(7),
    ];
    program.resize(20, C::Stop);
    program.extend([interrupt_config(0, 0), times(0, 10), add(0, 1), C::Reti]);
    program.resize(30, C::Stop);
    program.extend([
        interrupt_config(1, 0),
        times(0, 10),
        add(0, 2),
        wait(WaitCondition::Ticks, 10),
        C::Reti,
    ]);
    let mut sim = sim_with(&program);
    run(&mut sim);
    sim.advance(ms(100));
    assert_eq!(var(&sim, 0), 2);
    assert_eq!(sim.view().handling_interrupt, Some(1));
    assert!(sim.app.interrupts.pending.contains(&0));
    sim.advance(ms(100));
    assert_eq!(var(&sim, 0), 21);
    assert_eq!(sim.view().handling_interrupt, None);
    assert!(sim.view().waiting, "back in the main WAIT");
}

/// §3.5.6.2: A, X and the flags are saved on entry and restored by RETI;
/// the interrupted WAIT goes on to its original end.
#[test]
fn a_handler_returns_the_registers_it_found() {
    let mut program = vec![
        vect(0, 20),
        interrupt_config(0, 10),
        ei(0),
        ei(255),
        load_a(5),
        C::Calcx { op: CalcOp::Load },
        load_a(7),
        C::Comp { value: 7 },
        wait(WaitCondition::Ticks, 3),
        C::Jc {
            condition: Condition::Eq,
            address: 11,
        },
        C::Stop,
        a_to(0),
        C::Calcx { op: CalcOp::Swap },
        a_to(1),
        C::Di { interrupt: 255 },
        C::Stop,
    ];
    program.resize(20, C::Stop);
    program.extend([
        load_a(99),
        C::Calcx { op: CalcOp::Load },
        C::Comp { value: 100 },
        add(2, 1),
        C::Reti,
    ]);
    let mut sim = sim_with(&program);
    run(&mut sim);
    sim.advance(ms(30));
    assert_eq!(var(&sim, 2), 2, "two timer interrupts during the WAIT");
    assert!(sim.view().waiting, "the WAIT ends at 30.4 ms");
    run_until_stopped(&mut sim, ms(100));
    assert_eq!((var(&sim, 0), var(&sim, 1)), (7, 5));
    assert_eq!(pc(&mut sim), 15);
}

/// A timer expiring during a stepped WAIT is remembered, but the next step
/// executes the command at the PC; the handler runs once the program does.
#[test]
fn interrupts_wait_while_single_stepping() {
    let mut program = vec![
        vect(0, 10),
        interrupt_config(0, 20),
        ei(0),
        ei(255),
        wait(WaitCondition::Ticks, 3),
        set(0, 1),
        ja(5),
    ];
    program.resize(10, C::Stop);
    program.extend([set(1, 1), C::Reti]);
    let mut sim = sim_with(&program);
    for _ in 0..5 {
        step(&mut sim);
        sim.advance(ms(1));
    }
    sim.advance(ms(40));
    assert_eq!((status(&mut sim), pc(&mut sim)), (0, 5));
    assert!(sim.app.interrupts.pending.contains(&0));
    step(&mut sim);
    sim.advance(ms(1));
    assert_eq!((var(&sim, 0), var(&sim, 1)), (1, 0), "stepped at the PC");
    run(&mut sim);
    sim.advance(ms(1));
    assert_eq!(var(&sim, 1), 1, "served once running");
}

#[test]
fn target_reached_fires_interrupt_3() {
    let mut program = vec![
        vect(3, 10),
        ei(3),
        ei(255),
        mvp(5000),
        wait(WaitCondition::Ticks, 1000),
        C::Stop,
    ];
    program.resize(10, C::Stop);
    program.extend([gap(1), a_to(0), add(1, 1), C::Reti]);
    let mut sim = quiet_sim_with(&program);
    run(&mut sim);
    sim.advance(ms(100));
    assert_eq!(var(&sim, 1), 0);
    sim.advance(Duration::from_secs(2));
    assert_eq!((var(&sim, 0), var(&sim, 1)), (5000, 1));
}

#[test]
fn a_stall_stop_fires_interrupt_15() {
    let mut program = vec![
        vect(15, 10),
        ei(15),
        ei(255),
        C::Sap {
            param: 181,
            motor: 0,
            value: 100,
        },
        C::Ror {
            motor: 0,
            velocity: 500,
        },
        wait(WaitCondition::Ticks, 1000),
    ];
    program.resize(10, C::Stop);
    program.extend([add(0, 1), C::Reti]);
    let mut sim = quiet_sim_with(&program);
    run(&mut sim);
    sim.advance(ms(500));
    assert_eq!(var(&sim, 0), 0);
    sim.axis.set_load_percent(100);
    sim.advance(ms(10));
    assert_eq!(var(&sim, 0), 1);
    assert_eq!(sim.axis.param(2), 0, "the motor was stopped");
}

#[test]
fn a_deviation_stop_fires_interrupt_21_and_sets_edv() {
    let mut program = vec![
        vect(21, 20),
        ei(21),
        ei(255),
        C::Sap {
            param: 212,
            motor: 0,
            value: 100,
        },
        C::Ror {
            motor: 0,
            velocity: 500,
        },
        wait(WaitCondition::Ticks, 50),
        C::Jc {
            condition: Condition::Edv,
            address: 8,
        },
        C::Stop,
        set(1, 1),
        C::Stop,
    ];
    program.resize(20, C::Stop);
    program.extend([add(0, 1), C::Reti]);
    let mut sim = quiet_sim_with(&program);
    run(&mut sim);
    sim.advance(ms(100));
    sim.axis.inject_slip(1000);
    run_until_stopped(&mut sim, ms(1000));
    assert_eq!((var(&sim, 0), var(&sim, 1)), (1, 1));
}

/// Interrupt 28 on the right stop switch: 1 = low→high fires when the
/// switch closes, 2 = high→low does not.
#[test]
fn stop_switch_edges_fire_interrupts_27_and_28() {
    for (number, velocity, trigger, fires) in [
        (28, 1000, 1, true),
        (28, 1000, 2, false),
        (27, -1000, 3, true),
        (27, -1000, 0, false),
    ] {
        let mut program = vec![
            vect(number, 10),
            interrupt_config(number, trigger),
            ei(number),
            ei(255),
            C::Ror { motor: 0, velocity },
            wait(WaitCondition::Ticks, 1000),
        ];
        program.resize(10, C::Stop);
        program.extend([gap(1), a_to(0), add(1, 1), C::Reti]);
        let mut sim = sim_with(&program);
        run(&mut sim);
        sim.advance(Duration::from_secs(9));
        let expected = if fires {
            (200_000 * velocity.signum(), 1)
        } else {
            (0, 0)
        };
        assert_eq!(
            (var(&sim, 0), var(&sim, 1)),
            expected,
            "interrupt {number} trigger {trigger}"
        );
    }
}

#[test]
fn input_edges_fire_interrupts_39_to_44() {
    let mut program = vec![
        vect(39, 10),
        vect(40, 12),
        interrupt_config(39, 2),
        interrupt_config(40, 3),
        ei(39),
        ei(255),
        wait(WaitCondition::Ticks, 10),
        ja(6),
    ];
    program.resize(10, C::Stop);
    program.extend([add(0, 1), C::Reti, add(1, 1), C::Reti]);
    let mut sim = sim_with(&program);
    // Port 1 (PWMD0) is pulled up: high until driven low. An edge while no
    // program runs is not remembered.
    sim.set_input(1, Some(false)).expect("port 1");
    sim.advance(ms(10));
    run(&mut sim);
    sim.advance(ms(10));
    assert_eq!(var(&sim, 0), 0);
    sim.set_input(1, Some(true)).expect("port 1");
    sim.advance(ms(10));
    assert_eq!(var(&sim, 0), 0, "low→high does not fire");
    sim.set_input(1, Some(false)).expect("port 1");
    sim.advance(ms(10));
    assert_eq!(var(&sim, 0), 1, "high→low fires");
    sim.set_input(1, Some(true)).expect("port 1");
    sim.advance(ms(10));
    sim.set_input(1, Some(false)).expect("port 1");
    sim.set_input(2, Some(false)).expect("port 2");
    sim.advance(ms(10));
    assert_eq!(var(&sim, 0), 2);
    assert_eq!(var(&sim, 1), 0, "interrupt 40 not enabled");
}

#[test]
fn a_timer_raises_nothing_while_no_program_runs() {
    let mut program = vec![
        vect(0, 10),
        interrupt_config(0, 10),
        ei(0),
        ei(255),
        C::Stop,
    ];
    program.resize(10, C::Stop);
    program.extend([add(0, 1), C::Reti]);
    let mut sim = sim_with(&program);
    run(&mut sim);
    sim.advance(ms(100));
    assert!(sim.app.interrupts.pending.is_empty());
    assert_eq!(var(&sim, 0), 0);
}
