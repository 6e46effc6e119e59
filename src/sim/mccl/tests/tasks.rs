//! Background tasks (Ch4 "MCCL Multi-Tasking", Ch10 GT/ET).

use super::*;
use crate::sim::mccl::tasks::MOST_TASKS;

#[test]
fn a_task_runs_while_the_foreground_answers() {
    let mut s = Session::new();
    s.quiet(&["AL0,AR100", "MD100,AL@100,AA1,AR100,WA0.01,JR-4"]);
    assert_eq!(s.line("GT100,AR150,TR150"), ["01 1"], "the task ID in ACC");
    s.advance_ms(100);
    let first = s.tell("TR100");
    assert!((9.0..=11.0).contains(&first), "{first} counts in 100 ms");
    s.quiet(&["1MN,1MR1000,1WS"]);
    let later = s.tell("TR100");
    assert!(later > first, "it kept counting while the foreground ran");
    assert_eq!(s.sim.task_count(), 1);
    s.quiet(&["ET@150"]);
    assert_eq!(s.sim.task_count(), 0);
    let stopped = s.tell("TR100");
    s.advance_ms(100);
    assert_eq!(s.tell("TR100"), stopped);
}

#[test]
fn the_ch4_multitasking_example() {
    // Ch4: monitor input 4 in a task while axis 1 runs in velocity mode;
    // when it turns on, stop axis 1 and end the task (AR150 for the
    // printed AR@100: the ID goes into a register, not through one).
    let mut s = Session::new();
    s.quiet(&[
        "AL0,AR10",
        "AL0,AR100",
        "MD100, IN4, MJ101, NO, 1JR-3",
        "MD101,1ST,1WS.05,AL1,AR10,ET@100",
        "1MN",
        "GT100,AR100,1VM,1DI0,1GO",
    ]);
    s.advance_ms(200);
    assert!(s.tell("1TV") > 0.0, "moving");
    assert_eq!(s.sim.task_count(), 1);
    s.drive("IN4=1");
    s.advance_ms(1000);
    assert_eq!(s.sim.task_count(), 0, "the task ended itself");
    assert_eq!(s.line("TR10"), ["01 1"]);
    assert_eq!(s.tell("1TV"), 0.0);
}

#[test]
fn tasks_have_their_own_r0_to_r9() {
    let mut s = Session::new();
    s.quiet(&["AL5,AR5", "GT0,AL77,AR5,AR200"]);
    s.advance_ms(5);
    assert_eq!(s.line("TR5,TR200"), ["01 5", "01 77"]);
}

#[test]
fn at_most_21_tasks_and_bad_ids() {
    let mut s = Session::new();
    s.quiet(&["MD1,WA10"]);
    for _ in 0..MOST_TASKS {
        s.quiet(&["GT1"]);
    }
    assert_eq!(s.error("GT1"), -18);
    assert_eq!(s.error("ET0"), -20);
    assert_eq!(s.error("GT2"), -6);
    assert_eq!(s.line("ID7").len(), MOST_TASKS + 1);
}

#[test]
fn reporting_commands_end_a_task() {
    let mut s = Session::new();
    s.quiet(&["MD50,AL1,AR300,1TP,AL2,AR300", "GT50"]);
    s.advance_ms(5);
    assert_eq!(s.sim.task_count(), 0);
    assert_eq!(s.line("TR300"), ["01 1"], "it stopped at 1TP");
}

#[test]
fn a_task_started_with_gt0_runs_the_rest_of_the_line() {
    let mut s = Session::new();
    let exchange = s.exchange("GT0,WA0.1,AL9,AR400", 10);
    assert!(exchange.lines.is_empty());
    assert!(exchange.ms <= 1, "the foreground did not wait");
    assert_eq!(s.line("TR400"), ["01 0"]);
    s.advance_ms(110);
    assert_eq!(s.line("TR400"), ["01 9"]);
}
