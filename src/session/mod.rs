//! What the console knows of one connected controller: its axes and their
//! status snapshots, its identity, the connection state. Built from a
//! family's protocol knowledge on top of the device task.
