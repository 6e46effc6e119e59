//! Background tasks (manual Ch4 "MCCL Multi-Tasking", Ch10 GT/ET): at most
//! 21, each an interpreter of its own with private R0–R9, known by the ID
//! GT puts in the accumulator.
//!
//! Choices: IDs count up from 1 (never reused while the simulator runs,
//! so a stale ID cannot end a newer task); a 22nd task is refused with
//! −18 (insufficient memory).

use std::sync::Arc;

use super::errors::Code;
use super::interpreter::Interpreter;
use super::program::Program;

/// Ch4: "The maximum number of background tasks is 21."
pub const MOST_TASKS: usize = 21;

#[derive(Debug, Clone)]
struct Slot {
    id: i32,
    /// `None` while it runs its slice.
    interp: Option<Interpreter>,
}

#[derive(Debug, Clone)]
pub struct Tasks {
    slots: Vec<Slot>,
    next_id: i32,
}

impl Default for Tasks {
    fn default() -> Self {
        Tasks {
            slots: Vec::new(),
            next_id: 1,
        }
    }
}

impl Tasks {
    pub fn len(&self) -> usize {
        self.slots.len()
    }

    /// The IDs of the tasks that run (ID7).
    pub fn ids(&self) -> Vec<i32> {
        self.slots.iter().map(|s| s.id).collect()
    }

    /// Start a task running `program`; its ID.
    pub fn spawn(&mut self, program: Arc<Program>, default_axis: u8) -> Result<i32, Code> {
        if self.slots.len() >= MOST_TASKS {
            return Err(Code::NO_MEMORY);
        }
        let id = self.next_id;
        self.next_id = self.next_id.checked_add(1).unwrap_or(1);
        self.slots.push(Slot {
            id,
            interp: Some(Interpreter::task(id, program, default_axis)),
        });
        Ok(id)
    }

    /// The task at `index` in turn order, taken out to run.
    pub fn take(&mut self, index: usize) -> Option<Interpreter> {
        self.slots.get_mut(index)?.interp.take()
    }

    /// A task back after its slice.
    pub fn put_back(&mut self, task: Interpreter) {
        if let Some(slot) = self.slots.iter_mut().find(|s| Some(s.id) == task.task) {
            slot.interp = Some(task);
        }
    }

    /// ET, or the end of a task: `false` if there is no such task.
    pub fn end(&mut self, id: i32) -> bool {
        let before = self.slots.len();
        self.slots.retain(|s| s.id != id);
        self.slots.len() < before
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::mccl::program::Origin;

    #[test]
    fn at_most_21_tasks_with_ids_never_reused() {
        let mut tasks = Tasks::default();
        let program = Program::new(Vec::new(), Origin::Line);
        let ids: Vec<i32> = (0..MOST_TASKS)
            .map(|_| tasks.spawn(program.clone(), 0).expect("room"))
            .collect();
        assert_eq!(ids[0], 1);
        assert_eq!(tasks.spawn(program.clone(), 0), Err(Code::NO_MEMORY));
        assert!(tasks.end(5));
        assert!(!tasks.end(5));
        assert_eq!(tasks.spawn(program, 0), Ok(22));
        let running = tasks.take(0).expect("task 1");
        assert_eq!(running.task, Some(1));
        assert_eq!(
            running.accumulator(),
            crate::sim::mccl::values::Value::Int(1)
        );
        assert!(tasks.take(0).is_none(), "out while it runs");
        tasks.put_back(running);
        assert!(tasks.take(0).is_some());
    }
}
