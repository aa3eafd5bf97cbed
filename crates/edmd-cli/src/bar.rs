//! The progress bar on stderr: the library's `Progress`, drawn by indicatif.

use edmd_sweep::run::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// The progress bar on stderr (hidden with `--quiet` or when stderr is not a terminal).
pub(crate) struct Bar(ProgressBar);

impl Bar {
    pub(crate) fn new(quiet: bool) -> Bar {
        if quiet {
            Bar::with_target(ProgressDrawTarget::hidden())
        } else {
            Bar::with_target(ProgressDrawTarget::stderr())
        }
    }

    fn with_target(target: ProgressDrawTarget) -> Bar {
        let bar = ProgressBar::with_draw_target(Some(1), target);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:30} {msg} | collisions {per_sec:0} | ETA {eta}",
            )
            .expect("valid template"),
        );
        Bar(bar)
    }
}

impl Progress for Bar {
    fn start(&self, replicas: usize, collisions: u64) {
        self.0.set_length(collisions.max(1));
        self.0.set_message(format!("0/{replicas} replicas"));
    }
    fn advance(&self, collisions: u64) {
        self.0.inc(collisions);
    }
    fn replica_done(&self, done: usize, replicas: usize) {
        self.0.set_message(format!("{done}/{replicas} replicas"));
    }
    fn finish(&self) {
        self.0.finish_and_clear();
    }
    fn notice(&self, message: &str) {
        self.0.suspend(|| eprintln!("{message}"));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    /// A terminal that records what is drawn on it.
    #[derive(Debug, Clone, Default)]
    struct Screen(Arc<Mutex<String>>);

    impl indicatif::TermLike for Screen {
        fn width(&self) -> u16 {
            160
        }
        fn move_cursor_up(&self, _: usize) -> std::io::Result<()> {
            Ok(())
        }
        fn move_cursor_down(&self, _: usize) -> std::io::Result<()> {
            Ok(())
        }
        fn move_cursor_right(&self, _: usize) -> std::io::Result<()> {
            Ok(())
        }
        fn move_cursor_left(&self, _: usize) -> std::io::Result<()> {
            Ok(())
        }
        fn write_line(&self, s: &str) -> std::io::Result<()> {
            self.write_str(&format!("{s}\n"))
        }
        fn write_str(&self, s: &str) -> std::io::Result<()> {
            self.0.lock().unwrap().push_str(s);
            Ok(())
        }
        fn clear_line(&self) -> std::io::Result<()> {
            Ok(())
        }
        fn flush(&self) -> std::io::Result<()> {
            Ok(())
        }
    }

    /// The bar shows a collision rate with a number (the earlier `{human_per_sec}` is no indicatif
    /// key and drew nothing).
    #[test]
    fn the_progress_bar_shows_collisions_per_second() {
        let screen = Screen::default();
        let bar = Bar::with_target(ProgressDrawTarget::term_like(Box::new(screen.clone())));
        bar.start(3, 3_000_000);
        for _ in 0..5 {
            std::thread::sleep(std::time::Duration::from_millis(30));
            bar.advance(100_000);
            bar.0.tick();
        }
        bar.replica_done(1, 3);
        bar.0.tick();
        let drawn = screen.0.lock().unwrap().clone();
        // The last frame drawn (frames follow one another on one line).
        let line = drawn.rsplit('⠁').next().unwrap_or_default();
        let line = line.rsplit("[00:").next().unwrap_or_default().to_string();
        let rate = line
            .split("collisions ")
            .nth(1)
            .and_then(|r| r.split("/s").next())
            .unwrap_or_default()
            .replace(',', "");
        assert!(
            rate.parse::<u64>().is_ok_and(|x| x > 0),
            "no whole-number rate in {line:?}"
        );
        assert!(line.contains("1/3 replicas"), "{line:?}");
    }
}
