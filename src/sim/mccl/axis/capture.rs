//! Recording (PR), position capture (CB) and position compare (LC, NC, BC,
//! OC, OP, GC) of one axis (manual Ch7), in counts.
//!
//! PR and CB fill the one sample list DR/DO/DQ/DA read (CB's page says its
//! positions "are reported by using the Display Recorded position (aDRn)
//! command"); whichever started last owns it. PR takes a sample every
//! trajectory tick (1 kHz).

/// One recorded sample.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sample {
    pub actual: f64,
    pub optimal: f64,
    /// Command output, volts.
    pub output: f64,
    pub aux: f64,
}

/// The most samples kept (PR, CB: ≤ 1024).
pub const MOST_SAMPLES: usize = 1024;

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Record {
    pub samples: Vec<Sample>,
    /// PR: samples still to take.
    pub recording: usize,
    /// CB: how many captures make the count (status bit 5); `None` off.
    pub capturing: Option<usize>,
}

impl Record {
    /// PR n: start recording n samples.
    pub fn start_recording(&mut self, n: usize) {
        self.samples.clear();
        self.recording = n.min(MOST_SAMPLES);
        self.capturing = None;
    }

    /// CB n: capture n positions (0 or 1: one); negative stops.
    pub fn start_capturing(&mut self, n: i64) {
        if n < 0 {
            self.capturing = None;
            return;
        }
        self.samples.clear();
        self.recording = 0;
        self.capturing = Some(usize::try_from(n.max(1)).unwrap_or(1).min(MOST_SAMPLES));
    }

    /// A sample of this tick, if recording.
    pub fn tick(&mut self, sample: Sample) {
        if self.recording > 0 {
            self.samples.push(sample);
            self.recording -= 1;
        }
    }

    /// The capture input rose: keep the sample; `true` when the count is
    /// reached (status bit 5).
    pub fn capture(&mut self, sample: Sample) -> bool {
        let Some(wanted) = self.capturing else {
            return false;
        };
        self.samples.push(sample);
        if self.samples.len() >= wanted {
            self.capturing = None;
            return true;
        }
        false
    }

    pub fn sample(&self, i: usize) -> Option<&Sample> {
        self.samples.get(i)
    }
}

/// Position compare.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Compare {
    /// LC positions, counts (≤ 1024).
    pub positions: Vec<f64>,
    /// NC, counts.
    pub increment: f64,
    pub active: Option<CompareRun>,
    /// Events since BC (GC).
    pub count: u32,
    /// OC: 0 off, 1 static, 2 toggle, 3 one-shot; + 128 inverts.
    pub output_mode: u8,
    /// OP, seconds.
    pub period: f64,
    /// One-shot time left, seconds.
    pub pulse_left: f64,
}

/// A compare under way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CompareRun {
    /// BC0: from the first LC position, every NC.
    Interval { next: f64 },
    /// BC n: the first n LC positions in order.
    List { index: usize, last: usize },
}

impl Compare {
    /// LC: one more compare position.
    pub fn load(&mut self, position: f64) -> bool {
        if self.positions.len() >= MOST_SAMPLES {
            return false;
        }
        self.positions.push(position);
        true
    }

    /// BC n: start (0: every NC from the first position; n: the first n
    /// positions) or stop (negative). `false` if there is nothing to compare.
    pub fn begin(&mut self, n: i64) -> bool {
        if n < 0 {
            self.active = None;
            self.positions.clear();
            return true;
        }
        let Some(&first) = self.positions.first() else {
            return false;
        };
        self.count = 0;
        self.active = Some(if n == 0 {
            CompareRun::Interval { next: first }
        } else {
            let last = usize::try_from(n).unwrap_or(0).min(self.positions.len());
            CompareRun::List { index: 0, last }
        });
        true
    }

    /// The position moved from `from` to `to`: the compare events on the way.
    pub fn check(&mut self, from: f64, to: f64) -> u32 {
        let reached = |p: f64| {
            if to >= from {
                p > from && p <= to || p == to
            } else {
                p < from && p >= to
            }
        };
        let mut events = 0;
        while let Some(run) = self.active {
            match run {
                CompareRun::Interval { next } => {
                    if !reached(next) || events >= 1000 || self.increment == 0.0 && events > 0 {
                        break;
                    }
                    events += 1;
                    self.active = Some(CompareRun::Interval {
                        next: next + self.increment,
                    });
                }
                CompareRun::List { index, last } => {
                    let Some(&p) = self.positions.get(index).filter(|_| index < last) else {
                        self.active = None;
                        break;
                    };
                    if !reached(p) {
                        break;
                    }
                    events += 1;
                    self.active = if index + 1 < last {
                        Some(CompareRun::List {
                            index: index + 1,
                            last,
                        })
                    } else {
                        None
                    };
                }
            }
        }
        self.count = self.count.saturating_add(events);
        events
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_manuals_interval_compare_counts_every_250_counts() {
        // Ch7 BC: 1LC1000, 1NC250, 1BC0, 1MA3000, 1WP2100: events at 1000,
        // 1250, … 2000 by then.
        let mut compare = Compare::default();
        assert!(compare.load(1000.0));
        compare.increment = 250.0;
        assert!(compare.begin(0));
        let mut position = 0.0;
        let mut events = 0;
        while position < 2100.0 {
            let next = position + 7.0;
            events += compare.check(position, next);
            position = next;
        }
        assert_eq!(events, 5);
        assert_eq!(compare.count, 5);
        assert!(compare.begin(-1));
        assert_eq!(compare.check(2100.0, 3000.0), 0, "stopped");
    }

    #[test]
    fn a_list_compare_ends_after_its_positions() {
        let mut compare = Compare::default();
        for p in [300.0, 100.0, 200.0] {
            compare.load(p);
        }
        assert!(compare.begin(2));
        assert_eq!(compare.check(0.0, 250.0), 0, "300 comes first");
        assert_eq!(compare.check(250.0, 350.0), 1);
        assert_eq!(compare.check(350.0, 50.0), 1, "then 100, going back");
        assert_eq!(compare.active, None);
        assert!(!Compare::default().begin(0), "nothing loaded");
    }

    #[test]
    fn capture_counts_to_n_and_recording_takes_a_sample_a_tick() {
        let mut record = Record::default();
        record.start_capturing(2);
        assert!(!record.capture(Sample::default()));
        assert!(record.capture(Sample::default()));
        assert!(!record.capture(Sample::default()), "done");
        record.start_recording(3);
        for _ in 0..5 {
            record.tick(Sample::default());
        }
        assert_eq!(record.samples.len(), 3);
    }
}
