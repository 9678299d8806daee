//! A progress bar on standard error, drawn only when standard error is a terminal.

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::Instant;

/// Draws `label [#####.....] done/total elapsed` in place; silent when not on a terminal.
pub struct Progress {
    label: String,
    start: Instant,
    enabled: bool,
    last_drawn: Mutex<usize>,
}

impl Progress {
    /// A bar for a task called `label`.
    pub fn new(label: &str) -> Self {
        Self {
            label: label.to_string(),
            start: Instant::now(),
            enabled: std::io::stderr().is_terminal(),
            last_drawn: Mutex::new(usize::MAX),
        }
    }

    /// Reports `done` of `total` steps.
    pub fn update(&self, done: usize, total: usize) {
        if !self.enabled || total == 0 {
            return;
        }
        const WIDTH: usize = 30;
        let filled = done * WIDTH / total;
        let Ok(mut last) = self.last_drawn.lock() else {
            return;
        };
        if *last == filled && done != total {
            return;
        }
        *last = filled;
        let mut err = std::io::stderr().lock();
        let _ = write!(
            err,
            "\r{} [{}{}] {done}/{total} {:.1} s",
            self.label,
            "#".repeat(filled),
            ".".repeat(WIDTH - filled),
            self.start.elapsed().as_secs_f64()
        );
        if done == total {
            let _ = writeln!(err);
        }
        let _ = err.flush();
    }
}
