//! Progress bars on a terminal, silence when piped.

use indicatif::{ProgressBar, ProgressStyle};

/// A bar over `total` steps with a message; invisible unless stderr is a
/// terminal (indicatif hides it otherwise).
pub fn bar(message: &'static str, total: u64) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template("{msg:>12} [{bar:40}] {percent:>3}% {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(message);
    bar
}
